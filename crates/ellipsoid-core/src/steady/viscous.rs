//! Steady spins under the viscous sliding law (docs/physics.md, "Steady motions and their
//! stability", "Under viscous sliding").
//!
//! The law F = N(e3 − μ_v v_C) is smooth at v_C = 0, so the upright and inverted spins,
//! which do not slip, can be linearised. The horizontal velocity of G is then a state of
//! its own (it is neither constant, as without friction, nor slaved to ω, as rolling): the
//! reduced state is (ζ, ω, h) with h = Rᵀ(v_Gx, v_Gy, 0), G's horizontal velocity in
//! body axes (yaw-invariant, h·ζ = 0),
//! ```text
//!   ζ̇ = ζ × ω,   ω̇ = the viscous law's ω̇,   ḣ = Rᵀ(a_Gx, a_Gy, 0) − ω × h
//! ```
//! (d(Rᵀw)/dt = Rᵀẇ − ω × Rᵀw). |ζ| = 1 and h·ζ = 0 are invariant, so the Jacobian is taken
//! in the 7 tangent coordinates [`COORDINATES`]. The spin's family direction (a change of
//! n, δω = ζ0) is the one zero removed; the 6 eigenvalues left are the motion's.

use std::sync::atomic::AtomicBool;

use nalgebra::{Complex, DMatrix, DVector, SMatrix, SVector, Vector3};

use super::families::{self, Family};
use super::linearize::{ZETA_STEP, richardson, tangent_basis};
use super::reduce;
use super::spectrum::{STABLE_TOLERANCE, Shape, by_real_part, reduced_modes, tilt_name};
use super::sweep::{self, Stability, Sweep};
use super::tilted::Solve;
use crate::body::Body;
use crate::error::{ModelError, Value};
use crate::geometry::Contact;
use crate::model::{System, Viscous};
use crate::scenario::Scenario;
use crate::simulate::{ContactModel, Scene};
use crate::state;

/// The reduced coordinates under the viscous law, in the Jacobian's order: the tilt, ω,
/// and G's horizontal velocity along the tangent basis.
pub const COORDINATES: [&str; 7] = [
    "zeta_t1", "zeta_t2", "omega1", "omega2", "omega3", "v_t1", "v_t2",
];

/// A point of the viscous reduced phase space: (ζ, ω, h) stacked.
pub type State9 = SVector<f64, 9>;

/// The reduced field of a scene under the viscous law.
#[derive(Debug, Clone)]
pub struct ViscousField {
    pub system: System<Viscous, ()>,
}

impl ViscousField {
    /// The field of a scene of the viscous model without effects or contact disc.
    pub fn from_scene(scene: &Scene) -> Result<Self, ModelError> {
        let ContactModel::Viscous { viscous_friction } = scene.contact else {
            return Err(ModelError::invalid(
                "contact.model",
                Value::Choice(scene.contact.name().into()),
                "the viscous analysis needs model = \"viscous\"",
            ));
        };
        reduce::plain(scene)?;
        Ok(ViscousField {
            system: System {
                body: scene.body.clone(),
                gravity: scene.gravity,
                contact: Viscous {
                    coefficient: viscous_friction,
                },
                effects: (),
            },
        })
    }

    /// (ζ̇, ω̇, ḣ) at `x` (see the module docs).
    pub fn rate(&self, x: &State9) -> State9 {
        let (zeta, omega, h) = split(x);
        let mut y = reduce::full_state(&zeta, &omega);
        let rot = state::rotation(&y);
        let v = rot * h;
        y[state::VEL] = v.x;
        y[state::VEL + 1] = v.y;
        let ev = self.system.evaluate(&y);
        let a = ev.accel(&self.system.body, self.system.gravity);
        let h_dot = rot.tr_mul(&Vector3::new(a.x, a.y, 0.0)) - omega.cross(&h);
        let mut out = State9::zeros();
        out.fixed_rows_mut::<3>(0).copy_from(&zeta.cross(&omega));
        out.fixed_rows_mut::<3>(3).copy_from(&ev.response.omega_dot);
        out.fixed_rows_mut::<3>(6).copy_from(&h_dot);
        out
    }
}

/// (ζ, ω, h) of a reduced state.
pub fn split(x: &State9) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    (
        x.fixed_rows::<3>(0).into(),
        x.fixed_rows::<3>(3).into(),
        x.fixed_rows::<3>(6).into(),
    )
}

/// A steady spin under the viscous law and its stability.
#[derive(Debug, Clone)]
pub struct ViscousSpin {
    pub family: Family,
    /// ζ0, world up in body axes.
    pub zeta: Vector3<f64>,
    /// n, the spin about the upward vertical [rad/s].
    pub spin: f64,
    /// N \[N\].
    pub normal_force: f64,
    /// ∂ẋ/∂x in [`COORDINATES`].
    pub jacobian: SMatrix<f64, 7, 7>,
    /// The tangent basis (t1, t2) at ζ0, body axes.
    pub tangent: [Vector3<f64>; 2],
    /// The six eigenvalues, by decreasing real part [1/s] (body frame).
    pub eigenvalues: Vec<Complex<f64>>,
    /// Their eigenvectors in [`COORDINATES`], tilt part of unit norm.
    pub vectors: Vec<SVector<Complex<f64>, 7>>,
    /// Estimated error of the Jacobian's entries (Richardson's |sixth − fourth order|).
    pub error: f64,
    /// What moves in each mode ([`mode_name`]).
    pub names: Vec<&'static str>,
    /// How clearly each mode is what its name says ([`super::Mode::clarity`]).
    pub clarity: Vec<f64>,
}

impl ViscousSpin {
    /// The largest real part [1/s].
    pub fn max_real(&self) -> f64 {
        self.eigenvalues
            .iter()
            .map(|l| l.re)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// No real part above [`STABLE_TOLERANCE`] of max |λ|.
    pub fn stable(&self) -> bool {
        self.max_real() <= STABLE_TOLERANCE * self.scale()
    }

    /// max |λ| [1/s] (at least 1e-300).
    pub fn scale(&self) -> f64 {
        self.eigenvalues
            .iter()
            .map(|l| l.norm())
            .fold(1e-300, f64::max)
    }

    /// What moves in each mode, in the order of the eigenvalues (see [`mode_name`]).
    pub fn mode_names(&self) -> Vec<&'static str> {
        self.names.clone()
    }
}

impl Stability for ViscousSpin {
    fn eigenvalues(&self) -> Vec<Complex<f64>> {
        self.eigenvalues.clone()
    }
    fn stable(&self) -> bool {
        ViscousSpin::stable(self)
    }
    fn scale(&self) -> f64 {
        ViscousSpin::scale(self)
    }
    fn names(&self) -> Vec<(&'static str, f64)> {
        self.names
            .iter()
            .copied()
            .zip(self.clarity.iter().copied())
            .collect()
    }
    fn rename(&mut self, names: &[(&'static str, f64)]) {
        (self.names, self.clarity) = names.iter().copied().unzip();
    }
    fn vectors(&self) -> Vec<Vec<Complex<f64>>> {
        self.vectors.iter().map(|v| v.as_slice().to_vec()).collect()
    }
}

impl ViscousSpin {
    /// The displacement ε Re(v) of mode `k` as (δζ, δω, δh) in body axes.
    pub fn perturbation(&self, k: usize, epsilon: f64) -> State9 {
        direction(self.tangent, &self.vectors[k].map(|c| c.re * epsilon))
    }

    /// The steady state (ζ0, n ζ0, 0).
    pub fn at(&self) -> State9 {
        let mut x = State9::zeros();
        x.fixed_rows_mut::<3>(0).copy_from(&self.zeta);
        x.fixed_rows_mut::<3>(3).copy_from(&(self.zeta * self.spin));
        x
    }
}

/// The upright or inverted spin of `scene` (a scene of the viscous model; its spin as
/// [`families::steady_motion`] takes it) and its stability.
pub fn analyse(scene: &Scene, family: Family) -> Result<ViscousSpin, ModelError> {
    let field = ViscousField::from_scene(scene)?;
    if family.tilted() {
        return Err(ModelError::invalid(
            "family",
            Value::Choice(family.name().into()),
            "under the viscous law only the upright and inverted spins are steady (a tilted motion slips, and viscous friction then acts)",
        ));
    }
    let start = families::start_attitude(scene, family);
    let zeta = families::rest_attitude(&field.system.body, start)?;
    families::check_principal(&field.system.body, family, &zeta)?;
    let init = &scene.initial;
    let spin = init
        .omega_body
        .unwrap_or_else(|| init.angles.omega_body())
        .dot(&zeta);
    families::check_derived_rate(&field.system.body, field.system.gravity, "spin n", spin)?;
    spin_at(&field, family, zeta, spin)
}

/// The upright or inverted spin of `base` (a scenario of the viscous model) along the
/// values of one key, and the critical values where its stability changes
/// ([`sweep::sweep_with`], stopped when `cancel` is set).
pub fn sweep(
    base: &Scenario,
    family: Family,
    key: &str,
    values: &[f64],
    cancel: Option<&AtomicBool>,
) -> Result<Sweep<ViscousSpin>, ModelError> {
    sweep::sweep_with(
        base,
        (family, Solve::Spin),
        key,
        values,
        &|scene| analyse(scene, family),
        cancel,
    )
}

/// The steady spin at `spin` in the rest attitude `zeta` of `field` and its spectrum, or
/// why it has none (its Jacobian not finite, or not decomposed: see
/// [`super::spectrum::reduced_modes`]).
pub fn spin_at(
    field: &ViscousField,
    family: Family,
    zeta: Vector3<f64>,
    spin: f64,
) -> Result<ViscousSpin, ModelError> {
    let body = &field.system.body;
    let axes = body.semi_axes();
    let tangent = tangent_basis(&zeta);
    let mut x0 = State9::zeros();
    x0.fixed_rows_mut::<3>(0).copy_from(&zeta);
    x0.fixed_rows_mut::<3>(3).copy_from(&(zeta * spin));
    let rate_scale = spin.abs().max((field.system.gravity / axes.max()).sqrt());
    // Steps: along ζ as `linearize`; ω and h relative to the motion's rate and speed.
    let steps = [
        ZETA_STEP * (axes.min() / axes.max()).powi(2),
        ZETA_STEP * rate_scale,
        ZETA_STEP * rate_scale * axes.max(),
    ];
    let mut jacobian = SMatrix::<f64, 7, 7>::zeros();
    let mut error: f64 = 0.0;
    for col in 0..7 {
        let along = |s: f64| {
            let mut x = x0;
            match col {
                0 | 1 => {
                    let z = zeta * s.cos() + tangent[col] * s.sin();
                    x.fixed_rows_mut::<3>(0).copy_from(&z);
                }
                2..=4 => x[3 + col - 2] += s,
                _ => x.fixed_rows_mut::<3>(6).copy_from(&(tangent[col - 5] * s)),
            }
            field.rate(&x)
        };
        let step = steps[match col {
            0 | 1 => 0,
            2..=4 => 1,
            _ => 2,
        }];
        let (d, err) = richardson(along, step);
        error = error.max(err);
        let (dz, dw, dh) = split(&d);
        let reduced = [
            tangent[0].dot(&dz),
            tangent[1].dot(&dz),
            dw.x,
            dw.y,
            dw.z,
            tangent[0].dot(&dh),
            tangent[1].dot(&dh),
        ];
        for (row, value) in reduced.iter().enumerate() {
            jacobian[(row, col)] = *value;
        }
    }
    let family_direction =
        DVector::from_column_slice(&[0.0, 0.0, zeta.x, zeta.y, zeta.z, 0.0, 0.0]);
    let dynamic = DMatrix::from_fn(7, 7, |i, j| jacobian[(i, j)]);
    let mut modes = reduced_modes(&dynamic, &[family_direction])?;
    modes.sort_by(|x, y| by_real_part(&x.0, &y.0));
    let (eigenvalues, vectors): (Vec<_>, Vec<_>) = modes
        .into_iter()
        .map(|(lambda, v)| (lambda, normalise(&v)))
        .unzip();
    let shape = super::shape(body, zeta);
    let (names, clarity) = vectors
        .iter()
        .map(|v| mode_name(field, &x0, tangent, &shape, v))
        .unzip();
    let normal_force = {
        let y = reduce::full_state(&zeta, &(zeta * spin));
        field.system.evaluate(&y).response.normal
    };
    Ok(ViscousSpin {
        family,
        zeta,
        spin,
        normal_force,
        jacobian,
        tangent,
        eigenvalues,
        vectors,
        error,
        names,
        clarity,
    })
}

/// What moves in the mode `v` (in [`COORDINATES`]) of the spin at `x0`, as under the other
/// laws ([`super::Mode::name`]), told apart by kinetic energy: "slip" if the contact
/// point's slip would carry more of it than G's motion and the rotation together,
/// m |δv_C|² > m |δh|² + δωᵀ I δω (the viscous law's relaxation of the slip; a mode in
/// which the body rolls sideways, G moving but the contact point not slipping, is not
/// one); else, if the axis moves, named
/// by the tilt ("tilt" for a body of revolution; "roll", "pitch" or "wobble" of a triaxial
/// body such as the rattleback, [`tilt_name`]); else "spin". With its clarity
/// ([`super::Mode::clarity`]; a slip's is the ratio of the two energies).
fn mode_name(
    field: &ViscousField,
    x0: &State9,
    tangent: [Vector3<f64>; 2],
    shape: &Shape,
    v: &SVector<Complex<f64>, 7>,
) -> (&'static str, f64) {
    let body = &field.system.body;
    // δv_C = d/ds of the slip along Re v and Im v (central differences: the slip is
    // linear to O(s²), enough to compare energies).
    let step = 1e-7;
    let slip = |part: fn(&Complex<f64>) -> f64| {
        let u = SVector::<f64, 7>::from_iterator(v.iter().map(part));
        let d = direction(tangent, &u) * step;
        (slip_velocity(body, &(x0 + d)) - slip_velocity(body, &(x0 - d))) / (2.0 * step)
    };
    let (slip_re, slip_im) = (slip(|c| c.re), slip(|c| c.im));
    let omega_re = Vector3::new(v[2].re, v[3].re, v[4].re);
    let omega_im = Vector3::new(v[2].im, v[3].im, v[4].im);
    let inertia = body.inertia();
    let rotation = omega_re.dot(&(inertia * omega_re)) + omega_im.dot(&(inertia * omega_im));
    let slipping = body.mass() * (slip_re.norm_squared() + slip_im.norm_squared());
    let tilt = (v[0].norm_sqr() + v[1].norm_sqr()).sqrt();
    let moving = body.mass() * (v[5].norm_sqr() + v[6].norm_sqr());
    if slipping > moving + rotation {
        ("slip", slipping / (moving + rotation))
    } else if tilt > 1e-6 * v.norm() {
        tilt_name(tangent, v[0], v[1], shape)
    } else {
        ("spin", f64::INFINITY)
    }
}

/// The contact point's horizontal slip velocity at `x` (body axes): v_C = v_G + ω × r
/// with r = C − G, its component along ζ removed.
fn slip_velocity(body: &Body, x: &State9) -> Vector3<f64> {
    let (zeta, omega, h) = split(x);
    let zeta = zeta.normalize();
    let r = Contact::new(body, zeta, omega).r;
    let v = h + omega.cross(&r);
    v - zeta * zeta.dot(&v)
}

/// The phase-space displacement (δζ, δω, δh) of `u` (in [`COORDINATES`]) along the
/// tangent basis `tangent`.
fn direction(tangent: [Vector3<f64>; 2], u: &SVector<f64, 7>) -> State9 {
    let [t1, t2] = tangent;
    let mut d = State9::zeros();
    d.fixed_rows_mut::<3>(0).copy_from(&(t1 * u[0] + t2 * u[1]));
    d.fixed_rows_mut::<3>(3)
        .copy_from(&Vector3::new(u[2], u[3], u[4]));
    d.fixed_rows_mut::<3>(6).copy_from(&(t1 * u[5] + t2 * u[6]));
    d
}

/// `v` scaled so that its tilt part has unit norm (the whole vector if it has no tilt),
/// its largest component real and positive.
fn normalise(v: &DVector<Complex<f64>>) -> SVector<Complex<f64>, 7> {
    let v = SVector::<Complex<f64>, 7>::from_column_slice(v.as_slice());
    let tilt = (v[0].norm_sqr() + v[1].norm_sqr()).sqrt();
    let scale = if tilt > 1e-9 * v.norm() {
        tilt
    } else {
        v.norm()
    };
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

/// The scene started on the viscous steady spin displaced by `delta` (δζ tangent, δh
/// horizontal): attitude from ζ (φ = 0), ω in body axes, G's horizontal velocity R h.
pub fn started_at(scene: &Scene, at: &State9, delta: &State9) -> Scene {
    let (zeta, omega, h) = split(&(at + delta));
    let mut scene = scene.clone();
    let init = &mut scene.initial;
    init.angles = reduce::attitude(&zeta);
    init.omega_body = Some(omega);
    init.height = 0.0;
    init.velocity_z = None;
    let rot = init.angles.rotation().to_rotation_matrix().into_inner();
    init.velocity = Some((rot * h).xy());
    scene
}
