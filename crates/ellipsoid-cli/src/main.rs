//! `ellipsoid`: simulate a rigid ellipsoid on a plane from a TOML scenario.
//!
//! Exit status: 0 success; 1 the output could not be written, or an internal error
//! (nothing new written); 2 bad input (nothing written); 3 the simulation stopped early (trajectory and
//! summary up to the stop are written). See `docs/scenarios.md`.

// `run` is always built; every other command is behind a Cargo feature (Cargo.toml,
// `cli::NEEDS`), so that `--no-default-features` compiles only the core, the scenario
// reader and the CSV/JSON writers.
#[cfg(feature = "animate")]
mod animate;
#[cfg(feature = "study")]
mod check;
mod cli;
#[cfg(all(feature = "study", feature = "figures"))]
mod diagram;
mod error;
#[cfg(feature = "figures")]
mod figure;
mod interrupt;
mod oom;
mod plausible;
#[cfg(feature = "figures")]
mod plot_section;
#[cfg(feature = "study")]
mod power_law;
#[cfg(feature = "study")]
mod precision;
mod progress;
mod run;
#[cfg(feature = "study")]
mod steady;
#[cfg(feature = "study")]
mod study;
#[cfg(any(feature = "figures", feature = "view", feature = "animate"))]
mod visual;

use std::process::ExitCode;

#[global_allocator]
static ALLOCATOR: oom::CleanOom = oom::CleanOom;

fn main() -> ExitCode {
    // A bug must still end in one readable line, never a panic dump.
    std::panic::set_hook(Box::new(|info| {
        let msg = ellipsoid_core::error::panic_message(info.payload());
        let place = info
            .location()
            .map(|l| format!(" ({}:{})", l.file(), l.line()))
            .unwrap_or_default();
        eprintln!("error: internal error: {msg}{place}; please report it");
    }));
    // Before any HDF5 file is opened: HDF5 must never load code from its plugin directories.
    #[cfg(feature = "hdf5")]
    ellipsoid_io::hdf5::forbid_plugins();
    let cli = cli::parse();
    let result = match &cli.command {
        cli::Command::Run(args) => run::run(args),
        #[cfg(feature = "study")]
        cli::Command::Check(args) => check::check(args),
        #[cfg(feature = "study")]
        cli::Command::Precision(args) => precision::precision(args),
        #[cfg(feature = "figures")]
        cli::Command::Plot(args) => visual::plot(args),
        #[cfg(feature = "view")]
        cli::Command::View(args) => visual::view(args),
        #[cfg(feature = "animate")]
        cli::Command::Animate(args) => animate::animate(args),
        #[cfg(feature = "study")]
        cli::Command::Study(args) => study::study(args),
        #[cfg(feature = "study")]
        cli::Command::Steady(args) => steady::steady(args),
        #[cfg(feature = "study")]
        cli::Command::PowerLaw(args) => power_law::power_law(args),
        #[allow(unreachable_patterns)] // every command compiled in
        other => Err(compiled_out(other)),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            let code = e.exit_code();
            // Several scenario errors: one `error:` line each.
            for line in error::message(&e).lines() {
                eprintln!("error: {line}");
            }
            ExitCode::from(code)
        }
    }
}

/// The refusal of a command this build was compiled without.
fn compiled_out(command: &cli::Command) -> error::CliError {
    let name = match command {
        cli::Command::Run(_) => "run",
        cli::Command::Check(_) => "check",
        cli::Command::Precision(_) => "precision",
        cli::Command::Plot(_) => "plot",
        cli::Command::View(_) => "view",
        cli::Command::Animate(_) => "animate",
        cli::Command::Study(_) => "study",
        cli::Command::Steady(_) => "steady",
        cli::Command::PowerLaw(_) => "power-law",
    };
    let (command, feature) = cli::NEEDS
        .into_iter()
        .find(|(c, _)| *c == name)
        .unwrap_or((name, "default"));
    error::CliError::NoFeature { command, feature }
}
