//! ODE integrators for small fixed-size systems: RK4 (fixed step), Dormand–Prince
//! 5(4) (Hairer's DOPRI5) and Dormand–Prince 8(5,3) (Hairer's DOP853), with dense
//! output, event location and statistics. No heap allocation per step.
//!
//! One driver ([`integrate`]) handles sampling, events and stopping for every method.
//!
//! Layout: [`tableau`] holds the published coefficients; `rk4`, `dopri5` and `dop853`
//! are the steppers (work buffers only, behind one internal `Stepper` trait);
//! `controller` is Hairer's step-size controller, error norm and initial step;
//! `stiffness` is Hairer's stiffness test; `events` brackets and refines zero
//! crossings; `driver` is the single loop; [`problems`] are reference problems shared
//! by the tests and benches. See `docs/integrators.md`.

use nalgebra::SVector;

mod controller;
mod dop853;
mod dopri5;
mod driver;
mod error;
mod events;
mod options;
pub mod problems;
mod rk4;
mod solution;
mod stepper;
mod stiffness;
pub mod tableau;

pub use driver::{
    FAST_BUDGET_FACTOR, FAST_FRACTION, FAST_PACE, HOPELESS_FACTOR, MOTION_PACE, OVER_BUDGET_FACTOR,
    integrate,
};
pub use error::IntegrateError;
pub use options::{Method, Options};
pub(crate) use rk4::{RK4_LAST_STRETCH, step as rk4_step};
pub use solution::{EventRecord, Solution, Stats, StopReason, Warning};

/// A first-order system dy/dt = f(t, y) on a fixed-size state.
pub trait OdeSystem<const N: usize> {
    /// The right-hand side f(t, y). Must not allocate.
    fn rhs(&self, t: f64, y: &SVector<f64, N>) -> SVector<f64, N>;

    /// f(t, y) where the driver evaluates the event functions next: at t0, and at an
    /// accepted (projected) step end when the method needs f there anyway (DOP853). The
    /// same value as [`OdeSystem::rhs`]; a system whose event functions share its work may
    /// keep that work here for them. The default is `rhs`.
    fn rhs_accepted(&self, t: f64, y: &SVector<f64, N>) -> SVector<f64, N> {
        self.rhs(t, y)
    }

    /// Called on every accepted step end (and on located terminal events) before the
    /// state is used again; may restore invariants of the exact flow, e.g. renormalise
    /// a quaternion. The default does nothing.
    fn project(&self, _y: &mut SVector<f64, N>) {}
}

/// Which sign changes of an event function count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// g goes from negative to positive.
    Rising,
    /// g goes from positive to negative.
    Falling,
    /// Either.
    Either,
}

/// What the driver does when an event is located.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Record it and go on.
    Continue,
    /// Record it and end the integration at the event time.
    Stop,
    /// Record it and go on, except at its n-th crossing of this integration (n ≥ 1):
    /// record that one and end there, as [`Action::Stop`] (a bound on the crossings
    /// kept, e.g. the points of a Poincaré section).
    StopAfter(u64),
}

/// g(t, y), boxed so that events of different closures share one list.
pub type EventFn<'a, const N: usize> = Box<dyn Fn(f64, &SVector<f64, N>) -> f64 + 'a>;

/// An event function g(t, y) whose zero crossings are located on the dense output.
pub struct Event<'a, const N: usize> {
    pub g: EventFn<'a, N>,
    pub direction: Direction,
    pub action: Action,
    /// An upper bound A of |d²g/dt²| along the integration, where one is known. A step
    /// (t, t_new] of length h whose ends are both farther than A h²/8 from zero cannot hide
    /// a crossing (g stays within A h²/8 of the chord through its ends); any other is
    /// scanned, and each scan interval closer to zero than its own bound searched for a
    /// dip (`events::may_cross_inside`). Without a bound, a heuristic judges from the
    /// last two steps, which misses a dip narrower than a long step.
    pub curvature: Option<f64>,
}
