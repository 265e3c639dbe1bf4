//! Command-line arguments.

use std::path::PathBuf;

use clap::{Args, CommandFactory, FromArgMatches, Parser, Subcommand};

/// Fast, exact simulation of a rigid ellipsoid on a horizontal plane (SI units).
#[derive(Debug, Parser)]
#[command(name = "ellipsoid", version, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

/// Each command but `run` and the Cargo feature that compiles it in (crates/ellipsoid-cli's
/// Cargo.toml; docs/development.md, "Features").
pub const NEEDS: [(&str, &str); 8] = [
    ("check", "study"),
    ("precision", "study"),
    ("plot", "figures"),
    ("view", "view"),
    ("animate", "animate"),
    ("study", "study"),
    ("steady", "study"),
    ("power-law", "study"),
];

/// Whether this build has the feature `name` (of those [`NEEDS`] names).
pub fn has(feature: &str) -> bool {
    let built = [
        ("study", cfg!(feature = "study")),
        ("figures", cfg!(feature = "figures")),
        ("view", cfg!(feature = "view")),
        ("animate", cfg!(feature = "animate")),
    ];
    built.iter().all(|&(name, on)| name != feature || on)
}

/// How to get a build with the feature `feature` (after "needs the `…` feature, which
/// this build was compiled without: ").
pub fn feature_hint(feature: &str) -> String {
    format!(
        "build with the default features (`cargo build --release -p ellipsoid-cli`, or \
`cargo install --path crates/ellipsoid-cli`), or add `--features {feature}`"
    )
}

/// The arguments, parsed. A command compiled out stays listed, its help saying which
/// feature it needs; running it is refused (`error::CliError::NoFeature`, exit 2).
pub fn parse() -> Cli {
    let mut command = Cli::command();
    for (name, feature) in NEEDS.into_iter().filter(|(_, f)| !has(f)) {
        command = command.mut_subcommand(name, |sub| {
            let about = sub.get_about().map(ToString::to_string).unwrap_or_default();
            let note = format!(
                "Not in this build: `ellipsoid {name}` needs the `{feature}` feature, which this \
build was compiled without: {}.",
                feature_hint(feature)
            );
            sub.about(format!("[needs the `{feature}` feature] {about}"))
                .before_help(note.clone())
                .before_long_help(note)
        });
    }
    let matches = command.get_matches();
    Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit())
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate a scenario; write its trajectory (CSV or HDF5) and, on request, a JSON summary.
    ///
    /// Exit status: 0 completed (or ended at a terminal observable); 2 bad input (nothing
    /// written); 3 stopped early (lost
    /// contact, Painlevé, pure sliding reaching zero slip, solver failure, chattering,
    /// non-finite state, a surface found below the plane), with the trajectory up to the
    /// stop written; 1 output error
    /// (nothing new written).
    Run(RunArgs),
    /// Validate a scenario and print its derived quantities, without simulating.
    Check(CheckArgs),
    /// Work–precision report: run every method over a grid of settings, measure error
    /// against a reference, invariant drift, wall time, evaluations and steps; write
    /// precision.csv, error_vs_time.svg and error_vs_evaluations.svg.
    ///
    /// Grid: RK4 at h = 1e-2 … 1e-6 s (half decades), DOPRI5 and DOP853 at rtol = 1e-3 …
    /// 1e-13, atol = rtol × (the scenario's atol/rtol). Error: the relative nutation-period
    /// error and invariant drift for frictionless bodies of revolution (exact
    /// quadrature), otherwise the final-state error against DOP853 at rtol = 1e-14. See
    /// docs/performance.md.
    Precision(PrecisionArgs),
    /// Draw a trajectory file (CSV or HDF5) as a multi-panel figure (SVG, PNG or PDF): θ(t),
    /// Euler rates, energy and relative drift (log axis), normal force and slip speed with
    /// the contact mode shaded, paths on the plane; events marked.
    Plot(PlotArgs),
    /// Write a self-contained 3-D viewer page (HTML, opens offline) of a trajectory file:
    /// the body moving on the plane with its contact trace, play/pause, speed, a time
    /// slider, side plots (θ(t) and energy, or `--columns`) with a linked cursor.
    View(ViewArgs),
    /// Render a trajectory file (CSV or HDF5) as an animated GIF, without a browser: the
    /// body on the plane, its contact trace, the time and θ in a corner.
    Animate(AnimateArgs),
    /// Run a parameter study: every point of a study file's axes over a base scenario, in
    /// parallel on all cores, one table row per run (CSV, Parquet or HDF5). Resumable:
    /// finished rows are kept in RESULTS.journal beside the table, and a rerun skips them.
    ///
    /// Exit status: 0 the table was written (failed runs are rows with their status and
    /// message); 2 bad input (nothing run); 1 output error; 130/143 interrupted by
    /// SIGINT/SIGTERM (the finished rows stay in the journal; rerun to finish). See
    /// docs/studies.md.
    Study(StudyArgs),
    /// Steady motions and their linear stability: the scenario's steady motion of a family
    /// (its state, eigenvalues and modes), or with --vary the family against one scenario
    /// key, with the critical values where the stability changes. See docs/physics.md,
    /// "Steady motions and their stability".
    ///
    /// Exit status: 0 done; 2 bad input (nothing written); 1 output error.
    Steady(SteadyArgs),
    /// Simulate a scenario and fit the power law |y| ≈ A (t0 − t)^p of one output column
    /// over a window of t0 − t: the approach of Euler's disk to its finite-time end (its
    /// tilt `theta` and precession rate `phi_dot`; docs/physics.md, "Dissipation of a
    /// rolling disc"). Prints the fit as JSON (SI units): column, exponent, prefactor, t0,
    /// t0_from, window, samples, rms.
    ///
    /// Exit status: 0 fitted; 2 bad input (the scenario, the column, the window or t0, or
    /// too few samples in the window); 3 the run stopped early (nothing fitted).
    PowerLaw(PowerLawArgs),
}

#[derive(Debug, Args)]
#[cfg_attr(not(feature = "study"), allow(dead_code))] // read by `ellipsoid steady` only
pub struct SteadyArgs {
    /// The scenario file (TOML): its body, contact model (frictionless, rolling, or
    /// coulomb's rolling phase) and initial spin (upright, inverted) or tilt and
    /// precession rate (precession, rolling-circle: initial.theta, initial.phi_dot; the
    /// spin is solved for).
    pub scenario: PathBuf,
    /// The family: upright, inverted, precession (frictionless, G fixed) or
    /// rolling-circle (Routh's steady rolling; rolling or coulomb).
    #[arg(long, default_value = "upright")]
    pub family: String,
    /// What a tilted family solves for: spin (from initial.theta and initial.phi_dot),
    /// phi_dot (from initial.theta and the spin phi_dot cos theta + psi_dot; the root
    /// nearest initial.phi_dot) or theta (from initial.phi_dot and the spin; Newton from
    /// initial.theta).
    #[arg(long, default_value = "spin", value_name = "spin|phi_dot|theta")]
    pub solve: String,
    /// Vary one scenario key: KEY=a:b:n, n evenly spaced values from a to b
    /// (e.g. initial.psi_dot=0:200:201).
    #[arg(long, value_name = "KEY=a:b:n", allow_hyphen_values = true)]
    pub vary: Option<String>,
    /// Write the table (CSV: the key, spin, theta, normal_force, for the tilted families
    /// phi_dot, radius_g, radius_contact, then stable, max_real, lambdaK_re, lambdaK_im,
    /// modeK for K = 1..4 (tilted: 1..2), error), as .csv or .parquet by extension; with
    /// --perturb, the started scenario as .toml. Any other extension, or the path of
    /// --plot, is refused (exit 2, nothing written).
    #[arg(short, long, value_name = "OUT.csv|OUT.parquet")]
    pub output: Option<PathBuf>,
    /// Instead of the analysis, the scenario started on the steady motion displaced by
    /// EPS along mode MODE (its number K in the table, 1 = the least stable, or its name:
    /// tilt, nutation, roll, pitch, wobble, spin; the first of that name): printed as
    /// TOML, or written to -o OUT.toml. `ellipsoid run` of it shows the mode grow (Re λ
    /// > 0) or oscillate. |EPS| at most 0.1 (rad of tilt).
    #[arg(
        long,
        value_name = "MODE=EPS",
        allow_hyphen_values = true,
        conflicts_with = "vary"
    )]
    pub perturb: Option<String>,
    /// With --vary, draw the stability diagram: the growth rates Re λ (the largest bold)
    /// and the angular frequencies |Im λ| against the varied key, the stable and unstable
    /// ranges shaded, the critical values marked (SVG, PNG or PDF by the extension).
    #[arg(long, value_name = "OUT.svg|png|pdf")]
    pub plot: Option<PathBuf>,
    /// With --plot: the resolution of a PNG figure in pixels per inch, 24 to 1200 and at
    /// most 5e7 pixels (default 96: one pixel per pixel of the SVG; 192 is sharp on a
    /// HiDPI screen). PNG only.
    #[arg(long, value_name = "DPI", requires = "plot")]
    pub dpi: Option<f64>,
    /// Do not report the diagram written on stderr.
    #[arg(short, long)]
    pub quiet: bool,
    /// Do not print the plausibility warnings (values that are valid but likely a unit
    /// slip, such as theta = 80 in radians; docs/scenarios.md, "Plausibility warnings").
    #[arg(long)]
    pub quiet_plausibility: bool,
    /// Override a scenario value before validation (as for `run`). Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

#[derive(Debug, Args)]
#[cfg_attr(not(feature = "study"), allow(dead_code))] // read by `ellipsoid study` only
pub struct StudyArgs {
    /// The study file (TOML; see docs/studies.md).
    pub study: PathBuf,
    /// The table: `.csv`, `.parquet` or `.h5` (by extension). Its journal is
    /// RESULTS.journal in the same directory. Directories are created as needed.
    #[arg(short, long, value_name = "RESULTS.parquet|.csv|.h5")]
    pub output: PathBuf,
    /// Worker threads (default: one per CPU; at most 4 per CPU, at least 8, and never
    /// more than the runs).
    #[arg(short, long, value_name = "N")]
    pub jobs: Option<usize>,
    /// Ignore and replace the journal of an earlier run (start over).
    #[arg(long)]
    pub fresh: bool,
    /// Also write every run's sampled trajectory to this HDF5 file: a group per run,
    /// named by its row's key (docs/studies.md). Needs an empty journal (or --fresh):
    /// resumed rows have no trajectory. At most 10^8 samples over all runs.
    #[arg(long, value_name = "RUNS.h5")]
    pub trajectories: Option<PathBuf>,
    /// Print nothing but errors on standard error.
    #[arg(short, long)]
    pub quiet: bool,
    /// Do not print the plausibility warnings of the study's points (values that are
    /// valid but likely a unit slip; docs/scenarios.md, "Plausibility warnings").
    #[arg(long)]
    pub quiet_plausibility: bool,
}

#[derive(Debug, Args)]
pub struct RunArgs {
    /// The scenario file (TOML; see docs/scenarios.md).
    pub scenario: PathBuf,
    /// Trajectory file: `.csv`, or `.h5` (in the default build). Directories are
    /// created as needed. Default: out/STEM.csv, STEM the scenario file name without .toml.
    #[arg(short, long, value_name = "OUT.csv|OUT.h5")]
    pub output: Option<PathBuf>,
    /// Write the run summary as JSON to this file, or to standard output with `-`.
    #[arg(long, value_name = "FILE.json|-")]
    pub summary: Option<PathBuf>,
    /// Write the points of the scenario's Poincaré sections (`[[section]]`) to this CSV
    /// file: one table, a `section` column naming each point's section, then every
    /// output column (SI units, listed in the comment line).
    #[arg(long, value_name = "OUT.csv")]
    pub sections: Option<PathBuf>,
    /// Override a scenario value before validation, e.g. `--set output.t_end=1`
    /// (TOML syntax; a bare word is a string). Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Print nothing but errors on standard error (no progress, no plausibility warnings).
    #[arg(short, long)]
    pub quiet: bool,
    /// Do not print the plausibility warnings (values that are valid but likely a unit
    /// slip, such as theta = 80 in radians; docs/scenarios.md, "Plausibility warnings").
    #[arg(long)]
    pub quiet_plausibility: bool,
}

#[derive(Debug, Args)]
#[cfg_attr(not(feature = "study"), allow(dead_code))] // read by `ellipsoid precision` only
pub struct PrecisionArgs {
    /// The scenario file (TOML).
    pub scenario: PathBuf,
    /// Output directory (created as needed). Default: out/precision/STEM.
    #[arg(short, long, value_name = "DIR")]
    pub output: Option<PathBuf>,
    /// Simulated time per run (s). Default: the scenario's t_end, at most 10 s (RK4 at
    /// h = 1e-6 s then takes 1e7 steps, a few seconds per run). At least the largest RK4
    /// step (1e-2 s); at most what the finest RK4 step covers in solver.max_steps steps
    /// (10 s, or 1000 s with --quick, at the default 1e7).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub t_end: Option<f64>,
    /// Three settings per method (RK4 h = 1e-2, 1e-3, 1e-4 s; rtol = 1e-4, 1e-7, 1e-10)
    /// and one timing run each.
    #[arg(long)]
    pub quick: bool,
    /// Fewest timed runs per setting (more are made while a setting has taken under
    /// 0.3 s, at most 15); the median is reported. At least 1; default 3 (1 with --quick).
    #[arg(long, value_name = "N")]
    pub repeats: Option<u64>,
    /// Override a scenario value before validation (as for `run`). Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// No progress lines on standard error.
    #[arg(short, long)]
    pub quiet: bool,
    /// Do not print the plausibility warnings (values that are valid but likely a unit
    /// slip, such as theta = 80 in radians; docs/scenarios.md, "Plausibility warnings").
    #[arg(long)]
    pub quiet_plausibility: bool,
}

#[derive(Debug, Args)]
#[cfg_attr(not(feature = "study"), allow(dead_code))] // read by `ellipsoid check` only
pub struct CheckArgs {
    /// The scenario file (TOML).
    pub scenario: PathBuf,
    /// Override a scenario value before validation (as for `run`). Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Do not print the plausibility warnings (values that are valid but likely a unit
    /// slip, such as theta = 80 in radians; docs/scenarios.md, "Plausibility warnings").
    #[arg(long)]
    pub quiet_plausibility: bool,
}

#[derive(Debug, Args)]
#[cfg_attr(not(feature = "study"), allow(dead_code))] // read by `ellipsoid power-law` only
pub struct PowerLawArgs {
    /// The scenario file (TOML).
    pub scenario: PathBuf,
    /// The output column to fit (e.g. `theta`, `phi_dot`).
    #[arg(long, value_name = "NAME")]
    pub column: String,
    /// The window of t0 − t in seconds, `LO,HI` with 0 < LO < HI.
    #[arg(long, value_name = "LO,HI")]
    pub window: String,
    /// t0 in seconds, or `LO,HI` to fit it in that bracket. Default: the run's first flat
    /// landing (the event `flat`).
    #[arg(long, value_name = "T|LO,HI")]
    pub t0: Option<String>,
    /// Override a scenario value before validation (as for `run`). Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Do not print the plausibility warnings.
    #[arg(long)]
    pub quiet_plausibility: bool,
}

#[derive(Debug, Args)]
#[cfg_attr(not(feature = "figures"), allow(dead_code))] // read by `ellipsoid plot` only
pub struct PlotArgs {
    /// The trajectory: a `.csv` or `.h5` file written by `ellipsoid run` (with `--section`,
    /// the `.csv` table of `ellipsoid run --sections`).
    #[arg(value_name = "OUT.csv|OUT.h5")]
    pub input: PathBuf,
    /// The figure: `.svg`, `.png` or `.pdf` (vector, fonts embedded), by extension
    /// (directories created as needed).
    #[arg(short, long, value_name = "FIG.svg|FIG.png|FIG.pdf")]
    pub output: PathBuf,
    /// Panels, comma-separated, drawn top to bottom: theta, rates, energy, forces, surfaces
    /// (the normal force of each surface of a body with contact spheres), path. Default:
    /// all of them, `surfaces` only for a body with contact spheres.
    #[arg(long, value_name = "LIST")]
    pub panels: Option<String>,
    /// Output columns instead of the panels, comma-separated, each drawn against time with
    /// its unit (e.g. `omega_world_z,theta`).
    #[arg(long, value_name = "LIST", conflicts_with = "panels")]
    pub columns: Option<String>,
    /// The run's JSON summary (`ellipsoid run --summary`): marks its events and, through the
    /// scenario it names, gives the body's shape for the contact path. An `.h5` file
    /// carries its own.
    #[arg(long, value_name = "FILE.json")]
    pub summary: Option<PathBuf>,
    /// The input is a Poincaré section table (`ellipsoid run --sections OUT.csv`): draw
    /// its points, the column `--y` against the column `--x`, one colour per section.
    #[arg(long, requires_all = ["x", "y"], conflicts_with_all = ["panels", "columns", "summary"])]
    pub section: bool,
    /// With `--section`: the column along the horizontal axis (e.g. `psi`).
    #[arg(long, value_name = "COL", requires = "section")]
    pub x: Option<String>,
    /// With `--section`: the column along the vertical axis (e.g. `omega_z`).
    #[arg(long, value_name = "COL", requires = "section")]
    pub y: Option<String>,
    /// With `--section`: the angle columns (rad) of --x and --y drawn modulo 2π, in
    /// [0, 2π), comma-separated (e.g. `psi`).
    #[arg(long, value_name = "LIST", requires = "section")]
    pub wrap: Option<String>,
    /// Title line (default: the scenario named by the summary, else the input file name).
    #[arg(long)]
    pub title: Option<String>,
    /// The resolution of a PNG figure in pixels per inch, 24 to 1200 and at most 5e7
    /// pixels (default 96: one pixel per pixel of the SVG; 192 is sharp on a HiDPI screen;
    /// the six-panel figure takes up to about 480). PNG only.
    #[arg(long, value_name = "DPI")]
    pub dpi: Option<f64>,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
#[cfg_attr(not(feature = "view"), allow(dead_code))] // read by `ellipsoid view` only
pub struct ViewArgs {
    /// The trajectory: a `.csv` or `.h5` file written by `ellipsoid run`.
    #[arg(value_name = "OUT.csv|OUT.h5")]
    pub input: PathBuf,
    /// The page: `.html` (directories created as needed).
    #[arg(short, long, value_name = "VIEW.html")]
    pub output: PathBuf,
    /// The run's JSON summary (`ellipsoid run --summary`): events, and the body's shape
    /// through the scenario it names. An `.h5` file carries its own.
    #[arg(long, value_name = "FILE.json")]
    pub summary: Option<PathBuf>,
    /// Page title (default: the scenario named by the summary, else the input file name).
    #[arg(long)]
    pub title: Option<String>,
    /// The side plots against time, comma-separated output columns, at most 6 (e.g.
    /// `omega_world_z,theta` for a rattleback's spin); `energy` adds E + W when work is
    /// dissipated; a body's per-surface columns (`normal_force_stem`), or `QUANTITY_*` for
    /// that quantity of every surface in one plot (`normal_force_*`). Default: theta,energy,
    /// and normal_force_* for a body with contact spheres.
    #[arg(long, value_name = "LIST")]
    pub columns: Option<String>,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
#[cfg_attr(not(feature = "animate"), allow(dead_code))] // read by `ellipsoid animate` only
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
