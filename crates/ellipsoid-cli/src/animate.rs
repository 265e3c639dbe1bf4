//! `ellipsoid animate RUN.csv|h5 -o top.gif`: the run as an animated GIF, rendered without
//! a browser (`ellipsoid_io::animate`).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use ellipsoid_io::animate::{self, Options};

use crate::error::CliError;
use crate::visual::{check_output, load, put};

#[derive(Debug, Args)]
pub struct AnimateArgs {
    /// The trajectory: a `.csv` or `.h5` file written by `ellipsoid run`.
    #[arg(value_name = "OUT.csv|OUT.h5")]
    pub input: PathBuf,
    /// The animation: `.gif` (directories created as needed).
    #[arg(short, long, value_name = "ANIM.gif")]
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
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
}

pub fn animate(args: &AnimateArgs) -> Result<ExitCode, CliError> {
    check_output(&args.output, &["gif"], "animation")?;
    let opt = Options {
        width: args.width,
        height: args.height,
        fps: args.fps,
        speed: args.speed,
    };
    opt.check().map_err(|e| CliError::Usage(format!("--{e}")))?;
    let table = load(&args.input, None, args.summary.as_deref())?;
    let mut bytes = Vec::new();
    let frames = animate::gif(&table, &opt, &mut bytes).map_err(CliError::Usage)?;
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
