//! Streams samples to the caller's observer and keeps the invariant bookkeeping: the
//! initial values, each one's drift scale, the largest deviation seen, and the per-sample
//! drift of the scene's conserved quantity (the `drift` column).

use std::ops::ControlFlow;

use crate::columns;
use crate::invariants::{Conservation, Drift, Invariant, Invariants};
use crate::state::EulerAngles;

use super::outcome::{Sample, Status};

/// (Q − Q(0))/scale for the quantity Q of the `drift` column.
#[derive(Debug, Clone, Copy)]
pub(super) struct DriftGauge {
    which: Invariant,
    initial: f64,
    scale: f64,
}

impl DriftGauge {
    pub(super) fn of(&self, inv: &Invariants) -> f64 {
        (self.which.value(inv) - self.initial) / self.scale
    }
}

pub(super) struct Recorder<'o> {
    /// The caller's observer: every sample, in time order; `Break` cancels the run.
    observer: &'o mut dyn FnMut(&Sample) -> ControlFlow<()>,
    /// Index of the next sample time to emit.
    pub(super) next_sample: usize,
    /// Time of the last emitted row (−∞ before any).
    pub(super) last_t: f64,
    /// Euler angles of the last emitted state (for unwrapping).
    pub(super) angles: EulerAngles,
    /// What the scene conserves.
    conservation: Conservation,
    /// The quantity of the `drift` column: E where conserved, else E + W.
    headline: Invariant,
    initial: [f64; 6],
    /// Scale of each invariant's drift (see [`Invariant::scale`]).
    scale: [f64; 6],
    /// Largest |I(t) − I(0)| seen.
    deviation: [f64; 6],
    /// The conserved invariants the run has since stopped conserving (after an impact
    /// or a flight; see [`Recorder::lose`]).
    lost: [bool; 6],
    /// Why the recorder stopped the run, if it did (a non-finite sample).
    pub(super) stopped: Option<Status>,
    /// The points of each Poincaré section so far (`Scene::sections`).
    pub(super) sections: Vec<Vec<Sample>>,
}

impl<'o> Recorder<'o> {
    /// A recorder for a run starting with `initial` invariants scaled by `scale`.
    pub(super) fn new(
        observer: &'o mut dyn FnMut(&Sample) -> ControlFlow<()>,
        conservation: Conservation,
        initial: &Invariants,
        scale: [f64; 6],
        angles: EulerAngles,
    ) -> Self {
        let headline = if Invariant::Energy.conserved(&conservation) && conservation.elastic_impacts
        {
            Invariant::Energy
        } else {
            Invariant::EnergyPlusWork
        };
        Recorder {
            observer,
            next_sample: 0,
            last_t: f64::NEG_INFINITY,
            angles,
            conservation,
            headline,
            initial: Invariant::ALL.map(|i| i.value(initial)),
            scale: scale.map(|s| s.max(f64::MIN_POSITIVE)),
            deviation: [0.0; 6],
            lost: [false; 6],
            stopped: None,
            sections: Vec::new(),
        }
    }

    /// Notes the invariants of a state (the final one, or a sample's).
    pub(super) fn deviate(&mut self, inv: &Invariants) {
        for (k, which) in Invariant::ALL.into_iter().enumerate() {
            self.deviation[k] = self.deviation[k].max((which.value(inv) - self.initial[k]).abs());
        }
    }

    /// (I − I(0))/scale of the `drift` column's quantity.
    pub(super) fn relative_drift(&self, inv: &Invariants) -> f64 {
        self.gauge().of(inv)
    }

    /// The `drift` column's definition, detached from the recorder (for event functions
    /// that need the column while the recorder is lent to the sample observer).
    pub(super) fn gauge(&self) -> DriftGauge {
        let k = self.headline as usize;
        DriftGauge {
            which: self.headline,
            initial: self.initial[k],
            scale: self.scale[k],
        }
    }

    /// Fills in the sample's `drift` and hands it to the observer, unless it is not
    /// finite: then the run stops with [`Status::NonFinite`] (no NaN is ever reported as a
    /// result). The row is taken by reference, where it was built (no copy of it).
    pub(super) fn emit(&mut self, sample: &mut Sample, inv: &Invariants) -> ControlFlow<()> {
        sample.drift = self.relative_drift(inv);
        if let Some((column, value)) = columns::non_finite(sample) {
            self.stopped = Some(Status::NonFinite { column, value });
            return ControlFlow::Break(());
        }
        self.angles = sample.angles;
        self.last_t = sample.t;
        self.deviate(inv);
        (self.observer)(sample)
    }

    /// Notes that the run no longer conserves `which` (an impact dissipated energy; a
    /// flight moved the lever arm of Jellett's quantity without torque).
    pub(super) fn lose(&mut self, which: Invariant) {
        self.lost[which as usize] = true;
    }

    /// The relative drift of each invariant the run conserved.
    pub(super) fn drift(&self) -> Drift {
        Drift(Invariant::ALL.map(|which| {
            let k = which as usize;
            (which.conserved(&self.conservation) && !self.lost[k])
                .then(|| self.deviation[k] / self.scale[k])
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::outcome::Mode;
    use nalgebra::{Vector2, Vector3};

    /// A sample holding NaN is never handed on: the recorder stops the run and says which
    /// column held what.
    #[test]
    fn a_non_finite_sample_stops_the_run_by_name() {
        let mut seen = 0;
        let mut observer = |_: &Sample| {
            seen += 1;
            ControlFlow::Continue(())
        };
        let inv = Invariants {
            energy: 1.0,
            energy_plus_work: 1.0,
            momentum: [0.0; 2],
            angular_momentum_z: 0.0,
            axial_spin: 0.0,
            jellett: 0.0,
        };
        let all = Conservation {
            conservative: true,
            frictionless: true,
            energy: true,
            revolution: true,
            sphere: false,
            elastic_impacts: true,
        };
        let mut rec = Recorder::new(&mut observer, all, &inv, [1.0; 6], EulerAngles::default());
        let mut s = Sample {
            t: 0.1,
            position: Vector3::zeros(),
            angles: EulerAngles::default(),
            omega: Vector3::new(0.0, 0.0, 1.0),
            omega_world: Vector3::new(0.0, 0.0, 1.0),
            velocity: Vector3::zeros(),
            contact: Vector2::zeros(),
            energy: 1.0,
            work: 0.0,
            normal_force: 1.0,
            slip_speed: 0.0,
            drift: 0.0,
            gap: 0.0,
            mode: Mode::Rolling,
            touching: [None; crate::model::MOST_CONTACTS],
        };
        assert!(rec.emit(&mut s, &inv).is_continue());
        s.omega.y = f64::NAN;
        assert!(rec.emit(&mut s, &inv).is_break());
        let Some(Status::NonFinite { column, value }) = rec.stopped else {
            panic!("{:?}", rec.stopped)
        };
        assert_eq!(column, "omega_y");
        assert!(value.is_nan());
        drop(rec);
        assert_eq!(seen, 1, "the NaN sample reached the observer");
    }
}
