//! Studies of a scenario beyond one run, shared by the `ellipsoid` command-line tool and
//! the Python package so that both report the same data:
//!
//! - [`check`]: what follows from a scenario without simulating it (`ellipsoid check`,
//!   `ellipsoid.check`);
//! - [`precision`]: the work–precision study (`ellipsoid precision`,
//!   `ellipsoid.precision`), with its log–log plots drawn by [`plot`];
//! - [`study`]: parameter studies (`ellipsoid study`, `ellipsoid.study`): axes over any
//!   scenario key, one table row per point, resumable through a journal.

pub mod check;
pub mod plot;
pub mod power_law;
pub mod precision;
pub mod study;

use ellipsoid_core::simulate::Drift;

/// Each invariant's drift by its summary name, in summary order (`None` where the scene
/// does not conserve it).
pub fn drift_entries(drift: &Drift) -> Vec<(&'static str, Option<f64>)> {
    drift.iter().map(|(which, d)| (which.name(), d)).collect()
}
