//! Newton–Euler dynamics of the ellipsoid on the plane, generic over the contact law
//! and the optional effects (docs/physics.md, "Equations of motion").
//!
//! ```text
//!   m a_G   = F + f − m g e3                 F: contact force at C, f: effects' force
//!   I ω̇_b   = r_b × F_b + τ + N τ_N − ω_b × I ω_b
//!   ẋ_G     = v_G (horizontal),  q̇ = ½ q ⊗ ω_b
//!   Ẇ       = −F·v_C − f·v_G − (τ + N τ_N)·ω_b      dissipated power (≥ 0)
//! ```
//! τ_N includes a contact disc's drilling torque per unit N (`contensou`, added by the
//! law through [`ContactLaw::respond_loaded`]), so it enters N's solve and Ẇ.
//! z_G and v_Gz are functions of the orientation (`geometry`), so the contact
//! constraint cannot drift. The contact law ([`ContactLaw`]) decides F from the
//! acceleration-level constraint z̈_G = −u·ω̇ − κ (and, when rolling, v_C = 0).

pub mod contacts;
pub mod contensou;
mod face;
pub mod flight;
mod frictionless;
mod rolling;
pub mod sliding;
mod viscous;

pub use contacts::{Contacts, Forces, Hold, MOST_CONTACTS};
pub use contensou::ContactDisc;
pub use face::Face;
pub use flight::Flight;
pub use frictionless::Frictionless;
pub use rolling::Rolling;
pub use sliding::{Sliding, SlipBand};
pub use viscous::Viscous;

use nalgebra::{Vector2, Vector3};

use crate::body::Body;
use crate::effects::{Effect, Wrench};
use crate::integrate::OdeSystem;
use crate::kinematics::Kinematics;
use crate::state::{self, State};

/// The contact force and the accelerations it implies.
#[derive(Debug, Clone, Copy)]
pub struct Response {
    /// Contact force at C, world frame \[N\].
    pub force: Vector3<f64>,
    /// Normal force N = F·e3 \[N\].
    pub normal: f64,
    /// Angular acceleration, body frame [rad/s²].
    pub omega_dot: Vector3<f64>,
    /// The factor multiplying N in the unilateral contact equation; ≤ 0 means a
    /// Painlevé inconsistency (sliding). Infinite where it does not apply.
    pub painleve: f64,
    /// With several surfaces in contact ([`Contacts`]), the normal forces at the others
    /// \[N\] (`normal` is then the sum of all); 0 otherwise.
    pub other_normals: [f64; MOST_CONTACTS - 1],
    /// The power the contact forces dissipate, where the law computes it (two contacts)
    /// \[W\]; `None`: −F·v_C − N τ_N·ω of the one contact ([`Evaluation::dissipation`]).
    pub contact_power: Option<f64>,
}

/// A contact law: how the plane pushes on the body.
pub trait ContactLaw {
    /// Whether the horizontal velocity of G follows from the constraint (rolling).
    const ROLLING: bool;
    /// Whether the body is off the plane: z_G and v_Gz are states (`model::flight`).
    const FLIGHT: bool = false;
    /// Solves for the contact force given the kinematics, gravity g [m/s²] and effects.
    fn respond(
        &self,
        body: &Body,
        gravity: f64,
        kin: &Kinematics,
        y: &State,
        load: &Wrench,
    ) -> Response;
    /// Restores the law's algebraic relations on an accepted state (see [`OdeSystem::project`]).
    fn project(&self, _body: &Body, _y: &mut State) {}
    /// The point the law acts at, from G in world axes \[m\], and its horizontal velocity
    /// (the slip) [m/s]: the surface's contact point C and v_C by default, the face's
    /// centre for a face ([`Face`]), whose rim's support point is undefined when flat.
    #[inline(always)]
    fn acting_point(&self, _body: &Body, kin: &Kinematics) -> (Vector3<f64>, Vector2<f64>) {
        (kin.rot * kin.contact.r, kin.slip)
    }
    /// [`ContactLaw::respond`] for a law that also adds a load of its own to the effects'
    /// `load` (the drilling torque of a contact disc, per unit N): returns the total load,
    /// which the power balance then books, and the response to it. By default the law
    /// adds nothing.
    #[inline(always)]
    fn respond_loaded(
        &self,
        body: &Body,
        gravity: f64,
        kin: &Kinematics,
        y: &State,
        load: Wrench,
    ) -> (Wrench, Response) {
        let response = self.respond(body, gravity, kin, y, &load);
        (load, response)
    }
}

/// The body on the plane under gravity, a contact law `C` and effects `E`.
#[derive(Debug, Clone)]
pub struct System<C, E> {
    pub body: Body,
    /// g [m/s²].
    pub gravity: f64,
    pub contact: C,
    pub effects: E,
}

/// Everything the right-hand side computes about one state.
#[derive(Debug, Clone, Copy)]
pub struct Evaluation {
    pub kin: Kinematics,
    /// The effects' load, plus what the contact law adds (a contact disc's drilling torque).
    pub load: Wrench,
    pub response: Response,
}

impl Evaluation {
    /// Acceleration of G, world frame: a = (F + f)/m − g e3 [m/s²].
    #[inline]
    pub fn accel(&self, body: &Body, gravity: f64) -> Vector3<f64> {
        (self.response.force + self.load.force) / body.mass() - Vector3::new(0.0, 0.0, gravity)
    }

    /// Dissipated power Ẇ = −F·v_C − f·v_G − (τ + N τ_N)·ω \[W\] (with two contacts the
    /// law's own sum over them, [`Response::contact_power`], replaces −F·v_C − N τ_N·ω).
    #[inline]
    pub fn dissipation(&self) -> f64 {
        let r = &self.response;
        if let Some(contact) = r.contact_power {
            return contact
                - self.load.force.dot(&self.kin.v_g)
                - self.load.torque.dot(&self.kin.omega);
        }
        let torque = self.load.torque + r.normal * self.load.torque_per_normal;
        -(r.force.xy().dot(&self.kin.slip))
            - self.load.force.dot(&self.kin.v_g)
            - torque.dot(&self.kin.omega)
    }
}

impl<C: ContactLaw, E: Effect> System<C, E> {
    /// Evaluates kinematics, loads and the contact response at `y`.
    #[inline(always)]
    pub fn evaluate(&self, y: &State) -> Evaluation {
        let kin = if C::FLIGHT {
            Kinematics::flying(&self.body, y)
        } else {
            Kinematics::new(&self.body, y, C::ROLLING)
        };
        let load = self.effects.wrench(&self.body, &kin);
        let (load, response) = self
            .contact
            .respond_loaded(&self.body, self.gravity, &kin, y, load);
        Evaluation {
            kin,
            load,
            response,
        }
    }

    /// dy/dt at `y` from its evaluation `ev` (see the module docs): ẋ_G = v_G,
    /// q̇ = ½ q ⊗ ω_b, v̇_G = a_G, ω̇_b, Ẇ, and in flight ż_G = v_Gz, v̇_Gz = a_Gz.
    #[inline(always)]
    pub fn derivative(&self, y: &State, ev: &Evaluation) -> State {
        let accel = ev.accel(&self.body, self.gravity);
        let q_dot = state::quaternion_rate(&state::quaternion(y), &ev.kin.omega);
        let mut dy = State::zeros();
        dy[state::POS] = ev.kin.v_g.x;
        dy[state::POS + 1] = ev.kin.v_g.y;
        dy[state::QUAT] = q_dot.w;
        dy[state::QUAT + 1] = q_dot.i;
        dy[state::QUAT + 2] = q_dot.j;
        dy[state::QUAT + 3] = q_dot.k;
        dy[state::VEL] = accel.x;
        dy[state::VEL + 1] = accel.y;
        dy.fixed_rows_mut::<3>(state::OMEGA)
            .copy_from(&ev.response.omega_dot);
        dy[state::WORK] = ev.dissipation();
        if C::FLIGHT {
            dy[state::HEIGHT] = ev.kin.v_g.z;
            dy[state::VEL_Z] = accel.z;
        }
        dy
    }
}

impl<C: ContactLaw, E: Effect> OdeSystem<{ state::DIM }> for System<C, E> {
    #[inline]
    fn rhs(&self, _t: f64, y: &State) -> State {
        self.derivative(y, &self.evaluate(y))
    }

    fn project(&self, y: &mut State) {
        let q = state::quaternion(y).normalize();
        y.fixed_rows_mut::<4>(state::QUAT)
            .copy_from(&nalgebra::Vector4::new(q.w, q.i, q.j, q.k));
        self.contact.project(&self.body, y);
    }
}

/// Unilateral contact with the force along a known world direction d (d·e3 = 1):
/// F = N d. From m z̈_G = N + f_z − m g and z̈_G = −u·ω̇ − κ with
/// I ω̇ = N ℓ + T, ℓ = r × d_b + τ_N, T = τ − ω × Iω:
/// ```text
///   N (1 + m u·I⁻¹ℓ) = m g − f_z − m u·I⁻¹T − m κ
/// ```
/// (docs/physics.md, models 1 and 2; d = e3 gives the frictionless law, d = e3 − μ_v v_C
/// the viscous one.)
#[inline(always)]
pub(crate) fn unilateral(
    body: &Body,
    gravity: f64,
    kin: &Kinematics,
    load: &Wrench,
    d: Vector3<f64>,
) -> Response {
    let m = body.mass();
    let i_inv = body.inertia_inv();
    let c = &kin.contact;
    let d_b = kin.rot.tr_mul(&d);
    let lever = c.r.cross(&d_b) + load.torque_per_normal;
    let free = load.torque - kin.omega.cross(&(body.inertia() * kin.omega));
    let painleve = 1.0 + m * c.u.dot(&(i_inv * lever));
    let normal =
        (m * gravity - load.force.z - m * c.u.dot(&(i_inv * free)) - m * c.kappa) / painleve;
    Response {
        force: normal * d,
        normal,
        omega_dot: i_inv * (normal * lever + free),
        painleve,
        other_normals: [0.0; MOST_CONTACTS - 1],
        contact_power: None,
    }
}
