//! What every phase and transition reads: the scene, its numerics, its effects — and the
//! two things made from them with the run's contact state ([`ContactSet`], which the
//! machine owns and hands beside the state), a phase's ODE system and an output row.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use nalgebra::Vector3;

use crate::body::{Body, Surface};
use crate::invariants::Invariants;
use crate::model::{ContactLaw, Evaluation, MOST_CONTACTS, System};
use crate::state::{self, EulerAngles, State};

use super::numerics::Numerics;
use super::outcome::{Mode, Sample};
use super::phase::Phase;
use super::scene::Scene;

/// A run's inputs, shared by its phases (`phase`) and transitions (`transition`); read
/// only.
pub(super) struct Context<'s, E> {
    pub(super) scene: &'s Scene,
    pub(super) numerics: Numerics,
    /// The scene's effects, monomorphised (an absent effect is `()`).
    pub(super) effects: E,
    /// Set by another thread to stop the run at its next step.
    pub(super) cancel: Option<Arc<AtomicBool>>,
}

/// The run's contact state (docs/physics.md, "The hybrid machine"): the surfaces that
/// touch the plane and which of them stick. Owned by the machine (`Context::run`) beside
/// the state and its mode, read by the phases and changed only by the transitions; a
/// trial evaluation builds a value of its own ([`ContactSet::on`],
/// [`ContactSet::with_surfaces`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct ContactSet {
    /// The body's surface in contact with the plane (the last one that touched it while
    /// in flight): the contact phases' geometry is this surface's.
    pub(super) surface: Surface,
    /// The other surfaces in contact in the several-contact phases (`phase::contacts`),
    /// in order: the first `count − 1`.
    pub(super) others: [Surface; MOST_CONTACTS - 1],
    /// How many surfaces are in contact in the several-contact phases (2 or 3).
    pub(super) count: usize,
    /// Which contacts stick in the several-contact phases (`surface`, then `others`).
    pub(super) sticks: [bool; MOST_CONTACTS],
}

impl ContactSet {
    /// The contact state of a run that starts on (or nearest to) `surface`: the
    /// several-contact fields are set where the body enters a several-contact phase.
    pub(super) fn new(surface: Surface) -> Self {
        ContactSet {
            surface,
            others: [Surface::Ellipsoid; MOST_CONTACTS - 1],
            count: 2,
            sticks: [false; MOST_CONTACTS],
        }
    }

    /// This contact state with `surface` as the one in contact.
    pub(super) fn on(&self, surface: Surface) -> Self {
        ContactSet { surface, ..*self }
    }

    /// This contact state with `surfaces` (two or three, the first the one whose geometry
    /// the several-contact phase takes) in contact, their grip kept.
    pub(super) fn with_surfaces(&self, surfaces: &[Surface]) -> Self {
        ContactSet {
            surface: surfaces[0],
            others: std::array::from_fn(|k| surfaces.get(k + 1).copied().unwrap_or(surfaces[0])),
            count: surfaces.len(),
            ..*self
        }
    }

    /// The surfaces in contact in the several-contact phases: `surface`, then the others.
    pub(super) fn touching(&self) -> Vec<Surface> {
        std::iter::once(self.surface)
            .chain(self.others[..self.count - 1].iter().copied())
            .collect()
    }
}

impl<E> Context<'_, E> {
    /// The body, its geometry that of the surface in contact in `contacts`.
    pub(super) fn body(&self, contacts: &ContactSet) -> Body {
        self.scene.body.touching(contacts.surface)
    }
}

impl<'s, E: Copy> Context<'s, E> {
    pub(super) fn new(scene: &'s Scene, effects: E, cancel: Option<Arc<AtomicBool>>) -> Self {
        Context {
            scene,
            numerics: Numerics::new(scene),
            effects,
            cancel,
        }
    }

    /// The ODE system of phase `P` on `contacts`: the body under gravity and the
    /// effects, with the phase's contact law.
    pub(super) fn system<P: Phase>(&self, contacts: &ContactSet) -> System<P::Law, E> {
        System {
            body: self.body(contacts),
            gravity: self.scene.gravity,
            contact: P::law(self, contacts),
            effects: self.effects,
        }
    }

    /// The output row and invariants of state `y` in `mode` on `contacts`, `ev` its
    /// evaluation under `sys` (the `drift` column is filled in by the recorder).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn sample<C: ContactLaw>(
        &self,
        sys: &System<C, E>,
        contacts: &ContactSet,
        mode: Mode,
        t: f64,
        y: &State,
        ev: &Evaluation,
        prev: Option<&EulerAngles>,
    ) -> (Sample, Invariants) {
        let kin = &ev.kin;
        let inv = Invariants::from_kinematics(&sys.body, sys.gravity, kin, y[state::WORK]);
        let position = Vector3::new(y[state::POS], y[state::POS + 1], kin.z_g());
        let normal_force = self.numerics.reported_normal(&sys.body, sys.gravity, ev);
        let others = ev.response.other_normals;
        let (lever, slip) = sys.contact.acting_point(&sys.body, kin);
        let count = match mode {
            Mode::Flight => 0,
            Mode::TwoContacts | Mode::ThreeContacts => contacts.count,
            _ => 1,
        };
        let touching = std::array::from_fn(|i| match i {
            _ if i >= count => None,
            0 => Some((contacts.surface, normal_force - others.iter().sum::<f64>())),
            _ => Some((contacts.others[i - 1], others[i - 1])),
        });
        let sample = Sample {
            t,
            position,
            angles: EulerAngles::from_rotation(&kin.rot, &kin.omega, prev),
            omega: kin.omega,
            omega_world: kin.rot * kin.omega,
            velocity: kin.v_g,
            contact: position.xy() + lever.xy(),
            energy: inv.energy,
            work: y[state::WORK],
            normal_force,
            slip_speed: slip.norm(),
            drift: 0.0,
            gap: kin.gap,
            mode,
            touching,
        };
        (sample, inv)
    }
}
