//! Runs a scene: its contact phases (docs/physics.md, models 1–5) as a hybrid machine,
//! transitions and observables located as events on the dense output, sampling and
//! invariant bookkeeping.
//!
//! Layout, one job each: [`scene`] (what to simulate, validated), `start` (the initial
//! state and its checks), `context` (what phases and transitions read, and the run's
//! contact state, which the machine hands them beside the state), `phase` (the contact
//! phases: law, watches), `transition` (every switch between phases), `machine` (runs the
//! phases), `recorder` (samples and drift), [`outcome`] (what a run reports, as data).
//!
//! Each phase's system is monomorphised over exactly the scene's effects: an absent
//! effect is the empty tuple and compiles to nothing.

use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use crate::effects::{Effect, WithEffects};
use crate::error::ModelError;

mod context;
mod flat;
mod machine;
mod numerics;
pub mod outcome;
mod phase;
mod recorder;
pub mod scene;
mod start;
mod transition;

pub use crate::invariants::Drift;
pub use outcome::{
    Chatter, EventKind, EventRecord, ImpactReport, Mode, Outcome, RunWarning, Sample, Status,
    StatusKind,
};
pub use scene::{
    ContactModel, EffectSet, InitialState, Landing, LiftOff, MAX_OBSERVE, MAX_SECTION_POINTS,
    MAX_SECTIONS, MAX_VISCOUS_FRICTION, Observe, Scene, Section, SolverSettings,
};

use context::Context;

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
    scene.effects.dispatch(Call {
        scene,
        observer,
        cancel,
    })
}

/// One call of [`simulate_cancellable`], run with the scene's effects.
struct Call<'a> {
    scene: &'a Scene,
    observer: &'a mut dyn FnMut(&Sample) -> ControlFlow<()>,
    cancel: Option<Arc<AtomicBool>>,
}

impl WithEffects for Call<'_> {
    type Output = Result<Outcome, ModelError>;
    fn run<E: Effect + Copy + 'static>(self, effects: E) -> Self::Output {
        Context::new(self.scene, effects, self.cancel).run(self.observer)
    }
}
