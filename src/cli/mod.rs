//! Command-line front end: a thin layer that turns clap arguments into library calls, and
//! library errors into one-line messages and exit codes (2: bad input, 1: internal error).

mod attributes;
mod chart;
mod compare;
mod compare_report;
mod convert;
mod encode;
mod film;
mod glob;
mod info;
mod movie;
mod parse;
mod render;
mod render_args;
mod render_one;
mod render_scene;
mod sample;
mod sequence;
mod stability;
pub mod threads;
mod view;

use clap::{Parser, Subcommand};
use std::ffi::OsString;
use std::io::Write;

/// filmsplat: spectral thin-film renderer for SPH particle clouds.
#[derive(Debug, Parser)]
#[command(name = "filmsplat", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Worker threads (1..4096). Default: the FILMSPLAT_THREADS environment variable, else
    /// the CPUs this job was given (CPU affinity, cgroup quota, and at most Slurm's
    /// SLURM_CPUS_PER_TASK).
    #[arg(long, global = true, value_name = "N", value_parser = threads_arg)]
    threads: Option<usize>,
}

/// clap value parser for `--threads`.
fn threads_arg(s: &str) -> Result<usize, String> {
    threads::parse_threads(s, "thread count").map_err(|e| e.to_string())
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Print the reflectance/transmittance (or reflected colour) of a thin film as CSV.
    Film(film::FilmArgs),
    /// Draw the interference colour chart (colour against thickness and angle) as a PNG.
    Chart(chart::ChartArgs),
    /// Render particle files (PLY, VTK, VTK XML, PVD, BGEO, CSV, simulator frame folders) or a
    /// scene file (.toml) to PNG or EXR.
    Render(Box<render::RenderArgs>),
    /// Describe a particle file: counts, attributes, bounds, spacing, thickness.
    Info(info::InfoArgs),
    /// Write a built-in sample cloud (a gallery scene: bubble, catenoid, films, drip, ...) as
    /// PLY, or a sequence of them.
    Sample(sample::SampleArgs),
    /// Convert any particle file filmsplat reads to binary PLY (droplets, if any, to a second
    /// file).
    Convert(convert::ConvertArgs),
    /// Render one scene with two geometries (disk, sphere, mls, mesh:FILE, reconstructed):
    /// a side-by-side PNG with a ΔE heat map, timings, PSNR, SSIM and CIEDE2000.
    Compare(Box<compare::CompareArgs>),
    /// Measure the temporal stability of a rendered sequence (mean CIEDE2000 between adjacent
    /// frames where the depth changes little).
    Stability(stability::StabilityArgs),
    /// Join rendered frames ('out/{:04}.png', e.g. of a sharded or resumed render) into a
    /// movie (.mp4 H.264 or .webm VP9) with the system's ffmpeg.
    Encode(encode::EncodeArgs),
    /// Preview interactively in a browser: serves a page on this machine (URL with an access
    /// token printed) where you orbit, zoom, scrub frames and switch views; takes the inputs
    /// and flags of `render`.
    View(Box<view::ViewArgs>),
}

/// Runs the CLI with the given arguments (including the program name), writing its data (CSV,
/// `info`'s description, metrics) to `out` and its messages (summaries, notes, warnings,
/// progress lines) to standard error. Returns the library error for the caller to report (a
/// bad command line as [`crate::Error::Usage`], or [`crate::Error::Invalid`] naming a refused
/// value); never exits.
pub fn run<I, T>(args: I, out: &mut dyn Write) -> crate::Result<()>
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    run_with(args, out, &mut std::io::stderr())
}

/// [`run`], with the messages written to `err` instead of standard error.
pub fn run_with<I, T>(args: I, out: &mut dyn Write, err: &mut dyn Write) -> crate::Result<()>
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            // Help and version go to stdout with success; usage errors are bad input.
            if !e.use_stderr() {
                let _ = writeln!(out, "{}", e.render().to_string().trim_end());
                return Ok(());
            }
            // A refused value is one line naming the flag, like every other bad input.
            if matches!(
                e.kind(),
                clap::error::ErrorKind::ValueValidation | clap::error::ErrorKind::InvalidValue
            ) {
                let text = e.render().to_string();
                let first = text.lines().find(|l| !l.trim().is_empty()).unwrap_or("");
                return Err(crate::Error::invalid(
                    first.trim_start_matches("error: ").trim(),
                ));
            }
            return Err(crate::Error::Usage(Box::new(e)));
        }
    };
    threads::configure(cli.threads)?;
    match cli.command {
        Command::Film(a) => film::run(&a, out),
        Command::Chart(a) => chart::run(&a, err),
        // Rendering commands write files; everything they say is a message.
        Command::Render(a) => render::run(&a, err),
        Command::Info(a) => info::run(&a, out),
        Command::Sample(a) => sample::run(&a, err),
        Command::Convert(a) => convert::run(&a, err),
        Command::Compare(a) => compare::run(&a, out, err),
        Command::Stability(a) => stability::run(&a, out),
        Command::View(a) => view::run(&a, out, err),
        Command::Encode(a) => encode::run(&a, err),
    }
}

/// Runs the CLI on the process arguments; returns the exit code.
pub fn main() -> i32 {
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let result = run(std::env::args_os(), &mut out);
    let flushed = out.flush();
    match result {
        Ok(()) => match flushed {
            Ok(()) => 0,
            // A closed pipe (e.g. `| head`) is not an error worth a message.
            Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => 0,
            Err(e) => {
                eprintln!("filmsplat: error: writing output: {e}");
                1
            }
        },
        Err(crate::Error::Usage(e)) => {
            let _ = e.print();
            2
        }
        Err(e) => {
            eprintln!("filmsplat: error: {e}");
            e.exit_code()
        }
    }
}
