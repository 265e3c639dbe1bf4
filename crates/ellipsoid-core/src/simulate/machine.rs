//! The hybrid machine: runs a scene's contact phases one segment at a time, each
//! integrated until t_end or a terminal event, and moves between them as the phases
//! direct (docs/physics.md, models 1–5; `phase` for the phases themselves). Observables
//! (`Scene::observe`) and Poincaré sections (`Scene::sections`) are watched in every
//! phase.

use std::cell::{Cell, RefCell};
use std::ops::ControlFlow;

use crate::body::Surface;
use crate::columns;
use crate::effects::Effect;
use crate::error::ModelError;
use crate::geometry;
use crate::integrate::{
    self, Action, Direction, Event, OdeSystem, Options, Stats, StopReason, Warning,
};
use crate::invariants::{Conservation, Invariant, Invariants};
use nalgebra::Vector3;

use crate::kinematics::Kinematics;
use crate::model::{ContactLaw, Evaluation, System};
use crate::state::{self, EulerAngles, State};

use super::context::{ContactSet, Context};
use super::flat;
use super::numerics::MAX_SWITCHES;
use super::outcome::{Chatter, EventKind, EventRecord, Mode, Outcome, RunWarning, Sample, Status};
use super::phase::{Next, Phase, Slot, phase};
use super::recorder::Recorder;
use super::scene::{ContactModel, LiftOff, Observe};
use super::start::Start;

/// Where a segment ended, with the watch list it used.
pub(super) struct Segment {
    pub(super) solution: integrate::Solution<{ state::DIM }>,
    pub(super) watches: Vec<Slot>,
    /// (t, Euler angles) of the rows the segment emitted, when the scene has observables
    /// or sections (their events' φ and ψ are unwrapped against the row before them).
    pub(super) rows: Vec<(f64, EulerAngles)>,
}

impl<E: Effect + Copy + 'static> Context<'_, E> {
    /// Runs the scene from its initial state, handing every sample to `observer`.
    pub(super) fn run(
        &self,
        observer: &mut dyn FnMut(&Sample) -> ControlFlow<()>,
    ) -> Result<Outcome, ModelError> {
        let Start {
            mut mode,
            mut y,
            mut events,
            stopped,
            mut contacts,
        } = self.start()?;
        let mut t = 0.0;
        let (initial_sample, initial_invariants) =
            phase::<E>(mode).sample(self, &contacts, t, &y, None);
        let conservation = self.conservation();
        let mut rec = Recorder::new(
            observer,
            conservation,
            &initial_invariants,
            self.scales(&contacts, &y, &initial_invariants),
            initial_sample.angles,
        );
        let mut stats = Stats::default();
        let mut warnings = Vec::new();
        let mut switches = 0usize;
        rec.sections = vec![Vec::new(); self.scene.sections.len()];

        let status = match stopped {
            Some(status) => status,
            None => loop {
                let current = phase::<E>(mode);
                let kin = current.kinematics(self, &contacts, &y);
                if let Some(status) = self.below_plane(mode, &contacts, &kin) {
                    break status;
                }
                // A surface already below the plane where the phase starts touched it
                // before: its event at once (the integrator finds only zeros crossed).
                let mut before = events.len();
                let next = if flat_watched(mode, &contacts)
                    && flat::tilt(&kin, self.scene.landing.flat_tilt) <= 0.0
                {
                    flat::land_flat(self, &mut contacts, mode, t, &mut y, &mut events)
                } else if let Some(watch) = current.overdue(self, &contacts, &y) {
                    current.on_event(self, &mut contacts, watch, &mut t, &mut y, &mut events)
                } else {
                    let start_angles = rec.angles;
                    let seg = current.segment(self, &contacts, t, y, &mut rec)?;
                    let sol = seg.solution;
                    add_stats(&mut stats, &sol.stats);
                    warnings.extend(sol.warnings.iter().map(|w| match *w {
                        Warning::Stiff { t } => RunWarning::Stiff { t, mode },
                    }));
                    t = sol.t;
                    y = sol.y;
                    for record in &sol.events {
                        let slot = seg.watches[record.index];
                        let (Slot::Observe(index) | Slot::Section(index)) = slot else {
                            continue;
                        };
                        // φ and ψ unwrapped against the last row at or before the event.
                        let before = seg.rows.partition_point(|r| r.0 <= record.t);
                        let prev = before
                            .checked_sub(1)
                            .map_or(start_angles, |i| seg.rows[i].1);
                        let (mut sample, inv) =
                            current.sample(self, &contacts, record.t, &record.y, Some(&prev));
                        sample.drift = rec.relative_drift(&inv);
                        if let Slot::Section(_) = slot {
                            rec.sections[index].push(sample);
                        } else {
                            events.push(EventRecord {
                                kind: EventKind::Observed {
                                    index,
                                    sample: Box::new(sample),
                                },
                                t: record.t,
                            });
                        }
                    }
                    before = events.len();
                    match sol.stop {
                        StopReason::Reached => Next::Stop(Status::Completed, mode),
                        StopReason::Cancelled => {
                            Next::Stop(rec.stopped.take().unwrap_or(Status::Cancelled), mode)
                        }
                        StopReason::Failed(e) => {
                            current.on_failure(self, &mut contacts, &mut t, &mut y, e, &mut events)
                        }
                        StopReason::Event { index } => match seg.watches[index] {
                            Slot::Observe(index) => Next::Stop(Status::Observed { index }, mode),
                            Slot::Section(index) => Next::Stop(Status::SectionFull { index }, mode),
                            Slot::Phase(watch) => current.on_event(
                                self,
                                &mut contacts,
                                watch,
                                &mut t,
                                &mut y,
                                &mut events,
                            ),
                            Slot::Flat => {
                                flat::land_flat(self, &mut contacts, mode, t, &mut y, &mut events)
                            }
                            Slot::Guard => {
                                let kin = current.kinematics(self, &contacts, &y);
                                match self.below_plane(mode, &contacts, &kin) {
                                    Some(status) => Next::Stop(status, mode),
                                    // Located at the tolerance to within round-off.
                                    None => {
                                        Next::Stop(self.deepest_status(mode, &contacts, &kin), mode)
                                    }
                                }
                            }
                        },
                    }
                };
                if mode == Mode::Flight {
                    lose_in_flight(&mut rec, &events[before..], &conservation);
                }
                match next {
                    Next::Stop(status, at) => {
                        mode = at;
                        break status;
                    }
                    Next::Go(to) => mode = to,
                }
                switches += 1;
                if switches > MAX_SWITCHES {
                    break Status::Chattering {
                        switches: MAX_SWITCHES,
                        kind: chatter_kind(&events),
                    };
                }
            },
        };

        let (mut final_sample, final_invariants) =
            phase::<E>(mode).sample(self, &contacts, t, &y, Some(&rec.angles));
        if !status.completed() && rec.last_t < t && !matches!(status, Status::NonFinite { .. }) {
            // The trajectory ends where the run stopped (the run is over, so a request
            // to cancel from this last row changes nothing).
            let _ = rec.emit(&mut final_sample, &final_invariants);
        }
        rec.deviate(&final_invariants);
        let final_sample = Sample {
            drift: rec.relative_drift(&final_invariants),
            ..final_sample
        };
        Ok(Outcome {
            drift: rec.drift(),
            status,
            events,
            stats,
            warnings,
            final_state: y,
            final_sample,
            initial_invariants,
            final_invariants,
            sections: std::mem::take(&mut rec.sections),
        })
    }

    /// The surface not in contact in `mode` on `contacts` lowest under the plane at `kin`,
    /// with its gap g_k = z_G − h_k(ζ) \[m\] (`geometry::height`); `None` where every
    /// surface is in contact.
    pub(super) fn deepest(
        &self,
        mode: Mode,
        contacts: &ContactSet,
        kin: &Kinematics,
    ) -> Option<(Surface, f64)> {
        let body = &self.scene.body;
        (body.surfaces())
            .filter(|&s| !in_contact(mode, contacts, s))
            .map(|s| (s, kin.z_g() - geometry::height(body, s, kin.contact.zeta)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// The guard of every run (docs/physics.md, "The hybrid machine"): a surface not in
    /// contact whose gap is below −(the penetration tolerance,
    /// `Numerics::penetration`) is a touchdown the machine did not locate, and the run
    /// stops `below_plane` there instead of going on inside the plane. Checked where every
    /// phase starts, as an event of every segment at every accepted step, and at every
    /// sample before it is emitted.
    fn below_plane(&self, mode: Mode, contacts: &ContactSet, kin: &Kinematics) -> Option<Status> {
        let (_, gap) = self.deepest(mode, contacts, kin)?;
        (gap < -self.numerics.penetration()).then(|| self.deepest_status(mode, contacts, kin))
    }

    /// [`Status::BelowPlane`] of the deepest surface not in contact at `kin`.
    fn deepest_status(&self, mode: Mode, contacts: &ContactSet, kin: &Kinematics) -> Status {
        let (surface, gap) = (self.deepest(mode, contacts, kin)).unwrap_or((contacts.surface, 0.0));
        Status::BelowPlane { surface, gap }
    }

    /// Which invariants the scene conserves.
    fn conservation(&self) -> Conservation {
        let scene = self.scene;
        let body = &scene.body;
        let (a, i, g) = (body.semi_axes(), body.inertia(), body.com_offset());
        let conservative = !scene.effects.any();
        let axisymmetric_inertia =
            i[(0, 1)] == 0.0 && i[(0, 2)] == 0.0 && i[(1, 2)] == 0.0 && i[(0, 0)] == i[(1, 1)];
        let on_axis = |v: Vector3<f64>| v.x == 0.0 && v.y == 0.0;
        let revolution = a.x == a.y
            && on_axis(g)
            && axisymmetric_inertia
            && body.spheres().iter().all(|s| on_axis(s.center));
        // Rims lie on the axis (`Body::with_rims`).
        Conservation {
            conservative,
            frictionless: conservative && scene.contact == ContactModel::Frictionless,
            energy: conservative
                && matches!(
                    scene.contact,
                    ContactModel::Frictionless | ContactModel::Rolling
                ),
            revolution,
            // The drilling torque of a contact disc changes Jellett's J = L_G·(G − C), and
            // so does a change of the contacting surface (contact spheres).
            sphere: revolution && a.x == a.z && scene.disc.is_none() && body.plain(),
            elastic_impacts: scene.landing.lift_off == LiftOff::Stop
                || (scene.contact == ContactModel::Frictionless
                    && scene.landing.restitution == 1.0),
        }
    }

    /// Each invariant's drift scale at the initial state `y` on `contacts` (see
    /// [`Invariant::scale`]).
    fn scales(&self, contacts: &ContactSet, y: &State, inv: &Invariants) -> [f64; 6] {
        let kin = Kinematics::new(&self.body(contacts), y, false);
        Invariant::ALL.map(|which| which.scale(&self.scene.body, &kin, inv))
    }
}

/// Whether `surface` is in contact with the plane in `mode` on `contacts`.
fn in_contact(mode: Mode, contacts: &ContactSet, surface: Surface) -> bool {
    match mode {
        Mode::Flight => false,
        Mode::TwoContacts | Mode::ThreeContacts => {
            surface == contacts.surface || contacts.others[..contacts.count - 1].contains(&surface)
        }
        _ => surface == contacts.surface,
    }
}

/// Whether `mode` on `contacts` watches its surface in contact going flat (`flat::tilt`):
/// a rim in contact alone.
pub(super) fn flat_watched(mode: Mode, contacts: &ContactSet) -> bool {
    matches!(contacts.surface, Surface::Rim(_))
        && matches!(
            mode,
            Mode::Frictionless | Mode::Sliding | Mode::Rolling | Mode::Viscous
        )
}

/// Integrates phase `P` on `contacts` from (t0, y0) until t_end or a terminal event.
pub(super) fn segment<P: Phase, E: Effect + Copy + 'static>(
    ctx: &Context<'_, E>,
    contacts: &ContactSet,
    t0: f64,
    y0: State,
    rec: &mut Recorder<'_>,
) -> Result<Segment, ModelError> {
    let scene = ctx.scene;
    let law = &ctx.system::<P>(contacts);
    // The driver evaluates every event function at the same (t, y) in turn, at t0 and
    // at each step end right after DOP853's f there: evaluate the model once per state.
    let sys = &Watched {
        sys: law,
        last: Memo::default(),
    };
    let phase_watches = P::watches(ctx, contacts);
    // The guard where a surface can be off the plane: every one in flight, the others
    // than the one touching with contact spheres.
    let guarded = P::MODE == Mode::Flight || !scene.body.plain();
    let watches: Vec<Slot> = (0..phase_watches.len())
        .map(Slot::Phase)
        .chain((0..scene.observe.len()).map(Slot::Observe))
        .chain((0..scene.sections.len()).map(Slot::Section))
        .chain(guarded.then_some(Slot::Guard))
        .chain(flat_watched(P::MODE, contacts).then_some(Slot::Flat))
        .collect();
    // Observables unwrap φ and ψ against the last emitted row; they share one output
    // row per state.
    let angles = Cell::new(rec.angles);
    let gauge = rec.gauge();
    let observed: Memo<(Key, EulerAngles), Sample> = Memo::default();
    let layout = &columns::Layout::of(&scene.body);
    let (angles_ref, observed) = (&angles, &observed);
    // The event of an observable or a section: its column crossing its value.
    let crossing = |o: &Observe, action| {
        let (column, crosses) = (o.column, o.crosses);
        Event {
            g: Box::new(move |t, y: &State| {
                let prev = angles_ref.get();
                let row = || {
                    sys.with(t, y, |ev| {
                        let (mut sample, inv) =
                            ctx.sample(law, contacts, P::MODE, t, y, ev, Some(&prev));
                        sample.drift = gauge.of(&inv);
                        sample
                    })
                };
                observed.with(((t, (*y).into()), prev), row, |s| layout.value(s, column)) - crosses
            }),
            direction: o.direction,
            action,
            curvature: None,
        }
    };
    let events: Vec<Event<'_, { state::DIM }>> = watches
        .iter()
        .map(|&w| match w {
            Slot::Observe(k) => {
                let o = &scene.observe[k];
                crossing(
                    o,
                    if o.terminal {
                        Action::Stop
                    } else {
                        Action::Continue
                    },
                )
            }
            Slot::Section(k) => {
                let s = &scene.sections[k];
                // The points still to take before the section is full (≥ 1: a full
                // section ended the run).
                let kept = rec.sections[k].len() as u64;
                crossing(&s.crossing, Action::StopAfter(s.max_points - kept))
            }
            Slot::Guard => {
                let tolerance = ctx.numerics.penetration();
                Event {
                    g: Box::new(move |t, y: &State| {
                        sys.with(t, y, |ev| {
                            ctx.deepest(P::MODE, contacts, &ev.kin)
                                .map_or(f64::INFINITY, |d| d.1)
                        }) + tolerance
                    }),
                    direction: Direction::Falling,
                    action: Action::Stop,
                    curvature: None,
                }
            }
            Slot::Flat => Event {
                g: Box::new(move |t, y: &State| {
                    sys.with(t, y, |ev| flat::tilt(&ev.kin, ctx.scene.landing.flat_tilt))
                }),
                direction: Direction::Falling,
                action: Action::Stop,
                curvature: None,
            },
            Slot::Phase(i) => {
                let w = phase_watches[i];
                // A gap that starts at or below zero (by round-off, opening: see the
                // overdue gaps in `Context::run`) is watched from δz above where it
                // starts, so that closing again it is seen (the driver takes no zero
                // within round-off of t0 for an event).
                let start = law.evaluate(&y0);
                let w0 = P::watch(ctx, law, w, &start, &y0);
                let dz = ctx.numerics.gap_resolution(&start.kin);
                let offset = match P::gap_of(ctx, w, &start) {
                    Some(_) if w0 < dz => w0 - dz,
                    _ => 0.0,
                };
                Event {
                    g: Box::new(move |t, y: &State| {
                        sys.with(t, y, |ev| P::watch(ctx, law, w, ev, y)) - offset
                    }),
                    direction: Direction::Falling,
                    action: Action::Stop,
                    curvature: P::curvature(ctx, w, &start),
                }
            }
        })
        .collect();
    let mut options = Options::new(scene.solver.rtol, scene.solver.atol);
    options.h0 = scene.solver.initial_step;
    options.max_steps = scene.solver.max_steps;
    options.time_scale = scene.gravity_time();
    options.cancel = ctx.cancel.clone();
    let samples = &scene.sample_times[rec.next_sample..];
    let keep_rows = !(scene.observe.is_empty() && scene.sections.is_empty());
    let mut rows = Vec::new();
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
            let ev = law.evaluate(y);
            if let Some(status) = guarded
                .then(|| ctx.below_plane(P::MODE, contacts, &ev.kin))
                .flatten()
            {
                rec.stopped = Some(status);
                return ControlFlow::Break(());
            }
            let (mut sample, inv) =
                ctx.sample(law, contacts, P::MODE, t, y, &ev, Some(&rec.angles));
            rec.next_sample += 1;
            let flow = rec.emit(&mut sample, &inv);
            angles.set(rec.angles);
            if keep_rows {
                rows.push((t, rec.angles));
            }
            flow
        },
    )
    .map_err(ModelError::Solver)?;
    Ok(Segment {
        solution,
        watches,
        rows,
    })
}

/// The last value of a function and its argument, so that calls in turn with the same
/// argument compute it once.
struct Memo<K, V>(RefCell<Option<(K, V)>>);

impl<K, V> Default for Memo<K, V> {
    fn default() -> Self {
        Memo(RefCell::new(None))
    }
}

impl<K: PartialEq, V> Memo<K, V> {
    /// `read` of the value at `key`: the last one if `key` is the last argument, else
    /// `compute()`'s (kept).
    #[inline]
    fn with<R>(&self, key: K, compute: impl FnOnce() -> V, read: impl FnOnce(&V) -> R) -> R {
        if let Some((k, v)) = &*self.0.borrow()
            && *k == key
        {
            return read(v);
        }
        let v = compute();
        let r = read(&v);
        *self.0.borrow_mut() = Some((key, v));
        r
    }
}

/// A state as a memo key (compared as an array: plain float equality, component by
/// component).
type Key = (f64, [f64; state::DIM]);

/// A phase's system that keeps its evaluation of the state at which the driver
/// evaluates the watches next ([`OdeSystem::rhs_accepted`]).
struct Watched<'a, C, E> {
    sys: &'a System<C, E>,
    last: Memo<Key, Evaluation>,
}

impl<C: ContactLaw, E: Effect> Watched<'_, C, E> {
    /// `read` of the model's evaluation at (t, y), computed once per state.
    #[inline]
    fn with<R>(&self, t: f64, y: &State, read: impl FnOnce(&Evaluation) -> R) -> R {
        self.last
            .with((t, (*y).into()), || self.sys.evaluate(y), read)
    }
}

impl<C: ContactLaw, E: Effect> OdeSystem<{ state::DIM }> for Watched<'_, C, E> {
    #[inline]
    fn rhs(&self, t: f64, y: &State) -> State {
        self.sys.rhs(t, y)
    }

    fn rhs_accepted(&self, t: f64, y: &State) -> State {
        self.with(t, y, |ev| self.sys.derivative(y, ev))
    }

    fn project(&self, y: &mut State) {
        self.sys.project(y);
    }
}

/// What a flight ending with `events` costs the invariants: Jellett's quantity (its lever
/// arm moved without torque), and the energy at an inelastic impact.
fn lose_in_flight(rec: &mut Recorder<'_>, events: &[EventRecord], conservation: &Conservation) {
    rec.lose(Invariant::Jellett);
    let impact = events
        .iter()
        .any(|e| matches!(e.kind, EventKind::Impact(_)));
    if impact && !conservation.elastic_impacts {
        rec.lose(Invariant::Energy);
    }
}

/// What a run that switched too often was switching between: impacts (a bounce sequence
/// that does not settle) or the contact phases.
fn chatter_kind(events: &[EventRecord]) -> Chatter {
    let recent = &events[events.len().saturating_sub(100)..];
    if recent
        .iter()
        .any(|e| matches!(e.kind, EventKind::Impact(_)))
    {
        Chatter::Impacts
    } else {
        Chatter::Phases
    }
}

fn add_stats(total: &mut Stats, s: &Stats) {
    total.accepted += s.accepted;
    total.rejected += s.rejected;
    total.rhs_evals += s.rhs_evals;
    total.events += s.events;
    total.min_step = total.min_step.min(s.min_step);
}
