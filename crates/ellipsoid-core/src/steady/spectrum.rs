//! Eigenvalues and eigenvectors of a linearisation with the zeros that are not the
//! motion's removed, and each mode named by what moves (docs/physics.md, "Steady motions
//! and their stability", "The spectrum").
//!
//! A steady motion of a family x0(p) has J dx0/dp = 0 (every member is an equilibrium of
//! the reduced field), or, for a relative equilibrium in a turning frame, J dx0/dp in the
//! symmetry's direction, which J takes to zero: those zeros belong to the family and the
//! symmetry, not to the motion's stability. With an orthogonal Q whose first k columns
//! span these directions, QᵀJQ = [[N, T], [0, B]] (N nilpotent), and the spectrum left is
//! that of the (5 − k)×(5 − k) block B. An eigenvector u of B lifts to Q ((λ − N)⁻¹ T u, u),
//! an eigenvector of J.
//!
//! The decompositions are bounded: a Jacobian with a non-finite entry is refused before
//! them, and the Schur and singular value iterations stop after [`MAX_ITERATIONS`] (about
//! 20 per eigenvalue converge for a finite matrix; LAPACK allows 30), so a matrix they cannot
//! decompose is an error, never a panic or an endless loop.

use nalgebra::{Complex, DMatrix, DVector, SVector, Vector3};

use super::linearize::{Linearization, Reduced};
use crate::error::{ModelError, Value};

/// One eigenvalue, its eigenvector and what moves in it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mode {
    /// λ [1/s]: growth rate Re λ, angular frequency Im λ (body frame).
    pub eigenvalue: Complex<f64>,
    /// The eigenvector in the reduced coordinates (`linearize::COORDINATES`), scaled so
    /// that its tilt part (ζ·t1, ζ·t2) has unit norm (its ω part unit norm if it has no
    /// tilt), largest component real and positive.
    pub vector: SVector<Complex<f64>, 5>,
    /// What moves: "tilt" (a body of revolution: the axis circles), "nutation" (a tilted
    /// motion of a body of revolution: the tilt θ oscillates or grows), "roll" (a rotation
    /// mainly about the longer horizontal body axis), "pitch" (the shorter), "wobble"
    /// (both), "spin" (ω only).
    pub name: &'static str,
    /// How clearly the mode is what `name` says: ≥ 1, the larger the clearer (its distance
    /// inside the naming rule, e.g. a roll whose rotation about the longer axis is r times
    /// that about the shorter has r/3; [`tilt_name`]). A sweep gives every mode of a branch
    /// the name and clarity of the branch's clearest member.
    pub clarity: f64,
}

/// The spectrum of a steady motion: four modes (upright, inverted) or two (the tilted
/// families), by decreasing real part.
#[derive(Debug, Clone, PartialEq)]
pub struct Spectrum {
    pub modes: Vec<Mode>,
    /// The smallest scale [1/s]: 0 upright and inverted; for the tilted families, whose
    /// one pair passes through zero where the stability changes, the motion's rate
    /// max(|ω0|, √(g/c_max)), so that round-off in a small pair does not count as growth.
    pub floor: f64,
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

    /// The spectrum's scale max |λ| [1/s] (at least the floor and 1e-300).
    pub fn scale(&self) -> f64 {
        self.modes
            .iter()
            .map(|m| m.eigenvalue.norm())
            .fold(self.floor.max(1e-300), f64::max)
    }
}

/// Real parts below this fraction of max |λ| count as zero: above the derivatives'
/// error (~1e-12, docs/physics.md), far below any growth a run could show.
pub const STABLE_TOLERANCE: f64 = 1e-9;

/// Most iterations of the Schur and singular value decompositions of one matrix.
pub const MAX_ITERATIONS: usize = 1000;

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
    /// A tilted steady motion (its mode is the axis' nutation: "nutation").
    pub tilted: bool,
}

/// The spectrum of `lin` with the zeros along `removed` (reduced directions, linearly
/// independent, at most 4) taken out; `floor` as [`Spectrum::floor`]. An error if the
/// Jacobian or the removed directions are not finite, or the decompositions do not
/// converge ([`reduced_modes`]).
pub fn spectrum(
    lin: &Linearization,
    removed: &[Reduced],
    shape: &Shape,
    floor: f64,
) -> Result<Spectrum, ModelError> {
    let jacobian = DMatrix::from_fn(5, 5, |i, j| lin.jacobian[(i, j)]);
    let removed: Vec<DVector<f64>> = removed
        .iter()
        .map(|d| DVector::from_column_slice(d.as_slice()))
        .collect();
    let mut modes: Vec<Mode> = reduced_modes(&jacobian, &removed)?
        .into_iter()
        .map(|(lambda, v)| {
            let vector = normalise(SVector::<Complex<f64>, 5>::from_column_slice(v.as_slice()));
            let (name, clarity) = name(lin, &vector, shape);
            Mode {
                eigenvalue: lambda,
                vector,
                name,
                clarity,
            }
        })
        .collect();
    modes.sort_by(|x, y| by_real_part(&x.eigenvalue, &y.eigenvalue));
    Ok(Spectrum { modes, floor })
}

/// Decreasing real part, then decreasing imaginary part.
pub(super) fn by_real_part(x: &Complex<f64>, y: &Complex<f64>) -> std::cmp::Ordering {
    y.re.total_cmp(&x.re).then(y.im.total_cmp(&x.im))
}

/// An eigenvalue and its eigenvector, in a Jacobian's coordinates.
pub(super) type ModeOf = (Complex<f64>, DVector<Complex<f64>>);

/// The eigenvalues of the square `jacobian` with the zeros along `removed` (linearly
/// independent directions, fewer than its size) taken out, each with its eigenvector
/// lifted back to the full coordinates (see the module docs); unsorted, unscaled. An
/// error ([`unresolved`]) if an entry of `jacobian` or `removed` is not finite, or the
/// Schur or a singular value decomposition does not converge in [`MAX_ITERATIONS`].
pub(super) fn reduced_modes(
    jacobian: &DMatrix<f64>,
    removed: &[DVector<f64>],
) -> Result<Vec<ModeOf>, ModelError> {
    let finite = |m: &DMatrix<f64>| m.iter().all(|x| x.is_finite());
    if !(finite(jacobian) && removed.iter().all(|d| d.iter().all(|x| x.is_finite()))) {
        return Err(unresolved(jacobian, "an entry is not finite"));
    }
    let n = jacobian.nrows();
    let k = removed.len();
    let rest = n - k;
    let q = completion(n, removed);
    let b = q.transpose() * jacobian * &q;
    let block = DMatrix::from_fn(rest, rest, |i, j| b[(k + i, k + j)]);
    let complex = |m: DMatrix<f64>| m.map(|x| Complex::new(x, 0.0));
    let nil = complex(DMatrix::from_fn(k, k, |i, j| b[(i, j)]));
    let top = complex(DMatrix::from_fn(k, rest, |i, j| b[(i, k + j)]));
    let qc = complex(q);
    let no_schur = || {
        unresolved(
            jacobian,
            format!("its Schur decomposition did not converge in {MAX_ITERATIONS} iterations"),
        )
    };
    let eigenvalues = block
        .clone()
        .try_schur(f64::EPSILON, MAX_ITERATIONS)
        .ok_or_else(no_schur)?
        .complex_eigenvalues();
    if !eigenvalues
        .iter()
        .all(|l| l.re.is_finite() && l.im.is_finite())
    {
        return Err(unresolved(jacobian, "an eigenvalue is not finite"));
    }
    eigenvalues
        .iter()
        .map(|&lambda| {
            let u = null_vector(&block, lambda).ok_or_else(|| {
                unresolved(
                    jacobian,
                    format!(
                        "a singular value decomposition did not converge in {MAX_ITERATIONS} iterations"
                    ),
                )
            })?;
            let shifted = DMatrix::<Complex<f64>>::identity(k, k) * lambda - &nil;
            let y = if lambda.norm() > 0.0 {
                shifted
                    .lu()
                    .solve(&(&top * &u))
                    .unwrap_or_else(|| DVector::zeros(k))
            } else {
                DVector::zeros(k)
            };
            let lifted = DVector::from_fn(n, |i, _| if i < k { y[i] } else { u[i - k] });
            Ok((lambda, &qc * lifted))
        })
        .collect()
}

/// Why a Jacobian has no spectrum: its largest entry and `why`, placed at `initial` (the
/// motion the scenario's initial state defines).
fn unresolved(jacobian: &DMatrix<f64>, why: impl std::fmt::Display) -> ModelError {
    let largest = jacobian.iter().fold(0.0_f64, |m, x| {
        if x.is_nan() || m.is_nan() {
            f64::NAN
        } else {
            m.max(x.abs())
        }
    });
    ModelError::derived(
        "initial",
        "largest entry of the Jacobian",
        Value::Number(largest, "1/s"),
        format!("the linearisation at this steady motion has no spectrum: {why}"),
    )
}

/// An orthogonal n×n Q whose first k columns span `removed` (k vectors): the Householder
/// QR of [removed | 𝟙].
fn completion(n: usize, removed: &[DVector<f64>]) -> DMatrix<f64> {
    let k = removed.len();
    let m = DMatrix::from_fn(n, k + n, |i, j| {
        if j < k {
            removed[j][i]
        } else if i == j - k {
            1.0
        } else {
            0.0
        }
    });
    m.qr().q()
}

/// A unit u with (B − λ) u ≈ 0: the right singular vector of the smallest singular value
/// (`None` if the decomposition does not converge in [`MAX_ITERATIONS`]; `block` and `λ`
/// finite).
fn null_vector(block: &DMatrix<f64>, lambda: Complex<f64>) -> Option<DVector<Complex<f64>>> {
    let n = block.nrows();
    let m = block.map(|x| Complex::new(x, 0.0)) - DMatrix::identity(n, n) * lambda;
    let svd = m.try_svd_unordered(false, true, f64::EPSILON, MAX_ITERATIONS)?;
    let v_t = svd.v_t?;
    let (k, _) = svd
        .singular_values
        .iter()
        .enumerate()
        .fold(
            (0, f64::INFINITY),
            |acc, (i, &s)| if s < acc.1 { (i, s) } else { acc },
        );
    Some(v_t.row(k).transpose().map(|x| x.conj()))
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

/// What moves in a mode (see [`Mode::name`]) and how clearly ([`Mode::clarity`]; ∞ for
/// "spin", ω alone).
fn name(lin: &Linearization, v: &SVector<Complex<f64>, 5>, shape: &Shape) -> (&'static str, f64) {
    let tilt = (v[0].norm_sqr() + v[1].norm_sqr()).sqrt();
    if tilt < 1e-9 {
        return ("spin", f64::INFINITY);
    }
    tilt_name(lin.tangent, v[0], v[1], shape)
}

/// What moves in a mode that tilts the body by δζ = `a` t1 + `b` t2 (complex amplitudes
/// along the tangent basis `tangent` at ζ0): "nutation" for a tilted motion, "tilt" for a
/// body of revolution, else "roll", "pitch" or "wobble" by the rotation's horizontal part
/// about the body's longer and shorter horizontal axes (see [`Mode::name`]); and its
/// clarity ([`Mode::clarity`]: with r the ratio of the rotation about the longer axis to
/// that about the shorter, r/3 for a roll, 1/(3r) for a pitch, 3/max(r, 1/r) for a
/// wobble, ∞ for a pure roll or pitch; 1 for "tilt" and "nutation", which a body's
/// symmetry decides).
pub(super) fn tilt_name(
    tangent: [Vector3<f64>; 2],
    a: Complex<f64>,
    b: Complex<f64>,
    shape: &Shape,
) -> (&'static str, f64) {
    if shape.tilted {
        return ("nutation", 1.0);
    }
    if shape.revolution {
        return ("tilt", 1.0);
    }
    // δζ = ζ0 × δ, so the rotation's horizontal part is δ = δζ × ζ0.
    let [t1, t2] = tangent;
    let rotation = |axis: &Vector3<f64>| {
        // (δζ × ζ0)·axis = δζ·(ζ0 × axis), per tangent component.
        let g = shape.zeta.cross(axis);
        a * t1.dot(&g) + b * t2.dot(&g)
    };
    let about_long = rotation(&shape.long).norm();
    let about_short = rotation(&shape.short).norm();
    // A pure roll or pitch (the other rotation zero) is infinitely clear.
    if about_long > 3.0 * about_short {
        ("roll", about_long / (3.0 * about_short))
    } else if about_short > 3.0 * about_long {
        ("pitch", about_short / (3.0 * about_long))
    } else {
        let r = about_long / about_short;
        ("wobble", 3.0 / r.max(1.0 / r))
    }
}
