//! Command-line arguments.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

/// Fast, exact simulation of a rigid ellipsoid on a horizontal plane (SI units).
#[derive(Debug, Parser)]
#[command(name = "ellipsoid", version, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate a scenario; write its trajectory (CSV or HDF5) and, on request, a JSON summary.
    ///
    /// Exit status: 0 completed; 2 bad input (nothing written); 3 stopped early (lost
    /// contact, Painlevé, pure sliding reaching zero slip, solver failure, chattering,
    /// non-finite state), with the trajectory up to the stop written; 1 output error.
    Run(RunArgs),
    /// Validate a scenario and print its derived quantities, without simulating.
    Check(CheckArgs),
}

#[derive(Debug, Args)]
pub struct RunArgs {
    /// The scenario file (TOML; see docs/scenarios.md).
    pub scenario: PathBuf,
    /// Trajectory file: `.csv`, or `.h5` (build with `--features hdf5`). Directories are
    /// created as needed. Default: out/STEM.csv, STEM the scenario file name without .toml.
    #[arg(short, long, value_name = "OUT.csv|OUT.h5")]
    pub output: Option<PathBuf>,
    /// Write the run summary as JSON to this file, or to standard output with `-`.
    #[arg(long, value_name = "FILE.json|-")]
    pub summary: Option<PathBuf>,
    /// Override a scenario value before validation, e.g. `--set output.t_end=1`
    /// (TOML syntax; a bare word is a string). Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Print nothing but errors on standard error.
    #[arg(short, long)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
pub struct CheckArgs {
    /// The scenario file (TOML).
    pub scenario: PathBuf,
    /// Override a scenario value before validation (as for `run`). Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}
