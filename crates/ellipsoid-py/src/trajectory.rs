//! `ellipsoid.Trajectory`: the samples of a run as numpy columns named like the CSV
//! columns, the run summary, and writers shared with the command-line tool.

use std::path::{Path, PathBuf};

use ellipsoid_core::simulate::Sample;
use ellipsoid_io::columns::{self, NUMERIC, NUMERIC_COLUMNS};
use ellipsoid_io::{Format, Metadata, OutputError, Summary, TrajectoryWriter, csv::CsvFile};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyList};

use crate::errors::{self, Class};
use crate::run::Run;
use crate::scenario::PyScenario;

/// The result of a run: one float64 numpy array per output column, named like the
/// command-line tool's CSV columns, plus the run summary.
///
/// Columns (SI units; angles unwrapped): `t` [s]; `x`, `y`, `z` [m] (centre of mass G);
/// `theta`, `phi`, `psi` [rad] (z-x-z Euler angles); `theta_dot`, `phi_dot`, `psi_dot`
/// [rad/s]; `omega_x`, `omega_y`, `omega_z` [rad/s] (body axes); `vx`, `vy`, `vz` [m/s]
/// (velocity of G); `energy` [J]; `normal_force` [N]; `slip_speed` [m/s] (speed of the
/// contact point); `mode` (str array: "frictionless", "sliding", "rolling" or "flight");
/// `work` [J]
/// (dissipated so far); `omega_world_x`, `omega_world_y`, `omega_world_z` [rad/s] (world
/// axes); `contact_x`, `contact_y` [m] (contact point on the plane); `drift` [1]
/// (relative drift of E, or of E + W where E is not conserved); `gap` [m] (lowest point
/// above the plane, 0 in contact). The arrays are read-only
/// views of the run (copy to modify).
///
/// `len(traj)` is the number of samples. A run that ends early (loss of contact, the pure
/// sliding model's slip stop) is still a Trajectory: `status` and `events` say why.
#[pyclass(frozen, module = "ellipsoid")]
pub struct Trajectory {
    samples: Vec<Sample>,
    summary: Summary,
    scenario: PyScenario,
    numeric: [PyOnceLock<Py<PyArray1<f64>>>; NUMERIC],
    mode: PyOnceLock<Py<PyAny>>,
}

impl Trajectory {
    pub fn new(run: Run) -> Self {
        Trajectory {
            samples: run.samples,
            summary: run.summary,
            scenario: PyScenario {
                inner: run.scenario,
            },
            numeric: [const { PyOnceLock::new() }; NUMERIC],
            mode: PyOnceLock::new(),
        }
    }

    fn column<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let arr = self.numeric[index].get_or_try_init(py, || -> PyResult<_> {
            let data: Vec<f64> = self
                .samples
                .iter()
                .map(|s| columns::values(s)[index])
                .collect();
            let arr = PyArray1::from_vec(py, data);
            readonly(arr.as_any())?;
            Ok(arr.unbind())
        })?;
        Ok(arr.bind(py).clone())
    }

    fn modes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let arr = self.mode.get_or_try_init(py, || -> PyResult<_> {
            let names = PyList::new(py, self.samples.iter().map(|s| s.mode.name()))?;
            let arr = py
                .import("numpy")?
                .getattr("array")?
                .call((names,), Some(&[("dtype", "U12")].into_py_dict(py)?))?;
            readonly(&arr)?;
            Ok(arr.unbind())
        })?;
        Ok(arr.bind(py).clone())
    }

    /// The summary as a Python dict (a fresh copy).
    fn summary_dict<'py>(&self, py: Python<'py>, summary: &Summary) -> PyResult<Bound<'py, PyAny>> {
        py.import("json")?
            .getattr("loads")?
            .call1((summary.to_json(),))
    }

    /// Writes the samples with `writer`, without the GIL.
    fn write(
        &self,
        py: Python<'_>,
        path: &Path,
        writer: impl FnOnce(&Path) -> Result<TrajectoryWriter, OutputError> + Send,
    ) -> PyResult<()> {
        let mut summary = self.summary.clone();
        summary.output = Some(path.display().to_string());
        let text = &self.scenario.inner.text;
        let samples = &self.samples;
        errors::guard(py, || {
            py.detach(|| -> Result<(), OutputError> {
                let mut w = writer(path)?;
                for s in samples {
                    w.write(s)?;
                }
                w.finish(&Metadata {
                    scenario_text: text,
                    summary: &summary,
                })
            })
            .map_err(|e| errors::output_error(py, &e))
        })
    }
}

use pyo3::types::IntoPyDict;

/// A path on the plane as two numpy arrays, x and y [m].
type XyArrays<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

impl Trajectory {
    /// The run as a table for the viewer: the same columns, events and body as
    /// `ellipsoid view OUT.csv --summary S.json` reads back, so the pages are identical.
    fn table(&self) -> ellipsoid_io::table::Table {
        let names = NUMERIC_COLUMNS.map(|c| c.0);
        let mut t = ellipsoid_io::table::Table::from_rows(
            &self.scenario.inner.source,
            &names,
            self.samples.len(),
            |i| {
                let s = &self.samples[i];
                (columns::values(s).to_vec(), s.mode.name().to_owned())
            },
        );
        if let Ok(v) = serde_json::from_str::<serde_json::Value>(&self.summary.to_json()) {
            t.apply_events(&v);
        }
        t.set_body(&self.scenario.inner.scene.body, &self.scenario.inner.source);
        t
    }

    fn page(&self, py: Python<'_>, title: Option<&str>) -> PyResult<String> {
        let title = title.unwrap_or(&self.scenario.inner.source);
        ellipsoid_io::viewer::html(&self.table(), title)
            .map_err(|e| Class::Internal.error(py, &e.to_string(), &[]))
    }
}

fn readonly(arr: &Bound<'_, PyAny>) -> PyResult<()> {
    let kwargs = [("write", false)].into_py_dict(arr.py())?;
    arr.call_method("setflags", (), Some(&kwargs))?;
    Ok(())
}

#[pymethods]
impl Trajectory {
    /// Time [s].
    #[getter]
    fn t<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 0)
    }
    /// x of the centre of mass G [m].
    #[getter]
    fn x<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 1)
    }
    /// y of the centre of mass G [m].
    #[getter]
    fn y<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 2)
    }
    /// Height of the centre of mass G above the plane [m] (from the contact constraint).
    #[getter]
    fn z<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 3)
    }
    /// θ, tilt of the symmetry axis from the vertical [rad].
    #[getter]
    fn theta<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 4)
    }
    /// φ, precession angle [rad] (unwrapped).
    #[getter]
    fn phi<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 5)
    }
    /// ψ, spin angle [rad] (unwrapped).
    #[getter]
    fn psi<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 6)
    }
    /// θ̇ [rad/s].
    #[getter]
    fn theta_dot<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 7)
    }
    /// φ̇ [rad/s].
    #[getter]
    fn phi_dot<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 8)
    }
    /// ψ̇ [rad/s].
    #[getter]
    fn psi_dot<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 9)
    }
    /// Angular velocity, body x component [rad/s].
    #[getter]
    fn omega_x<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 10)
    }
    /// Angular velocity, body y component [rad/s].
    #[getter]
    fn omega_y<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 11)
    }
    /// Angular velocity, body z component [rad/s].
    #[getter]
    fn omega_z<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 12)
    }
    /// Velocity of G, x [m/s].
    #[getter]
    fn vx<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 13)
    }
    /// Velocity of G, y [m/s].
    #[getter]
    fn vy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 14)
    }
    /// Velocity of G, z [m/s].
    #[getter]
    fn vz<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 15)
    }
    /// Mechanical energy E = ½m|v_G|² + ½ωᵀIω + m g z_G [J].
    #[getter]
    fn energy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 16)
    }
    /// Normal force N of the plane on the body [N].
    #[getter]
    fn normal_force<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 17)
    }
    /// |v_C|, speed of the material contact point [m/s].
    #[getter]
    fn slip_speed<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 18)
    }
    /// Work dissipated so far by friction and the effects [J].
    #[getter]
    fn work<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 19)
    }
    /// Angular velocity about world x [rad/s].
    #[getter]
    fn omega_world_x<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 20)
    }
    /// Angular velocity about world y [rad/s].
    #[getter]
    fn omega_world_y<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 21)
    }
    /// Angular velocity about the vertical, world z [rad/s] (the vertical spin).
    #[getter]
    fn omega_world_z<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 22)
    }
    /// x of the contact point on the plane [m].
    #[getter]
    fn contact_x<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 23)
    }
    /// y of the contact point on the plane [m].
    #[getter]
    fn contact_y<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 24)
    }
    /// Relative drift of the scene's conserved quantity (E, or E + W) since t = 0 [1].
    #[getter]
    fn drift<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 25)
    }
    /// Height of the body's lowest point above the plane [m] (0 in contact).
    #[getter]
    fn gap<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, 26)
    }
    /// Contact regime of each sample: "frictionless", "sliding", "rolling" or "flight"
    /// (numpy str array).
    #[getter]
    fn mode<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.modes(py)
    }

    /// Column names in the CSV file's order.
    #[classattr]
    fn columns() -> Vec<&'static str> {
        columns::names()
    }

    /// Column name → unit ("1" for `mode`).
    #[classattr]
    fn units(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        columns::units().into_py_dict(py)
    }

    /// The run summary: the same dict as the command-line tool's `--summary` JSON (status,
    /// message, events, stats, wall_time_s [s], samples, final, drift, invariants,
    /// warnings, checks, units, scenario, overrides, output = None, version).
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.summary_dict(py, &self.summary)
    }

    /// Why the run ended (one of `Status::NAMES`): "completed", "observed" (a terminal
    /// observable), "lost_contact", "slip_stopped" (outcomes), or "painleve",
    /// "solver_failure", "chattering", "non_finite", "cancelled" (on a SimulationError's
    /// trajectory).
    #[getter]
    fn status(&self) -> &'static str {
        self.summary.status
    }

    /// Why the run ended, in a sentence.
    #[getter]
    fn message(&self) -> &str {
        &self.summary.message
    }

    /// Whether the run reached t_end.
    #[getter]
    fn completed(&self) -> bool {
        self.summary.status == "completed"
    }

    /// Located events, in time order: dicts `{"kind": ..., "t": [s]}`, kind one of
    /// "slip_stop", "mode_switch" (with "from" and "to"), "lost_contact", "painleve",
    /// "observed" (with "name" and "state", a dict of every column at the event).
    #[getter]
    fn events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let json = serde_json::to_string(&self.summary.events)
            .map_err(|e| Class::Internal.error(py, &e.to_string(), &[]))?;
        py.import("json")?.getattr("loads")?.call1((json,))
    }

    /// The scenario that was run.
    #[getter]
    fn scenario(&self) -> PyScenario {
        self.scenario.clone()
    }

    fn __len__(&self) -> usize {
        self.samples.len()
    }

    fn __repr__(&self) -> String {
        let t = self.samples.last().map_or(f64::NAN, |s| s.t);
        format!(
            "<ellipsoid.Trajectory {}: {} samples to t = {t} s, {}>",
            self.scenario.inner.source,
            self.samples.len(),
            self.summary.status
        )
    }

    /// The columns as a dict name → array, in file order.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (i, (name, _)) in NUMERIC_COLUMNS.iter().enumerate() {
            if i == columns::MODE_POSITION {
                d.set_item(columns::MODE, self.modes(py)?)?;
            }
            d.set_item(*name, self.column(py, i)?)?;
        }
        Ok(d)
    }

    /// The columns as a pandas DataFrame (needs pandas), in file order.
    fn to_pandas<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let pandas = py.import("pandas").map_err(|e| {
            pyo3::exceptions::PyImportError::new_err(format!(
                "Trajectory.to_pandas needs pandas (`pip install pandas`): {e}"
            ))
        })?;
        pandas.getattr("DataFrame")?.call1((self.to_dict(py)?,))
    }

    /// Writes the trajectory as CSV, byte for byte what `ellipsoid run -o PATH` writes for
    /// the same run (the same writer). The file appears only when complete; its directory
    /// must exist. Raises OutputError.
    fn to_csv(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        self.write(py, &path, |p| {
            Ok(TrajectoryWriter::Csv(CsvFile::create(p)?))
        })
    }

    /// Writes the trajectory as HDF5 (one float64 dataset per column with a `units`
    /// attribute, `mode` as ASCII strings, the scenario and the summary JSON as root
    /// attributes), as `ellipsoid run -o PATH.h5` does. Needs a build with the `hdf5`
    /// feature (see `ellipsoid.HDF5`); otherwise raises OutputError saying how to get one.
    fn to_hdf5(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        #[cfg(feature = "hdf5")]
        {
            self.write(py, &path, |p| {
                Ok(TrajectoryWriter::Hdf5(
                    ellipsoid_io::hdf5::Hdf5File::create(p)?,
                ))
            })
        }
        #[cfg(not(feature = "hdf5"))]
        {
            Err(errors::output_error(
                py,
                &OutputError::Hdf5Unavailable { path },
            ))
        }
    }

    /// The 3-D viewer page of this run (the same HTML as `ellipsoid view`): the body on the
    /// plane with its contact trace, play/pause, speed, a time slider, θ(t) and energy
    /// plots with a linked cursor; self-contained (opens offline). With `path`, writes it
    /// there atomically and returns None; without, returns the HTML text.
    #[pyo3(signature = (path=None, *, title=None))]
    fn view(
        &self,
        py: Python<'_>,
        path: Option<PathBuf>,
        title: Option<String>,
    ) -> PyResult<Option<String>> {
        let html = self.page(py, title.as_deref())?;
        match path {
            None => Ok(Some(html)),
            Some(p) => {
                ellipsoid_io::atomic::write(&p, html.as_bytes())
                    .map_err(|e| errors::output_error(py, &e))?;
                Ok(None)
            }
        }
    }

    /// Jupyter: the viewer inline, in an iframe.
    fn _repr_html_(&self, py: Python<'_>) -> PyResult<String> {
        let html = self.page(py, None)?;
        let doc = html.replace('&', "&amp;").replace('"', "&quot;");
        Ok(format!(
            "<iframe srcdoc=\"{doc}\" style=\"width: 100%; height: 680px; border: 1px solid #ccc\" sandbox=\"allow-scripts\"></iframe>"
        ))
    }

    /// The geometric centre C0's path on the plane, (x, y) [m] (used by `plot`); None
    /// when C0 is G.
    fn _centre_path<'py>(&self, py: Python<'py>) -> Option<XyArrays<'py>> {
        self.table()
            .centre_path()
            .map(|(x, y)| (PyArray1::from_vec(py, x), PyArray1::from_vec(py, y)))
    }

    /// The contact point's path on the plane, (x, y) [m], from G, the Euler angles and the
    /// body's shape (used by `plot`).
    fn _contact_path<'py>(&self, py: Python<'py>) -> Option<XyArrays<'py>> {
        self.table()
            .contact_path()
            .map(|(x, y)| (PyArray1::from_vec(py, x), PyArray1::from_vec(py, y)))
    }

    /// The multi-panel figure of `ellipsoid plot` drawn with matplotlib (needed; raises
    /// ImportError saying how to install it): `panels` a comma-separated string or a list
    /// of "theta", "rates", "energy", "forces", "path" (default: all). Returns the
    /// matplotlib Figure.
    #[pyo3(signature = (panels=None))]
    fn plot<'py>(
        slf: &Bound<'py, Self>,
        panels: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        slf.py()
            .import("ellipsoid._plot")?
            .getattr("plot")?
            .call1((slf, panels))
    }

    /// Writes the trajectory in the format its extension names (`.csv`, `.h5`, `.hdf5`),
    /// as `ellipsoid run -o PATH` does.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let format = Format::from_path(&path).map_err(|e| errors::output_error(py, &e))?;
        match format {
            Format::Csv => self.to_csv(py, path),
            Format::Hdf5 => self.to_hdf5(py, path),
        }
    }
}
