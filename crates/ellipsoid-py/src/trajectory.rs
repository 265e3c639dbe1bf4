//! `ellipsoid.Trajectory`: the samples of a run as numpy columns named like the CSV
//! columns, the run summary, and writers shared with the command-line tool.

use std::path::{Path, PathBuf};

use ellipsoid_core::simulate::{Mode, Sample, Status};
use ellipsoid_io::columns::{self, Layout};
use ellipsoid_io::{
    Format, Metadata, OutputError, Summary, TrajectoryWriter, csv::CsvFile, restore,
};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyDict;

use ellipsoid_study::power_law::{self, T0};

use crate::args;
use crate::errors::{self, Class};
use crate::run::{self, Run};
use crate::scenario::PyScenario;

/// The result of a run: one float64 numpy array per output column, named like the
/// command-line tool's CSV columns, plus the run summary.
///
/// Columns (SI units; angles unwrapped): `t` [s]; `x`, `y`, `z` [m] (centre of mass G);
/// `theta`, `phi`, `psi` [rad] (z-x-z Euler angles); `theta_dot`, `phi_dot`, `psi_dot`
/// [rad/s]; `omega_x`, `omega_y`, `omega_z` [rad/s] (body axes); `vx`, `vy`, `vz` [m/s]
/// (velocity of G); `energy` [J]; `normal_force` [N]; `slip_speed` [m/s] (speed of the
/// contact point); `mode` (str array: "frictionless", "sliding", "rolling", "flight",
/// "viscous", "two_contacts", "three_contacts" or "face");
/// `work` [J]
/// (dissipated so far); `omega_world_x`, `omega_world_y`, `omega_world_z` [rad/s] (world
/// axes); `contact_x`, `contact_y` [m] (contact point on the plane); `drift` [1]
/// (relative drift of E, or of E + W where E is not conserved); `gap` [m] (lowest point
/// above the plane, 0 in contact). A body with contact spheres adds five columns per
/// surface (`normal_force_stem`, `slip_speed_stem`, `gap_stem`, `contact_x_stem`,
/// `contact_y_stem`; the ellipsoid's named `ellipsoid`), read as `traj["gap_stem"]`
/// (`columns` lists them). The arrays are read-only views of the run (copy to modify).
///
/// `len(traj)` is the number of samples. A run that ends early (loss of contact, the pure
/// sliding model's slip stop) is still a Trajectory: `status` and `events` say why.
#[pyclass(frozen, module = "ellipsoid")]
pub struct Trajectory {
    samples: Vec<Sample>,
    summary: Summary,
    scenario: PyScenario,
    /// The columns of a run of the scenario's body.
    layout: Layout,
    numeric: PyOnceLock<Vec<Py<PyArray1<f64>>>>,
    mode: PyOnceLock<Py<PyAny>>,
    /// The points of the scene's Poincaré sections, in its order.
    sections: Vec<Vec<Sample>>,
}

impl Trajectory {
    /// `samples` as pickled: every numeric column's float64 values, row by row, and the
    /// modes by label.
    fn encode(&self, samples: &[Sample]) -> (Vec<u8>, Vec<String>) {
        let mut row = Vec::with_capacity(self.layout.numeric());
        let mut values: Vec<u8> = Vec::with_capacity(8 * row.capacity() * samples.len());
        for s in samples {
            row.clear();
            row.extend(columns::values(s));
            self.layout.surface_values(s, &mut row);
            values.extend(row.iter().flat_map(|v| v.to_le_bytes()));
        }
        let modes = samples
            .iter()
            .map(|s| self.layout.mode(s).into_owned())
            .collect();
        (values, modes)
    }

    pub fn new(run: Run) -> Self {
        Self::from_parts(
            run.samples,
            run.summary,
            PyScenario {
                inner: run.scenario,
            },
            run.sections,
        )
    }

    fn from_parts(
        samples: Vec<Sample>,
        summary: Summary,
        scenario: PyScenario,
        sections: Vec<Vec<Sample>>,
    ) -> Self {
        Trajectory {
            sections,
            layout: Layout::of(&scenario.inner.scene.body),
            samples,
            summary,
            scenario,
            numeric: PyOnceLock::new(),
            mode: PyOnceLock::new(),
        }
    }

    /// Where the run ended [s] (its last state, which a trajectory sampled at explicit
    /// times may not hold as a row).
    fn t_final(&self) -> f64 {
        self.summary.final_sample.t
    }

    /// Numeric column `index` (the layout's order). Every column is made on the first
    /// access of any, in one pass over the samples (a column at a time would read each
    /// sample 27 times); numpy takes the vectors over without a copy.
    fn column<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let all = self.numeric.get_or_try_init(py, || -> PyResult<_> {
            columns::column_major(&self.layout, &self.samples)
                .into_iter()
                .map(|col| {
                    let arr = PyArray1::from_vec(py, col);
                    readonly(arr.as_any())?;
                    Ok(arr.unbind())
                })
                .collect::<PyResult<Vec<_>>>()
        })?;
        Ok(all[index].bind(py).clone())
    }

    /// The numeric column called `name` (one of the fixed columns).
    fn named<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let index = columns::index(name)
            .ok_or_else(|| Class::Internal.error(py, &format!("no column {name:?}"), &[]))?;
        self.column(py, index)
    }

    /// The `mode` column: a numpy str array, made from one byte per sample (the mode's
    /// index in `Mode::NAMES`, or for a body with contact spheres in the labels met).
    fn modes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let arr = self.mode.get_or_try_init(py, || -> PyResult<_> {
            let (codes, labels, dtype) = if self.layout.extra() == 0 {
                let codes: Vec<u8> = self.samples.iter().map(|s| s.mode as u8).collect();
                let labels: Vec<String> = Mode::NAMES.map(String::from).to_vec();
                (codes, labels, "U12")
            } else {
                let mut labels: Vec<String> = Vec::new();
                let codes = self
                    .samples
                    .iter()
                    .map(|s| {
                        let label = self.layout.mode(s);
                        let k = labels.iter().position(|l| *l == label).unwrap_or_else(|| {
                            labels.push(label.into_owned());
                            labels.len() - 1
                        });
                        u8::try_from(k).expect("fewer than 256 mode labels")
                    })
                    .collect();
                (codes, labels, "U64")
            };
            let numpy = py.import("numpy")?;
            let names = numpy
                .getattr("array")?
                .call((labels,), Some(&[("dtype", dtype)].into_py_dict(py)?))?;
            let arr = names.get_item(PyArray1::from_vec(py, codes))?;
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

/// Rows of `Trajectory.states`: the configuration and velocities in output coordinates,
/// and the dissipated work.
const STATE_NAMES: [&str; 13] = [
    "x", "y", "z", "theta", "phi", "psi", "omega_x", "omega_y", "omega_z", "vx", "vy", "vz", "work",
];

/// `ellipsoid._result.NAME(traj)`: the result conventions written in Python.
fn result_helper<'py>(slf: &Bound<'py, Trajectory>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    slf.py()
        .import("ellipsoid._result")?
        .getattr(name)?
        .call1((slf,))
}

/// A path on the plane as two numpy arrays, x and y [m].
type XyArrays<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

impl Trajectory {
    /// The run as a table for the viewer: the same columns, events and body as
    /// `ellipsoid view OUT.csv --summary S.json` reads back, so the pages are identical.
    fn table(&self) -> ellipsoid_io::table::Table {
        let numeric = self.layout.numeric_columns();
        let names: Vec<&str> = numeric.iter().map(|c| &*c.0).collect();
        let mut t = ellipsoid_io::table::Table::from_rows(
            &self.scenario.inner.source,
            &names,
            self.samples.len(),
            |i| {
                let s = &self.samples[i];
                let mut v = columns::values(s).to_vec();
                self.layout.surface_values(s, &mut v);
                (v, self.layout.mode(s).into_owned())
            },
        );
        if let Ok(v) = serde_json::from_str::<serde_json::Value>(&self.summary.to_json()) {
            t.apply_events(&v);
        }
        t.set_body(&self.scenario.inner.scene.body, &self.scenario.inner.source);
        t
    }

    /// The viewer page (`path` None) or the file written at `path`, as `view` returns them,
    /// with the side plots `columns` (see [`Trajectory::page`]).
    fn page_or_file<'py>(
        &self,
        py: Python<'py>,
        path: Option<PathBuf>,
        title: Option<String>,
        columns: Option<String>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let html = self.page(py, title.as_deref(), columns.as_deref())?;
        let display = py.import("ellipsoid._display")?;
        match path {
            None => display.getattr("ViewerPage")?.call1((html,)),
            Some(p) => {
                ellipsoid_io::atomic::write(&p, html.as_bytes())
                    .map_err(|e| errors::output_error(py, &e))?;
                display.getattr("ViewerFile")?.call1((p,))
            }
        }
    }

    /// The viewer page, titled `title` (default: the scenario's file name, as `ellipsoid
    /// view` titles it; never its directories), with the side plots `columns` (comma-
    /// separated column names; default θ and the energy, and each surface's normal force
    /// for a body with contact spheres).
    fn page(&self, py: Python<'_>, title: Option<&str>, columns: Option<&str>) -> PyResult<String> {
        let source = &self.scenario.inner.source;
        let name = Path::new(source)
            .file_name()
            .map_or_else(|| source.clone(), |n| n.to_string_lossy().into_owned());
        let table = self.table();
        let plots = match columns {
            None => ellipsoid_io::viewer::default_plots(&table),
            Some(spec) => ellipsoid_io::viewer::parse_plots(spec).map_err(|rule| {
                errors::value_error(py, source, Some("columns"), Some(spec), rule)
            })?,
        };
        let plots: Vec<&str> = plots.iter().map(String::as_str).collect();
        ellipsoid_io::viewer::check_plots(&table, &plots)
            .map_err(|rule| errors::value_error(py, source, Some("columns"), columns, rule))?;
        ellipsoid_io::viewer::html(&table, title.unwrap_or(&name), &plots)
            .map_err(|e| Class::Internal.error(py, &e.to_string(), &[]))
    }
}

/// `x` to about 6 significant digits, for `repr`.
fn short(x: f64) -> String {
    if x == 0.0 || (1e-3..1e5).contains(&x.abs()) {
        let s = format!("{x:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        format!("{x:.5e}")
    }
}

/// Whether a run that ended with `status` ended as a run may: an outcome, not an error
/// and not cancelled.
fn succeeded(status: &Status) -> bool {
    !status.is_error() && !matches!(status, Status::Cancelled)
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
        self.named(py, "t")
    }
    /// x of the centre of mass G [m].
    #[getter]
    fn x<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "x")
    }
    /// y of the centre of mass G [m].
    #[getter]
    fn y<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "y")
    }
    /// Height of the centre of mass G above the plane [m] (from the contact constraint).
    #[getter]
    fn z<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "z")
    }
    /// θ, tilt of the symmetry axis from the vertical [rad].
    #[getter]
    fn theta<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "theta")
    }
    /// φ, precession angle [rad] (unwrapped).
    #[getter]
    fn phi<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "phi")
    }
    /// ψ, spin angle [rad] (unwrapped).
    #[getter]
    fn psi<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "psi")
    }
    /// θ̇ [rad/s].
    #[getter]
    fn theta_dot<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "theta_dot")
    }
    /// φ̇ [rad/s].
    #[getter]
    fn phi_dot<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "phi_dot")
    }
    /// ψ̇ [rad/s].
    #[getter]
    fn psi_dot<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "psi_dot")
    }
    /// Angular velocity, body x component [rad/s].
    #[getter]
    fn omega_x<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "omega_x")
    }
    /// Angular velocity, body y component [rad/s].
    #[getter]
    fn omega_y<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "omega_y")
    }
    /// Angular velocity, body z component [rad/s].
    #[getter]
    fn omega_z<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "omega_z")
    }
    /// Velocity of G, x [m/s].
    #[getter]
    fn vx<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "vx")
    }
    /// Velocity of G, y [m/s].
    #[getter]
    fn vy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "vy")
    }
    /// Velocity of G, z [m/s].
    #[getter]
    fn vz<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "vz")
    }
    /// Mechanical energy E = ½m|v_G|² + ½ωᵀIω + m g z_G [J].
    #[getter]
    fn energy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "energy")
    }
    /// Normal force N of the plane on the body [N].
    #[getter]
    fn normal_force<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "normal_force")
    }
    /// |v_C|, speed of the material contact point [m/s].
    #[getter]
    fn slip_speed<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "slip_speed")
    }
    /// Work dissipated so far by friction and the effects [J].
    #[getter]
    fn work<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "work")
    }
    /// Angular velocity about world x [rad/s].
    #[getter]
    fn omega_world_x<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "omega_world_x")
    }
    /// Angular velocity about world y [rad/s].
    #[getter]
    fn omega_world_y<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "omega_world_y")
    }
    /// Angular velocity about the vertical, world z [rad/s] (the vertical spin).
    #[getter]
    fn omega_world_z<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "omega_world_z")
    }
    /// x of the contact point on the plane [m].
    #[getter]
    fn contact_x<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "contact_x")
    }
    /// y of the contact point on the plane [m].
    #[getter]
    fn contact_y<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "contact_y")
    }
    /// Relative drift of the scene's conserved quantity (E, or E + W) since t = 0 [1].
    #[getter]
    fn drift<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "drift")
    }
    /// Height of the body's lowest point above the plane [m] (0 in contact).
    #[getter]
    fn gap<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.named(py, "gap")
    }
    /// Contact regime of each sample: "frictionless", "sliding", "rolling", "flight",
    /// "viscous", "two_contacts", "three_contacts" or "face" (numpy str array); for a body with contact spheres, the surfaces in
    /// contact after `@` ("sliding@stem", "two_contacts@ellipsoid+stem").
    #[getter]
    fn mode<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.modes(py)
    }

    /// Whether the run ended as a run may (solve_ivp's `success`): it reached t_end or
    /// stopped at an outcome (a terminal observable, loss of contact with
    /// `on_lift_off = "stop"`, the sliding model's slip stop). False for a Painlevé
    /// inconsistency, a solver failure, chattering, a non-finite state or a cancelled run;
    /// `message` says why.
    #[getter]
    fn success(&self) -> bool {
        succeeded(&self.summary.status)
    }

    /// solve_ivp's integer status: 0 reached t_end, 1 stopped at a terminal event (an
    /// outcome), -1 failed. (`status` is the string that summaries and study tables carry.)
    #[getter]
    fn status_code(&self) -> i32 {
        match self.summary.status {
            Status::Completed => 0,
            _ if self.success() => 1,
            _ => -1,
        }
    }

    /// Evaluations of the right-hand side (solve_ivp's `nfev`; `summary["stats"]` has
    /// the steps).
    #[getter]
    fn nfev(&self) -> u64 {
        self.summary.stats.rhs_evals
    }

    /// The state as a matrix, shape (n_states, n_t), rows named by `state_names` (x, y, z
    /// [m]; theta, phi, psi [rad]; omega_x, omega_y, omega_z [rad/s], body axes; vx, vy,
    /// vz [m/s]; work [J]), like solve_ivp's `y`. (`traj.y` is the y coordinate of G.)
    #[getter]
    fn states<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        result_helper(slf, "states")
    }

    /// Names of the rows of `states` (and of the columns of `y_events`).
    #[classattr]
    fn state_names() -> Vec<&'static str> {
        STATE_NAMES.to_vec()
    }

    /// Event times [s] by name (solve_ivp's `t_events`): one float64 array per observable
    /// of the scenario (by its `name`) and per built-in event kind ("slip_stop",
    /// "mode_switch", "lost_contact", "lift_off", "touchdown", "impact", "painleve",
    /// "contact_surface", "grip", "flat"), empty when it did not occur.
    #[getter]
    fn t_events<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        result_helper(slf, "t_events")
    }

    /// The state at each event, by the names of `t_events`: arrays of shape
    /// (n_events, n_states), columns named by `state_names`. An observable's is the state
    /// located with it; a built-in event's is the dense output there (`sol`, which reruns
    /// the scenario once for all of them).
    #[getter]
    fn y_events<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        result_helper(slf, "y_events")
    }

    /// The run's dense interpolant (solve_ivp's `sol`): the state at the times `t` [s]
    /// (a number or an array, any order, repeats allowed, each in [0, t_final]) as a
    /// Trajectory whose rows are those times, in the order given: `traj.sol(ts).theta`.
    ///
    /// It reruns the scenario with `t` as its output times: the integrator's steps do not
    /// depend on the output times, and each value comes from the dense output (Hermite or
    /// DOP853's own interpolant) of the step that holds it, piecewise over the phases and
    /// events, so `sol(ts)` is identical to `simulate(scenario, t_eval=sorted(ts))` and
    /// costs one run.
    fn sol(&self, py: Python<'_>, t: &Bound<'_, PyAny>) -> PyResult<Trajectory> {
        let source = &self.scenario.inner.source;
        // numpy's conversion error (a ValueError or TypeError) named as the argument's.
        let times: Vec<f64> = py
            .import("numpy")?
            .getattr("asarray")?
            .call1((t, "float64"))
            .and_then(|a| a.call_method0("ravel")?.extract())
            .map_err(|e| {
                errors::type_error(
                    py,
                    source,
                    Some("t"),
                    None,
                    format!("expected times (a number or an array of numbers): {e}"),
                )
            })?;
        let end = self.t_final();
        if times.len() > ellipsoid_core::scenario::MAX_SAMPLES {
            return Err(errors::value_error(
                py,
                source,
                Some("t"),
                Some(&times.len().to_string()),
                format!(
                    "Trajectory.sol takes at most {} times at once",
                    ellipsoid_core::scenario::MAX_SAMPLES
                ),
            ));
        }
        if let Some(bad) = times.iter().find(|&&x| !(0.0..=end).contains(&x)) {
            return Err(errors::value_error(
                py,
                source,
                Some("t"),
                Some(&bad.to_string()),
                format!("Trajectory.sol: every time must lie in [0, {end}] s, the span of the run"),
            ));
        }
        let mut sorted = times.clone();
        sorted.sort_by(f64::total_cmp);
        sorted.dedup();
        let mut scenario = self.scenario.inner.clone();
        scenario.scene.sample_times = sorted.clone();
        let (result, interrupt) =
            run::detached(py, move |cancel| run::run_caught(scenario, true, cancel))?;
        if let Some(e) = interrupt {
            return Err(e);
        }
        let rerun = match result {
            Ok(r) => r,
            Err(run::Failure::Model(e)) => return Err(errors::scenario_error(py, &e)),
            Err(run::Failure::Panic(msg)) => return Err(errors::internal_error(py, &msg)),
        };
        if rerun.samples.len() != sorted.len() {
            return Err(errors::internal_error(
                py,
                &format!(
                    "the rerun for Trajectory.sol gave {} of {} samples",
                    rerun.samples.len(),
                    sorted.len()
                ),
            ));
        }
        let samples = times
            .iter()
            .map(|x| rerun.samples[sorted.partition_point(|s| s < x)])
            .collect();
        Ok(Trajectory::new(Run { samples, ..rerun }))
    }

    /// Names of the scenario's observables (`[[observe]]`), in order.
    #[getter]
    fn _observables(&self) -> Vec<String> {
        self.scenario
            .inner
            .scene
            .observe
            .iter()
            .map(|o| o.name.clone())
            .collect()
    }

    /// Pickling (joblib, multiprocessing): the samples as float64 values, the modes, the
    /// summary JSON and the scenario; unpickled, the trajectory is the same in every column
    /// and writes the same files.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let (values, modes) = self.encode(&self.samples);
        let sections: Vec<(Bound<'py, pyo3::types::PyBytes>, Vec<String>)> = self
            .sections
            .iter()
            .map(|points| {
                let (v, m) = self.encode(points);
                (pyo3::types::PyBytes::new(py, &v), m)
            })
            .collect();
        let rebuild = py.import("ellipsoid._result")?.getattr("_trajectory")?;
        let args = (
            self.scenario.clone(),
            pyo3::types::PyBytes::new(py, &values),
            modes,
            self.summary.to_json(),
            restore::status_text(&self.summary.status, &self.scenario.inner.scene.body),
            sections,
        );
        (rebuild, args).into_pyobject(py).map(Bound::into_any)
    }

    /// The inverse of `__reduce__`.
    #[staticmethod]
    #[pyo3(signature = (scenario, values, modes, summary, status, sections=Vec::new()))]
    fn _from_pickle(
        py: Python<'_>,
        scenario: &Bound<'_, PyScenario>,
        values: &[u8],
        modes: Vec<String>,
        summary: &str,
        status: &str,
        sections: Vec<(Vec<u8>, Vec<String>)>,
    ) -> PyResult<Trajectory> {
        let bad = |what: String| {
            Class::Internal.error(py, &format!("cannot unpickle a Trajectory: {what}"), &[])
        };
        let layout = Layout::of(&scenario.get().inner.scene.body);
        let samples = decode(&layout, values, &modes).map_err(bad)?;
        let sections = sections
            .iter()
            .map(|(v, m)| decode(&layout, v, m))
            .collect::<Result<Vec<_>, _>>()
            .map_err(bad)?;
        let summary = restore::summary(summary, status, &scenario.get().inner).map_err(bad)?;
        Ok(Trajectory::from_parts(
            samples,
            summary,
            scenario.get().clone(),
            sections,
        ))
    }

    /// The points of each Poincaré section of the scenario (`[[section]]`; docs/scenarios.md,
    /// "Poincaré sections"): section name → a dict of read-only numpy arrays named like the
    /// trajectory's columns (`mode` a str array), one element per crossing, in time order.
    /// `ellipsoid run --sections` writes the same points.
    #[getter]
    fn sections<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        let numpy = py.import("numpy")?;
        let names = self.layout.names();
        for (section, points) in self
            .scenario
            .inner
            .scene
            .sections
            .iter()
            .zip(&self.sections)
        {
            let table = PyDict::new(py);
            let data = columns::column_major(&self.layout, points);
            let modes: Vec<String> = points
                .iter()
                .map(|p| self.layout.mode(p).into_owned())
                .collect();
            let mut data = data.into_iter();
            for name in &names {
                if name == columns::MODE {
                    table.set_item(
                        name.as_ref(),
                        numpy.call_method1("array", (modes.clone(),))?,
                    )?;
                } else {
                    let arr = PyArray1::from_vec(py, data.next().expect("a numeric column"));
                    readonly(arr.as_any())?;
                    table.set_item(name.as_ref(), arr)?;
                }
            }
            out.set_item(&section.crossing.name, table)?;
        }
        Ok(out)
    }

    /// Plots section `name`'s points (`sections[name]`): column `y` against column `x`,
    /// one marker per crossing, the axes labelled with the columns' units, on a new
    /// pyplot figure or, with `ax` (a matplotlib Axes), there. `wrap` names the angle
    /// columns (rad) of `x` and `y` drawn modulo 2π, in [0, 2π) (`wrap="psi"`, or a list).
    /// Returns the Axes, as pandas' `DataFrame.plot` does (needs matplotlib).
    #[pyo3(signature = (name, x, y, ax=None, wrap=None))]
    fn plot_section<'py>(
        slf: &Bound<'py, Self>,
        name: Bound<'py, PyAny>,
        x: Bound<'py, PyAny>,
        y: Bound<'py, PyAny>,
        ax: Option<Bound<'py, PyAny>>,
        wrap: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        slf.py()
            .import("ellipsoid._plot")?
            .getattr("plot_section")?
            .call1((slf, name, x, y, ax, wrap))
    }

    /// Column names in the CSV file's order: `ellipsoid.COLUMNS`, and for a body with
    /// contact spheres five per surface after them (`normal_force_stem`, `slip_speed_stem`,
    /// `gap_stem`, `contact_x_stem`, `contact_y_stem`; the ellipsoid's named `ellipsoid`).
    #[getter]
    fn columns(&self) -> Vec<String> {
        self.layout.names().into_iter().map(String::from).collect()
    }

    /// Column name → unit ("1" for `mode`).
    #[getter]
    fn units<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.layout
            .units()
            .into_iter()
            .map(|(c, u)| (c.into_owned(), u))
            .collect::<Vec<_>>()
            .into_py_dict(py)
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
    /// "solver_failure", "chattering", "non_finite", "below_plane", "cancelled" (on a
    /// SimulationError's trajectory).
    #[getter]
    fn status(&self) -> &'static str {
        self.summary.status.name()
    }

    /// Why the run ended, in a sentence.
    #[getter]
    fn message(&self) -> &str {
        &self.summary.message
    }

    /// Whether the run reached t_end.
    #[getter]
    fn completed(&self) -> bool {
        self.summary.status.completed()
    }

    /// Located events, in time order: dicts `{"kind": ..., "t": [s]}`, kind one of
    /// "slip_stop", "mode_switch" (with "from" and "to"), "lost_contact", "lift_off",
    /// "touchdown", "impact", "painleve", "contact_surface" (with "from" and "to", the
    /// surfaces by name), "grip" (with "surface" and "sticks": with two surfaces in
    /// contact, that surface's contact started to stick, or to slide), "flat" (a rim
    /// landing on its face, docs/physics.md "Rims"), "observed" (with
    /// "name" and "state", a dict of every column at the event). A touchdown and an impact of a body with contact spheres name the
    /// `surface` struck.
    #[getter]
    fn events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let json = serde_json::to_string(&self.summary.events_json())
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
        let last = self.samples.last().map(columns::values);
        let value = |name: &str| {
            last.and_then(|v| columns::index(name).map(|i| v[i]))
                .map_or("-".to_owned(), short)
        };
        format!(
            "<ellipsoid.Trajectory {}: {} samples, t = 0 to {} s, {} ({}); final theta = {} rad, omega_world_z = {} rad/s, energy = {} J, {} events, nfev = {}>",
            self.scenario.inner.source,
            self.samples.len(),
            self.t_final(),
            self.summary.status.name(),
            if self.success() { "success" } else { "failure" },
            value("theta"),
            value("omega_world_z"),
            value("energy"),
            self.summary.events.len(),
            self.summary.stats.rhs_evals,
        )
    }

    /// The column called `name` (any of `columns`: the per-surface ones of a body with
    /// contact spheres too, and `mode`), as its attribute gives it; ScenarioKeyError (a
    /// KeyError) for another name, ScenarioTypeError for a name that is not a str.
    fn __getitem__<'py>(
        &self,
        py: Python<'py>,
        name: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let source = &self.scenario.inner.source;
        let Ok(name) = name.extract::<String>() else {
            return Err(errors::type_error(
                py,
                source,
                Some("name"),
                None,
                format!(
                    "a column is named by a str, found {}",
                    crate::args::type_name(name)
                ),
            ));
        };
        if name == columns::MODE {
            return self.modes(py);
        }
        match self.layout.index(&name) {
            Some(i) => Ok(self.column(py, i)?.into_any()),
            None => Err(errors::input_error(
                py,
                errors::Class::ScenarioKey,
                ellipsoid_core::scenario::ErrorKind::UnknownKey,
                source,
                Some(&name),
                None,
                format!(
                    "not a column of this trajectory; the columns are {}",
                    self.layout.names().join(", ")
                ),
            )),
        }
    }

    /// The columns as a dict name → array, in file order.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (i, (name, _)) in self.layout.numeric_columns().iter().enumerate() {
            if i == columns::MODE_POSITION {
                d.set_item(columns::MODE, self.modes(py)?)?;
            }
            d.set_item(&**name, self.column(py, i)?)?;
        }
        Ok(d)
    }

    /// The columns as a pandas DataFrame (needs pandas), indexed by `t` [s], the other
    /// columns in file order; `df.attrs["units"]` maps every column (and `t`) to its SI
    /// unit, `df.attrs["scenario"]` and `df.attrs["status"]` say what was run and how it
    /// ended.
    fn to_pandas<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        result_helper(slf, "to_pandas")
    }

    /// The power law |y| ≈ A (t0 − t)^p of column `column` (any numeric column: `theta`
    /// for a disc's tilt α, `phi_dot` for its precession rate Ω) over the samples with
    /// t0 − t in `window` = (lo, hi) [s], by least squares of ln|y| on ln(t0 − t)
    /// (docs/physics.md, "Dissipation of a rolling disc"). `t0` None takes the run's first
    /// flat landing (the event `flat`); a number gives t0 [s]; a pair (lo, hi) fits it
    /// there. Returns a dict: `column`, `exponent` p, `prefactor` A, `t0` [s], `t0_from`
    /// ("landing", "given" or "fitted"), `window`, `samples` (used) and `rms` (of ln|y|).
    /// ScenarioError names a bad window or t0 (or too few samples in the window),
    /// ScenarioKeyError an unknown column.
    #[pyo3(signature = (column, window, t0=None))]
    fn power_law<'py>(
        &self,
        py: Python<'py>,
        column: &str,
        window: (f64, f64),
        t0: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let source = &self.scenario.inner.source;
        let k = self.layout.index(column).ok_or_else(|| {
            errors::input_error(
                py,
                errors::Class::ScenarioKey,
                ellipsoid_core::scenario::ErrorKind::UnknownKey,
                source,
                Some(column),
                None,
                format!(
                    "not a numeric column of this trajectory; the columns are {}",
                    self.layout.names().join(", ")
                ),
            )
        })?;
        let t0 = match t0 {
            None => T0::Landing(power_law::landing(&self.summary.events)),
            Some(v) if v.is_none() => T0::Landing(power_law::landing(&self.summary.events)),
            Some(v) => match (v.extract::<f64>(), v.extract::<(f64, f64)>()) {
                (Ok(t), _) => T0::Given(t),
                (_, Ok((lo, hi))) => T0::Fitted(lo, hi),
                _ => {
                    return Err(errors::type_error(
                        py,
                        source,
                        Some("t0"),
                        None,
                        format!(
                            "t0 is None (the flat landing), a number (s) or a pair (lo, hi) to fit it in, found {}",
                            args::type_name(v)
                        ),
                    ));
                }
            },
        };
        let t: Vec<f64> = self.samples.iter().map(|s| s.t).collect();
        let y: Vec<f64> = (self.samples.iter())
            .map(|s| self.layout.value(s, k))
            .collect();
        let fitted = power_law::fit(column, &t, &y, window, t0)
            .map_err(|rule| errors::value_error(py, source, Some("power_law"), None, rule))?;
        let json = serde_json::to_string(&fitted)
            .map_err(|e| Class::Internal.error(py, &e.to_string(), &[]))?;
        py.import("json")?.getattr("loads")?.call1((json,))
    }

    /// The columns as an xarray Dataset (needs xarray) over the dimension `t` [s], each
    /// variable with its `units` attribute; the scenario and the status as attributes.
    fn to_xarray<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        result_helper(slf, "to_xarray")
    }

    /// Writes the trajectory as CSV, byte for byte what `ellipsoid run -o PATH` writes for
    /// the same run (the same writer): a comment line naming the scenario and its body
    /// (`# ellipsoid {...}`; read it back with `pandas.read_csv(path, comment="#")`), the
    /// header, the rows. The file appears only when complete; its directory must exist.
    /// Raises OutputError.
    fn to_csv(&self, py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<()> {
        let path = args::path(py, &self.scenario.inner.source, "path", path)?;
        let comment = ellipsoid_io::csv::comment(&self.scenario.inner);
        self.write(py, &path, |p| {
            Ok(TrajectoryWriter::Csv(CsvFile::create(
                p,
                Some(&comment),
                self.layout.clone(),
            )?))
        })
    }

    /// Writes the trajectory as HDF5 (one float64 dataset per column with a `units`
    /// attribute, `mode` as ASCII strings, the scenario and the summary JSON as root
    /// attributes), as `ellipsoid run -o PATH.h5` does. Needs a build with the `hdf5`
    /// feature (see `ellipsoid.HDF5`); otherwise raises OutputError saying how to get one.
    fn to_hdf5(&self, py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<()> {
        let path = args::path(py, &self.scenario.inner.source, "path", path)?;
        #[cfg(feature = "hdf5")]
        {
            self.write(py, &path, |p| {
                Ok(TrajectoryWriter::Hdf5(
                    ellipsoid_io::hdf5::Hdf5File::create(p, self.layout.clone())?,
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
    /// plane with its contact trace (and its contact spheres, the surface touching the plane
    /// marked green), play/pause, speed, a time slider, side plots with a linked cursor —
    /// θ(t) and the energy (and each surface's normal force for a body with contact
    /// spheres), or the output columns `columns` (a list, or a comma-separated string, at
    /// most 6: `columns=["omega_world_z", "theta"]`; a per-surface column such as
    /// `"normal_force_stem"`, or `"normal_force_*"` for every surface in one plot); titled
    /// `title` (default: the scenario's file name); self-contained (opens offline). Without `path`, returns
    /// the HTML text as an `ellipsoid._display.ViewerPage` (a `str` that Jupyter displays
    /// as the viewer, inline: 0.7–1.4 MB in the notebook). With `path`, writes it there
    /// atomically and returns a `ViewerFile` (an `os.PathLike` that Jupyter displays as an
    /// iframe of the file: a notebook stays small).
    #[pyo3(signature = (path=None, *, title=None, columns=None))]
    fn view<'py>(
        &self,
        py: Python<'py>,
        path: Option<&Bound<'py, PyAny>>,
        title: Option<&Bound<'py, PyAny>>,
        columns: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let source = &self.scenario.inner.source;
        let path = args::opt_path(py, source, "path", path)?;
        let title = args::opt_string(py, source, "title", title)?;
        let columns = args::opt_names(py, source, "columns", columns)?;
        self.page_or_file(py, path, title, columns)
    }

    /// Writes the run as an animated GIF at `path`, rendered without a browser (the same
    /// renderer as `ellipsoid animate`): the body on the plane, its contact trace, the time
    /// and θ in a corner; `width`×`height` px (16 to 2000), `fps` frames per second (at
    /// most 100), `speed` simulated seconds per second (0.25: four times slower). A `path`
    /// ending in `.mp4` writes the same frames as H.264 MP4, encoded by the system's ffmpeg
    /// (on the PATH, or named by $ELLIPSOID_FFMPEG). Returns the number of frames (at most
    /// 2000: the animation always shows the whole run, and a `speed` at which the run needs
    /// more frames raises ScenarioError naming the speed that fits). Raises OutputError if
    /// the file cannot be written (or, for MP4, ffmpeg is missing or fails: the message
    /// says what to install), ScenarioError for a bad option;
    /// Ctrl-C stops it before the next frame and raises KeyboardInterrupt, nothing written.
    #[pyo3(signature = (path, *, width=None, height=None, fps=None, speed=None))]
    #[pyo3(text_signature = "(self, /, path, *, width=480, height=360, fps=25.0, speed=1.0)")]
    fn animate(
        &self,
        py: Python<'_>,
        path: &Bound<'_, PyAny>,
        width: Option<&Bound<'_, PyAny>>,
        height: Option<&Bound<'_, PyAny>>,
        fps: Option<&Bound<'_, PyAny>>,
        speed: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<usize> {
        let source = &self.scenario.inner.source;
        let path = args::path(py, source, "path", path)?;
        let pixels = |key, v, default| {
            args::opt_count(py, source, key, v, u32::MAX as usize)
                .map(|n| n.map_or(default, |n| n as u32))
        };
        let number = |key, v: Option<&Bound<'_, PyAny>>, default| {
            v.filter(|v| !v.is_none())
                .map_or(Ok(default), |v| args::number(py, source, key, v))
        };
        let opt = ellipsoid_io::animate::Options {
            width: pixels("width", width, 480)?,
            height: pixels("height", height, 360)?,
            fps: number("fps", fps, 25.0)?,
            speed: number("speed", speed, 1.0)?,
        };
        opt.check()
            .map_err(|rule| errors::value_error(py, source, Some("animate"), None, rule))?;
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_lowercase())
            .unwrap_or_default();
        if ext != "gif" && ext != "mp4" {
            return Err(errors::value_error(
                py,
                source,
                Some("path"),
                Some(&path.display().to_string()),
                "an animation is written as .gif, or as .mp4 where ffmpeg is installed",
            ));
        }
        let table = self.table();
        ellipsoid_io::animate::check(&table, &opt)
            .map_err(|rule| errors::value_error(py, source, Some("animate"), None, rule))?;
        // Ctrl-C stops the frames (read before each) and raises KeyboardInterrupt,
        // nothing written.
        let (rendered, interrupt) = run::detached(py, |cancel| {
            if ext == "mp4" {
                ellipsoid_io::animate::mp4(&table, &opt, cancel).map_err(|e| (true, e))
            } else {
                let mut bytes = Vec::new();
                ellipsoid_io::animate::gif(&table, &opt, &mut bytes, cancel)
                    .map(|frames| (bytes, frames))
                    .map_err(|e| (false, e))
            }
        })?;
        if let Some(e) = interrupt {
            return Err(e);
        }
        let (bytes, frames) = rendered.map_err(|(mp4, e)| {
            if mp4 {
                errors::output_error(
                    py,
                    &OutputError::Io {
                        path: path.clone(),
                        source: std::io::Error::other(e),
                    },
                )
            } else {
                errors::internal_error(py, &e)
            }
        })?;
        ellipsoid_io::atomic::write(&path, &bytes).map_err(|e| errors::output_error(py, &e))?;
        Ok(frames)
    }

    /// Jupyter: the viewer inline, in an iframe.
    fn _repr_html_<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.page_or_file(py, None, None, None)?
            .call_method0("_repr_html_")
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
    /// of "theta", "rates", "energy", "forces", "surfaces", "path" (default: all, "surfaces"
    /// — each surface's normal force — only for a body with contact spheres); or `columns`,
    /// any numeric output columns (a list or a comma-separated string), one panel each. With
    /// `ax` (a matplotlib Axes) it draws there instead: the columns, or one of the panels
    /// theta, rates, path. As pandas' `DataFrame.plot`: the figure is made by pyplot, so
    /// Jupyter shows it once (with or without a trailing `;`), `plt.show()` shows it and
    /// `plt.savefig("x.pdf")` writes it; returns the Axes (`ax` when given), or for
    /// several a numpy array of them, top to bottom (`axes[0].figure` is the Figure).
    #[pyo3(signature = (panels=None, *, columns=None, ax=None))]
    fn plot<'py>(
        slf: &Bound<'py, Self>,
        panels: Option<Bound<'py, PyAny>>,
        columns: Option<Bound<'py, PyAny>>,
        ax: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        slf.py()
            .import("ellipsoid._plot")?
            .getattr("plot")?
            .call1((slf, panels, columns, ax))
    }

    /// Writes the trajectory in the format its extension names (`.csv`, `.h5`, `.hdf5`),
    /// as `ellipsoid run -o PATH` does.
    fn save(&self, py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<()> {
        let given = args::path(py, &self.scenario.inner.source, "path", path)?;
        let format = Format::from_path(&given).map_err(|e| errors::output_error(py, &e))?;
        match format {
            Format::Csv => self.to_csv(py, path),
            Format::Hdf5 => self.to_hdf5(py, path),
        }
    }
}

/// The inverse of [`Trajectory::encode`].
fn decode(layout: &Layout, values: &[u8], modes: &[String]) -> Result<Vec<Sample>, String> {
    let row = layout.numeric() * 8;
    if values.len() != modes.len() * row {
        return Err(format!(
            "{} bytes for {} samples",
            values.len(),
            modes.len()
        ));
    }
    values
        .chunks_exact(row)
        .zip(modes)
        .map(|(chunk, m)| {
            let v: Vec<f64> = chunk
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes(b.try_into().expect("chunks of 8 bytes")))
                .collect();
            restore::sample(layout, &v, m).ok_or_else(|| format!("unknown mode {m:?}"))
        })
        .collect()
}
