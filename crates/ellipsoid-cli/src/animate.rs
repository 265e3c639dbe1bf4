//! `ellipsoid animate RUN.csv|h5 -o top.gif`: the run as an animated GIF, rendered without
//! a browser (`ellipsoid_io::animate`), or `-o top.mp4`, the same frames encoded by the
//! system's ffmpeg. SIGINT or SIGTERM stops it before the next frame, nothing written
//! (exit 130 or 143, `interrupt`).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use ellipsoid_io::animate::{self, Options};

use crate::error::CliError;
use crate::interrupt::Interrupt;
use crate::visual::{check_output, load, put};

#[derive(Debug, Args)]
pub struct AnimateArgs {
    /// The trajectory: a `.csv` or `.h5` file written by `ellipsoid run`.
    #[arg(value_name = "OUT.csv|OUT.h5")]
    pub input: PathBuf,
    /// The animation: `.gif`, or `.mp4` (H.264, encoded by the system's ffmpeg: on the
    /// PATH or named by ELLIPSOID_FFMPEG), by extension (directories created as needed).
    #[arg(short, long, value_name = "ANIM.gif|ANIM.mp4")]
    pub output: PathBuf,
    /// The run's JSON summary (`ellipsoid run --summary`): the body's shape, through the
    /// scenario it names (needed for a CSV file; an `.h5` file carries its own).
    #[arg(long, value_name = "FILE.json")]
    pub summary: Option<PathBuf>,
    /// Frame width and height, px (16 to 2000).
    #[arg(long, default_value_t = 480)]
    pub width: u32,
    #[arg(long, default_value_t = 360)]
    pub height: u32,
    /// Frames per second (at most 100).
    #[arg(long, default_value_t = 25.0)]
    pub fps: f64,
    /// Simulated seconds per second of animation (0.1 = ten times slower than real time).
    /// An animation has at most 2000 frames and shows the whole run: a speed at which the
    /// run needs more frames is refused (exit 2), the message naming the speed that fits.
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
}

pub fn animate(args: &AnimateArgs) -> Result<ExitCode, CliError> {
    let ext = check_output(&args.output, &["gif", "mp4"], "animation")?;
    let opt = Options {
        width: args.width,
        height: args.height,
        fps: args.fps,
        speed: args.speed,
    };
    opt.check().map_err(|e| CliError::Usage(format!("--{e}")))?;
    let table = load(&args.input, None, args.summary.as_deref())?;
    animate::check(&table, &opt).map_err(CliError::Usage)?;
    // Until here a signal ends the process by its default action (nothing is written
    // yet); from here it stops the frames.
    let interrupt = Interrupt::install();
    // An error after a signal (the frames stopped, or ffmpeg ended by the same Ctrl-C)
    // is the interruption.
    let stopped = |e: CliError| interrupt.check("the animation").err().unwrap_or(e);
    let (bytes, frames) = if ext == "mp4" {
        animate::mp4(&table, &opt, &interrupt.any).map_err(|e| {
            stopped(CliError::from(ellipsoid_io::OutputError::Io {
                path: args.output.clone(),
                source: std::io::Error::other(e),
            }))
        })?
    } else {
        let mut bytes = Vec::new();
        let frames = animate::gif(&table, &opt, &mut bytes, &interrupt.any)
            .map_err(|e| stopped(CliError::Usage(e)))?;
        (bytes, frames)
    };
    // The last moment to honour a signal: after it, the file is put in place.
    interrupt.check("the animation")?;
    put(&args.output, &bytes)?;
    if !args.quiet {
        eprintln!(
            "wrote {} ({frames} frames of {}×{} px at {} fps, {:.2} MB)",
            args.output.display(),
            args.width,
            args.height,
            args.fps,
            bytes.len() as f64 / 1e6
        );
    }
    Ok(ExitCode::SUCCESS)
}
