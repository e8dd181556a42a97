//! `filmsplat render`: render a particle cloud or a scene file: one image, a quoted glob's
//! matches, or a frame sequence.

pub use super::render_args::RenderArgs;
use super::render_one::render_one;
use super::{glob, sequence};
use crate::{Error, Result};
use std::io::Write;

/// Runs `filmsplat render`: one image, or a sequence with --frames.
pub fn run(a: &RenderArgs, out: &mut dyn Write) -> Result<()> {
    if let [only] = a.inputs.as_slice()
        && a.frames.is_none()
        && glob::is_glob(only)
        && !only.exists()
    {
        return run_glob(a, out);
    }
    let Some(frames) = &a.frames else {
        if a.frame_all {
            return Err(Error::invalid(
                "--frame-all frames a whole sequence; it needs --frames",
            ));
        }
        return render_one(a, out, None);
    };
    sequence::render_sequence(a, &frames.0, out)
}

/// Renders every match of a quoted glob input (`'frames/*.ply'`), sorted by name, as a sequence:
/// `{stem}` in -o (and --exr) names each output after its input; the n-th match's seed is the
/// seed plus n.
fn run_glob(a: &RenderArgs, out: &mut dyn Write) -> Result<()> {
    let pattern = a.inputs.first().cloned().unwrap_or_default();
    let inputs = glob::expand(&pattern)?;
    let output = a.output.as_ref().ok_or_else(|| {
        Error::invalid(format!(
            "{}: a glob input needs -o with {{stem}}, e.g. -o 'out/{{stem}}.png'",
            pattern.display()
        ))
    })?;
    for p in std::iter::once(output).chain(a.exr.as_ref()) {
        if inputs.len() > 1 && !p.to_string_lossy().contains("{stem}") {
            return Err(Error::invalid(format!(
                "{}: {} files match {}; the output needs {{stem}} (e.g. 'out/{{stem}}.png') so \
                 they do not overwrite each other",
                p.display(),
                inputs.len(),
                pattern.display()
            )));
        }
    }
    let mut failed = Vec::new();
    for (n, input) in inputs.iter().enumerate() {
        let mut one = a.clone();
        one.inputs = vec![input.clone()];
        one.output = Some(glob::with_stem(output, input));
        one.exr = a.exr.as_ref().map(|e| glob::with_stem(e, input));
        one.seed = Some(a.seed.unwrap_or(0).wrapping_add(n as u64));
        let target = one.output.clone().expect("set");
        if a.resume
            && std::iter::once(&target)
                .chain(one.exr.as_ref())
                .all(|p| p.exists())
        {
            if !a.quiet {
                let _ = writeln!(
                    out,
                    "{}: {} exists, skipped",
                    input.display(),
                    target.display()
                );
            }
            continue;
        }
        if !a.quiet {
            let _ = writeln!(out, "{} ({}/{}):", input.display(), n + 1, inputs.len());
        }
        match render_one(&one, out, None) {
            Ok(()) => {}
            Err(e) if a.keep_going => {
                eprintln!("filmsplat: error: {e}");
                failed.push(input.display().to_string());
            }
            Err(e) => return Err(e),
        }
    }
    if !failed.is_empty() {
        return Err(Error::invalid(format!(
            "{} of {} inputs failed: {}",
            failed.len(),
            inputs.len(),
            failed.join(", ")
        )));
    }
    Ok(())
}
