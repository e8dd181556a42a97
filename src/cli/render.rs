//! `filmsplat render`: render a particle cloud or a scene file: one image, a quoted glob's
//! matches, or a frame sequence.

pub use super::render_args::RenderArgs;
use super::render_one::render_one;
use super::{glob, sequence};
use crate::pipeline::sequence as seq;
use crate::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Runs `filmsplat render`: one image, or a sequence with --frames.
pub fn run(a: &RenderArgs, out: &mut dyn Write) -> Result<()> {
    // --max-memory first, for the whole command: resolving a scene checks the image size
    // against the allowance, and every reader's allocation checks use it.
    if let Some(bytes) = a.max_memory {
        crate::budget::set_allowance(bytes);
    }
    if a.frames.is_none() {
        for (given, flag) in [(a.fps.is_some(), "--fps"), (a.crf.is_some(), "--crf")] {
            if given {
                return Err(Error::invalid(format!(
                    "{flag} is a flag of sequences and movies: give --frames (e.g. --frames \
                     0..48 -o movie.mp4)"
                )));
            }
        }
    }
    if let Some(o) = &a.output
        && a.frames.is_none()
        && crate::image::video::Container::of(o).is_some()
    {
        return Err(Error::invalid(format!(
            "{}: a movie is made of a sequence: give --frames with a frame pattern in the \
             input (e.g. 'frames/{{:04}}.ply' --frames 0..48), or join images with \
             `filmsplat encode`",
            o.display()
        )));
    }
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
        if a.orbit.is_some() {
            return Err(Error::invalid(
                "--orbit turns the camera over a sequence; it needs --frames (e.g. --frames \
                 0..120 for 120 views)",
            ));
        }
        return render_one(a, out, None);
    };
    sequence::render_sequence(a, &frames.0, out)
}

/// Renders every match of a quoted glob input (`'frames/*.ply'`), sorted by name, as a sequence:
/// `{stem}` in -o (and --exr) names each output after its input; the n-th match's seed is the
/// seed plus n. `--shard K/N` renders every N-th match from the K-th; outputs are checked
/// first (two matches with one output name, such as `a.ply` and `a.csv`, are refused); resume
/// skips finished outputs as the frame sequences do ([`seq::finished`]).
fn run_glob(a: &RenderArgs, out: &mut dyn Write) -> Result<()> {
    let pattern = a.inputs.first().cloned().unwrap_or_default();
    let (inputs, beside) = glob::without_droplets_beside(glob::expand(&pattern)?);
    if beside > 0 {
        let _ = writeln!(
            out,
            "note: {beside} of the files matching {} are droplets beside a film \
             (NAME.droplets.ply, written by convert): each is read with its film, not as a \
             frame of its own",
            pattern.display()
        );
    }
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
    let outputs = |input: &Path| -> Vec<PathBuf> {
        std::iter::once(glob::with_stem(output, input))
            .chain(a.exr.as_ref().map(|e| glob::with_stem(e, input)))
            .collect()
    };
    glob::refuse_shared_outputs(&inputs, outputs)?;
    let all: Vec<u64> = (0..inputs.len() as u64).collect();
    let mine = seq::sharded(&all, a.shard);
    seq::check_outputs(&mine, |n| Ok(outputs(&inputs[n as usize])))?;
    let mut failed = Vec::new();
    for (k, &n) in mine.iter().enumerate() {
        let input = &inputs[n as usize];
        let these = outputs(input);
        let label = input.display().to_string();
        if a.resume && seq::finished(&label, &these, a.quiet, out)? {
            continue;
        }
        seq::refuse_directories(&these)?;
        if !a.quiet {
            let _ = writeln!(out, "{label} ({}/{}):", k + 1, mine.len());
        }
        let mut one = a.clone();
        one.inputs = vec![input.clone()];
        (one.output, one.exr) = (these.first().cloned(), these.get(1).cloned());
        one.seed = Some(a.seed.unwrap_or(0).wrapping_add(n));
        match render_one(&one, out, None) {
            Ok(()) => {}
            Err(e) if a.keep_going => {
                eprintln!("filmsplat: error: {e}");
                failed.push(label);
            }
            Err(e) => return Err(e),
        }
    }
    if !failed.is_empty() {
        return Err(Error::invalid(format!(
            "{} of {} inputs failed: {}",
            failed.len(),
            mine.len(),
            failed.join(", ")
        )));
    }
    Ok(())
}
