//! `ellipsoid`: simulate a rigid ellipsoid on a plane from a TOML scenario.
//!
//! Exit status: 0 success; 1 the output could not be written, or an internal error
//! (nothing new written); 2 bad input (nothing written); 3 the simulation stopped early (trajectory and
//! summary up to the stop are written). See `docs/scenarios.md`.

mod animate;
mod check;
mod cli;
mod diagram;
mod error;
mod figure;
mod interrupt;
mod oom;
mod plausible;
mod plot_section;
mod precision;
mod progress;
mod run;
mod steady;
mod study;
mod visual;

use std::process::ExitCode;

use clap::Parser;

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
    let cli = cli::Cli::parse();
    let result = match &cli.command {
        cli::Command::Run(args) => run::run(args),
        cli::Command::Check(args) => check::check(args),
        cli::Command::Precision(args) => precision::precision(args),
        cli::Command::Plot(args) => visual::plot(args),
        cli::Command::View(args) => visual::view(args),
        cli::Command::Animate(args) => animate::animate(args),
        cli::Command::Study(args) => study::study(args),
        cli::Command::Steady(args) => steady::steady(args),
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
