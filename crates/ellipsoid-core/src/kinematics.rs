//! The velocity-level description of one state that the contact laws, the effects and
//! the hybrid machine share: rotation, ω, the contact geometry, v_G, the slip v_C and the
//! gap (docs/physics.md, "Equations of motion" and "Flight").

use nalgebra::{Matrix3, Vector2, Vector3};

use crate::body::{Body, Surface};
use crate::geometry::Contact;
use crate::state::{self, State};

/// Everything velocity-level about one state, shared by the contact laws and effects.
#[derive(Debug, Clone, Copy)]
pub struct Kinematics {
    /// Rotation body -> world.
    pub rot: Matrix3<f64>,
    /// Angular velocity, body frame [rad/s].
    pub omega: Vector3<f64>,
    /// Contact geometry (body frame).
    pub contact: Contact,
    /// Velocity of G, world frame, v_Gz from the constraint [m/s].
    pub v_g: Vector3<f64>,
    /// Horizontal velocity of the material contact point, v_C = v_G + ω × r [m/s].
    pub slip: Vector2<f64>,
    /// Gap between the body's lowest point and the plane, z_G − h(ζ) \[m\]: 0 in contact.
    pub gap: f64,
}

impl Kinematics {
    /// Kinematics of state `y`; with `rolling`, v_G = −ω × r (the state's v_G is ignored).
    #[inline(always)]
    pub fn new(body: &Body, y: &State, rolling: bool) -> Self {
        let rot = state::rotation(y);
        let omega = state::omega(y);
        let zeta = Vector3::new(rot[(2, 0)], rot[(2, 1)], rot[(2, 2)]);
        let contact = Contact::new(body, zeta, omega);
        let spin_lever = rot * omega.cross(&contact.r); // ω × r, world
        let v_h = if rolling {
            -spin_lever.xy()
        } else {
            state::velocity(y)
        };
        let v_g = Vector3::new(v_h.x, v_h.y, contact.vz());
        Kinematics {
            rot,
            omega,
            contact,
            v_g,
            slip: v_h + spin_lever.xy(),
            gap: 0.0,
        }
    }

    /// Kinematics of a state in flight (docs/physics.md, "Flight"): z_G and v_Gz are
    /// states, the gap is g = z_G − h(ζ) with h(ζ) the height G would have touching
    /// (`geometry`), and `contact` describes the body's lowest point, on whichever
    /// surface it is (`Contact::lowest`); `slip` is that point's horizontal velocity.
    #[inline]
    pub fn flying(body: &Body, y: &State) -> Self {
        let rot = state::rotation(y);
        let omega = state::omega(y);
        let zeta = Vector3::new(rot[(2, 0)], rot[(2, 1)], rot[(2, 2)]);
        Kinematics::flying_with(Contact::lowest(body, zeta, omega), rot, omega, y)
    }

    /// [`Kinematics::flying`] with `contact` describing the lowest point of `surface`
    /// (its gap may be above another surface's).
    #[inline]
    pub fn flying_at(body: &Body, surface: Surface, y: &State) -> Self {
        let rot = state::rotation(y);
        let omega = state::omega(y);
        let zeta = Vector3::new(rot[(2, 0)], rot[(2, 1)], rot[(2, 2)]);
        Kinematics::flying_with(Contact::of(body, surface, zeta, omega), rot, omega, y)
    }

    #[inline(always)]
    fn flying_with(contact: Contact, rot: Matrix3<f64>, omega: Vector3<f64>, y: &State) -> Self {
        let spin_lever = rot * omega.cross(&contact.r);
        let v_h = state::velocity(y);
        Kinematics {
            rot,
            omega,
            contact,
            v_g: Vector3::new(v_h.x, v_h.y, y[state::VEL_Z]),
            slip: v_h + spin_lever.xy(),
            gap: y[state::HEIGHT] - contact.height,
        }
    }

    /// Height of G, h(ζ) + gap \[m\].
    #[inline]
    pub fn z_g(&self) -> f64 {
        self.contact.height + self.gap
    }
}
