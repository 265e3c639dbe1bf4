//! Trajectory files read back (CSV, and HDF5 with the `hdf5` feature) as named columns,
//! with what the plots and the viewer need besides: the events (from a JSON summary or
//! the summary stored in an HDF5 file) and the body's shape with its contact spheres
//! (from a CSV's comment line, or the scenario, when it can be found), so that the body
//! can be drawn and the contact point placed on the plane.
//!
//! Columns are read by name, so a file with more columns than this build writes (e.g.
//! `omega_world_x`, `contact_x`, `drift`) is read whole, and one with fewer is read as
//! long as it has `t`; each consumer says which columns it needs.
//!
//! Bounds: at most [`MAX_ROWS`] rows and [`MAX_FILE_BYTES`] bytes; every number finite;
//! times non-decreasing. Every error names the file, and the line, column and value.

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

use ellipsoid_core::body::MAX_NAME;
use ellipsoid_core::columns::{NUMERIC_COLUMNS, SURFACE_COLUMNS};
use ellipsoid_core::geometry;
use ellipsoid_core::scenario::{self, MAX_SAMPLES};
use ellipsoid_core::state::EulerAngles;
use nalgebra::{Matrix3, Vector3};
use serde_json::Value;

/// Most rows read (the most a scenario may produce).
pub const MAX_ROWS: usize = MAX_SAMPLES;
/// Largest trajectory or summary file read (a 10⁷-row CSV is about 4.6 GB).
pub const MAX_FILE_BYTES: u64 = 6 << 30;
/// Largest JSON summary read.
pub const MAX_SUMMARY_BYTES: u64 = 64 << 20;

/// Why a trajectory could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The content is not a trajectory this program can read.
    #[error("{path}{}: {message}", line.map(|l| format!(":{l}")).unwrap_or_default())]
    Format {
        path: PathBuf,
        line: Option<u64>,
        message: String,
    },
    /// `.h5` asked of a build without the `hdf5` feature.
    #[error("{path}: {}", crate::HDF5_HINT)]
    Hdf5Unavailable { path: PathBuf },
}

impl ReadError {
    fn format(path: &Path, line: Option<u64>, message: impl Into<String>) -> Self {
        ReadError::Format {
            path: path.to_owned(),
            line,
            message: message.into(),
        }
    }
}

/// A located event, for marking on plots and the viewer's timeline.
#[derive(Debug, Clone, PartialEq)]
pub struct Event {
    /// Time \[s\].
    pub t: f64,
    /// `mode_switch`, `slip_stop`, `lost_contact`, `painleve`, or an observable's name.
    pub kind: String,
    /// Short text: `sliding → rolling`, `slip stop`, …
    pub label: String,
}

/// The body's geometry, enough to draw it and place its contact point.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// Semi-axes (a, b, c) along body x, y, z \[m\].
    pub semi_axes: [f64; 3],
    /// G − C0 in body axes \[m\].
    pub com_offset: [f64; 3],
    /// The contact spheres fixed in the body (a tippe top's stem, a top's peg), in the
    /// body's order; empty for a one-surface body.
    pub spheres: Vec<SphereShape>,
    /// The rims (circular edges: a coin's, a disc's), in the body's order.
    pub rims: Vec<RimShape>,
    /// Whether the ellipsoid itself touches the plane (false: a coin, which touches with
    /// its rim only).
    pub ellipsoid_contact: bool,
}

/// A rim of the body, as drawn: the torus of `body::Rim`.
#[derive(Debug, Clone, PartialEq)]
pub struct RimShape {
    /// Its name (the per-surface columns name it).
    pub name: String,
    /// The centre of its circle in body axes, from the ellipsoid's centre C0 \[m\].
    pub center: [f64; 3],
    /// The radius of the circle through the centres of the edge's cross-section \[m\].
    pub radius: f64,
    /// The radius of the rounded edge (0: sharp) \[m\].
    pub edge: f64,
}

/// A contact sphere of the body, as drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct SphereShape {
    /// Its name (the per-surface columns and the modes name it).
    pub name: String,
    /// Its centre in body axes, from the ellipsoid's centre C0 \[m\].
    pub center: [f64; 3],
    /// Its radius \[m\].
    pub radius: f64,
}

/// The name of the ellipsoid among a body's surfaces (the per-surface columns' suffix).
pub const ELLIPSOID: &str = "ellipsoid";

impl Shape {
    /// The drawing of `body`: its ellipsoid, contact spheres and rims.
    pub fn of(body: &ellipsoid_core::body::Body) -> Shape {
        let (a, g) = (body.semi_axes(), body.com_offset());
        let triple = |v: &Vector3<f64>| [v.x, v.y, v.z];
        Shape {
            semi_axes: triple(&a),
            com_offset: triple(&g),
            spheres: (body.spheres().iter())
                .map(|s| SphereShape {
                    name: s.name.clone(),
                    center: triple(&s.center),
                    radius: s.radius,
                })
                .collect(),
            rims: (body.rims().iter())
                .map(|r| RimShape {
                    name: r.name.clone(),
                    center: triple(&r.center),
                    radius: r.radius,
                    edge: r.edge,
                })
                .collect(),
            ellipsoid_contact: body.ellipsoid_contact(),
        }
    }

    /// Whether the body has a surface besides its ellipsoid (its outputs then name each
    /// surface).
    pub fn several(&self) -> bool {
        !(self.spheres.is_empty() && self.rims.is_empty())
    }

    /// The surfaces that touch, in the body's order (`Body::surfaces`): the ellipsoid
    /// unless it does not touch, the spheres, the rims.
    pub fn surface_names(&self) -> Vec<&str> {
        (self.ellipsoid_contact.then_some(ELLIPSOID).into_iter())
            .chain(self.spheres.iter().map(|s| s.name.as_str()))
            .chain(self.rims.iter().map(|r| r.name.as_str()))
            .collect()
    }

    /// The world position of the contact point for G at `g` and z-x-z Euler angles
    /// (θ, φ, ψ): C0 = G − R g_b, C = C0 + R p_c with p_c = −A²ζ/√(ζᵀA²ζ), ζ = Rᵀe3
    /// (docs/physics.md, "Contact geometry").
    pub fn contact_point(&self, g: [f64; 3], theta: f64, phi: f64, psi: f64) -> [f64; 3] {
        let r = euler_rotation(theta, phi, psi);
        let zeta = r.transpose() * Vector3::z();
        let p_c = geometry::support_point(Vector3::from(self.semi_axes), zeta);
        let c = Vector3::from(g) + r * (p_c - Vector3::from(self.com_offset));
        [c.x, c.y, c.z]
    }
}

/// R = Rz(φ) Rx(θ) Rz(ψ), body → world (paper eq. 1), as the core makes it
/// ([`EulerAngles::rotation`]).
pub fn euler_rotation(theta: f64, phi: f64, psi: f64) -> Matrix3<f64> {
    EulerAngles {
        theta,
        phi,
        psi,
        ..EulerAngles::default()
    }
    .rotation()
    .to_rotation_matrix()
    .into_inner()
}

/// A trajectory as columns.
#[derive(Debug, Clone, Default)]
pub struct Table {
    /// Where it came from (a file name, or the scenario's name for a run in memory).
    pub source: String,
    /// Numeric columns in file order: name and values.
    pub columns: Vec<(String, Vec<f64>)>,
    /// The `mode` column as indices into `mode_names`, if the file has one.
    pub modes: Option<Vec<u8>>,
    /// Names of the contact modes met, in order of first appearance.
    pub mode_names: Vec<String>,
    /// Located events, in time order.
    pub events: Vec<Event>,
    /// The body, when the scenario could be found.
    pub shape: Option<Shape>,
    /// Where the shape came from, or why there is none (one sentence).
    pub shape_note: String,
    /// Status of the run, if known (`completed`, `lost_contact`, …).
    pub status: Option<String>,
    /// The file name (no directories) of the scenario the run's summary names, if known.
    pub scenario: Option<String>,
}

impl Table {
    /// The column `name`, if present.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|c| c.0 == name)
            .map(|c| c.1.as_slice())
    }

    /// The columns `names`, or an error naming the first one missing and what needs it.
    pub fn require(&self, names: &[&str], needed_by: &str) -> Result<Vec<&[f64]>, String> {
        names
            .iter()
            .map(|n| {
                self.column(n).ok_or_else(|| {
                    format!(
                        "{needed_by} needs the column `{n}`, which {} does not have",
                        self.source
                    )
                })
            })
            .collect()
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.column("t").map_or(0, <[f64]>::len)
    }

    /// Time column (every table has one).
    pub fn t(&self) -> &[f64] {
        self.column("t").unwrap_or(&[])
    }

    /// The mode name of row `i`.
    pub fn mode(&self, i: usize) -> Option<&str> {
        self.modes
            .as_ref()
            .and_then(|m| m.get(i))
            .and_then(|&k| self.mode_names.get(k as usize))
            .map(String::as_str)
    }

    /// The columns of `quantity` (one of [`SURFACE_COLUMNS`], e.g. `normal_force`) per
    /// surface, as (surface, values) in file order: `normal_force_ellipsoid`,
    /// `normal_force_stem`, … (none for a one-surface body's file).
    pub fn per_surface(&self, quantity: &str) -> Vec<(&str, &[f64])> {
        self.columns
            .iter()
            .filter_map(|(name, v)| {
                let (q, surface) = surface_column(name)?;
                (q == quantity).then_some((surface, v.as_slice()))
            })
            .collect()
    }

    /// The surfaces that have per-surface columns, in file order, each once (`ellipsoid`,
    /// then the contact spheres; none for a one-surface body's file).
    pub fn surfaces(&self) -> Vec<&str> {
        let mut out: Vec<&str> = Vec::new();
        for (_, s) in self.columns.iter().filter_map(|c| surface_column(&c.0)) {
            if !out.contains(&s) {
                out.push(s);
            }
        }
        out
    }

    /// The surfaces of the body in contact at row `i`, as bits over `surfaces` (bit k for
    /// `surfaces[k]`): those the row's mode names after `@` (`sliding@stem`,
    /// `two_contacts@ellipsoid+stem`); for a row whose mode names none (`flight`, or a
    /// file without a mode column), those whose `gap_S` column is 0.
    pub fn in_contact(&self, i: usize, surfaces: &[&str]) -> u32 {
        let bits = |touching: &dyn Fn(&str) -> bool| {
            surfaces
                .iter()
                .enumerate()
                .filter(|(_, s)| touching(s))
                .fold(0u32, |m, (k, _)| m | 1 << k)
        };
        if let Some((_, list)) = self.mode(i).and_then(|m| m.split_once('@')) {
            return bits(&|s| list.split('+').any(|n| n == s));
        }
        bits(&|s| {
            self.column(&format!("gap_{s}"))
                .and_then(|g| g.get(i))
                .is_some_and(|g| *g == 0.0)
        })
    }

    /// The contact point's horizontal path: the `contact_x`, `contact_y` columns when the
    /// file has them, else computed from G, the Euler angles and the shape of a body that
    /// touches with its ellipsoid alone; `None` if neither is possible.
    pub fn contact_path(&self) -> Option<(Vec<f64>, Vec<f64>)> {
        if let (Some(x), Some(y)) = (self.column("contact_x"), self.column("contact_y")) {
            return Some((x.to_vec(), y.to_vec()));
        }
        // Computed, it is the ellipsoid's lowest point: of a body that touches with
        // other surfaces only the written columns say where it touches.
        let shape = self.shape.as_ref().filter(|s| !s.several())?;
        let cols = self
            .require(&["x", "y", "z", "theta", "phi", "psi"], "the contact path")
            .ok()?;
        let n = self.rows();
        let (mut cx, mut cy) = (Vec::with_capacity(n), Vec::with_capacity(n));
        #[allow(clippy::needless_range_loop)] // row i of six columns at once
        for i in 0..n {
            let c = shape.contact_point(
                [cols[0][i], cols[1][i], cols[2][i]],
                cols[3][i],
                cols[4][i],
                cols[5][i],
            );
            cx.push(c[0]);
            cy.push(c[1]);
        }
        Some((cx, cy))
    }

    /// The path of the geometric centre C0 = G − R g_b on the plane (paper Figs. 15–24);
    /// `None` without the shape, or when C0 is G (no centre-of-mass offset).
    pub fn centre_path(&self) -> Option<(Vec<f64>, Vec<f64>)> {
        let shape = self
            .shape
            .as_ref()
            .filter(|s| s.com_offset.iter().any(|v| *v != 0.0))?;
        let cols = self
            .require(&["x", "y", "theta", "phi", "psi"], "the centre path")
            .ok()?;
        let g = Vector3::from(shape.com_offset);
        let n = self.rows();
        let (mut cx, mut cy) = (Vec::with_capacity(n), Vec::with_capacity(n));
        #[allow(clippy::needless_range_loop)] // row i of five columns at once
        for i in 0..n {
            let c = euler_rotation(cols[2][i], cols[3][i], cols[4][i]) * g;
            cx.push(cols[0][i] - c.x);
            cy.push(cols[1][i] - c.y);
        }
        Some((cx, cy))
    }

    /// The relative drift of the scene's conserved quantity per row, and its name: the
    /// `drift` column when present; else (E + W − E0 − W0)/|E0 + W0| (E alone when no
    /// work is dissipated). `None` without an energy column.
    pub fn drift(&self) -> Option<(Vec<f64>, &'static str)> {
        let w = self.column("work").filter(|w| w.iter().any(|v| *v != 0.0));
        if let Some(d) = self.column("drift") {
            // The run's own: E where energy is conserved, else E + W.
            return Some((d.to_vec(), if w.is_some() { "E + W" } else { "E" }));
        }
        let e = self.column("energy")?;
        let total: Vec<f64> = match w {
            Some(w) => e.iter().zip(w).map(|(e, w)| e + w).collect(),
            None => e.to_vec(),
        };
        let e0 = *total.first()?;
        let scale = if e0 != 0.0 {
            e0.abs()
        } else {
            total
                .iter()
                .fold(0.0f64, |m, v| m.max(v.abs()))
                .max(f64::MIN_POSITIVE)
        };
        Some((
            total.iter().map(|v| (v - e0) / scale).collect(),
            if w.is_some() { "E + W" } else { "E" },
        ))
    }

    /// Builds a table from rows of `names` (numeric columns) and modes, e.g. a run held in
    /// memory. `values(i)` gives row i.
    pub fn from_rows(
        source: &str,
        names: &[&str],
        rows: usize,
        mut values: impl FnMut(usize) -> (Vec<f64>, String),
    ) -> Table {
        let mut columns: Vec<(String, Vec<f64>)> = names
            .iter()
            .map(|n| ((*n).to_owned(), Vec::with_capacity(rows)))
            .collect();
        let mut modes = Vec::with_capacity(rows);
        let mut mode_names = Vec::new();
        for i in 0..rows {
            let (v, mode) = values(i);
            for (col, x) in columns.iter_mut().zip(v) {
                col.1.push(x);
            }
            modes.push(mode_index(&mut mode_names, &mode));
        }
        Table {
            source: source.to_owned(),
            columns,
            modes: Some(modes),
            mode_names,
            ..Default::default()
        }
    }

    /// Sets the events, status and shape from a run summary (the JSON of `--summary`).
    /// The shape comes from `scenario_text` if given, else from the scenario file the
    /// summary names (with its overrides), if it can be read. A summary may come from
    /// someone else: what it makes the table carry (and so a page or figure) names that
    /// file by its name alone, never its directories, and never quotes the file.
    pub fn apply_summary(&mut self, summary: &Value, scenario_text: Option<&str>) {
        self.apply_events(summary);
        let source = summary.get("scenario").and_then(Value::as_str);
        self.scenario = source
            .and_then(|s| Path::new(s).file_name())
            .map(|n| n.to_string_lossy().into_owned());
        let name = self
            .scenario
            .clone()
            .unwrap_or_else(|| "the scenario".into());
        let overrides: Vec<String> = summary
            .get("overrides")
            .and_then(Value::as_array)
            .map(|a| {
                a.iter()
                    .filter_map(|v| v.as_str().map(str::to_owned))
                    .collect()
            })
            .unwrap_or_default();
        let parsed = match (scenario_text, source) {
            (Some(text), _) => scenario::parse(text, &name, &overrides),
            (None, Some(path)) => scenario::load(Path::new(path), &overrides),
            (None, None) => return,
        };
        match parsed {
            Ok(s) => self.set_body(&s.scene.body, &name),
            Err(_) if self.shape.is_none() => {
                self.shape_note = format!(
                    "body unknown: the scenario {name} that the summary names could not be read as a scenario (`ellipsoid check` says why)"
                )
            }
            Err(_) => {} // the CSV's comment line gave the body
        }
    }

    /// Sets the scenario's name and the body's shape, with its contact spheres, from the
    /// JSON of a CSV file's comment line (`ellipsoid_io::csv::comment`); a comment that does
    /// not parse changes nothing (a summary can still give them). A comment that gives a
    /// body and a `spheres` or `rims` list that is not one a body may have (see [`comment_body`])
    /// is an error, the rule it breaks.
    pub fn apply_comment(&mut self, json: &str) -> Result<(), String> {
        let Ok(v) = serde_json::from_str::<Value>(json) else {
            return Ok(());
        };
        let triple = |key: &str| -> Option<[f64; 3]> {
            let a = v.get(key)?.as_array()?;
            let x: Vec<f64> = a.iter().filter_map(Value::as_f64).collect();
            <[f64; 3]>::try_from(x)
                .ok()
                .filter(|x| x.iter().all(|c| c.is_finite()))
        };
        let name = v
            .get("scenario")
            .and_then(Value::as_str)
            .and_then(|s| Path::new(s).file_name())
            .map(|n| n.to_string_lossy().into_owned());
        if let (Some(semi_axes), Some(com_offset)) = (triple("semi_axes"), triple("com_offset"))
            && semi_axes.iter().all(|a| *a > 0.0)
        {
            self.shape = Some(comment_body(&v, semi_axes, com_offset)?);
            self.shape_note = format!(
                "body from the file's comment line ({})",
                name.as_deref().unwrap_or("its scenario")
            );
        }
        if name.is_some() {
            self.scenario = name;
        }
        Ok(())
    }

    /// Sets the events and status from a run summary, nothing else.
    pub fn apply_events(&mut self, summary: &Value) {
        if let Some(events) = summary.get("events").and_then(Value::as_array) {
            self.events = events.iter().filter_map(event).collect();
            self.events.sort_by(|a, b| a.t.total_cmp(&b.t));
        }
        self.status = summary
            .get("status")
            .and_then(Value::as_str)
            .map(str::to_owned);
    }

    /// Sets the shape from the body of the scenario `source`, which the note names by its
    /// file name alone (a page carries no directories of the machine that made it).
    pub fn set_body(&mut self, body: &ellipsoid_core::body::Body, source: &str) {
        self.shape = Some(Shape::of(body));
        let name = Path::new(source)
            .file_name()
            .map_or_else(|| source.into(), |n| n.to_string_lossy());
        self.shape_note = format!("body from {name}");
    }
}

/// One entry of a comment line's `spheres` or `rims`: its name, centre and the numbers
/// asked for, in their order.
struct Entry {
    name: String,
    center: Vector3<f64>,
    numbers: Vec<f64>,
}

/// The entries of the comment line's list `key` (`spheres` or `rims`): each
/// `{"name": …, "center": [x, y, z], n: …}` for the numbers `numbers` names, at most
/// `max` of them. The error names the entry and the rule.
fn comment_entries(
    list: &Value,
    key: &str,
    max: usize,
    numbers: &[&str],
) -> Result<Vec<Entry>, String> {
    let entries = list
        .as_array()
        .ok_or_else(|| format!("the comment line's `{key}` is not a list"))?;
    if entries.len() > max {
        return Err(format!(
            "the comment line's `{key}` has {} entries; a body has at most {max}",
            entries.len()
        ));
    }
    let quoted: Vec<String> = ["name", "center"]
        .iter()
        .chain(numbers)
        .map(|n| format!("\"{n}\""))
        .collect();
    let typed: Vec<String> = numbers
        .iter()
        .map(|n| format!(", \"{n}\": a number"))
        .collect();
    let mut out = Vec::with_capacity(entries.len());
    for (k, e) in entries.iter().enumerate() {
        let bad = |rule: &str| format!("the comment line's {key}[{k}]: {rule}");
        let fields = e
            .as_object()
            .filter(|o| o.len() == 2 + numbers.len())
            .ok_or_else(|| bad(&format!("expected {{{}}}", quoted.join(", "))))?;
        let name = fields.get("name").and_then(Value::as_str);
        let center: Option<Vec<f64>> = fields
            .get("center")
            .and_then(Value::as_array)
            .and_then(|c| c.iter().map(Value::as_f64).collect());
        let values: Option<Vec<f64>> = numbers
            .iter()
            .map(|n| fields.get(*n).and_then(Value::as_f64))
            .collect();
        let (Some(name), Some(center), Some(values)) = (name, center, values) else {
            return Err(bad(&format!(
                "expected {{\"name\": text, \"center\": [x, y, z]{}}}",
                typed.concat()
            )));
        };
        let center = <[f64; 3]>::try_from(center)
            .map_err(|c| bad(&format!("center has {} coordinates, not 3", c.len())))?;
        out.push(Entry {
            name: name.to_owned(),
            center: Vector3::from(center),
            numbers: values,
        });
    }
    Ok(out)
}

/// The body of a CSV comment line `v` with `semi_axes` and `com_offset`: its `spheres`
/// (`[{"name": …, "center": [x, y, z], "radius": …}]`), `rims` (the same with `edge`) and
/// `ellipsoid_contact` (true unless given false), each optional, with values a body may
/// have (`Body::with_spheres`, `with_rims`, `without_ellipsoid_contact`: names unique
/// words of at most `body::MAX_NAME` bytes, centres finite, radii positive lengths, rims
/// on the axis, at most `MAX_SPHERES` spheres and `MAX_RIMS` rims). The error names the
/// entry, its value and the rule.
pub fn comment_body(v: &Value, semi_axes: [f64; 3], com_offset: [f64; 3]) -> Result<Shape, String> {
    use ellipsoid_core::body::{Body, MAX_RIMS, MAX_SPHERES, Rim, Sphere, uniform_inertia};
    let list = |key: &str, max: usize, numbers: &[&str]| match v.get(key) {
        Some(list) => comment_entries(list, key, max, numbers),
        None => Ok(Vec::new()),
    };
    let spheres = list("spheres", MAX_SPHERES, &["radius"])?
        .into_iter()
        .map(|e| Sphere {
            name: e.name,
            center: e.center,
            radius: e.numbers[0],
        })
        .collect();
    let rims = list("rims", MAX_RIMS, &["radius", "edge"])?
        .into_iter()
        .map(|e| Rim {
            name: e.name,
            center: e.center,
            radius: e.numbers[0],
            edge: e.numbers[1],
        })
        .collect();
    let touches = match v.get("ellipsoid_contact") {
        None => true,
        Some(b) => b
            .as_bool()
            .ok_or("the comment line's `ellipsoid_contact` is not true or false")?,
    };
    let a = Vector3::from(semi_axes);
    Body::new(a, 1.0, uniform_inertia(a, 1.0), Vector3::from(com_offset))
        .and_then(|b| b.with_spheres(spheres))
        .and_then(|b| b.with_rims(rims))
        .and_then(|b| {
            if touches {
                Ok(b)
            } else {
                b.without_ellipsoid_contact()
            }
        })
        .map(|b| Shape::of(&b))
        .map_err(|e| format!("the comment line's body: {e}"))
}

fn mode_index(names: &mut Vec<String>, mode: &str) -> u8 {
    match names.iter().position(|n| n == mode) {
        Some(k) => k as u8,
        None => {
            names.push(mode.to_owned());
            (names.len() - 1).min(255) as u8
        }
    }
}

/// An event of a summary's `events` list: `{kind, t, …}` (mode switches carry `from`,
/// `to`; observables `name`).
fn event(v: &Value) -> Option<Event> {
    let t = v.get("t")?.as_f64().filter(|t| t.is_finite())?;
    let kind = v
        .get("kind")
        .and_then(Value::as_str)
        .unwrap_or("event")
        .to_owned();
    let text = |k: &str| v.get(k).and_then(Value::as_str);
    let label = match (text("name"), text("from"), text("to")) {
        (Some(name), _, _) => name.to_owned(),
        (None, Some(from), Some(to)) => format!("{from} → {to}"),
        _ => kind.replace('_', " "),
    };
    Some(Event { t, kind, label })
}

/// Reads a JSON summary (`ellipsoid run --summary FILE.json`).
pub fn read_summary(path: &Path) -> Result<Value, ReadError> {
    let text = scenario::read_bounded(path, MAX_SUMMARY_BYTES)
        .map_err(|e| ReadError::format(path, None, e))?;
    let text = String::from_utf8(text)
        .map_err(|_| ReadError::format(path, None, "the summary is not UTF-8 text"))?;
    let v: Value = serde_json::from_str(&text).map_err(|e| {
        ReadError::format(
            path,
            Some(e.line() as u64),
            format!("not a JSON summary: {e}"),
        )
    })?;
    if !v.is_object() || v.get("events").is_none() {
        return Err(ReadError::format(
            path,
            None,
            "not a run summary (no `events` field); write one with `ellipsoid run --summary FILE.json`",
        ));
    }
    Ok(v)
}

/// Refuses a CSV file of more than [`MAX_ROWS`] rows before any is parsed: a scan of its
/// bytes (at memory speed; parsing 10⁷ rows takes tens of seconds) counts the line
/// breaks, and where they pass the bound, counts the rows as the reader does (a line
/// neither blank nor a comment, after the header) to name the first row beyond it. A
/// file of `len` bytes too short to hold that many rows is not scanned.
fn refuse_too_many_rows(path: &Path, len: u64) -> Result<(), ReadError> {
    // A row is at least one character and a line break.
    if len < 2 * (MAX_ROWS as u64 + 1) {
        return Ok(());
    }
    // Blank and comment lines aside, the header and MAX_ROWS rows are MAX_ROWS + 1 lines.
    let (mut breaks, mut last) = (0usize, b'\n');
    scan(path, |b| {
        breaks += b.iter().filter(|&&c| c == b'\n').count();
        last = b[b.len() - 1];
        true
    })?;
    if breaks + usize::from(last != b'\n') <= MAX_ROWS + 1 {
        return Ok(());
    }
    // Each line's first character other than a carriage return, if any.
    let (mut line, mut lines, mut first) = (1u64, 0usize, None::<u8>);
    let counts = |first: Option<u8>| first.is_some_and(|c| c != b'#');
    let mut beyond = None;
    scan(path, |b| {
        for &c in b {
            match c {
                b'\n' => {
                    if counts(first) {
                        lines += 1;
                        if lines > MAX_ROWS + 1 {
                            beyond = Some(line);
                            return false;
                        }
                    }
                    (line, first) = (line + 1, None);
                }
                b'\r' => {}
                c => first = first.or(Some(c)),
            }
        }
        true
    })?;
    if beyond.is_none() && counts(first) && lines + 1 > MAX_ROWS + 1 {
        beyond = Some(line);
    }
    match beyond {
        Some(line) => Err(ReadError::format(
            path,
            Some(line),
            format!(
                "more than {MAX_ROWS} rows, the most a run writes (counted before reading any; this line is the first beyond)"
            ),
        )),
        None => Ok(()),
    }
}

/// Reads the file at `path` in chunks of 1 MiB (at most [`MAX_FILE_BYTES`]), handing each
/// to `each` until it returns false.
fn scan(path: &Path, mut each: impl FnMut(&[u8]) -> bool) -> Result<(), ReadError> {
    let (file, _) = open_bounded(path, MAX_FILE_BYTES)?;
    let mut file = file.take(MAX_FILE_BYTES);
    let mut buf = vec![0u8; 1 << 20];
    loop {
        let n = file.read(&mut buf).map_err(|e| ReadError::Io {
            path: path.to_owned(),
            source: e,
        })?;
        if n == 0 || !each(&buf[..n]) {
            return Ok(());
        }
    }
}

/// Opens `path`, which must be a regular file of at most `limit` bytes (by its size; the
/// readers also stop after `limit` bytes read).
fn open_bounded(path: &Path, limit: u64) -> Result<(std::fs::File, u64), ReadError> {
    let file = scenario::open_regular(path).map_err(|e| ReadError::format(path, None, e))?;
    let len = file.metadata().map_or(0, |m| m.len());
    if len > limit {
        return Err(ReadError::format(
            path,
            None,
            format!("{len} bytes is more than the {limit} read at most"),
        ));
    }
    Ok((file, len))
}

/// Reads a trajectory file by extension: `.csv`, or `.h5`/`.hdf5` (feature `hdf5`; the
/// events and the body then come from the summary and scenario stored in the file).
pub fn read(path: &Path) -> Result<Table, ReadError> {
    read_columns(path, None)
}

/// [`read`], keeping only the columns named in `keep` (and `t` and `mode`) when it is
/// given: a caller that draws a few columns holds those alone (a 10⁷-row file of 27
/// columns is 2.2 GB of f64 in memory, a dozen of them 1 GB). The others are not parsed.
/// A name `QUANTITY_*` keeps that quantity's column of every surface
/// (`normal_force_*`: `normal_force_ellipsoid`, `normal_force_stem`, …).
pub fn read_columns(path: &Path, keep: Option<&[&str]>) -> Result<Table, ReadError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "csv" => read_csv(path, keep),
        "h5" | "hdf5" => read_hdf5(path, keep),
        _ => Err(ReadError::format(
            path,
            None,
            format!(
                "unknown trajectory format {ext:?}; give a .csv or .h5 file written by `ellipsoid run`"
            ),
        )),
    }
}

/// Reads a CSV trajectory: a header of column names (`t` required), one row per sample,
/// `mode` as a name, every other value a finite number.
pub fn read_csv(path: &Path, keep: Option<&[&str]>) -> Result<Table, ReadError> {
    let (file, len) = open_bounded(path, MAX_FILE_BYTES)?;
    refuse_too_many_rows(path, len)?;
    let mut reader = BufReader::with_capacity(1 << 16, file.take(MAX_FILE_BYTES));
    let mut line = String::new();
    // Comment lines before the header: ours names the scenario and its body.
    let (mut lineno, mut comment) = (0u64, None::<(u64, String)>);
    loop {
        line.clear();
        let n = reader
            .read_line(&mut line)
            .map_err(|e| bad_text(path, lineno + 1, e))?;
        if n == 0 {
            return Err(ReadError::format(
                path,
                None,
                "the file is empty; expected a header line such as `t,x,y,z,theta,…`",
            ));
        }
        lineno += 1;
        if !line.starts_with('#') {
            break;
        }
        if let Some(json) = line.strip_prefix(crate::csv::COMMENT) {
            comment = Some((lineno, json.trim().to_owned()));
        }
    }
    let header_line = lineno;
    let header: Vec<String> = line
        .trim_end_matches(['\n', '\r'])
        .split(',')
        .map(|s| s.trim().to_owned())
        .collect();
    let mut seen = BTreeMap::new();
    for (k, name) in header.iter().enumerate() {
        if name.is_empty() {
            return Err(ReadError::format(
                path,
                Some(header_line),
                format!("column {} of the header has no name", k + 1),
            ));
        }
        if seen.insert(name.as_str(), k).is_some() {
            return Err(ReadError::format(
                path,
                Some(header_line),
                format!("the column `{name}` appears twice in the header"),
            ));
        }
    }
    if !seen.contains_key("t") {
        return Err(ReadError::format(
            path,
            Some(header_line),
            format!(
                "the header has no `t` column (got `{}`); is this a trajectory written by `ellipsoid run`?",
                truncate(line.trim(), 80)
            ),
        ));
    }
    let mode_col = seen.get("mode").copied();
    let kept = |name: &str| name == "t" || keeps(keep, name);
    let mut columns: Vec<(String, Vec<f64>)> = header
        .iter()
        .enumerate()
        .filter(|(k, n)| Some(*k) != mode_col && kept(n))
        .map(|(_, n)| (n.clone(), Vec::new()))
        .collect();
    let t_index = columns
        .iter()
        .position(|c| c.0 == "t")
        .expect("checked above");
    let mut modes = mode_col.map(|_| Vec::new());
    let mut mode_names = Vec::new();
    let mut last_t = f64::NEG_INFINITY;
    loop {
        line.clear();
        let n = reader
            .read_line(&mut line)
            .map_err(|e| bad_text(path, lineno + 1, e))?;
        if n == 0 {
            break;
        }
        lineno += 1;
        let text = line.trim_end_matches(['\n', '\r']);
        if text.is_empty() {
            continue;
        }
        if columns[0].1.len() >= MAX_ROWS {
            return Err(ReadError::format(
                path,
                Some(lineno),
                format!(
                    "more than {MAX_ROWS} rows, the most a run writes; reading stopped at this row"
                ),
            ));
        }
        let mut fields = text.split(',');
        let mut numeric = 0;
        for (k, name) in header.iter().enumerate() {
            let Some(field) = fields.next() else {
                return Err(ReadError::format(
                    path,
                    Some(lineno),
                    format!(
                        "{} fields where the header has {} (the column `{name}` is missing)",
                        k,
                        header.len()
                    ),
                ));
            };
            if Some(k) == mode_col {
                let m = modes.as_mut().expect("mode column");
                m.push(mode_index(&mut mode_names, field.trim()));
                continue;
            }
            if !kept(name) {
                continue;
            }
            let v: f64 = field.trim().parse().map_err(|_| {
                ReadError::format(
                    path,
                    Some(lineno),
                    format!("column `{name}`: {:?} is not a number", truncate(field, 40)),
                )
            })?;
            if !v.is_finite() {
                return Err(ReadError::format(
                    path,
                    Some(lineno),
                    format!("column `{name}` = {v}: values must be finite"),
                ));
            }
            columns[numeric].1.push(v);
            numeric += 1;
        }
        if fields.next().is_some() {
            return Err(ReadError::format(
                path,
                Some(lineno),
                format!(
                    "more fields than the {} columns of the header",
                    header.len()
                ),
            ));
        }
        let t = *columns[t_index].1.last().expect("just pushed");
        if t < last_t {
            return Err(ReadError::format(
                path,
                Some(lineno),
                format!("t = {t} s comes after t = {last_t} s: times must not decrease"),
            ));
        }
        last_t = t;
    }
    if columns[0].1.is_empty() {
        return Err(ReadError::format(path, None, "no rows after the header"));
    }
    // The growth's slack (up to half of each column) back to the allocator.
    for c in &mut columns {
        c.1.shrink_to_fit();
    }
    let mut table = Table {
        source: path.display().to_string(),
        columns,
        modes,
        mode_names,
        shape_note: "body unknown: pass the run's --summary FILE.json (or an .h5 file) to draw the body and its contact point".to_owned(),
        ..Default::default()
    };
    if let Some((line, json)) = comment {
        table
            .apply_comment(&json)
            .map_err(|rule| ReadError::format(path, Some(line), rule))?;
    }
    Ok(table)
}

/// Whether the column `name` is among those `keep` names (all when `None`; see
/// [`read_columns`] for `QUANTITY_*`).
pub fn keeps(keep: Option<&[&str]>, name: &str) -> bool {
    keep.is_none_or(|k| {
        k.iter().any(|&p| match p.strip_suffix("_*") {
            Some(quantity) => surface_column(name).is_some_and(|(q, _)| q == quantity),
            None => p == name,
        })
    })
}

/// A per-surface column's name split into its quantity (one of [`SURFACE_COLUMNS`]) and
/// its surface (a word: `ellipsoid`, or a contact sphere's name): `contact_x_stem` →
/// (`contact_x`, `stem`); `None` for any other name.
pub fn surface_column(name: &str) -> Option<(&'static str, &str)> {
    SURFACE_COLUMNS.iter().find_map(|&(q, _)| {
        let surface = name.strip_prefix(q)?.strip_prefix('_')?;
        let word = |c: char| c.is_ascii_alphanumeric() || c == '_';
        (!surface.is_empty() && surface.len() <= MAX_NAME && surface.chars().all(word))
            .then_some((q, surface))
    })
}

/// The unit of the output column `name`: a fixed column's, or a per-surface column's
/// (`normal_force_stem`: N); `None` for any other name.
pub fn unit(name: &str) -> Option<&'static str> {
    NUMERIC_COLUMNS
        .iter()
        .find(|c| c.0 == name)
        .map(|c| c.1)
        .or_else(|| {
            let (q, _) = surface_column(name)?;
            SURFACE_COLUMNS.iter().find(|c| c.0 == q).map(|c| c.1)
        })
}

fn bad_text(path: &Path, line: u64, e: std::io::Error) -> ReadError {
    if e.kind() == std::io::ErrorKind::InvalidData {
        ReadError::format(path, Some(line), "not UTF-8 text (is this a CSV file?)")
    } else {
        ReadError::Io {
            path: path.to_owned(),
            source: e,
        }
    }
}

fn truncate(s: &str, n: usize) -> String {
    if s.chars().count() <= n {
        s.to_owned()
    } else {
        format!("{}…", s.chars().take(n).collect::<String>())
    }
}

#[cfg(not(feature = "hdf5"))]
fn read_hdf5(path: &Path, _keep: Option<&[&str]>) -> Result<Table, ReadError> {
    Err(ReadError::Hdf5Unavailable {
        path: path.to_owned(),
    })
}

/// Reads an HDF5 trajectory written by `ellipsoid run -o FILE.h5`: the datasets listed in
/// the root attribute `columns`, the events and status from the stored summary, the body
/// from the stored scenario.
#[cfg(feature = "hdf5")]
fn read_hdf5(path: &Path, keep: Option<&[&str]>) -> Result<Table, ReadError> {
    use h5::types::{FixedAscii, VarLenUnicode};
    use hdf5_metno as h5;
    let meta = std::fs::metadata(path).map_err(|e| ReadError::Io {
        path: path.to_owned(),
        source: e,
    })?;
    if !meta.is_file() {
        return Err(ReadError::format(path, None, "not a regular file"));
    }
    let fail = |e: h5::Error| ReadError::format(path, None, format!("HDF5: {e}"));
    let file = crate::hdf5::open(path).map_err(|e| {
        ReadError::format(
            path,
            None,
            format!("not an HDF5 file written by `ellipsoid run` ({e})"),
        )
    })?;
    let attr = |name: &str| -> Option<String> {
        file.attr(name)
            .ok()?
            .read_scalar::<VarLenUnicode>()
            .ok()
            .map(|v| v.as_str().to_owned())
    };
    let names = attr("columns").ok_or_else(|| {
        ReadError::format(
            path,
            None,
            "no `columns` attribute: not a trajectory written by `ellipsoid run`",
        )
    })?;
    let mut columns = Vec::new();
    let mut modes = None;
    let mut mode_names = Vec::new();
    let kept = |name: &str| name == "t" || name == crate::columns::MODE || keeps(keep, name);
    for name in names
        .split(',')
        .map(str::trim)
        .filter(|n| !n.is_empty() && kept(n))
    {
        let ds = file.dataset(name).map_err(|e| {
            ReadError::format(
                path,
                None,
                format!("the column `{name}` listed in `columns` has no dataset ({e})"),
            )
        })?;
        if ds.size() > MAX_ROWS {
            return Err(ReadError::format(
                path,
                None,
                format!(
                    "the column `{name}` has {} rows, more than {MAX_ROWS}, the most a run writes (refused before reading it)",
                    ds.size()
                ),
            ));
        }
        crate::hdf5::check_filters(&ds, name).map_err(|e| ReadError::format(path, None, e))?;
        if name == crate::columns::MODE {
            let raw = ds
                .read_raw::<FixedAscii<{ crate::hdf5::LABEL_LEN }>>()
                .map_err(fail)?;
            modes = Some(
                raw.iter()
                    .map(|m| mode_index(&mut mode_names, m.as_str()))
                    .collect::<Vec<_>>(),
            );
            continue;
        }
        let data = ds.read_raw::<f64>().map_err(|e| {
            ReadError::format(
                path,
                None,
                format!("the column `{name}` is not float64 ({e})"),
            )
        })?;
        if let Some((i, v)) = data.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(ReadError::format(
                path,
                None,
                format!("column `{name}`, row {}: {v}: values must be finite", i + 1),
            ));
        }
        columns.push((name.to_owned(), data));
    }
    let Some(t) = columns.iter().find(|c| c.0 == "t") else {
        return Err(ReadError::format(path, None, "no `t` column"));
    };
    if t.1.is_empty() {
        return Err(ReadError::format(path, None, "no rows"));
    }
    if let Some(w) = t.1.windows(2).position(|w| w[1] < w[0]) {
        return Err(ReadError::format(
            path,
            None,
            format!("t decreases at row {}: times must not decrease", w + 2),
        ));
    }
    let n = t.1.len();
    if let Some(c) = columns.iter().find(|c| c.1.len() != n) {
        return Err(ReadError::format(
            path,
            None,
            format!(
                "the column `{}` has {} rows where `t` has {n}",
                c.0,
                c.1.len()
            ),
        ));
    }
    if modes.as_ref().is_some_and(|m| m.len() != n) {
        return Err(ReadError::format(
            path,
            None,
            format!("the `mode` column has a different length from `t` ({n})"),
        ));
    }
    let mut table = Table {
        source: path.display().to_string(),
        columns,
        modes,
        mode_names,
        shape_note: "body unknown: the file stores no scenario".to_owned(),
        ..Default::default()
    };
    if let Some(summary) = attr("summary").and_then(|s| serde_json::from_str::<Value>(&s).ok()) {
        table.apply_summary(&summary, attr("scenario").as_deref());
    }
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    /// A CSV of `MAX_ROWS` rows is read; one of `MAX_ROWS` + 1 rows is refused at that
    /// row, naming the limit and the line, without reading further: the line after it is
    /// not a number, and is never reached.
    #[test]
    fn csv_past_the_row_limit_is_refused_at_the_row_after_it() {
        use std::io::Write;
        let dir = tempfile::tempdir().unwrap();
        let make = |name: &str, rows: usize, tail: &str| {
            let p = dir.path().join(name);
            let mut w = std::io::BufWriter::new(std::fs::File::create(&p).unwrap());
            w.write_all(b"t\n").unwrap();
            for _ in 0..rows {
                w.write_all(b"0\n").unwrap();
            }
            w.write_all(tail.as_bytes()).unwrap();
            w.flush().unwrap();
            p
        };
        let full = read_csv(&make("full.csv", MAX_ROWS, ""), None).unwrap();
        assert_eq!(full.rows(), MAX_ROWS);
        drop(full);
        let over = make("over.csv", MAX_ROWS + 1, "not a number\n");
        let ReadError::Format {
            line: Some(line),
            message,
            ..
        } = read_csv(&over, None).unwrap_err()
        else {
            panic!("not a format error")
        };
        // the header is line 1, row k is line k + 1
        assert_eq!(line, MAX_ROWS as u64 + 2);
        assert!(message.contains("more than 10000000 rows"), "{message}");
    }

    /// An HDF5 column of `MAX_ROWS` + 1 rows is refused from its shape before any value is
    /// read: its storage is never written (the file is a few kB) and its fill value is
    /// NaN, which a read would report as a non-finite value instead.
    #[cfg(feature = "hdf5")]
    #[test]
    fn hdf5_past_the_row_limit_is_refused_from_the_shape() {
        use hdf5_metno as h5;
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("over.h5");
        {
            let f = h5::File::create(&p).unwrap();
            let names: h5::types::VarLenUnicode = "t,x".parse().unwrap();
            f.new_attr::<h5::types::VarLenUnicode>()
                .create("columns")
                .unwrap()
                .write_scalar(&names)
                .unwrap();
            for name in ["t", "x"] {
                f.new_dataset::<f64>()
                    .shape(MAX_ROWS + 1)
                    .fill_value(f64::NAN)
                    .create(name)
                    .unwrap();
            }
        }
        assert!(std::fs::metadata(&p).unwrap().len() < 100_000);
        let err = read(&p).unwrap_err().to_string();
        assert!(
            err.contains("the column `t` has 10000001 rows, more than 10000000")
                && err.contains("before reading"),
            "{err}"
        );
    }

    #[test]
    fn csv_reads_any_columns_by_name_and_modes_by_index() {
        let dir = tempfile::tempdir().unwrap();
        let p = write(
            dir.path(),
            "a.csv",
            "t,theta,mode,drift\n0,0.1,sliding,0\n0.5,0.2,rolling,1e-12\n1,0.3,sliding,2e-12\n",
        );
        let t = read(&p).unwrap();
        assert_eq!(t.t(), &[0.0, 0.5, 1.0]);
        assert_eq!(t.column("drift").unwrap(), &[0.0, 1e-12, 2e-12]);
        assert_eq!(
            (t.mode(0), t.mode(1), t.mode(2)),
            (Some("sliding"), Some("rolling"), Some("sliding"))
        );
        assert_eq!(t.drift().unwrap(), (vec![0.0, 1e-12, 2e-12], "E"));
        assert!(
            t.require(&["x"], "the path panel")
                .unwrap_err()
                .contains("`x`")
        );
    }

    /// The comment line `ellipsoid run` writes first gives the body and the scenario's name
    /// without a summary; other comment lines are skipped; lines are counted from the top.
    #[test]
    fn csv_comment_line_gives_the_body_and_is_not_a_row() {
        let dir = tempfile::tempdir().unwrap();
        let comment = r#"# ellipsoid {"scenario":"top.toml","semi_axes":[0.02,0.02,0.03],"com_offset":[0.0,0.0,-0.004]}"#;
        let p = write(
            dir.path(),
            "a.csv",
            &format!("{comment}\n# another comment\nt,x\n0,1\n1,2\n"),
        );
        let t = read(&p).unwrap();
        assert_eq!(t.t(), &[0.0, 1.0]);
        let shape = t.shape.expect("the body from the comment");
        assert_eq!(shape.semi_axes, [0.02, 0.02, 0.03]);
        assert_eq!(shape.com_offset, [0.0, 0.0, -0.004]);
        assert_eq!(t.scenario.as_deref(), Some("top.toml"));
        assert!(t.shape_note.contains("top.toml"), "{}", t.shape_note);
        let bad = write(
            dir.path(),
            "b.csv",
            &format!("{comment}\nt,x\n0,1\n1,abc\n"),
        );
        let err = read(&bad).unwrap_err().to_string();
        assert!(err.contains(":4: column `x`"), "{err}");
        // A comment that is not ours, or not valid, gives nothing.
        for c in [
            "# ellipsoid {\"semi_axes\":[0,1,1],\"com_offset\":[0,0,0]}",
            "# ellipsoid nope",
        ] {
            let p = write(dir.path(), "c.csv", &format!("{c}\nt,x\n0,1\n"));
            assert!(read(&p).unwrap().shape.is_none(), "{c}");
        }
    }

    fn bundled(name: &str) -> ellipsoid_core::scenario::Scenario {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios")
            .join(name);
        scenario::load(&path, &[] as &[String]).unwrap()
    }

    /// The comment line `ellipsoid run` writes carries a body's contact spheres, and they
    /// read back as the scenario gives them; a one-surface body's line is as it always
    /// was (the format its readers know).
    #[test]
    fn csv_comment_carries_the_spheres_and_they_read_back() {
        let dir = tempfile::tempdir().unwrap();
        let one = crate::csv::comment(&bundled("tippe-top.toml"));
        assert_eq!(
            one,
            r#"# ellipsoid {"scenario":"tippe-top.toml","semi_axes":[0.015,0.015,0.015],"com_offset":[0.0,0.0,-0.003]}"#
        );
        let p = write(dir.path(), "one.csv", &format!("{one}\nt,x\n0,1\n"));
        assert!(read(&p).unwrap().shape.unwrap().spheres.is_empty());
        let stem = crate::csv::comment(&bundled("tippe-top-stem.toml"));
        assert!(
            stem.ends_with(
                r#","spheres":[{"name":"stem","center":[0.0,0.0,0.013],"radius":0.005}]}"#
            ),
            "{stem}"
        );
        let p = write(dir.path(), "stem.csv", &format!("{stem}\nt,x\n0,1\n"));
        let shape = read(&p).unwrap().shape.unwrap();
        assert_eq!(
            shape.spheres,
            [SphereShape {
                name: "stem".into(),
                center: [0.0, 0.0, 0.013],
                radius: 0.005
            }]
        );
        assert_eq!(shape.semi_axes, [0.015; 3]);
        // A coin: its rim, and its ellipsoid that does not touch.
        let coin = crate::csv::comment(&bundled("coin.toml"));
        let p = write(dir.path(), "coin.csv", &format!("{coin}\nt,x\n0,1\n"));
        let shape = read(&p).unwrap().shape.unwrap();
        assert_eq!(
            shape.rims,
            [RimShape {
                name: "edge".into(),
                center: [0.0; 3],
                radius: 0.011255,
                edge: 0.000875
            }]
        );
        assert!(!shape.ellipsoid_contact && shape.several());
        assert_eq!(shape.surface_names(), ["edge"]);
        // Hostile rims and flags: the body's own rules, named.
        let body = r#""semi_axes":[0.01,0.01,0.001],"com_offset":[0.0,0.0,0.0]"#;
        for (extra, rule) in [
            (
                r#""rims":[{"name":"edge","center":[0.001,0,0],"radius":0.01,"edge":0}]"#,
                "body.rim[0].center",
            ),
            (
                r#""rims":[{"name":"edge","center":[0,0,0],"radius":0.01}]"#,
                "rims[0]: expected {\"name\", \"center\", \"radius\", \"edge\"}",
            ),
            (r#""ellipsoid_contact":3"#, "is not true or false"),
            (
                r#""ellipsoid_contact":false"#,
                "needs a contact sphere or a rim",
            ),
        ] {
            let text = format!("# ellipsoid {{{body},{extra}}}\nt,x\n0,1\n");
            let p = write(dir.path(), "bad.csv", &text);
            let err = read(&p).unwrap_err().to_string();
            assert!(err.contains(rule), "{extra}: {err}");
        }
    }

    /// A comment line whose spheres are not a body's is refused, naming the line, the
    /// entry and the rule; nothing panics.
    #[test]
    fn a_hostile_spheres_list_is_a_clear_error() {
        let dir = tempfile::tempdir().unwrap();
        let body = r#""semi_axes":[0.015,0.015,0.015],"com_offset":[0.0,0.0,-0.003]"#;
        let sphere = |name: &str, center: &str, radius: &str| {
            format!(r#"{{"name":{name},"center":{center},"radius":{radius}}}"#)
        };
        let ok = sphere("\"stem\"", "[0,0,0.013]", "0.005");
        let nine = vec![ok.clone(); 9].join(",");
        let many: Vec<String> = (0..9)
            .map(|k| sphere(&format!("\"s{k}\""), "[0,0,0.013]", "0.005"))
            .collect();
        let cases = [
            ("{}".to_owned(), "`spheres` is not a list"),
            (
                format!("[{}]", many.join(",")),
                "has 9 entries; a body has at most 8",
            ),
            (format!("[{nine}]"), "at most 8"),
            (format!("[{ok},{ok}]"), "names must be unique"),
            (
                format!("[{}]", sphere("\"ellipsoid\"", "[0,0,0]", "0.005")),
                "not \"ellipsoid\"",
            ),
            (
                format!("[{}]", sphere("\"a b\"", "[0,0,0]", "0.005")),
                "body.sphere[0].name = \"a b\": a sphere's name is 1 to 24",
            ),
            (
                format!("[{}]", sphere("\"stem\"", "[0,0,0]", "-0.005")),
                "body.sphere[0].radius = -0.005",
            ),
            (
                format!("[{}]", sphere("\"stem\"", "[0,0,0]", "1e300")),
                "a sphere's radius must be a length",
            ),
            (
                format!("[{}]", sphere("\"stem\"", "[0,1e300,0]", "0.005")),
                "a sphere's centre must be finite",
            ),
            (
                format!("[{}]", sphere("\"stem\"", "[0,0]", "0.005")),
                "spheres[0]: center has 2 coordinates, not 3",
            ),
            (
                format!("[{}]", sphere("\"stem\"", "[0,0,0]", "\"big\"")),
                "spheres[0]: expected {\"name\": text",
            ),
            (
                r#"[{"name":"stem","center":[0,0,0],"radius":0.005,"colour":1}]"#.to_owned(),
                "spheres[0]: expected {\"name\", \"center\", \"radius\"}",
            ),
            (r#"[17]"#.to_owned(), "spheres[0]: expected"),
        ];
        for (k, (spheres, rule)) in cases.iter().enumerate() {
            let text = format!("# ellipsoid {{{body},\"spheres\":{spheres}}}\nt,x\n0,1\n");
            let p = write(dir.path(), &format!("h{k}.csv"), &text);
            let err = read(&p).unwrap_err().to_string();
            assert!(
                err.starts_with(&format!("{}:1: the comment line's", p.display()))
                    && err.contains(rule),
                "{spheres}: {err}"
            );
        }
    }

    #[test]
    fn per_surface_columns_and_the_surfaces_in_contact() {
        let names = [
            "t",
            "gap",
            "normal_force_ellipsoid",
            "gap_ellipsoid",
            "normal_force_stem",
            "gap_stem",
        ];
        let rows = [
            ([0.0, 0.0, 0.06, 0.0, 0.0, 0.01], "sliding@ellipsoid"),
            (
                [1.0, 0.0, 0.02, 0.0, 0.04, 0.0],
                "two_contacts@ellipsoid+stem",
            ),
            ([2.0, 0.0, 0.0, 0.002, 0.06, 0.0], "sliding@stem"),
            ([3.0, 0.001, 0.0, 0.003, 0.0, 0.001], "flight"),
        ];
        let mut t = Table::from_rows("m", &names, 4, |i| (rows[i].0.to_vec(), rows[i].1.into()));
        let forces = t.per_surface("normal_force");
        assert_eq!(
            forces.iter().map(|f| f.0).collect::<Vec<_>>(),
            ["ellipsoid", "stem"]
        );
        assert_eq!(forces[1].1, [0.0, 0.04, 0.06, 0.0]);
        assert_eq!(t.surfaces(), ["ellipsoid", "stem"]);
        let surfaces = ["ellipsoid", "stem"];
        let bits: Vec<u32> = (0..4).map(|i| t.in_contact(i, &surfaces)).collect();
        assert_eq!(bits, [0b01, 0b11, 0b10, 0b00]);
        // Without modes, a surface touches where its gap is 0.
        t.modes = None;
        let bits: Vec<u32> = (0..4).map(|i| t.in_contact(i, &surfaces)).collect();
        assert_eq!(bits, [0b01, 0b11, 0b10, 0b00]);
        assert_eq!(unit("normal_force_stem"), Some("N"));
        assert_eq!(unit("contact_y_peg_2"), Some("m"));
        assert_eq!(unit("normal_force"), Some("N"));
        assert_eq!(unit("normal_force_"), None);
        assert_eq!(unit("normal_force_a-b"), None);
        assert_eq!(
            surface_column("contact_x_stem"),
            Some(("contact_x", "stem"))
        );
        assert!(keeps(Some(&["gap_*"]), "gap_stem") && !keeps(Some(&["gap_*"]), "gap"));
    }

    #[test]
    fn csv_errors_name_the_file_line_column_and_value() {
        let dir = tempfile::tempdir().unwrap();
        let cases = [
            ("", "empty"),
            ("x,y\n1,2\n", "no `t` column"),
            (
                "t,x\n0,1\n1,abc\n",
                ":3: column `x`: \"abc\" is not a number",
            ),
            (
                "t,x\n0,1\n1,inf\n",
                ":3: column `x` = inf: values must be finite",
            ),
            ("t,x\n0,1\n1\n", ":3: 1 fields where the header has 2"),
            ("t,x\n0,1,2\n", ":2: more fields"),
            ("t,x\n1,1\n0,1\n", ":3: t = 0 s comes after t = 1 s"),
            ("t,t\n0,1\n", "appears twice"),
            ("t,x\n", "no rows"),
        ];
        for (k, (text, want)) in cases.iter().enumerate() {
            let p = write(dir.path(), &format!("c{k}.csv"), text);
            let err = read(&p).unwrap_err().to_string();
            assert!(
                err.starts_with(&p.display().to_string()) && err.contains(want),
                "{text:?}: {err}"
            );
        }
        let err = read(&dir.path().join("missing.csv"))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("missing.csv") && err.contains("No such file"),
            "{err}"
        );
        assert!(
            read(&write(dir.path(), "x.txt", "t\n0\n"))
                .unwrap_err()
                .to_string()
                .contains("unknown trajectory format")
        );
        let bin = dir.path().join("bin.csv");
        std::fs::write(&bin, [0xff, 0xfe, 0x00, b'\n']).unwrap();
        assert!(read(&bin).unwrap_err().to_string().contains("not UTF-8"));
    }

    #[test]
    fn drift_is_relative_to_the_initial_energy_plus_work() {
        let t = Table::from_rows("m", &["t", "energy", "work"], 3, |i| {
            (
                vec![
                    i as f64,
                    2.0 - i as f64 * 0.5,
                    i as f64 * 0.5 * (1.0 + 1e-9),
                ],
                "sliding".into(),
            )
        });
        let (d, name) = t.drift().unwrap();
        assert_eq!(name, "E + W");
        assert!((d[2] - 1e-9 / 2.0).abs() < 1e-15, "{d:?}");
    }

    #[test]
    fn contact_point_of_a_tilted_sphere_is_below_its_centre() {
        // A sphere of radius 0.1 with G 0.02 below C0: the contact point lies under C0.
        let s = Shape {
            semi_axes: [0.1; 3],
            com_offset: [0.0, 0.0, -0.02],
            spheres: Vec::new(),
            rims: Vec::new(),
            ellipsoid_contact: true,
        };
        let theta: f64 = 0.7;
        // C0 is at G + R(0,0,0.02); the contact point at C0 − 0.1 e3.
        let g = [1.0, 2.0, 0.1 - 0.02 * theta.cos()];
        let c = s.contact_point(g, theta, 0.3, 1.1);
        let r = euler_rotation(theta, 0.3, 1.1);
        let c0 = Vector3::from(g) + r * Vector3::new(0.0, 0.0, 0.02);
        assert!(
            (c[0] - c0.x).abs() < 1e-15 && (c[1] - c0.y).abs() < 1e-15 && c[2].abs() < 1e-15,
            "{c:?} {c0:?}"
        );
    }

    #[test]
    fn the_centre_lies_above_g_by_the_offset() {
        let mut t = Table::from_rows("m", &["t", "x", "y", "theta", "phi", "psi"], 1, |_| {
            (vec![0.0, 1.0, 2.0, 0.5, 0.2, 0.0], "rolling".into())
        });
        assert!(t.centre_path().is_none(), "no shape");
        t.shape = Some(Shape {
            semi_axes: [0.1; 3],
            com_offset: [0.0, 0.0, -0.02],
            spheres: Vec::new(),
            rims: Vec::new(),
            ellipsoid_contact: true,
        });
        let (x, y) = t.centre_path().unwrap();
        // C0 = G + 0.02 e3*, e3* = (sin φ sin θ, −cos φ sin θ, cos θ).
        let (st, sp, cp) = (0.5f64.sin(), 0.2f64.sin(), 0.2f64.cos());
        assert!(
            (x[0] - (1.0 + 0.02 * sp * st)).abs() < 1e-15
                && (y[0] - (2.0 - 0.02 * cp * st)).abs() < 1e-15
        );
        t.shape = Some(Shape {
            semi_axes: [0.1; 3],
            com_offset: [0.0; 3],
            spheres: Vec::new(),
            rims: Vec::new(),
            ellipsoid_contact: true,
        });
        assert!(t.centre_path().is_none(), "C0 is G");
    }

    #[test]
    fn summary_events_and_labels() {
        let v: Value = serde_json::from_str(r#"{"status":"completed","events":[{"kind":"mode_switch","from":"sliding","to":"rolling","t":0.3},{"kind":"slip_stop","t":0.1}]}"#).unwrap();
        let mut t = Table::default();
        t.apply_summary(&v, None);
        assert_eq!(
            t.events
                .iter()
                .map(|e| (e.t, e.label.as_str()))
                .collect::<Vec<_>>(),
            [(0.1, "slip stop"), (0.3, "sliding → rolling")]
        );
        assert!(t.shape.is_none());
    }
}
