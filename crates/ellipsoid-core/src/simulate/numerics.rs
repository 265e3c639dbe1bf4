//! The hybrid machine's numerics, named once: every floor, band, confirmation tolerance
//! and settling rule the transitions use, built once per run from the solver, the
//! contact and gravity (docs/physics.md, "The slip stop, numerically", "Settling", "The
//! hybrid machine"). Each constant states its derivation or the measurement that chose
//! it.

use crate::body::Body;
use crate::integrate::{Method, Options};
use crate::kinematics::Kinematics;
use crate::model::sliding::SLIP_FLOOR;
use crate::model::{Evaluation, Sliding, SlipBand};
use crate::state;

use super::scene::Scene;

/// Most mode switches (impacts included) a run may make before it is declared
/// chattering.
pub(super) const MAX_SWITCHES: usize = 10_000;

/// Below this the sliding normal-force denominator (≥ 1 without friction) has collapsed:
/// N = numerator/denominator is a thousand times its frictionless size and goes to
/// infinity with the denominator (the Painlevé singularity). The sliding phase stops where
/// the denominator falls through this value — a state whose N is still determined (to
/// ~1e-13 relative), where a stop located at the zero itself would report N from a
/// denominator of round-off size and either sign — and a solver failure below it is
/// reported as that singularity.
pub(super) const PAINLEVE_COLLAPSE: f64 = 1e-3;

/// A fixed-step method cannot resolve a slip smaller than friction removes in a few
/// steps (μ g h each, times the lever's gain): below this many of those, the slip counts
/// as stopped. Chosen so that the paper's RK4 at h = 1e-4 s stops the paper's sliding
/// scene where DOP853 does instead of chattering on (see docs/hard-cases.md).
const RK4_SLIP_STEPS: f64 = 10.0;

/// A located slip stop is taken at once if its stop speed is within this many stop
/// thresholds ([`Numerics::stop_threshold`]); above that it is checked by the tight
/// solve (`phase::sliding`).
const SLIP_ACCEPT: f64 = 2.0;

/// The tight solve that confirms a slip stop: its tolerances relative to the scene's
/// (never below [`CONFIRM_RTOL_MIN`]); its horizon in units of the time s/(μ g) Coulomb
/// friction of μ m g needs to remove the slip s (a slip being removed at less than a
/// tenth of that rate is not stopping); the largest s it is tried for, in stop thresholds
/// (the stop leaves s to the sticking impulse, so s must stay a small multiple of the
/// integration error: a crossing at a larger slip is a turn, docs/hard-cases.md row 2d);
/// the growth of the slip that refutes the stop; and its step budget.
const CONFIRM_TIGHTEN: f64 = 1e-3;
const CONFIRM_RTOL_MIN: f64 = 1e-13;
pub(super) const CONFIRM_HORIZON: f64 = 10.0;
const CONFIRM_BAND: f64 = 20.0;
pub(super) const CONFIRM_GROWTH: f64 = 2.0;
const CONFIRM_MAX_STEPS: u64 = 10_000;

/// A sliding run that fails with `FastRate` at a fastest rate ρ within this factor of its
/// slip's direction relaxation μN/(m|v_C|) was held by that relaxation at a vanishing
/// slip, and takes the slip stop there (`phase::sliding`, on failure). The factor covers
/// the contact's mobility, which exceeds 1/m by the body's rotation (measured: ρ from
/// 1.2 to 6 times μN/(m|v_C|) on the random scenes that failed so).
pub(super) const SLIP_RATE_FACTOR: f64 = 30.0;

/// Slips below this many slip floors (or absolute tolerances), and below [`SLIP_BAND_CAP`]
/// of the speed scale, have their friction direction blended towards s_ref
/// (docs/physics.md, "The slip stop, numerically"). Measured on random stick–slip scenes:
/// 10 floors leaves DOPRI5 trapped at 20 floors on some (slip held at 7e-7 m/s for 0.03 s
/// where DOP853's grows to 3e-3), 100 floors frees it; a band of 1e-4 of the speed scale
/// (100 floors at rtol 1e-6) changes the stick–slip sequence, 1e-5 does not.
const SLIP_BAND_FLOORS: f64 = 100.0;
const SLIP_BAND_CAP: f64 = 1e-5;

/// A contact disc's stop is taken within this many slip floors (or absolute tolerances)
/// under an adaptive method: near w = 0 the disc's friction turns at a rate ∝ 1/|w|, and
/// measured on 1000 random scenes (seed 7 of `examples/campaign.rs`) DOPRI5 at rtol 1e-10
/// held |w| a few floors up with collapsing steps until max_steps (2 scenes), or crossed
/// w = 0 at 2.4 floors and slid on through the stop; the threshold scales with the
/// tolerances, so the stop converges with them.
const DISC_STOP_FLOORS: f64 = 10.0;

/// The slip a sliding onset starts with, relative to the speed scale |v_G| + |ω||r|: ten
/// times the round-off bound of `model::sliding` (below it the law takes s_ref for the
/// slip's direction), far below every slip floor (≥ 1e-10).
pub(super) const SLIP_SEED: f64 = 1e-12;

/// The slip a contact released on several contacts starts with, in several-contact slip
/// stops ([`Numerics::two_contact_stop`]): twice the stop, so that its slip-stop watch
/// starts above its zero (docs/physics.md, "Several contacts"). Where a contact that stops
/// cannot stick alone, another whose slip is within this seed stops with it
/// (`transition::grip`).
pub(super) const RELEASE_SEED_STOPS: f64 = 2.0;

/// Round-off of the gap z_G − h(ζ), in units of ε (|z_G| + L) (see
/// [`Numerics::gap_resolution`]).
const GAP_ROUNDOFF: f64 = 4.0;

/// The rise, in gap resolutions δz, below which a second surface's rebound is not
/// resolved while the body touches the plane with another (docs/physics.md, "Settling at a
/// second surface"): its gap h_1(ζ) − h_2(ζ) is a difference of two heights, located on
/// the contact phase's dense output, and bounces that rise 4 to 8 δz stall there instead
/// of decaying (random scenes with contact spheres).
pub(super) const SECOND_GAP_RISE: f64 = 16.0;

/// The depth below the plane, in units of the body's size L, beyond which a surface not
/// in contact stops the run `below_plane` (`Numerics::penetration`): a million times the
/// gap's round-off (4ε), where every located touchdown leaves gaps within a few δz (the
/// deepest measured on the random scenes with contact spheres, −2e-17 m).
const PENETRATION: f64 = 1e-9;

/// Round-off of an event's time t, in units of ε |t|: four times the tolerance to which
/// the integrator locates it (`integrate::events` `time_tolerance`, 4ε max(|t|, h)), and
/// below which it takes no zero at the start of a segment (see
/// [`Numerics::time_resolution`]).
const TIME_ROUNDOFF: f64 = 16.0;

/// Newton steps that take a touchdown back to gap = 0 (`transition::back_to_contact`);
/// each is one RK4 step of the flight system, and the first already leaves a gap of
/// O(a δz²/v_n²).
pub(super) const BACK_STEPS: usize = 3;

/// Relative size below which the gap's free acceleration counts as zero: N's solve sums
/// terms of size m(g + |ω|²L + |f|/m), each a few roundings deep.
pub(super) const GAP_ACCEL_ROUNDOFF: f64 = 1e-9;

/// Round-off of the normal force, in units of ε m (g + |ω|²L + |f|/m) (see
/// [`Numerics::reported_normal`]).
const NORMAL_ROUNDOFF: f64 = 16.0;

/// The numbers of one run (see the module docs).
#[derive(Debug, Clone, Copy)]
pub(super) struct Numerics {
    /// The relative slip floor ε = max([`SLIP_FLOOR`], rtol): a slip below the
    /// integration error is no slip.
    pub(super) slip_floor: f64,
    /// The absolute slip floor [m/s]: for fixed-step RK4, [`RK4_SLIP_STEPS`]·μ g h (a slip
    /// friction removes within a few steps cannot be resolved); 0 otherwise.
    pub(super) v_min: f64,
    /// The speed √(g L) of a body of size L under gravity [m/s]: the scale of a contact
    /// disc's stop speed where the motion's own scale |v_G| + |ω||r| vanishes with it (a
    /// body spinning in place).
    gravity_speed: f64,
    /// The slip band of the sliding law.
    pub(super) band: SlipBand,
    /// The body's size L \[m\]: its largest semi-axis, or a contact sphere's reach
    /// |c| + ρ from C0 where that is larger.
    size: f64,
    /// The scene's tolerances and method.
    rtol: f64,
    atol: f64,
    rk4: bool,
}

impl Numerics {
    /// The numerics of `scene`.
    pub(super) fn new(scene: &Scene) -> Self {
        let s = &scene.solver;
        let rk4 = matches!(s.method, Method::Rk4 { .. });
        let slip_floor = SLIP_FLOOR.max(s.rtol);
        let v_min = match (s.method, scene.contact.friction()) {
            (Method::Rk4 { h }, Some(friction)) => RK4_SLIP_STEPS * friction * scene.gravity * h,
            _ => 0.0,
        };
        // The body's extent from C0: its largest semi-axis, or a contact sphere's reach.
        let size = scene.body.reach();
        // The band: SLIP_BAND_FLOORS slip floors or as many absolute tolerances (the error
        // allowed in v_G alone, which dominates a slow motion's), whichever is wider, and at
        // most SLIP_BAND_CAP of the speed scale; none for fixed-step RK4, whose absolute
        // floor v_min already covers the slips it cannot resolve.
        let band = if rk4 {
            SlipBand::NONE
        } else {
            SlipBand {
                relative: SLIP_BAND_FLOORS * slip_floor,
                absolute: SLIP_BAND_FLOORS * s.atol,
                cap: SLIP_BAND_CAP,
            }
        };
        Numerics {
            slip_floor,
            v_min,
            gravity_speed: (scene.gravity * size).sqrt(),
            band,
            size,
            rtol: s.rtol,
            atol: s.atol,
            rk4,
        }
    }

    /// The stop speed below which the slip counts as stopped [m/s]: for a point contact
    /// max(ε S, v_min), S = |v_G| + |ω||r|. For a contact disc, whose stop speed
    /// |w| = √(|v_C|² + (R ω_n)²) may vanish with the whole motion (a body spinning in
    /// place), S' = max(S, √(g L)) replaces S, and the stop is taken within
    /// [`DISC_STOP_FLOORS`] times max(ε S', atol) (adaptive methods; see there).
    pub(super) fn stop_threshold(&self, kin: &Kinematics, disc: bool) -> f64 {
        let scale = Sliding::speed_scale(kin);
        if !disc {
            return (self.slip_floor * scale).max(self.v_min);
        }
        let floor = self.slip_floor * scale.max(self.gravity_speed);
        if self.rk4 {
            floor.max(self.v_min)
        } else {
            DISC_STOP_FLOORS * floor.max(self.atol)
        }
    }

    /// The slip below which one of two contacts counts as stopped [m/s] (in the Coulomb
    /// model it sticks there; docs/physics.md, "Several contacts"): the sliding law's slip
    /// band width ([`SlipBand::width_at`]), at least the stop threshold, both for the
    /// speed scale S' = max(S, √(g L)), as a contact disc's stop takes it: where the whole
    /// body barely moves (settling on two contacts from rest), S is of the size of the
    /// slip itself, and a stop relative to S alone is never reached. The
    /// two-contact law has no band: its friction direction turns at a rate ∝ 1/|v_C| all
    /// the way down, and DOPRI5 at rtol 1e-10 held such slips near the floor (1.0–1.02
    /// floors where instrumented) with collapsing steps until the pace check ended the
    /// run (`FastRate`; seed 26 scene 28 and seed 27 scenes 367 and 585 of
    /// `examples/campaign.rs --spheres`, pinned in tests/campaign.rs), where DOP853
    /// crossed the floor. At the band's edge both cross in a few steps; the stop moves by
    /// at most the time friction takes to remove the band's slip, band/(μ g).
    pub(super) fn two_contact_stop(&self, kin: &Kinematics) -> f64 {
        let scale = Sliding::speed_scale(kin).max(self.gravity_speed);
        (self.band.width_at(scale))
            .max(self.slip_floor * scale)
            .max(self.v_min)
    }

    /// Whether stop speed `speed` has stopped at `kin`: within [`SLIP_ACCEPT`] stop
    /// thresholds.
    pub(super) fn has_stopped(&self, speed: f64, kin: &Kinematics, disc: bool) -> bool {
        speed <= SLIP_ACCEPT * self.stop_threshold(kin, disc)
    }

    /// Whether a located slip stop at stop speed `speed` is close enough to zero for the
    /// tight solve to try it (within [`CONFIRM_BAND`] stop thresholds); never for RK4.
    pub(super) fn may_confirm(&self, speed: f64, kin: &Kinematics, disc: bool) -> bool {
        !self.rk4 && speed <= CONFIRM_BAND * self.stop_threshold(kin, disc)
    }

    /// The tight solve's options: [`CONFIRM_TIGHTEN`] times the scene's tolerances (rtol
    /// never below [`CONFIRM_RTOL_MIN`]), [`CONFIRM_MAX_STEPS`] steps, no stiffness test.
    pub(super) fn confirm_options(&self) -> Options<{ state::DIM }> {
        let rtol = (self.rtol * CONFIRM_TIGHTEN).max(CONFIRM_RTOL_MIN);
        let mut options = Options::new(rtol, self.atol * CONFIRM_TIGHTEN);
        options.max_steps = CONFIRM_MAX_STEPS;
        options.stiffness_check = false;
        options
    }

    /// The normal force of evaluation `ev` as reported in a sample \[N\]: 0 where it is
    /// round-off, |N| ≤ [`NORMAL_ROUNDOFF`]·ε·m (g + |ω|²L + |f|/m) — the size of the terms
    /// N's solve sums (a rolling body without gravity has N ~ −1e-17 N, which is no force).
    pub(super) fn reported_normal(&self, body: &Body, gravity: f64, ev: &Evaluation) -> f64 {
        let n = ev.response.normal;
        let m = body.mass();
        let scale = m * (gravity + ev.kin.omega.norm_squared() * self.size) + ev.load.force.norm();
        if n.abs() <= NORMAL_ROUNDOFF * f64::EPSILON * scale {
            0.0
        } else {
            n
        }
    }

    /// The gap's round-off δz = 4ε(|z_G| + L) \[m\]: the gap z_G − h(ζ) is a difference of
    /// two heights of that size, each a few roundings deep. Touchdown is the gap falling
    /// through −δz, so that a gap that is zero to round-off (a body leaving the plane, or
    /// touching it without approaching) is no touchdown.
    pub(super) fn gap_resolution(&self, kin: &Kinematics) -> f64 {
        GAP_ROUNDOFF * f64::EPSILON * (kin.z_g().abs() + self.size)
    }

    /// The body's size L \[m\]: its extent from C0.
    pub(super) fn size(&self) -> f64 {
        self.size
    }

    /// The penetration tolerance 1e-9 L \[m\] (see [`PENETRATION`]).
    pub(super) fn penetration(&self) -> f64 {
        PENETRATION * self.size
    }

    /// The time resolution of an event located at t, τ = 16 ε |t| \[s\]: two events closer
    /// than it are one instant to the integrator (it takes no zero within round-off of a
    /// segment's start), so a surface whose gap its approach closes within τ of another's
    /// touchdown touches down with it (`transition::coinciding`).
    pub(super) fn time_resolution(&self, t: f64) -> f64 {
        TIME_ROUNDOFF * f64::EPSILON * t.abs()
    }

    /// The round-off of a material point's normal velocity v_Gz + e3·(R (ω × r)) \[m/s\]:
    /// 4ε (|v_G| + |ω| |r| + √(g L)), the last term for a body at rest, whose velocities
    /// are themselves round-off (1e-41 m/s measured on a dumbbell resting on three
    /// collinear contacts).
    pub(super) fn velocity_resolution(&self, kin: &Kinematics, lever: f64) -> f64 {
        GAP_ROUNDOFF
            * f64::EPSILON
            * (kin.v_g.norm() + kin.omega.norm() * lever + self.gravity_speed)
    }

    /// The settling speed (docs/physics.md, "Settling") [m/s]: a rebound at v_n rises
    /// v_n²/(2a) before it falls back, a ≥ 0 the gap's deceleration with no contact force
    /// (g for a body that does not turn; more for one whose spin presses it on the plane),
    /// and a rise below the gap's round-off δz cannot be resolved, so contact is
    /// persistent below v_settle = √(2 a δz). Where nothing presses the body on the plane
    /// (a = 0) no rebound settles.
    pub(super) fn settling_speed(&self, decel: f64, kin: &Kinematics) -> f64 {
        (2.0 * decel.max(0.0) * self.gap_resolution(kin)).sqrt()
    }
}
