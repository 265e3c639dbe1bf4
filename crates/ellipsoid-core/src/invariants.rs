//! Conserved and balanced quantities (docs/physics.md, "Invariants"), each declared once
//! ([`Invariant`]) with its name, unit, drift scale and the scenes that conserve it.
//!
//! ```text
//!   E   = ½ m |v_G|² + ½ ω_bᵀ I ω_b + m g z_G          energy
//!   p   = m v_G (horizontal)                            momentum (frictionless)
//!   L_z = e3·(R I ω_b) = ζ·(I ω_b)                      vertical angular momentum about G
//!   n   = ω·e3* = ω_b,3                                 axial spin (body of revolution)
//!   J   = L_G·(G − C) = −(I ω_b)·r_b                    Jellett's quantity (sphere, CM on axis)
//!   E + W                                               work–energy balance (W dissipated)
//! ```

use nalgebra::Vector2;
use serde::Serialize;

use crate::body::Body;
use crate::kinematics::Kinematics;
use crate::state::{self, State};

/// The invariant quantities of one state (SI units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Invariants {
    /// E \[J\].
    pub energy: f64,
    /// E + W \[J\].
    pub energy_plus_work: f64,
    /// m v_G, horizontal [kg·m/s].
    pub momentum: [f64; 2],
    /// L_z about G [kg·m²/s].
    pub angular_momentum_z: f64,
    /// ω·e3* [rad/s].
    pub axial_spin: f64,
    /// J = L_G·(G − C) [kg·m³/s].
    pub jellett: f64,
}

impl Invariants {
    /// Evaluates the invariants; `rolling` takes v_G from the no-slip constraint.
    pub fn of(body: &Body, gravity: f64, y: &State, rolling: bool) -> Self {
        let kin = Kinematics::new(body, y, rolling);
        Invariants::from_kinematics(body, gravity, &kin, y[state::WORK])
    }

    /// Evaluates the invariants from already computed kinematics and dissipated work W \[J\].
    pub fn from_kinematics(body: &Body, gravity: f64, kin: &Kinematics, work: f64) -> Self {
        let m = body.mass();
        let l_body = body.inertia() * kin.omega;
        let energy = 0.5 * m * kin.v_g.norm_squared()
            + 0.5 * kin.omega.dot(&l_body)
            + m * gravity * kin.z_g();
        let p: Vector2<f64> = m * kin.v_g.xy();
        Invariants {
            energy,
            energy_plus_work: energy + work,
            momentum: [p.x, p.y],
            angular_momentum_z: kin.contact.zeta.dot(&l_body),
            axial_spin: kin.omega.z,
            jellett: -l_body.dot(&kin.contact.r),
        }
    }
}

/// The invariants a run tracks, declared once: name (in summaries and `[check]`), unit,
/// value, the scale its drift is divided by, and the scenes that conserve it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Invariant {
    Energy,
    EnergyPlusWork,
    Momentum,
    AngularMomentumZ,
    AxialSpin,
    Jellett,
}

/// Which conservation laws a scene has (from its body, contact model and effects).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Conservation {
    /// No optional effects.
    pub conservative: bool,
    /// Conservative and frictionless.
    pub frictionless: bool,
    /// Conservative, frictionless or rolling: E itself is conserved.
    pub energy: bool,
    /// A body of revolution with G on its axis and axisymmetric inertia.
    pub revolution: bool,
    /// A sphere (of revolution with a = c).
    pub sphere: bool,
    /// No impact can dissipate energy: lift-off stops the run, or impacts are
    /// frictionless and elastic (e = 1). Else E is conserved only until the first impact
    /// and the `drift` column follows E + W (equal to E until then).
    pub elastic_impacts: bool,
}

impl Invariant {
    /// Every invariant, in summary order.
    pub const ALL: [Invariant; 6] = [
        Invariant::Energy,
        Invariant::EnergyPlusWork,
        Invariant::Momentum,
        Invariant::AngularMomentumZ,
        Invariant::AxialSpin,
        Invariant::Jellett,
    ];

    /// The names of [`Invariant::ALL`], as summaries and `[check]` tables spell them.
    pub const NAMES: [&'static str; 6] = [
        "energy",
        "energy_plus_work",
        "momentum",
        "angular_momentum_z",
        "axial_spin",
        "jellett",
    ];

    /// Its name in summaries and `[check]` tables.
    pub fn name(self) -> &'static str {
        Invariant::NAMES[self as usize]
    }

    /// Its SI unit.
    pub fn unit(self) -> &'static str {
        match self {
            Invariant::Energy | Invariant::EnergyPlusWork => "J",
            Invariant::Momentum => "kg m/s",
            Invariant::AngularMomentumZ => "kg m^2/s",
            Invariant::AxialSpin => "rad/s",
            Invariant::Jellett => "kg m^3/s",
        }
    }

    /// Its value in `inv` (the horizontal momentum by its magnitude).
    pub fn value(self, inv: &Invariants) -> f64 {
        match self {
            Invariant::Energy => inv.energy,
            Invariant::EnergyPlusWork => inv.energy_plus_work,
            Invariant::Momentum => inv.momentum[0].hypot(inv.momentum[1]),
            Invariant::AngularMomentumZ => inv.angular_momentum_z,
            Invariant::AxialSpin => inv.axial_spin,
            Invariant::Jellett => inv.jellett,
        }
    }

    /// The scale of its drift, from the initial state: |E|, |E + W|, m(|v_G| + |ω||r|),
    /// |Iω|, |ω|, |Iω||r| (momentum-like quantities may start at 0, so they are scaled by
    /// what the body's motion could give them).
    pub fn scale(self, body: &Body, kin: &Kinematics, inv: &Invariants) -> f64 {
        let l = (body.inertia() * kin.omega).norm();
        let r = kin.contact.r.norm();
        match self {
            Invariant::Energy => inv.energy.abs(),
            Invariant::EnergyPlusWork => inv.energy_plus_work.abs(),
            Invariant::Momentum => body.mass() * (kin.v_g.norm() + kin.omega.norm() * r),
            Invariant::AngularMomentumZ => l,
            Invariant::AxialSpin => kin.omega.norm(),
            Invariant::Jellett => l * r,
        }
    }

    /// Whether a scene with these conservation laws conserves it (docs/physics.md,
    /// "Invariants"): E + W always; E without friction or effects, or rolling; p, L_z
    /// frictionless; ω·e3* frictionless for a body of revolution; Jellett's J for a
    /// sphere without effects.
    pub fn conserved(self, c: &Conservation) -> bool {
        match self {
            Invariant::Energy => c.energy,
            Invariant::EnergyPlusWork => true,
            Invariant::Momentum | Invariant::AngularMomentumZ => c.frictionless,
            Invariant::AxialSpin => c.frictionless && c.revolution,
            Invariant::Jellett => c.conservative && c.sphere,
        }
    }
}

/// Largest deviation of each conserved invariant from its initial value, over the output
/// samples and the final state (not between samples), divided by its
/// [`Invariant::scale`]; `None` where the scene does not conserve it. Serialised as a map
/// from [`Invariant::name`] to the drift (or null).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Drift(pub [Option<f64>; 6]);

impl Drift {
    /// The drift of one invariant.
    pub fn get(&self, which: Invariant) -> Option<f64> {
        self.0[which as usize]
    }

    /// (invariant, drift) in [`Invariant::ALL`] order.
    pub fn iter(&self) -> impl Iterator<Item = (Invariant, Option<f64>)> + '_ {
        Invariant::ALL.into_iter().zip(self.0)
    }

    /// The largest drift of any conserved invariant.
    pub fn max(&self) -> Option<f64> {
        self.0.iter().flatten().copied().reduce(f64::max)
    }
}

impl Serialize for Drift {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = serializer.serialize_map(Some(6))?;
        for (which, d) in self.iter() {
            map.serialize_entry(which.name(), &d)?;
        }
        map.end()
    }
}
