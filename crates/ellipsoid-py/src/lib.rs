use pyo3::prelude::*;

/// The compiled core of the `ellipsoid` Python package.
#[pymodule]
fn _ellipsoid(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
