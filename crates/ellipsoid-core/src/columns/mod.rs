//! The output columns, declared once: name, unit, and how each is read off a sample.
//!
//! ```text
//! column        unit    meaning
//! t             s       time
//! x, y, z       m       position of the centre of mass G (z from the contact constraint)
//! theta..psi    rad     z-x-z Euler angles (paper eq. 1), φ and ψ unwrapped
//! *_dot         rad/s   their rates
//! omega_x..z    rad/s   angular velocity in body axes
//! vx, vy, vz    m/s     velocity of G
//! energy        J       E = ½m|v_G|² + ½ωᵀIω + m g z_G
//! normal_force  N       N = F·e3
//! slip_speed    m/s     |v_C|, speed of the material contact point (a face: of its centre)
//! mode          -       contact regime: frictionless | sliding | rolling | flight | two_contacts | viscous | three_contacts | face
//! work          J       work dissipated so far (friction and effects)
//! omega_world_* rad/s   angular velocity in world axes (omega_world_z: the vertical spin)
//! contact_x, _y m       the contact point C on the plane (a rim lying on its face: the
//!                       face's centre)
//! drift         1       (Q − Q(0))/scale of the scene's conserved quantity Q: E where
//!                       energy is conserved, else E + W (docs/physics.md, "Invariants")
//! gap           m       height of the body's lowest point above the plane (0 in contact)
//! ```
//! Observables (`[[observe]]`) name these columns too.
//!
//! A body with contact spheres ([`Layout`]) adds five columns per surface after these,
//! the ellipsoid first, then the spheres in their order, each named after its surface
//! (`normal_force_stem`, …; [`SURFACE_COLUMNS`]), and its `mode` names the surfaces in
//! contact (`sliding@stem`, `two_contacts@ellipsoid+stem`; docs/physics.md, "Contact
//! spheres").

use std::borrow::Cow;
use std::sync::Arc;

use nalgebra::{UnitQuaternion, Vector2, Vector3};

use crate::body::{Body, Surface};
use crate::geometry::{self, Contact};
use crate::model::MOST_CONTACTS;
use crate::state::EulerAngles;

mod sample;

pub use sample::{Mode, Sample};

/// Number of numeric columns.
pub const NUMERIC: usize = 27;

/// One numeric output column: its name, its unit (SI), and how its value is read off a
/// [`Sample`] and written back into one (a row read back from a file).
#[derive(Clone, Copy)]
pub struct Column {
    pub name: &'static str,
    pub unit: &'static str,
    /// Its value in a sample.
    pub get: fn(&Sample) -> f64,
    /// Sets it in a sample.
    pub set: fn(&mut Sample, f64),
}

/// Declares [`COLUMNS`], each column once: `name [unit] field`, `field` the sample's
/// field (or a component of one) that holds it.
macro_rules! columns {
    ($($name:ident [$unit:literal] $($field:ident).+),* $(,)?) => {
        /// The numeric columns in file order (`mode` sits between `slip_speed` and `work`).
        pub const COLUMNS: [Column; NUMERIC] = [$(Column {
            name: stringify!($name),
            unit: $unit,
            get: |s| s.$($field).+,
            set: |s, v| s.$($field).+ = v,
        }),*];
    };
}

columns! {
    t ["s"] t,
    x ["m"] position.x,
    y ["m"] position.y,
    z ["m"] position.z,
    theta ["rad"] angles.theta,
    phi ["rad"] angles.phi,
    psi ["rad"] angles.psi,
    theta_dot ["rad/s"] angles.theta_dot,
    phi_dot ["rad/s"] angles.phi_dot,
    psi_dot ["rad/s"] angles.psi_dot,
    omega_x ["rad/s"] omega.x,
    omega_y ["rad/s"] omega.y,
    omega_z ["rad/s"] omega.z,
    vx ["m/s"] velocity.x,
    vy ["m/s"] velocity.y,
    vz ["m/s"] velocity.z,
    energy ["J"] energy,
    normal_force ["N"] normal_force,
    slip_speed ["m/s"] slip_speed,
    work ["J"] work,
    omega_world_x ["rad/s"] omega_world.x,
    omega_world_y ["rad/s"] omega_world.y,
    omega_world_z ["rad/s"] omega_world.z,
    contact_x ["m"] contact.x,
    contact_y ["m"] contact.y,
    drift ["1"] drift,
    gap ["m"] gap,
}

/// Numeric columns in file order, with units ([`COLUMNS`]' names and units).
pub const NUMERIC_COLUMNS: [(&str, &str); NUMERIC] = {
    let mut out = [("", ""); NUMERIC];
    let mut k = 0;
    while k < NUMERIC {
        out[k] = (COLUMNS[k].name, COLUMNS[k].unit);
        k += 1;
    }
    out
};

/// Index in [`NUMERIC_COLUMNS`] before which the `mode` column is written.
pub const MODE_POSITION: usize = 19;

/// Name of the string column.
pub const MODE: &str = "mode";

/// All column names in file order.
pub fn names() -> Vec<&'static str> {
    let mut v: Vec<&str> = NUMERIC_COLUMNS.iter().map(|c| c.0).collect();
    v.insert(MODE_POSITION, MODE);
    v
}

/// Column → unit (`mode` has the unit "1": a name, dimensionless).
pub fn units() -> Vec<(&'static str, &'static str)> {
    let mut v = NUMERIC_COLUMNS.to_vec();
    v.insert(MODE_POSITION, (MODE, "1"));
    v
}

/// The numeric values of a sample, in [`NUMERIC_COLUMNS`] order.
pub fn values(s: &Sample) -> [f64; NUMERIC] {
    std::array::from_fn(|k| (COLUMNS[k].get)(s))
}

/// The sample whose numeric columns are `values` ([`NUMERIC_COLUMNS`] order), in `mode`
/// and `touching` the plane with those surfaces: the inverse of [`values`].
pub fn sample(
    values: &[f64; NUMERIC],
    mode: Mode,
    touching: [Option<(Surface, f64)>; MOST_CONTACTS],
) -> Sample {
    let mut s = Sample {
        t: 0.0,
        position: Vector3::zeros(),
        angles: EulerAngles::default(),
        omega: Vector3::zeros(),
        omega_world: Vector3::zeros(),
        velocity: Vector3::zeros(),
        contact: Vector2::zeros(),
        energy: 0.0,
        work: 0.0,
        normal_force: 0.0,
        slip_speed: 0.0,
        drift: 0.0,
        gap: 0.0,
        mode,
        touching,
    };
    for (column, &v) in COLUMNS.iter().zip(values) {
        (column.set)(&mut s, v);
    }
    s
}

/// The columns of each surface of a body with contact spheres, named
/// `{quantity}_{surface}`, with units:
/// ```text
/// normal_force_S  N    normal force of the plane on surface S (0 when S is open)
/// slip_speed_S    m/s  horizontal speed of S's lowest material point (its slip in contact)
/// gap_S           m    height of S's lowest point above the plane (0 in contact)
/// contact_x_S, _y m    S's lowest point on the plane (its contact point in contact;
///                      the face's centre for a rim lying on its face)
/// ```
pub const SURFACE_COLUMNS: [(&str, &str); 5] = [
    ("normal_force", "N"),
    ("slip_speed", "m/s"),
    ("gap", "m"),
    ("contact_x", "m"),
    ("contact_y", "m"),
];

/// The columns of a run: the [`NUMERIC_COLUMNS`] and `mode` of every run, and for a body
/// with contact spheres the [`SURFACE_COLUMNS`] of each surface after them. A one-surface
/// body's layout is exactly the fixed columns.
#[derive(Debug, Clone)]
pub struct Layout {
    /// The body, when it has contact spheres (shared by the writers of a run).
    body: Option<Arc<Body>>,
}

impl Layout {
    /// The layout of a run of `body`.
    pub fn of(body: &Body) -> Layout {
        Layout {
            body: (!body.plain()).then(|| Arc::new(body.clone())),
        }
    }

    /// The fixed columns only (a one-surface body's layout).
    pub fn fixed() -> Layout {
        Layout { body: None }
    }

    /// Number of numeric columns.
    pub fn numeric(&self) -> usize {
        NUMERIC + self.extra()
    }

    /// Number of per-surface columns.
    pub fn extra(&self) -> usize {
        self.body
            .as_ref()
            .map_or(0, |b| SURFACE_COLUMNS.len() * b.surfaces().count())
    }

    /// Numeric columns in file order (`mode` not among them), with units.
    pub fn numeric_columns(&self) -> Vec<(Cow<'static, str>, &'static str)> {
        let mut v: Vec<(Cow<'static, str>, &'static str)> = NUMERIC_COLUMNS
            .iter()
            .map(|&(n, u)| (Cow::Borrowed(n), u))
            .collect();
        if let Some(body) = &self.body {
            for surface in body.surfaces() {
                let name = body.surface_name(surface);
                for (q, u) in SURFACE_COLUMNS {
                    v.push((Cow::Owned(format!("{q}_{name}")), u));
                }
            }
        }
        v
    }

    /// Column → unit, every column in file order (`mode` has the unit "1").
    pub fn units(&self) -> Vec<(Cow<'static, str>, &'static str)> {
        let mut v = self.numeric_columns();
        v.insert(MODE_POSITION, (Cow::Borrowed(MODE), "1"));
        v
    }

    /// All column names in file order.
    pub fn names(&self) -> Vec<Cow<'static, str>> {
        self.units().into_iter().map(|c| c.0).collect()
    }

    /// The index among [`Layout::numeric_columns`] of the column called `name`.
    pub fn index(&self, name: &str) -> Option<usize> {
        index(name).or_else(|| {
            self.numeric_columns()[NUMERIC..]
                .iter()
                .position(|c| c.0 == name)
                .map(|k| NUMERIC + k)
        })
    }

    /// The index among [`Layout::numeric_columns`] of `surface`'s column of `quantity`
    /// (one of [`SURFACE_COLUMNS`]), if the layout has per-surface columns.
    pub fn surface_column(&self, quantity: &str, surface: Surface) -> Option<usize> {
        let body = self.body.as_ref()?;
        self.index(&format!("{quantity}_{}", body.surface_name(surface)))
    }

    /// Appends the per-surface values of `s` to `out` ([`SURFACE_COLUMNS`] of each
    /// surface; nothing for a one-surface body).
    pub fn surface_values(&self, s: &Sample, out: &mut Vec<f64>) {
        let Some(body) = &self.body else { return };
        let rot = s.angles.rotation();
        for surface in body.surfaces() {
            out.extend(surface_row(body, &rot, s, surface));
        }
    }

    /// The value in `s` of numeric column `k` (the layout's order).
    pub fn value(&self, s: &Sample, k: usize) -> f64 {
        match &self.body {
            Some(body) if k >= NUMERIC => {
                let (surface, q) = (
                    (k - NUMERIC) / SURFACE_COLUMNS.len(),
                    (k - NUMERIC) % SURFACE_COLUMNS.len(),
                );
                let surface = body
                    .surfaces()
                    .nth(surface)
                    .expect("a column of the layout");
                surface_row(body, &s.angles.rotation(), s, surface)[q]
            }
            _ => values(s)[k],
        }
    }

    /// The `mode` column of `s`: the contact phase's name, and for a body with contact
    /// spheres the surfaces in contact after `@`, in the body's order (the ellipsoid
    /// first), joined by `+` (`flight` alone).
    pub fn mode(&self, s: &Sample) -> Cow<'static, str> {
        match &self.body {
            Some(body) if s.mode != Mode::Flight => {
                // In the body's order, whichever touched first.
                let mut touching: Vec<Surface> = s.touching.iter().flatten().map(|t| t.0).collect();
                touching.sort_by_key(|&surface| body.surfaces().position(|s| s == surface));
                let names: Vec<&str> = touching.iter().map(|&t| body.surface_name(t)).collect();
                Cow::Owned(format!("{}@{}", s.mode.name(), names.join("+")))
            }
            _ => Cow::Borrowed(s.mode.name()),
        }
    }

    /// The sample a mode label names (the inverse of [`Layout::mode`]): its phase and the
    /// surfaces in contact, or `None` for a label this layout cannot write.
    pub fn parse_mode(&self, label: &str) -> Option<(Mode, Vec<Surface>)> {
        let (phase, surfaces) = match (&self.body, label.split_once('@')) {
            (Some(body), Some((phase, list))) => {
                let named = |n: &str| body.surfaces().find(|&s| body.surface_name(s) == n);
                let surfaces: Option<Vec<Surface>> = list.split('+').map(named).collect();
                (phase, surfaces?)
            }
            (_, None) => (label, Vec::new()),
            (None, Some(_)) => return None,
        };
        let mode = Mode::ALL.into_iter().find(|m| m.name() == phase)?;
        Some((mode, surfaces))
    }
}

/// The [`SURFACE_COLUMNS`] of `surface` in sample `s`, `rot` its attitude: the surface's
/// support point at that attitude (docs/physics.md, "Contact spheres"); a surface in
/// contact has gap 0 and its normal force from the contact law.
fn surface_row(body: &Body, rot: &UnitQuaternion<f64>, s: &Sample, surface: Surface) -> [f64; 5] {
    let zeta = rot.inverse_transform_vector(&Vector3::z());
    let normal = s.touching.iter().flatten().find(|t| t.0 == surface);
    if let (Some(&(_, n)), Mode::Face) = (normal, s.mode) {
        // The face's centre, where the law acts (the rim's support point is undefined).
        return [n, s.slip_speed, 0.0, s.contact.x, s.contact.y];
    }
    let c = Contact::of(body, surface, zeta, s.omega);
    let point = s.position + rot * c.r;
    let slip = s.velocity + rot * s.omega.cross(&c.r);
    let gap = if normal.is_some() {
        0.0
    } else {
        s.position.z - geometry::height(body, surface, zeta)
    };
    [
        normal.map_or(0.0, |t| t.1),
        slip.xy().norm(),
        gap,
        point.x,
        point.y,
    ]
}

/// The index in [`NUMERIC_COLUMNS`] of the numeric column called `name`.
pub fn index(name: &str) -> Option<usize> {
    NUMERIC_COLUMNS.iter().position(|c| c.0 == name)
}

/// The first non-finite value of a sample, as (column, value).
///
/// Checked once per sample, so first by the sum: NaN and ±∞ propagate through a sum
/// (∞ − ∞ is NaN), so a finite sum proves every value finite; only a sum that is not
/// (a non-finite value, or an overflow of large finite ones) is searched column by column.
pub fn non_finite(s: &Sample) -> Option<(&'static str, f64)> {
    let v = values(s);
    if v.iter().sum::<f64>().is_finite() {
        return None;
    }
    v.iter()
        .zip(NUMERIC_COLUMNS.iter())
        .find(|(v, _)| !v.is_finite())
        .map(|(v, c)| (c.0, *v))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_of(v: f64) -> Sample {
        let w = Vector3::new(v, v, v);
        Sample {
            t: v,
            position: w,
            angles: EulerAngles {
                theta: v,
                phi: v,
                psi: v,
                theta_dot: v,
                phi_dot: v,
                psi_dot: v,
            },
            omega: w,
            omega_world: w,
            velocity: w,
            contact: Vector2::new(v, v),
            energy: v,
            work: v,
            normal_force: v,
            slip_speed: v,
            drift: v,
            gap: v,
            mode: Mode::Sliding,
            touching: [None; MOST_CONTACTS],
        }
    }

    /// Each column is declared once: names are distinct, and reading a sample's values
    /// back gives the sample (every field of [`Sample`] but `mode` and `touching` is a
    /// column, each set by exactly its own column: all values distinct, so a column
    /// reading or writing another's field fails).
    #[test]
    fn every_column_reads_back_its_own_field() {
        let names: std::collections::BTreeSet<&str> = COLUMNS.iter().map(|c| c.name).collect();
        assert_eq!(names.len(), NUMERIC);
        assert_eq!(index("gap"), Some(NUMERIC - 1));
        let v: [f64; NUMERIC] = std::array::from_fn(|k| 1.0 + k as f64 / 8.0);
        let touching = [Some((Surface::Sphere(1), 2.5)), None, None];
        let s = sample(&v, Mode::TwoContacts, touching);
        assert_eq!(values(&s), v);
        assert_eq!((s.mode, s.touching), (Mode::TwoContacts, touching));
        let full = sample(
            &values(&sample_of(0.75)),
            Mode::Sliding,
            [None; MOST_CONTACTS],
        );
        assert_eq!(full, sample_of(0.75));
    }

    /// Large finite values whose sum overflows are finite; +∞ and −∞ that cancel to NaN
    /// in the sum, or a lone NaN, are found by column.
    #[test]
    fn non_finite_sees_through_overflowing_and_cancelling_sums() {
        assert_eq!(non_finite(&sample_of(1e308)), None);
        assert_eq!(non_finite(&sample_of(-0.5)), None);
        let mut s = sample_of(1.0);
        s.omega_world.y = f64::INFINITY;
        s.gap = f64::NEG_INFINITY;
        assert_eq!(non_finite(&s), Some(("omega_world_y", f64::INFINITY)));
        let mut s = sample_of(1.0);
        s.drift = f64::NAN;
        let (column, value) = non_finite(&s).unwrap();
        assert!(column == "drift" && value.is_nan());
    }
}
