//! `ellipsoid._ellipsoid`, the compiled core of the `ellipsoid` Python package.
//!
//! - [`scenario`]: `Scenario`, `load` (the core's TOML parser; Python dicts → TOML in [`convert`]);
//! - [`api`]: `simulate`, `sweep` (runs without the GIL in [`run`], interruptible);
//! - [`trajectory`]: `Trajectory` (numpy columns named like the CSV, summary, writers from
//!   `ellipsoid-io`, so files are the command-line tool's byte for byte);
//! - [`study`]: `precision` (`PrecisionTable`) and `check`, from `ellipsoid-study` (the code
//!   behind `ellipsoid precision` and `ellipsoid check`);
//! - [`parameter_study`]: `Study` and `make_study`, parameter studies from `ellipsoid-study`
//!   (`ellipsoid.study` itself, with executors and the DataFrame, is `python/ellipsoid/_study.py`);
//! - [`steady`]: `linearize` and the arrays behind `ellipsoid.steady` (`python/ellipsoid/_steady.py`);
//! - [`errors`]: the exception tree, one base class `EllipsoidError`;
//! - [`plausible`]: the plausibility warnings, `PlausibilityWarning` (a UserWarning).
//!
//! The Python sources (`python/ellipsoid/`) re-export these names and carry the stubs.

mod api;
mod args;
mod convert;
mod errors;
mod parameter_study;
mod plausible;
mod run;
mod scenario;
mod steady;
mod study;
mod trajectory;

use pyo3::prelude::*;

/// The compiled core of the `ellipsoid` package (import `ellipsoid`, not this module).
#[pymodule]
fn _ellipsoid(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // Before any HDF5 file is opened: HDF5 must never load code from its plugin directories.
    #[cfg(feature = "hdf5")]
    ellipsoid_io::hdf5::forbid_plugins();
    let py = m.py();
    m.add("__version__", run::VERSION)?;
    m.add("HDF5", cfg!(feature = "hdf5"))?;
    m.add("COLUMNS", ellipsoid_io::columns::names())?;
    let units: std::collections::BTreeMap<&str, &str> =
        ellipsoid_io::columns::units().into_iter().collect();
    m.add("UNITS", units)?;
    // The figure's panels, declared once for `ellipsoid plot` and `Trajectory.plot`.
    m.add("_PANELS", ellipsoid_io::panels::JSON)?;
    for class in errors::Class::ALL {
        m.add(class.name(), class.get(py)?)?;
    }
    m.add(plausible::NAME, plausible::class(py)?)?;
    m.add_class::<scenario::PyScenario>()?;
    m.add_class::<trajectory::Trajectory>()?;
    m.add_class::<study::PrecisionTable>()?;
    m.add_class::<parameter_study::PyStudy>()?;
    m.add_function(wrap_pyfunction!(parameter_study::make_study, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::load, m)?)?;
    m.add_function(wrap_pyfunction!(api::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(api::sweep, m)?)?;
    m.add_function(wrap_pyfunction!(study::precision, m)?)?;
    m.add_function(wrap_pyfunction!(study::check, m)?)?;
    m.add_function(wrap_pyfunction!(steady::steady_raw, m)?)?;
    m.add_function(wrap_pyfunction!(steady::steady_start, m)?)?;
    m.add_function(wrap_pyfunction!(steady::linearize, m)?)?;
    m.add_function(wrap_pyfunction!(hdf5_plugins, m)?)?;
    m.add_function(wrap_pyfunction!(parameter_study::study_workers, m)?)?;
    m.add_function(wrap_pyfunction!(parameter_study::argument_error, m)?)?;
    Ok(())
}

/// Whether the HDF5 library inside this module may load plugins, and how many plugin
/// directories it searches: `(False, 0)` (turned off at import; a test checks it).
#[pyfunction]
#[pyo3(name = "_hdf5_plugins")]
fn hdf5_plugins() -> (bool, u32) {
    #[cfg(feature = "hdf5")]
    return ellipsoid_io::hdf5::plugin_state();
    #[cfg(not(feature = "hdf5"))]
    (false, 0)
}
