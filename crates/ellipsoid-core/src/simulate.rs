//! Runs a scene: the contact model's modes (docs/physics.md models 1–5), their transitions
//! located as events on the dense output, sampling and invariant bookkeeping.
//!
//! Each mode is a monomorphised [`System`] over the scene's effects; the Coulomb model
//! alternates between [`Sliding`] and [`Rolling`] segments:
//! - sliding → rolling when the slip speed reaches zero (event g = v_C·s_ref) and the
//!   rolling contact force lies inside the friction cone;
//! - rolling → sliding when the cone is violated (event g = μN − |F_h|), the slip
//!   starting opposite to the friction rolling needed.
//!
//! Every model stops at loss of contact (event g = N) and, while sliding, at a
//! Painlevé inconsistency (event g = 1 + m u·I⁻¹(r × d_b), or a solver failure where
//! that denominator has collapsed). The slip stop is watched by two events: the sign
//! change of v_C·s_ref, and |v_C| falling to a floor far below the tolerance for a slip
//! that grazes zero (see `model::sliding`).

use std::cell::Cell;
use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use nalgebra::{Vector2, Vector3};
use serde::Serialize;

use crate::body::Body;
use crate::effects::{AirDrag, Effect, RollingResistance, SpinFriction};
use crate::error::{ModelError, number};
use crate::integrate::{
    self, Action, Direction, Event, Method, OdeSystem, Options, Stats, StopReason, Warning,
};
use crate::invariants::Invariants;
use crate::model::sliding::SLIP_FLOOR;
use crate::model::{ContactLaw, Evaluation, Frictionless, Rolling, Sliding, System};
use crate::state::{self, EulerAngles, State};

/// The contact model a scene asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactModel {
    /// F = N e3.
    Frictionless,
    /// Coulomb friction while slipping; stops when the slip does.
    Sliding { friction: f64 },
    /// No slip, unlimited friction.
    Rolling,
    /// Sliding and rolling with transitions; `friction` is μ.
    Coulomb { friction: f64 },
}

/// The optional effects a scene names (absent = not simulated, no cost).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EffectSet {
    pub air_drag: Option<AirDrag>,
    pub rolling_resistance: Option<RollingResistance>,
    pub spin_friction: Option<SpinFriction>,
}

impl EffectSet {
    /// Whether any effect is present.
    pub fn any(&self) -> bool {
        self.air_drag.is_some() || self.rolling_resistance.is_some() || self.spin_friction.is_some()
    }
}

/// Initial conditions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialState {
    /// Euler angles and rates (paper eq. 1) [rad, rad/s].
    pub angles: EulerAngles,
    /// Body angular velocity [rad/s]; when given it replaces the Euler-angle rates.
    pub omega_body: Option<Vector3<f64>>,
    /// Horizontal position of G \[m\].
    pub position: Vector2<f64>,
    /// Horizontal velocity of G [m/s]. Must be `None` for rolling, where it is implied;
    /// `None` means zero for frictionless and sliding, and no slip (v_G = −ω × r) for
    /// Coulomb.
    pub velocity: Option<Vector2<f64>>,
}

/// Integrator settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    pub method: Method,
    pub rtol: f64,
    pub atol: f64,
    /// Initial step hint for the adaptive methods \[s\].
    pub initial_step: Option<f64>,
    pub max_steps: u64,
}

/// Everything a run needs.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub body: Body,
    /// g [m/s²].
    pub gravity: f64,
    pub contact: ContactModel,
    pub effects: EffectSet,
    pub initial: InitialState,
    pub solver: SolverSettings,
    /// End time \[s\].
    pub t_end: f64,
    /// Output times, sorted, within [0, t_end] \[s\].
    pub sample_times: Vec<f64>,
}

/// The contact regime in force.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    Frictionless,
    Sliding,
    Rolling,
}

impl Mode {
    /// Its name in output files.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Frictionless => "frictionless",
            Mode::Sliding => "sliding",
            Mode::Rolling => "rolling",
        }
    }
}

/// One output row (SI units; ω in body axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub t: f64,
    /// Position of G \[m\] (z from the contact constraint).
    pub position: Vector3<f64>,
    pub angles: EulerAngles,
    /// Body angular velocity [rad/s].
    pub omega: Vector3<f64>,
    /// Velocity of G [m/s].
    pub velocity: Vector3<f64>,
    pub energy: f64,
    /// Dissipated work W \[J\].
    pub work: f64,
    pub normal_force: f64,
    /// |v_C| [m/s].
    pub slip_speed: f64,
    pub mode: Mode,
}

/// What happened during a run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum EventKind {
    /// The slip speed reached zero.
    SlipStop,
    /// The contact regime changed.
    ModeSwitch { from: Mode, to: Mode },
    /// N reached zero: the body leaves the plane.
    LostContact,
    /// The sliding normal-force denominator reached zero.
    Painleve,
}

/// A located event.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EventRecord {
    #[serde(flatten)]
    pub kind: EventKind,
    /// Time \[s\].
    pub t: f64,
}

/// Why a run ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "status", content = "message", rename_all = "snake_case")]
pub enum Status {
    /// Reached t_end.
    Completed,
    /// N reached zero (an outcome, not an error).
    LostContact,
    /// The pure sliding model's slip reached zero (an outcome).
    SlipStopped,
    /// The sliding normal force has no consistent value (an error).
    Painleve(String),
    /// The integrator failed (an error).
    SolverFailure(String),
    /// Too many mode switches (an error).
    Chattering(String),
    /// The observer asked to stop.
    Cancelled,
}

impl Status {
    /// Its name in summaries (`status` field), as serialised.
    pub fn name(&self) -> &'static str {
        match self {
            Status::Completed => "completed",
            Status::LostContact => "lost_contact",
            Status::SlipStopped => "slip_stopped",
            Status::Painleve(_) => "painleve",
            Status::SolverFailure(_) => "solver_failure",
            Status::Chattering(_) => "chattering",
            Status::Cancelled => "cancelled",
        }
    }

    /// Whether the run reached its end time.
    pub fn completed(&self) -> bool {
        matches!(self, Status::Completed)
    }
}

/// Largest deviation of each applicable invariant from its initial value, over the
/// output samples and the final state (not between samples), relative to a scale from
/// the initial state: |E|, |E + W|, m(|v_G| + |ω||r|), |Iω|, |ω|, |Iω||r|. `None` where
/// the quantity is not conserved in the scene.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Drift {
    pub energy: Option<f64>,
    pub energy_plus_work: Option<f64>,
    pub momentum: Option<f64>,
    pub angular_momentum_z: Option<f64>,
    pub axial_spin: Option<f64>,
    pub jellett: Option<f64>,
}

/// The result of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    pub status: Status,
    pub events: Vec<EventRecord>,
    pub stats: Stats,
    pub warnings: Vec<String>,
    /// State where the run ended.
    pub final_state: State,
    /// Output row where the run ended.
    pub final_sample: Sample,
    pub initial_invariants: Invariants,
    pub final_invariants: Invariants,
    pub drift: Drift,
}

/// Below this the sliding normal-force denominator (≥ 1 without friction) has collapsed:
/// a solver failure there is the Painlevé singularity, N → ∞, and is reported as such.
const PAINLEVE_COLLAPSE: f64 = 1e-3;

/// A fixed-step method cannot resolve a slip smaller than friction removes in a few
/// steps (μ g h each, times the lever's gain): below this many of those, the slip counts
/// as stopped. Chosen so that the paper's RK4 at h = 1e-4 s stops the paper's sliding
/// scene where DOP853 does instead of chattering on (see docs/hard-cases.md).
const RK4_SLIP_STEPS: f64 = 10.0;

/// A located slip stop is taken only if |v_C| is within this many slip floors (see
/// `Runner::slip_floor`); otherwise v_C·s_ref changed sign because the slip direction
/// turned by more than 90° within one step, and sliding goes on.
const SLIP_ACCEPT: f64 = 2.0;

/// Most mode switches a run may make before it is declared chattering.
const MAX_SWITCHES: usize = 10_000;

/// Simulates `scene`, handing every sample to `observer` (return `Break` to cancel).
pub fn simulate(
    scene: &Scene,
    observer: &mut dyn FnMut(&Sample) -> ControlFlow<()>,
) -> Result<Outcome, ModelError> {
    simulate_cancellable(scene, observer, None)
}

/// [`simulate`] that also stops, with [`Status::Cancelled`], at the next integration
/// step after `cancel` is set (e.g. by another thread on Ctrl-C), however sparse the
/// samples.
pub fn simulate_cancellable(
    scene: &Scene,
    observer: &mut dyn FnMut(&Sample) -> ControlFlow<()>,
    cancel: Option<Arc<AtomicBool>>,
) -> Result<Outcome, ModelError> {
    scene.validate()?;
    // Monomorphise over exactly the effects present: each level below doubles the
    // variants, and an absent effect is the empty tuple, which compiles to nothing.
    dispatch_drag(
        Call {
            scene,
            observer,
            cancel,
        },
        (),
    )
}

/// One call of [`simulate_cancellable`], passed down the effect dispatch.
struct Call<'a> {
    scene: &'a Scene,
    observer: &'a mut dyn FnMut(&Sample) -> ControlFlow<()>,
    cancel: Option<Arc<AtomicBool>>,
}

fn dispatch_drag<E: Effect + Copy>(call: Call<'_>, acc: E) -> Result<Outcome, ModelError> {
    match call.scene.effects.air_drag {
        Some(d) => dispatch_rolling(call, (acc, d)),
        None => dispatch_rolling(call, acc),
    }
}

fn dispatch_rolling<E: Effect + Copy>(call: Call<'_>, acc: E) -> Result<Outcome, ModelError> {
    match call.scene.effects.rolling_resistance {
        Some(r) => dispatch_spin(call, (acc, r)),
        None => dispatch_spin(call, acc),
    }
}

fn dispatch_spin<E: Effect + Copy>(call: Call<'_>, acc: E) -> Result<Outcome, ModelError> {
    match call.scene.effects.spin_friction {
        Some(s) => Runner::new(call.scene, (acc, s), call.cancel).run(call.observer),
        None => Runner::new(call.scene, acc, call.cancel).run(call.observer),
    }
}

/// What a segment watches for, in the order of its event list.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Watch {
    /// g = N (loss of contact).
    Normal,
    /// g = v_C·s_ref (slip stop).
    Slip,
    /// g = |v_C| − max(ε·scale, v_min) (a grazing slip stop; see `Runner::slip_floor`).
    SlipFloor,
    /// g = Painlevé denominator.
    Painleve,
    /// g = μN − |F_h| (rolling leaves the friction cone).
    Cone(f64),
}

/// The three contact laws over one set of effects.
struct Runner<'s, E> {
    scene: &'s Scene,
    cancel: Option<Arc<AtomicBool>>,
    free: System<Frictionless, E>,
    slide: System<Sliding, E>,
    roll: System<Rolling, E>,
}

/// Where a segment ended, with the watch list it used.
struct Segment {
    solution: integrate::Solution<{ state::DIM }>,
    watches: Vec<Watch>,
}

impl<'s, E: Effect + Copy> Runner<'s, E> {
    fn new(scene: &'s Scene, effects: E, cancel: Option<Arc<AtomicBool>>) -> Self {
        let body = scene.body.clone();
        let g = scene.gravity;
        let friction = match scene.contact {
            ContactModel::Sliding { friction } | ContactModel::Coulomb { friction } => friction,
            _ => 0.0,
        };
        Runner {
            scene,
            cancel,
            free: System {
                body: body.clone(),
                gravity: g,
                contact: Frictionless,
                effects,
            },
            slide: System {
                body: body.clone(),
                gravity: g,
                contact: Sliding { friction },
                effects,
            },
            roll: System {
                body,
                gravity: g,
                contact: Rolling,
                effects,
            },
        }
    }

    /// μ when the model switches between sliding and rolling.
    fn coulomb(&self) -> Option<f64> {
        match self.scene.contact {
            ContactModel::Coulomb { friction } => Some(friction),
            _ => None,
        }
    }

    fn run(
        &self,
        observer: &mut dyn FnMut(&Sample) -> ControlFlow<()>,
    ) -> Result<Outcome, ModelError> {
        let scene = self.scene;
        let (mut mode, mut y) = self.start()?;
        let mut rec = Recorder::new(observer);
        let mut t = 0.0;
        let mut events = Vec::new();
        let mut stats = Stats::default();
        let mut warnings = Vec::new();
        let mut switches = 0usize;
        let (initial_sample, initial_invariants) = self.sample(mode, t, &y, None);
        rec.start(
            initial_invariants,
            self.scales(&y, &initial_invariants),
            initial_sample.angles,
        );

        let pure_sliding = matches!(scene.contact, ContactModel::Sliding { .. });
        let status = if pure_sliding && self.slip_is_zero(&y) {
            // Only the pure sliding model starts here with zero slip (see `start`).
            events.push(EventRecord {
                kind: EventKind::SlipStop,
                t,
            });
            Status::SlipStopped
        } else {
            loop {
                let seg = match mode {
                    Mode::Frictionless => self.segment(&self.free, mode, t, y, &mut rec)?,
                    Mode::Sliding => self.segment(&self.slide, mode, t, y, &mut rec)?,
                    Mode::Rolling => self.segment(&self.roll, mode, t, y, &mut rec)?,
                };
                let sol = seg.solution;
                add_stats(&mut stats, &sol.stats);
                warnings.extend(sol.warnings.iter().map(|w| match w {
                    Warning::Stiff { t } => format!(
                        "the problem looks stiff at t = {t} s; an explicit method will be slow here"
                    ),
                }));
                t = sol.t;
                y = sol.y;
                match sol.stop {
                    StopReason::Reached => break Status::Completed,
                    StopReason::Cancelled => break Status::Cancelled,
                    StopReason::Failed(e) => {
                        let painleve = self.slide.evaluate(&y).response.painleve;
                        if mode == Mode::Sliding && painleve < PAINLEVE_COLLAPSE {
                            events.push(EventRecord {
                                kind: EventKind::Painleve,
                                t,
                            });
                            break Status::Painleve(format!(
                                "Painlevé inconsistency at t = {t} s: the sliding normal-force denominator 1 + m u·I⁻¹(r × d) fell to {painleve:.1e}, \
                                 so N grows without bound (a tangential impact) and Coulomb sliding has no consistent contact force ({e})"
                            ));
                        }
                        break Status::SolverFailure(format!("{e} (mode {})", mode.name()));
                    }
                    StopReason::Event { index } => match seg.watches[index] {
                        Watch::Normal => {
                            events.push(EventRecord {
                                kind: EventKind::LostContact,
                                t,
                            });
                            break Status::LostContact;
                        }
                        Watch::Painleve => {
                            events.push(EventRecord {
                                kind: EventKind::Painleve,
                                t,
                            });
                            break Status::Painleve(format!(
                                "Painlevé inconsistency at t = {t} s: the sliding normal-force denominator 1 + m u·I⁻¹(r × d) reached 0, \
                                 so Coulomb sliding has no consistent contact force (reduce contact.friction or use the rolling model)"
                            ));
                        }
                        Watch::Slip | Watch::SlipFloor if !self.slip_has_stopped(&y) => {
                            // v_C·s_ref changed sign because the slip turned by more than
                            // 90° within one (loose-tolerance) step, not because it
                            // stopped: go on sliding with the reference renewed.
                            let s = self.slide.evaluate(&y).kin.slip.normalize();
                            y[state::SLIP_REF] = s.x;
                            y[state::SLIP_REF + 1] = s.y;
                            switches += 1;
                        }
                        Watch::Slip | Watch::SlipFloor => {
                            let Some(mu) = self.coulomb() else {
                                events.push(EventRecord {
                                    kind: EventKind::SlipStop,
                                    t,
                                });
                                break Status::SlipStopped;
                            };
                            // Outside the cone the slip passes through zero and goes on
                            // (opposite to the friction rolling would need).
                            events.push(EventRecord {
                                kind: EventKind::SlipStop,
                                t,
                            });
                            let next = self.after_slip_stop(mu, &mut y);
                            if next == Mode::Rolling {
                                events.push(EventRecord {
                                    kind: EventKind::ModeSwitch {
                                        from: mode,
                                        to: next,
                                    },
                                    t,
                                });
                            }
                            switches += 1;
                            mode = next;
                        }
                        Watch::Cone(_) => {
                            self.start_sliding_from_rest(&mut y);
                            events.push(EventRecord {
                                kind: EventKind::ModeSwitch {
                                    from: mode,
                                    to: Mode::Sliding,
                                },
                                t,
                            });
                            switches += 1;
                            mode = Mode::Sliding;
                        }
                    },
                }
                if switches > MAX_SWITCHES {
                    break Status::Chattering(format!(
                        "more than {MAX_SWITCHES} switches between sliding and rolling by t = {t} s; the motion is chattering at the friction-cone boundary"
                    ));
                }
            }
        };

        let (final_sample, final_invariants) = self.sample(mode, t, &y, Some(&rec.angles));
        if !status.completed() && rec.last_t < t {
            // The trajectory ends where the run stopped (the run is over, so a request
            // to cancel from this last row changes nothing).
            let _ = rec.emit(final_sample, final_invariants);
        }
        rec.deviate(&final_invariants);
        Ok(Outcome {
            drift: self.drift(&rec),
            status,
            events,
            stats,
            warnings,
            final_state: y,
            final_sample,
            initial_invariants,
            final_invariants,
        })
    }

    /// The initial state and mode, checked: N > 0, no velocity for rolling.
    fn start(&self) -> Result<(Mode, State), ModelError> {
        let scene = self.scene;
        let init = &scene.initial;
        let mut y = State::zeros();
        y[state::POS] = init.position.x;
        y[state::POS + 1] = init.position.y;
        state::set_quaternion(&mut y, &init.angles.rotation());
        let omega = init.omega_body.unwrap_or_else(|| init.angles.omega_body());
        y.fixed_rows_mut::<3>(state::OMEGA).copy_from(&omega);
        match init.velocity {
            Some(v) => {
                y[state::VEL] = v.x;
                y[state::VEL + 1] = v.y;
            }
            None if matches!(scene.contact, ContactModel::Coulomb { .. }) => {
                self.roll.project(&mut y)
            }
            None => {}
        }
        let mode = match scene.contact {
            ContactModel::Frictionless => Mode::Frictionless,
            ContactModel::Sliding { .. } => Mode::Sliding,
            ContactModel::Rolling => Mode::Rolling,
            ContactModel::Coulomb { friction } => {
                if self.slip_is_zero(&y) {
                    self.after_slip_stop(friction, &mut y)
                } else {
                    Mode::Sliding
                }
            }
        };
        if mode == Mode::Rolling {
            if let (ContactModel::Rolling, Some(v)) = (scene.contact, init.velocity) {
                return Err(ModelError::invalid(
                    "initial.velocity",
                    format!("[{}, {}]", number(v.x), number(v.y)),
                    "not allowed for the rolling model, where the velocity of G is implied by ω (v_G = −ω × r)",
                ));
            }
            self.roll.project(&mut y);
        }
        if mode == Mode::Sliding && !self.slip_is_zero(&y) {
            let kin = self.slide.evaluate(&y).kin;
            let s = kin.slip.normalize();
            y[state::SLIP_REF] = s.x;
            y[state::SLIP_REF + 1] = s.y;
        }
        let response = match mode {
            Mode::Frictionless => self.free.evaluate(&y).response,
            Mode::Sliding => self.slide.evaluate(&y).response,
            Mode::Rolling => self.roll.evaluate(&y).response,
        };
        let (sample, inv) = self.sample(mode, 0.0, &y, None);
        let derived = [
            ("the normal force N", response.normal, "N"),
            ("the energy E", inv.energy, "J"),
            ("the speed of G", sample.velocity.norm(), "m/s"),
            ("the angular speed", sample.omega.norm(), "rad/s"),
            ("the height of G", sample.position.z, "m"),
            (
                "the angular momentum L_z",
                inv.angular_momentum_z,
                "kg m^2/s",
            ),
            ("Jellett's quantity", inv.jellett, "kg m^3/s"),
        ];
        if let Some((name, value, unit)) = derived.into_iter().find(|(_, v, _)| !v.is_finite()) {
            return Err(ModelError::invalid(
                "initial state",
                format!("{name} = {} {unit}", number(value)),
                "every quantity derived from [body] and [initial] must be finite at t = 0; these inputs overflow \
                 double precision (state the problem in SI units of ordinary magnitude)",
            ));
        }
        if let ContactModel::Sliding { friction: mu } | ContactModel::Coulomb { friction: mu } =
            scene.contact
            && !(response.painleve > 0.0)
        {
            return Err(ModelError::invalid(
                "contact.friction",
                number(mu),
                format!(
                    "Painlevé inconsistency at t = 0: with this coefficient the sliding normal-force denominator \
                     1 + m u·I⁻¹(r × d) = {} is not positive, so Coulomb sliding has no consistent contact force (reduce the friction)",
                    number(response.painleve)
                ),
            ));
        }
        if !(response.normal > 0.0) {
            return Err(ModelError::invalid(
                "initial normal force N",
                format!("{} N", number(response.normal)),
                "the plane must push on the body at t = 0 (N > 0); with these angles and rates the body would leave the plane at once",
            ));
        }
        Ok((mode, y))
    }

    /// Scales for the relative drifts, from the initial state: |E|, |E + W|,
    /// m(|v_G| + |ω||r|), |Iω|, |ω|, |Iω||r| (momentum-like quantities may start at 0).
    fn scales(&self, y: &State, inv: &Invariants) -> [f64; 6] {
        let body = &self.scene.body;
        let kin = self.slide.evaluate(y).kin;
        let l = (body.inertia() * kin.omega).norm();
        let r = kin.contact.r.norm();
        [
            inv.energy.abs(),
            inv.energy_plus_work.abs(),
            body.mass() * (kin.v_g.norm() + kin.omega.norm() * r),
            l,
            kin.omega.norm(),
            l * r,
        ]
    }

    /// The slip below which sliding counts as stopped: relative to |v_G| + |ω||r|, the
    /// larger of [`SLIP_FLOOR`] and rtol (a slip below the integration error is no slip);
    /// absolute, for fixed-step RK4, [`RK4_SLIP_STEPS`]·μ g h (a slip friction removes
    /// within a few steps cannot be resolved).
    fn slip_floor(&self) -> (f64, f64) {
        let scene = self.scene;
        let v_min = match (scene.solver.method, scene.contact) {
            (
                Method::Rk4 { h },
                ContactModel::Sliding { friction } | ContactModel::Coulomb { friction },
            ) => RK4_SLIP_STEPS * friction * scene.gravity * h,
            _ => 0.0,
        };
        (SLIP_FLOOR.max(scene.solver.rtol), v_min)
    }

    /// Whether a located slip-stop event is one: |v_C| within [`SLIP_ACCEPT`] times the
    /// floor of [`Runner::slip_floor`].
    fn slip_has_stopped(&self, y: &State) -> bool {
        let kin = self.slide.evaluate(y).kin;
        let (floor, v_min) = self.slip_floor();
        kin.slip.norm() <= SLIP_ACCEPT * (floor * Sliding::speed_scale(&kin)).max(v_min)
    }

    /// Whether the material contact point's slip is zero to round-off.
    fn slip_is_zero(&self, y: &State) -> bool {
        let kin = self.slide.evaluate(y).kin;
        Sliding::direction(&kin, Vector2::zeros()) == Vector2::zeros()
    }

    /// At zero slip under Coulomb friction (a residual slip removed by [`Rolling::stick`]):
    /// roll if the cone holds (N > 0 and
    /// |F_h| ≤ μN), else start sliding opposite to the friction rolling would need.
    fn after_slip_stop(&self, mu: f64, y: &mut State) -> Mode {
        Rolling::stick(&self.scene.body, y);
        self.roll.project(y);
        let response = self.roll.evaluate(y).response;
        if Rolling::cone_margin(&response, mu) >= 0.0 {
            Mode::Rolling
        } else {
            self.start_sliding_from_rest(y);
            Mode::Sliding
        }
    }

    /// Sets the slip reference to −F_h/|F_h| of the rolling contact force: the slip that
    /// develops when rolling fails opposes the friction it needed.
    fn start_sliding_from_rest(&self, y: &mut State) {
        let f_h = self.roll.evaluate(y).response.force.xy();
        let s = if f_h.norm() > 0.0 {
            -f_h.normalize()
        } else {
            Vector2::x()
        };
        y[state::SLIP_REF] = s.x;
        y[state::SLIP_REF + 1] = s.y;
    }

    /// Integrates one mode from (t0, y0) until t_end or a terminal event.
    fn segment<C: ContactLaw>(
        &self,
        sys: &System<C, E>,
        mode: Mode,
        t0: f64,
        y0: State,
        rec: &mut Recorder<'_>,
    ) -> Result<Segment, ModelError> {
        let scene = self.scene;
        let mut watches = vec![Watch::Normal];
        match mode {
            Mode::Sliding => watches.extend([Watch::Slip, Watch::SlipFloor, Watch::Painleve]),
            Mode::Rolling => watches.extend(self.coulomb().map(Watch::Cone)),
            Mode::Frictionless => {}
        }
        let (floor, v_min) = self.slip_floor();
        // The driver evaluates every event function at the same (t, y) in turn: evaluate
        // the model once per state for all of them.
        let last: Cell<Option<(f64, State, Evaluation)>> = Cell::new(None);
        let evaluate = |t: f64, y: &State| match last.get() {
            Some((tc, yc, ev)) if tc == t && yc == *y => ev,
            _ => {
                let ev = sys.evaluate(y);
                last.set(Some((t, *y, ev)));
                ev
            }
        };
        let evaluate = &evaluate;
        let events: Vec<Event<'_, { state::DIM }>> = watches
            .iter()
            .map(|&w| Event {
                g: Box::new(move |t, y: &State| {
                    let ev = evaluate(t, y);
                    match w {
                        Watch::Normal => ev.response.normal,
                        Watch::Slip => Sliding::slip_along_reference(&ev.kin, y),
                        Watch::SlipFloor => Sliding::slip_above_floor(&ev.kin, floor, v_min),
                        Watch::Painleve => ev.response.painleve,
                        Watch::Cone(mu) => Rolling::cone_margin(&ev.response, mu),
                    }
                }),
                direction: Direction::Falling,
                action: Action::Stop,
            })
            .collect();
        let mut options = Options::new(scene.solver.rtol, scene.solver.atol);
        options.h0 = scene.solver.initial_step;
        options.max_steps = scene.solver.max_steps;
        options.cancel = self.cancel.clone();
        let samples = &scene.sample_times[rec.next_sample..];
        let solution = integrate::integrate(
            scene.solver.method,
            sys,
            t0,
            y0,
            scene.t_end,
            &options,
            &events,
            samples,
            &mut |t, y| {
                let (sample, inv) = self.sample_with(sys, mode, t, y, Some(&rec.angles));
                rec.next_sample += 1;
                rec.emit(sample, inv)
            },
        )
        .map_err(|e| {
            ModelError::invalid(
                "solver",
                e.to_string(),
                "the integrator rejected these settings",
            )
        })?;
        Ok(Segment { solution, watches })
    }

    /// The output row and invariants of state `y` in `mode`.
    fn sample(
        &self,
        mode: Mode,
        t: f64,
        y: &State,
        prev: Option<&EulerAngles>,
    ) -> (Sample, Invariants) {
        match mode {
            Mode::Frictionless => self.sample_with(&self.free, mode, t, y, prev),
            Mode::Sliding => self.sample_with(&self.slide, mode, t, y, prev),
            Mode::Rolling => self.sample_with(&self.roll, mode, t, y, prev),
        }
    }

    fn sample_with<C: ContactLaw>(
        &self,
        sys: &System<C, E>,
        mode: Mode,
        t: f64,
        y: &State,
        prev: Option<&EulerAngles>,
    ) -> (Sample, Invariants) {
        let ev = sys.evaluate(y);
        let kin = &ev.kin;
        let inv = Invariants::from_kinematics(&sys.body, sys.gravity, kin, y[state::WORK]);
        let sample = Sample {
            t,
            position: Vector3::new(y[state::POS], y[state::POS + 1], kin.contact.height),
            angles: EulerAngles::from_rotation(&kin.rot, &kin.omega, prev),
            omega: kin.omega,
            velocity: kin.v_g,
            energy: inv.energy,
            work: y[state::WORK],
            normal_force: ev.response.normal,
            slip_speed: kin.slip.norm(),
            mode,
        };
        (sample, inv)
    }

    /// Relative drifts of the invariants that the scene conserves.
    fn drift(&self, rec: &Recorder<'_>) -> Drift {
        let scene = self.scene;
        let body = &scene.body;
        let (a, i, g) = (body.semi_axes(), body.inertia(), body.com_offset());
        let conservative = !scene.effects.any();
        let frictionless = conservative && scene.contact == ContactModel::Frictionless;
        let energy = conservative
            && matches!(
                scene.contact,
                ContactModel::Frictionless | ContactModel::Rolling
            );
        let axisymmetric_inertia =
            i[(0, 1)] == 0.0 && i[(0, 2)] == 0.0 && i[(1, 2)] == 0.0 && i[(0, 0)] == i[(1, 1)];
        let revolution = a.x == a.y && g.x == 0.0 && g.y == 0.0 && axisymmetric_inertia;
        let sphere = revolution && a.x == a.z;
        let d = &rec.deviation;
        let s = &rec.scale;
        let rel = |k: usize, applies: bool| applies.then(|| d[k] / s[k]);
        Drift {
            energy: rel(0, energy),
            energy_plus_work: rel(1, true),
            momentum: rel(2, frictionless),
            angular_momentum_z: rel(3, frictionless),
            axial_spin: rel(4, frictionless && revolution),
            jellett: rel(5, conservative && sphere),
        }
    }
}

fn add_stats(total: &mut Stats, s: &Stats) {
    total.accepted += s.accepted;
    total.rejected += s.rejected;
    total.rhs_evals += s.rhs_evals;
    total.events += s.events;
    total.min_step = total.min_step.min(s.min_step);
}

/// Streams samples to the observer and tracks invariant deviations.
struct Recorder<'o> {
    observer: &'o mut dyn FnMut(&Sample) -> ControlFlow<()>,
    /// Index of the next sample time to emit.
    next_sample: usize,
    /// Time of the last emitted row (−∞ before any).
    last_t: f64,
    /// Euler angles of the last evaluated state (for unwrapping).
    angles: EulerAngles,
    initial: [f64; 6],
    /// Scale of each invariant (see [`Drift`]).
    scale: [f64; 6],
    /// Largest |I(t) − I(0)| seen.
    deviation: [f64; 6],
}

impl<'o> Recorder<'o> {
    fn new(observer: &'o mut dyn FnMut(&Sample) -> ControlFlow<()>) -> Self {
        Recorder {
            observer,
            next_sample: 0,
            last_t: f64::NEG_INFINITY,
            angles: EulerAngles::default(),
            initial: [0.0; 6],
            scale: [1.0; 6],
            deviation: [0.0; 6],
        }
    }

    /// Records the initial invariants and the scale each deviation is divided by.
    fn start(&mut self, inv: Invariants, scale: [f64; 6], angles: EulerAngles) {
        self.angles = angles;
        self.initial = flatten(&inv);
        self.scale = scale.map(|s| s.max(f64::MIN_POSITIVE));
    }

    fn deviate(&mut self, inv: &Invariants) {
        for (k, v) in flatten(inv).iter().enumerate() {
            self.deviation[k] = self.deviation[k].max((v - self.initial[k]).abs());
        }
    }

    fn emit(&mut self, sample: Sample, inv: Invariants) -> ControlFlow<()> {
        self.angles = sample.angles;
        self.last_t = sample.t;
        self.deviate(&inv);
        (self.observer)(&sample)
    }
}

fn flatten(inv: &Invariants) -> [f64; 6] {
    [
        inv.energy,
        inv.energy_plus_work,
        inv.momentum[0].hypot(inv.momentum[1]),
        inv.angular_momentum_z,
        inv.axial_spin,
        inv.jellett,
    ]
}

impl Scene {
    /// The contact mode and state a run of this scene starts from, after the same checks
    /// as [`simulate`] (N > 0 and a consistent sliding force at t = 0; optional effects
    /// do not enter the initial state).
    pub fn initial_state(&self) -> Result<(Mode, State), ModelError> {
        self.validate()?;
        Runner::new(self, (), None).start()
    }

    /// Checks the settings that the body and the integrator do not check themselves.
    pub fn validate(&self) -> Result<(), ModelError> {
        if !(self.t_end.is_finite() && self.t_end > 0.0) {
            return Err(ModelError::invalid(
                "output.t_end",
                number(self.t_end),
                "the end time must be positive and finite (s)",
            ));
        }
        if !(self.gravity.is_finite() && self.gravity >= 0.0) {
            return Err(ModelError::invalid(
                "effects.gravity",
                number(self.gravity),
                "g must be finite and non-negative (m/s^2)",
            ));
        }
        if let ContactModel::Sliding { friction } | ContactModel::Coulomb { friction } =
            self.contact
            && !(friction.is_finite() && friction >= 0.0)
        {
            return Err(ModelError::invalid(
                "contact.friction",
                number(friction),
                "the Coulomb coefficient must be finite and non-negative",
            ));
        }
        if let Some(bad) = self
            .sample_times
            .iter()
            .find(|t| !(t.is_finite() && **t >= 0.0 && **t <= self.t_end))
        {
            return Err(ModelError::invalid(
                "output.times",
                number(*bad),
                format!(
                    "output times must lie within [0, t_end = {}] s",
                    number(self.t_end)
                ),
            ));
        }
        if let Some(w) = self.sample_times.windows(2).find(|w| w[1] <= w[0]) {
            return Err(ModelError::invalid(
                "output.times",
                format!("{} after {}", number(w[1]), number(w[0])),
                "output times must be strictly increasing",
            ));
        }
        if let Method::Rk4 { h } = self.solver.method {
            if h > self.t_end {
                return Err(ModelError::invalid(
                    "solver.step",
                    number(h),
                    format!(
                        "the fixed step must not exceed output.t_end = {} s",
                        number(self.t_end)
                    ),
                ));
            }
            let steps = (self.t_end / h - (integrate::RK4_LAST_STRETCH - 1.0)).ceil();
            if steps > self.solver.max_steps as f64 {
                return Err(ModelError::invalid(
                    "solver.step",
                    number(h),
                    format!(
                        "rk4 would take {} steps to t_end = {} s, more than solver.max_steps = {} (raise the step or max_steps)",
                        number(steps),
                        number(self.t_end),
                        self.solver.max_steps
                    ),
                ));
            }
        }
        let init = &self.initial;
        let vectors = [
            ("initial.position", init.position.as_slice().to_vec()),
            (
                "initial.velocity",
                init.velocity.map_or(vec![], |v| v.as_slice().to_vec()),
            ),
            (
                "initial.omega_body",
                init.omega_body.map_or(vec![], |w| w.as_slice().to_vec()),
            ),
        ];
        for (name, v) in vectors {
            if v.iter().any(|x| !x.is_finite()) {
                return Err(ModelError::invalid(
                    name,
                    format!("{v:?}"),
                    "every component must be finite",
                ));
            }
        }
        let a = &self.initial.angles;
        for (name, v) in [
            ("theta", a.theta),
            ("phi", a.phi),
            ("psi", a.psi),
            ("theta_dot", a.theta_dot),
            ("phi_dot", a.phi_dot),
            ("psi_dot", a.psi_dot),
        ] {
            if !v.is_finite() {
                return Err(ModelError::invalid(
                    format!("initial.{name}"),
                    number(v),
                    "must be finite",
                ));
            }
        }
        Ok(())
    }
}
