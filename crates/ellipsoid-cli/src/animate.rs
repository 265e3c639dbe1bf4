//! `ellipsoid animate RUN.csv|h5 -o top.gif`: the run as an animated GIF, rendered without
//! a browser (`ellipsoid_io::animate`), or `-o top.mp4`, the same frames encoded by the
//! system's ffmpeg. SIGINT or SIGTERM stops it before the next frame, nothing written
//! (exit 130 or 143, `interrupt`).

use std::process::ExitCode;

use ellipsoid_io::animate::{self, Options};

use crate::cli::AnimateArgs;
use crate::error::CliError;
use crate::interrupt::Interrupt;
use crate::visual::{check_output, load, put};

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
