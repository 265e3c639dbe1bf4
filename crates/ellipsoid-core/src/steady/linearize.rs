//! The Jacobian of the reduced field (`reduce`) in tangent coordinates of S² × R³
//! (docs/physics.md, "Steady motions and their stability", "Linearisation").
//!
//! Coordinates: x = (ζ·t1, ζ·t2, ω1, ω2, ω3), with t1 the unit vector along
//! e1 − (e1·ζ0)ζ0 (e2 instead when ζ0 is within 25° of e1) and t2 = ζ0 × t1. The direction
//! normal to the sphere, ζ0, is the constraint |ζ| = 1: since d|ζ|²/dt = 0 everywhere, the
//! full Jacobian maps into the tangent space and its spectrum is that of the 5×5 block
//! plus one zero, which is dropped.
//!
//! Derivatives. ω̇ is a quadratic polynomial in ω at fixed ζ (Coriolis, gyroscopic and
//! curvature terms), so a central difference in ω is exact up to round-off whatever its
//! step. Along ζ the field is analytic; the columns are central differences along great
//! circles, ζ(h) = cos h ζ0 + sin h t, with h = 0.01 (c_min/c_max)² (the support function
//! varies on the scale c_min/c_max in ζ), extrapolated by Richardson from the steps h, h/2,
//! h/4 to sixth order: error ~ h⁶ f⁽⁷⁾/… plus round-off ~ ε |f|/h. The difference between
//! the sixth- and fourth-order values is returned as an error estimate.

use nalgebra::{Matrix5, SVector, Vector3};

use super::reduce::{Phase, ReducedField, join, split};

/// Names of the reduced coordinates, in the Jacobian's order.
pub const COORDINATES: [&str; 5] = ["zeta_t1", "zeta_t2", "omega1", "omega2", "omega3"];

/// A reduced state or direction in [`COORDINATES`].
pub type Reduced = SVector<f64, 5>;

/// The linearised reduced dynamics about one state.
#[derive(Debug, Clone, Copy)]
pub struct Linearization {
    /// ∂ẋ/∂x in [`COORDINATES`] [1/s, or rad/s² per unit of ζ, …].
    pub jacobian: Matrix5<f64>,
    /// The state (ζ0, ω0) it is taken at.
    pub at: Phase,
    /// The tangent basis (t1, t2) at ζ0, body axes.
    pub tangent: [Vector3<f64>; 2],
    /// Estimated error of the ζ columns: |sixth − fourth order|, max over entries.
    pub error: f64,
}

impl Linearization {
    /// The reduced vector of a phase-space direction (δζ, δω) (δζ's normal part dropped).
    pub fn reduced(&self, d: &Phase) -> Reduced {
        let (dz, dw) = split(d);
        Reduced::new(
            self.tangent[0].dot(&dz),
            self.tangent[1].dot(&dz),
            dw.x,
            dw.y,
            dw.z,
        )
    }

    /// The phase-space direction (δζ, δω) of a reduced vector.
    pub fn direction(&self, v: &Reduced) -> Phase {
        let dz = self.tangent[0] * v[0] + self.tangent[1] * v[1];
        join(&dz, &Vector3::new(v[2], v[3], v[4]))
    }
}

/// Relative step along ζ (radians of great circle), before the aspect-ratio scaling.
pub(super) const ZETA_STEP: f64 = 0.01;

/// The derivative at s = 0 of `f`, analytic near 0: central differences with the steps
/// h, h/2, h/4 extrapolated by Richardson to sixth order; with the error estimate
/// |sixth − fourth order| (max over entries).
pub(super) fn richardson<const D: usize>(
    f: impl Fn(f64) -> SVector<f64, D>,
    h: f64,
) -> (SVector<f64, D>, f64) {
    let central = |s: f64| (f(s) - f(-s)) / (2.0 * s);
    let (d1, d2, d3) = (central(h), central(h / 2.0), central(h / 4.0));
    let r1 = (d2 * 4.0 - d1) / 3.0;
    let r2 = (d3 * 4.0 - d2) / 3.0;
    let sixth = (r2 * 16.0 - r1) / 15.0;
    let error = (sixth - r2).amax();
    (sixth, error)
}

/// The tangent basis (t1, t2) at unit ζ0.
pub fn tangent_basis(zeta: &Vector3<f64>) -> [Vector3<f64>; 2] {
    let seed = if zeta.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let t1 = (seed - zeta * zeta.dot(&seed)).normalize();
    [t1, zeta.cross(&t1)]
}

/// Linearises `field` at (ζ0, ω0), ζ0 unit, in the frame turning about the body axis
/// `generator` at rate ν (x ↦ f(x) − ν (e × ζ, e × ω); `None` for the body frame).
/// Costs 2 × 6 + 3 × 2 = 18 evaluations of the field.
pub fn linearize(
    field: &ReducedField,
    at: &Phase,
    generator: Option<(Vector3<f64>, f64)>,
) -> Linearization {
    let (zeta0, omega0) = split(at);
    let zeta0 = zeta0.normalize();
    let at = join(&zeta0, &omega0);
    let tangent = tangent_basis(&zeta0);
    let rate = |x: &Phase| {
        let mut f = field.rate(x);
        if let Some((axis, nu)) = generator {
            let (z, w) = split(x);
            f -= join(&axis.cross(&z), &axis.cross(&w)) * nu;
        }
        f
    };
    let axes = field.body().semi_axes();
    let h = ZETA_STEP * (axes.min() / axes.max()).powi(2);
    let mut columns = [Phase::zeros(); 5];
    let mut error: f64 = 0.0;
    for (k, t) in tangent.iter().enumerate() {
        let along = |s: f64| join(&(zeta0 * s.cos() + t * s.sin()), &omega0);
        let (column, err) = richardson(|s| rate(&along(s)), h);
        columns[k] = column;
        error = error.max(err);
    }
    let scale = omega0
        .norm()
        .max((field.gravity() / axes.max()).sqrt())
        .max(1e-300);
    for k in 0..3 {
        let mut dw = Vector3::zeros();
        dw[k] = scale;
        let plus = join(&zeta0, &(omega0 + dw));
        let minus = join(&zeta0, &(omega0 - dw));
        columns[2 + k] = (rate(&plus) - rate(&minus)) / (2.0 * scale);
    }
    let mut jacobian = Matrix5::zeros();
    for (k, col) in columns.iter().enumerate() {
        let (dz, dw) = split(col);
        jacobian[(0, k)] = tangent[0].dot(&dz);
        jacobian[(1, k)] = tangent[1].dot(&dz);
        for i in 0..3 {
            jacobian[(2 + i, k)] = dw[i];
        }
    }
    Linearization {
        jacobian,
        at,
        tangent,
        error,
    }
}
