//! Eigenvalues and eigenvectors of a linearisation with the family's zero removed, and
//! each mode named by what moves (docs/physics.md, "Steady motions and their
//! stability", "The spectrum").
//!
//! A steady motion of a one-parameter family x0(p) has J dx0/dp = 0 (every member is an
//! equilibrium of the reduced field): that zero belongs to the family, not to the motion's
//! stability. With an orthogonal Q whose first column is the unit family direction,
//! QᵀJQ = [[0, b], [0, B]], and the spectrum left is that of the 4×4 block B. An
//! eigenvector u of B lifts to Q (bᵀu/λ, u), an eigenvector of J.

use nalgebra::{Complex, Matrix4, Matrix5, SVector, Vector3};

use super::linearize::{Linearization, Reduced};

/// One eigenvalue, its eigenvector and what moves in it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mode {
    /// λ [1/s]: growth rate Re λ, angular frequency Im λ (body frame).
    pub eigenvalue: Complex<f64>,
    /// The eigenvector in the reduced coordinates (`linearize::COORDINATES`), scaled so
    /// that its tilt part (ζ·t1, ζ·t2) has unit norm (its ω part unit norm if it has no
    /// tilt), largest component real and positive.
    pub vector: SVector<Complex<f64>, 5>,
    /// What moves: "tilt" (a body of revolution: the axis circles), "roll" (a rotation
    /// mainly about the longer horizontal body axis), "pitch" (the shorter), "wobble"
    /// (both), "spin" (ω only).
    pub name: &'static str,
}

/// The spectrum of a steady motion: four modes, by decreasing real part.
#[derive(Debug, Clone, PartialEq)]
pub struct Spectrum {
    pub modes: Vec<Mode>,
}

impl Spectrum {
    /// The eigenvalues, by decreasing real part.
    pub fn eigenvalues(&self) -> Vec<Complex<f64>> {
        self.modes.iter().map(|m| m.eigenvalue).collect()
    }

    /// The largest real part [1/s].
    pub fn max_real(&self) -> f64 {
        self.modes
            .iter()
            .map(|m| m.eigenvalue.re)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Whether no eigenvalue has a real part above `STABLE_TOLERANCE` of the spectrum's
    /// scale (linear stability: neutral stability counts as stable).
    pub fn stable(&self) -> bool {
        self.max_real() <= STABLE_TOLERANCE * self.scale()
    }

    /// The spectrum's scale max |λ| [1/s] (at least 1e-300).
    pub fn scale(&self) -> f64 {
        self.modes
            .iter()
            .map(|m| m.eigenvalue.norm())
            .fold(1e-300, f64::max)
    }
}

/// Real parts below this fraction of max |λ| count as zero: above the derivatives'
/// error (~1e-12, docs/physics.md), far below any growth a run could show.
pub const STABLE_TOLERANCE: f64 = 1e-9;

/// What the body looks like, for naming modes.
#[derive(Debug, Clone, Copy)]
pub struct Shape {
    /// ζ0, world up in body axes.
    pub zeta: Vector3<f64>,
    /// Body axes as seen from above, longest first (for roll and pitch).
    pub long: Vector3<f64>,
    pub short: Vector3<f64>,
    /// A body of revolution about ζ0 (its modes are circular: "tilt").
    pub revolution: bool,
}

/// The spectrum of `lin` with the zero along `family` (a reduced direction) removed.
pub fn spectrum(lin: &Linearization, family: &Reduced, shape: &Shape) -> Spectrum {
    let q = householder(&family.normalize());
    let b = q.transpose() * lin.jacobian * q;
    let block: Matrix4<f64> = b.fixed_view::<4, 4>(1, 1).into();
    let top = b.fixed_view::<1, 4>(0, 1).transpose();
    let mut modes: Vec<Mode> = block
        .complex_eigenvalues()
        .iter()
        .map(|&lambda| {
            let u = null_vector(&block, lambda);
            let top_u: Complex<f64> = (0..4).map(|i| u[i] * top[i]).sum();
            let a = if lambda.norm() > 0.0 {
                top_u / lambda
            } else {
                Complex::new(0.0, 0.0)
            };
            let lifted =
                SVector::<Complex<f64>, 5>::from_fn(|i, _| if i == 0 { a } else { u[i - 1] });
            let v = q.map(|x| Complex::new(x, 0.0)) * lifted;
            let vector = normalise(v);
            Mode {
                eigenvalue: lambda,
                vector,
                name: name(lin, &vector, shape),
            }
        })
        .collect();
    modes.sort_by(|x, y| {
        y.eigenvalue
            .re
            .total_cmp(&x.eigenvalue.re)
            .then(y.eigenvalue.im.total_cmp(&x.eigenvalue.im))
    });
    Spectrum { modes }
}

/// An orthogonal Q with Q e1 = v (v unit): the Householder reflection that takes v to
/// ∓e1 (the sign chosen to avoid cancellation), its first column's sign then fixed.
fn householder(v: &Reduced) -> Matrix5<f64> {
    let sign = if v[0] >= 0.0 { 1.0 } else { -1.0 };
    let w = (v + Reduced::x() * sign).normalize();
    let mut q = Matrix5::identity() - w * w.transpose() * 2.0;
    q.column_mut(0).scale_mut(-sign);
    q
}

/// A unit u with (B − λ) u ≈ 0: the right singular vector of the smallest singular value.
fn null_vector(block: &Matrix4<f64>, lambda: Complex<f64>) -> SVector<Complex<f64>, 4> {
    let m = block.map(|x| Complex::new(x, 0.0)) - Matrix4::identity() * lambda;
    let svd = m.svd(false, true);
    let v_t = svd.v_t.expect("requested");
    let (k, _) = svd
        .singular_values
        .iter()
        .enumerate()
        .fold(
            (0, f64::INFINITY),
            |acc, (i, &s)| if s < acc.1 { (i, s) } else { acc },
        );
    v_t.row(k).transpose().map(|x| x.conj())
}

/// Scales `v` so that its tilt part has unit norm (its ω part if it has no tilt) and its
/// largest component is real and positive.
fn normalise(v: SVector<Complex<f64>, 5>) -> SVector<Complex<f64>, 5> {
    let tilt = (v[0].norm_sqr() + v[1].norm_sqr()).sqrt();
    let whole = v.norm();
    let scale = if tilt > 1e-9 * whole { tilt } else { whole };
    let big = v.iter().copied().fold(Complex::new(0.0, 0.0), |a, x| {
        if x.norm() > a.norm() { x } else { a }
    });
    let phase = if big.norm() > 0.0 {
        big.conj() / big.norm()
    } else {
        Complex::new(1.0, 0.0)
    };
    v * (phase / scale)
}

/// What moves in a mode (see [`Mode::name`]).
fn name(lin: &Linearization, v: &SVector<Complex<f64>, 5>, shape: &Shape) -> &'static str {
    let tilt = (v[0].norm_sqr() + v[1].norm_sqr()).sqrt();
    if tilt < 1e-9 {
        return "spin";
    }
    if shape.revolution {
        return "tilt";
    }
    // δζ = ζ0 × δ, so the rotation's horizontal part is δ = δζ × ζ0.
    let [t1, t2] = lin.tangent;
    let rotation = |axis: &Vector3<f64>| {
        // (δζ × ζ0)·axis = δζ·(ζ0 × axis), per tangent component.
        let g = shape.zeta.cross(axis);
        v[0] * t1.dot(&g) + v[1] * t2.dot(&g)
    };
    let about_long = rotation(&shape.long).norm();
    let about_short = rotation(&shape.short).norm();
    if about_long > 3.0 * about_short {
        "roll"
    } else if about_short > 3.0 * about_long {
        "pitch"
    } else {
        "wobble"
    }
}
