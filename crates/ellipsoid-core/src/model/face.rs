//! A body lying on the flat face a rim bounds (docs/physics.md, "Rims": "Lying on the
//! face"). The rim's axis stands vertical, so ω = Ω e3 and v_Gz = 0; the face's pressure
//! holds the tilt (its centre of pressure inside the face), and the contact acts on the
//! face's centre C_f = c − r ζ̂ (c the rim's centre, r its edge):
//! ```text
//!   N   = m g − f_z                                   the plane carries the weight
//!   v_f = v_G + ω × (C_f − G)                          slip of the face's centre
//!   F_h = μN f(d) (−v̂_f),   M = −μN R g(d) sgn Ω      Coulomb–Contensou over the face's
//!                                                     disc of radius R, uniform pressure
//!   m v̇_G = F_h + f_h,      I_zz Ω̇ = M + τ_z + N τ_N,z + ((C_f − G) × F)_z
//! ```
//! I_zz = e3·I_w e3 (I_w the inertia in world axes); the horizontal torques are the
//! face's to carry. Frictionless, F_h = M = 0. A face at rest (v_f = 0, Ω = 0) stays at
//! rest: the plane holds it (the rolling model's face grips at once).

use nalgebra::{UnitQuaternion, Vector2, Vector3};

use super::contensou::Law;
use super::{ContactLaw, MOST_CONTACTS, Response};
use crate::body::Body;
use crate::effects::Wrench;
use crate::kinematics::Kinematics;
use crate::state::{self, State};

/// The face's contact: its rim, and the friction on it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Face {
    /// The rim's centre c from C0, body axes \[m\].
    pub center: Vector3<f64>,
    /// The rim's edge radius r \[m\]: the face lies r below the rim's circle.
    pub edge: f64,
    /// The face's radius R (the rim's) \[m\].
    pub radius: f64,
    /// The friction coefficient μ and the disc's law; `None` frictionless.
    pub friction: Option<(f64, Law)>,
}

impl Face {
    /// Turns the attitude of `y` so that the body's z axis, up or down, is vertical: the
    /// shortest rotation, by the tilt (at most the scene's `Landing::flat_tilt` at a flat
    /// landing). With u = ±(R e3) = (x, y, z), z > 0, it is the quaternion
    /// (w, y/2w, −x/2w, 0), w = √((1 + z)/2): exact to round-off however small the tilt.
    pub fn flatten(y: &mut State) {
        let q = UnitQuaternion::new_normalize(state::quaternion(y));
        let up = q * Vector3::z();
        let up = up * up.z.signum();
        let w = (0.5 * (1.0 + up.z)).sqrt();
        let turn = UnitQuaternion::new_normalize(nalgebra::Quaternion::new(
            w,
            up.y / (2.0 * w),
            -up.x / (2.0 * w),
            0.0,
        ));
        state::set_quaternion(y, &(turn * q));
    }

    /// The lever C_f − G in world axes at `kin` \[m\], C_f = c − r ζ (ζ = ±e3 in body
    /// axes, the face below).
    #[inline]
    pub fn lever(&self, body: &Body, kin: &Kinematics) -> Vector3<f64> {
        kin.rot * (self.center - self.edge * kin.contact.zeta - body.com_offset())
    }

    /// The slip of the face's centre v_f = v_G + ω × (C_f − G), horizontal [m/s], and the
    /// spin Ω = ω·e3 [rad/s].
    #[inline]
    pub fn slip(&self, body: &Body, kin: &Kinematics) -> (Vector2<f64>, f64) {
        let omega = kin.rot * kin.omega;
        let v = kin.v_g + omega.cross(&self.lever(body, kin));
        (v.xy(), omega.z)
    }
}

impl ContactLaw for Face {
    const ROLLING: bool = false;

    #[inline]
    fn acting_point(&self, body: &Body, kin: &Kinematics) -> (Vector3<f64>, Vector2<f64>) {
        (self.lever(body, kin), self.slip(body, kin).0)
    }

    #[inline]
    fn respond(
        &self,
        body: &Body,
        gravity: f64,
        kin: &Kinematics,
        _y: &State,
        load: &Wrench,
    ) -> Response {
        let normal = body.mass() * gravity - load.force.z;
        let (slip, spin) = self.slip(body, kin);
        let traction = self
            .friction
            .and_then(|(mu, law)| {
                let (f, m) = law.traction(slip, spin, self.radius)?;
                Some((mu * normal * f, mu * normal * m))
            })
            .unwrap_or((Vector2::zeros(), 0.0));
        let force = Vector3::new(traction.0.x, traction.0.y, normal);
        // The effects' torques, the per-unit-N ones (spin friction) at this N.
        let effects = load.torque + normal * load.torque_per_normal;
        let torque_z = traction.1 + (kin.rot * effects).z + self.lever(body, kin).cross(&force).z;
        // I_zz = e3·(R I Rᵀ) e3 = ζᵀ I ζ.
        let zeta = kin.contact.zeta;
        let i_zz = zeta.dot(&(body.inertia() * zeta));
        Response {
            force,
            normal,
            omega_dot: zeta * (torque_z / i_zz),
            painleve: f64::INFINITY,
            other_normals: [0.0; MOST_CONTACTS - 1],
            contact_power: Some(
                -traction.0.dot(&slip)
                    - traction.1 * spin
                    - normal * load.torque_per_normal.dot(&kin.omega),
            ),
        }
    }

    /// Keeps the face flat and ω along the vertical: the axis turned back onto the
    /// vertical (the integrator's error in q, of the tolerance's size), ω_b = (ω_b·ζ) ζ.
    fn project(&self, _body: &Body, y: &mut State) {
        Face::flatten(y);
        let zeta = state::rotation(y).row(2).transpose();
        let omega = state::omega(y);
        y.fixed_rows_mut::<3>(state::OMEGA)
            .copy_from(&(zeta * omega.dot(&zeta)));
    }
}
