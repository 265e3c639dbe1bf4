//! What a run reports, as data: the output row ([`Sample`]), the located events, why the
//! run ended ([`Status`], carrying its numbers), warnings and the [`Outcome`]. Names are
//! declared here once; sentences are made by the callers (`ellipsoid-io`, the CLI, Python).

use nalgebra::Vector3;

use crate::body::Surface;
use crate::integrate::{IntegrateError, Stats};
use crate::invariants::{Drift, Invariants};
use crate::state::State;

pub use crate::columns::{Mode, Sample};

/// What happened during a run.
#[derive(Debug, Clone, PartialEq)]
pub enum EventKind {
    /// The slip speed reached zero.
    SlipStop,
    /// The contact phase changed.
    ModeSwitch { from: Mode, to: Mode },
    /// N reached zero and the run stops there (`on_lift_off = "stop"`).
    LostContact,
    /// N reached zero: the body leaves the plane and flies.
    LiftOff,
    /// The body's `surface` reached the plane, approaching at `speed` [m/s].
    Touchdown { speed: f64, surface: Surface },
    /// The impact at a touchdown (docs/physics.md, "Impact at touchdown").
    Impact(ImpactReport),
    /// The sliding normal-force denominator collapsed (to 10⁻³, on its way to zero).
    Painleve,
    /// Observable `index` of the scene (`Scene::observe`) crossed its value; `sample` is
    /// the full state there.
    Observed { index: usize, sample: Box<Sample> },
    /// The body's surface in contact changed (bodies with contact spheres).
    ContactSurface { from: Surface, to: Surface },
    /// Rim `surface` reached the plane flat (its tilt sin α below `Landing::flat_tilt`):
    /// the body landed on the face the rim bounds, its far side approaching at `speed`
    /// [m/s], the face's impact removing `energy_loss` \[J\] (docs/physics.md, "Rims").
    Flat {
        surface: Surface,
        speed: f64,
        energy_loss: f64,
    },
    /// With two surfaces in contact, `surface`'s contact started to stick (`sticks`) or
    /// to slide (docs/physics.md, "Several contacts"); entering two contacts, one for each
    /// contact that sticks.
    Grip { surface: Surface, sticks: bool },
}

impl EventKind {
    /// Its `kind` in summaries.
    pub fn name(&self) -> &'static str {
        match self {
            EventKind::SlipStop => "slip_stop",
            EventKind::ModeSwitch { .. } => "mode_switch",
            EventKind::LostContact => "lost_contact",
            EventKind::LiftOff => "lift_off",
            EventKind::Touchdown { .. } => "touchdown",
            EventKind::Impact(_) => "impact",
            EventKind::Painleve => "painleve",
            EventKind::ContactSurface { .. } => "contact_surface",
            EventKind::Grip { .. } => "grip",
            EventKind::Flat { .. } => "flat",
            EventKind::Observed { .. } => "observed",
        }
    }
}

/// What an impact did (world frame, SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpactReport {
    /// The impulse P at the contact point [N·s] (P·e3 ≥ 0 is the normal impulse).
    pub impulse: Vector3<f64>,
    /// Kinetic energy the impact removed \[J\] (booked in W).
    pub energy_loss: f64,
    /// Whether the contact point's slip was zero when the impact ended.
    pub stuck: bool,
    /// Normal velocity of the contact point after the impact [m/s] (≥ 0: separating).
    pub rebound: f64,
    /// Whether contact became persistent here (the bounce was below the settling speed,
    /// docs/physics.md "Settling"); the run goes on in contact.
    pub persistent: bool,
    /// The surface struck.
    pub surface: Surface,
}

/// A located event.
#[derive(Debug, Clone, PartialEq)]
pub struct EventRecord {
    pub kind: EventKind,
    /// Time \[s\].
    pub t: f64,
}

/// Why a run ended, with the numbers that say so (the time is the final sample's).
#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    /// Reached t_end.
    Completed,
    /// A terminal observable (`Scene::observe[index]`) crossed its value.
    Observed { index: usize },
    /// Section `index` (`Scene::sections[index]`) reached its `max_points`-th point (an
    /// outcome the scene asked for; the run ends there).
    SectionFull { index: usize },
    /// N reached zero (an outcome, not an error).
    LostContact,
    /// The pure sliding model's slip reached zero (an outcome).
    SlipStopped,
    /// The sliding normal force has no consistent value (an error): its denominator
    /// 1 + m u·I⁻¹(r × d) fell to `denominator` (10⁻³ at a located event, where N is a
    /// thousand times its frictionless size and still determined; below it when the
    /// integrator failed first, with `error`).
    Painleve {
        denominator: f64,
        error: Option<IntegrateError>,
    },
    /// The integrator failed in `mode` (an error).
    SolverFailure { mode: Mode, error: IntegrateError },
    /// More than `switches` mode switches (an error), between the phases or at impacts.
    Chattering { switches: usize, kind: Chatter },
    /// At N = 0 in `mode` neither the contact nor flight is consistent (an error): the
    /// contact would need the plane to pull (`normal` < 0 \[N\]) while with no contact
    /// force the gap accelerates into the plane (`gap_acceleration` < 0 \[m/s²\]):
    /// the rolling model's analogue of Painlevé's paradox (docs/physics.md, "The hybrid
    /// machine").
    InconsistentContact {
        mode: Mode,
        normal: f64,
        gap_acceleration: f64,
    },
    /// Several surfaces on the plane in a way that is not simulated (an error;
    /// docs/physics.md, "Contact spheres"): surface `touching` reached the plane while
    /// `pressed` (and perhaps another) was in contact and the impact at them has no solution
    /// (`pressed` approaching at `approach` \[m/s\] after the impact at `touching` alone, or
    /// `touching`'s own approach at a third touchdown), or the several-contact phase cannot
    /// take them or any subset of them (on each a normal force ≤ 0 or another surface
    /// driven into the plane: "Which contacts stay"; three contact points on one line), or
    /// a fourth surface (`touching`) touched while on three (`approach` = 0).
    SeveralContacts {
        touching: Surface,
        pressed: Surface,
        approach: f64,
    },
    /// A sample held NaN or infinity: `column` = `value` (an error; never reported as a result).
    NonFinite { column: &'static str, value: f64 },
    /// A surface not in contact was found below the plane, its gap `gap` < 0 \[m\] beyond
    /// the run's penetration tolerance (an error: a touchdown the machine did not locate;
    /// docs/physics.md, "The hybrid machine"). The run stops at the first accepted step or
    /// phase start where it is seen, never reporting a body inside the plane as a result.
    BelowPlane { surface: Surface, gap: f64 },
    /// The caller asked to stop.
    Cancelled,
}

/// What kind of end a [`Status`] is, without its numbers: what a name in a summary, a
/// `[check]` table or a study's `status` column stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StatusKind {
    Completed,
    Observed,
    LostContact,
    SlipStopped,
    Painleve,
    SolverFailure,
    Chattering,
    NonFinite,
    Cancelled,
    InconsistentContact,
    SeveralContacts,
    SectionFull,
    BelowPlane,
}

impl StatusKind {
    /// Every kind, in the order of [`StatusKind::NAMES`].
    pub const ALL: [StatusKind; 13] = [
        StatusKind::Completed,
        StatusKind::Observed,
        StatusKind::LostContact,
        StatusKind::SlipStopped,
        StatusKind::Painleve,
        StatusKind::SolverFailure,
        StatusKind::Chattering,
        StatusKind::NonFinite,
        StatusKind::Cancelled,
        StatusKind::InconsistentContact,
        StatusKind::SeveralContacts,
        StatusKind::SectionFull,
        StatusKind::BelowPlane,
    ];

    /// The names of every kind, as summaries and `[check]` tables spell them.
    pub const NAMES: [&'static str; 13] = [
        "completed",
        "observed",
        "lost_contact",
        "slip_stopped",
        "painleve",
        "solver_failure",
        "chattering",
        "non_finite",
        "cancelled",
        "inconsistent_contact",
        "several_contacts",
        "section_full",
        "below_plane",
    ];

    /// Its name in summaries (`status` field).
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The kind named `name` (one of [`StatusKind::NAMES`]).
    pub fn named(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Whether a run of this kind ended where the scene asked it to: at t_end, at a
    /// terminal observable or at a full section.
    pub fn finished(self) -> bool {
        matches!(
            self,
            StatusKind::Completed | StatusKind::Observed | StatusKind::SectionFull
        )
    }
}

impl Status {
    /// The names of every status, as summaries and `[check]` tables spell them.
    pub const NAMES: [&'static str; 13] = StatusKind::NAMES;

    /// Its kind, without its numbers.
    pub fn kind(&self) -> StatusKind {
        match self {
            Status::Completed => StatusKind::Completed,
            Status::Observed { .. } => StatusKind::Observed,
            Status::LostContact => StatusKind::LostContact,
            Status::SlipStopped => StatusKind::SlipStopped,
            Status::Painleve { .. } => StatusKind::Painleve,
            Status::SolverFailure { .. } => StatusKind::SolverFailure,
            Status::Chattering { .. } => StatusKind::Chattering,
            Status::NonFinite { .. } => StatusKind::NonFinite,
            Status::Cancelled => StatusKind::Cancelled,
            Status::InconsistentContact { .. } => StatusKind::InconsistentContact,
            Status::SeveralContacts { .. } => StatusKind::SeveralContacts,
            Status::SectionFull { .. } => StatusKind::SectionFull,
            Status::BelowPlane { .. } => StatusKind::BelowPlane,
        }
    }

    /// Its name in summaries (`status` field).
    pub fn name(&self) -> &'static str {
        self.kind().name()
    }

    /// Whether the run reached its end time.
    pub fn completed(&self) -> bool {
        matches!(self, Status::Completed)
    }

    /// Whether the run ended where the scene asked it to ([`StatusKind::finished`]).
    pub fn finished(&self) -> bool {
        self.kind().finished()
    }

    /// Whether the run ended on an error (not an outcome of the physics or a request).
    pub fn is_error(&self) -> bool {
        matches!(
            self,
            Status::Painleve { .. }
                | Status::SolverFailure { .. }
                | Status::Chattering { .. }
                | Status::NonFinite { .. }
                | Status::InconsistentContact { .. }
                | Status::SeveralContacts { .. }
                | Status::BelowPlane { .. }
        )
    }
}

/// What a chattering run kept switching between.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Chatter {
    /// Contact phases (sliding and rolling at the friction cone's boundary).
    Phases,
    /// Impacts: a bounce sequence that did not settle.
    Impacts,
}

/// Something the caller should know about a run that still went on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RunWarning {
    /// The integrator's stiffness test fired at `t` in `mode`: an explicit method is
    /// slow there.
    Stiff { t: f64, mode: Mode },
}

/// The result of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    pub status: Status,
    pub events: Vec<EventRecord>,
    pub stats: Stats,
    pub warnings: Vec<RunWarning>,
    /// State where the run ended.
    pub final_state: State,
    /// Output row where the run ended.
    pub final_sample: Sample,
    pub initial_invariants: Invariants,
    pub final_invariants: Invariants,
    pub drift: Drift,
    /// The points of each Poincaré section (`Scene::sections`, in its order): the full
    /// state at each crossing, in time order.
    pub sections: Vec<Vec<Sample>>,
}

#[cfg(test)]
mod tests {
    use super::StatusKind;

    #[test]
    fn every_status_kind_has_its_own_name_and_reads_back() {
        for (i, kind) in StatusKind::ALL.into_iter().enumerate() {
            assert_eq!(kind as usize, i, "ALL follows the declaration");
            assert_eq!(StatusKind::named(kind.name()), Some(kind));
        }
        assert_eq!(StatusKind::named("invalid"), None);
        let finished: Vec<_> = StatusKind::ALL
            .into_iter()
            .filter(|k| k.finished())
            .collect();
        assert_eq!(
            finished,
            [
                StatusKind::Completed,
                StatusKind::Observed,
                StatusKind::SectionFull
            ]
        );
    }
}
