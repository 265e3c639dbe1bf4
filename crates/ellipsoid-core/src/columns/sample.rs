//! One output row ([`Sample`]) and the contact phase it was in ([`Mode`]): what every
//! column of this module is read from.

use nalgebra::{Vector2, Vector3};
use serde::Serialize;

use crate::body::Surface;
use crate::model::MOST_CONTACTS;
use crate::state::EulerAngles;

/// One output row (SI units; see `columns` for every column).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub t: f64,
    /// Position of G \[m\] (z from the contact constraint).
    pub position: Vector3<f64>,
    pub angles: EulerAngles,
    /// Body angular velocity [rad/s].
    pub omega: Vector3<f64>,
    /// Angular velocity in world axes [rad/s].
    pub omega_world: Vector3<f64>,
    /// Velocity of G [m/s].
    pub velocity: Vector3<f64>,
    /// The contact point C on the plane \[m\].
    pub contact: Vector2<f64>,
    pub energy: f64,
    /// Dissipated work W \[J\].
    pub work: f64,
    pub normal_force: f64,
    /// |v_C| [m/s].
    pub slip_speed: f64,
    /// Relative drift of the scene's conserved quantity (E, or E + W) since t = 0.
    pub drift: f64,
    /// Height of the body's lowest point above the plane \[m\] (0 in contact).
    pub gap: f64,
    pub mode: Mode,
    /// The surfaces in contact, each with its normal force \[N\]: none in flight, more
    /// than one only in the several-contact phases (their sum is `normal_force`).
    pub touching: [Option<(Surface, f64)>; MOST_CONTACTS],
}

/// The contact phase in force (docs/physics.md, models 1–5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    Frictionless,
    Sliding,
    Rolling,
    /// Off the plane (docs/physics.md, "Flight").
    Flight,
    /// Two surfaces on the plane at once (docs/physics.md, "Several contacts").
    TwoContacts,
    /// Viscous sliding friction (docs/physics.md, "Viscous sliding").
    Viscous,
    /// Three surfaces on the plane at once (docs/physics.md, "Several contacts").
    ThreeContacts,
    /// A rim lying flat: the body on the face its circle bounds (docs/physics.md, "Rims").
    Face,
}

impl Mode {
    /// Every mode, in [`Mode::NAMES`] order.
    pub const ALL: [Mode; 8] = [
        Mode::Frictionless,
        Mode::Sliding,
        Mode::Rolling,
        Mode::Flight,
        Mode::TwoContacts,
        Mode::Viscous,
        Mode::ThreeContacts,
        Mode::Face,
    ];
    /// Their names in output files.
    pub const NAMES: [&'static str; 8] = [
        "frictionless",
        "sliding",
        "rolling",
        "flight",
        "two_contacts",
        "viscous",
        "three_contacts",
        "face",
    ];

    /// Its name in output files.
    pub fn name(self) -> &'static str {
        Mode::NAMES[self as usize]
    }
}
