//! What every phase and transition reads: the scene, its numerics, its effects — and the
//! two things made from them, a phase's ODE system and an output row.

use std::cell::Cell;
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

/// A run's inputs, shared by its phases (`phase`) and transitions (`transition`).
pub(super) struct Context<'s, E> {
    pub(super) scene: &'s Scene,
    pub(super) numerics: Numerics,
    /// The scene's effects, monomorphised (an absent effect is `()`).
    pub(super) effects: E,
    /// Set by another thread to stop the run at its next step.
    pub(super) cancel: Option<Arc<AtomicBool>>,
    /// The run's contact state: which surfaces touch the plane, which stick. Changed only
    /// by the transitions.
    pub(super) contacts: Cell<ContactSet>,
}

/// The run's contact state (docs/physics.md, "The hybrid machine"): the surfaces that
/// touch the plane and which of them stick. One value, so that a trial evaluation saves
/// and restores it whole (`transition::keeping`).
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

impl<E> Context<'_, E> {
    /// The body, its geometry that of the surface in contact.
    pub(super) fn body(&self) -> Body {
        self.scene.body.touching(self.surface())
    }

    /// The surface in contact ([`ContactSet::surface`]).
    pub(super) fn surface(&self) -> Surface {
        self.contacts.get().surface
    }

    /// The other surfaces in contact in the several-contact phases ([`ContactSet::others`]).
    pub(super) fn others(&self) -> [Surface; MOST_CONTACTS - 1] {
        self.contacts.get().others
    }

    /// How many surfaces are in contact in the several-contact phases.
    pub(super) fn count(&self) -> usize {
        self.contacts.get().count
    }

    /// Which contacts stick in the several-contact phases.
    pub(super) fn sticks(&self) -> [bool; MOST_CONTACTS] {
        self.contacts.get().sticks
    }

    /// Makes `surface` the one in contact; returns the one before.
    pub(super) fn set_surface(&self, surface: Surface) -> Surface {
        let mut c = self.contacts.get();
        let was = std::mem::replace(&mut c.surface, surface);
        self.contacts.set(c);
        was
    }

    /// Sets which contacts stick.
    pub(super) fn set_sticks(&self, sticks: [bool; MOST_CONTACTS]) {
        let mut c = self.contacts.get();
        c.sticks = sticks;
        self.contacts.set(c);
    }
}

impl<'s, E: Copy> Context<'s, E> {
    pub(super) fn new(scene: &'s Scene, effects: E, cancel: Option<Arc<AtomicBool>>) -> Self {
        Context {
            scene,
            numerics: Numerics::new(scene),
            effects,
            cancel,
            contacts: Cell::new(ContactSet {
                surface: Surface::Ellipsoid,
                others: [Surface::Ellipsoid; MOST_CONTACTS - 1],
                count: 2,
                sticks: [false; MOST_CONTACTS],
            }),
        }
    }

    /// The ODE system of phase `P`: the body under gravity and the effects, with the
    /// phase's contact law.
    pub(super) fn system<P: Phase>(&self) -> System<P::Law, E> {
        System {
            body: self.body(),
            gravity: self.scene.gravity,
            contact: P::law(self),
            effects: self.effects,
        }
    }

    /// The output row and invariants of state `y` in `mode`, `ev` its evaluation under
    /// `sys` (the `drift` column is filled in by the recorder).
    pub(super) fn sample<C: ContactLaw>(
        &self,
        sys: &System<C, E>,
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
        let count = match mode {
            Mode::Flight => 0,
            Mode::TwoContacts | Mode::ThreeContacts => self.count(),
            _ => 1,
        };
        let touching = std::array::from_fn(|i| match i {
            _ if i >= count => None,
            0 => Some((self.surface(), normal_force - others.iter().sum::<f64>())),
            _ => Some((self.others()[i - 1], others[i - 1])),
        });
        let sample = Sample {
            t,
            position,
            angles: EulerAngles::from_rotation(&kin.rot, &kin.omega, prev),
            omega: kin.omega,
            omega_world: kin.rot * kin.omega,
            velocity: kin.v_g,
            contact: position.xy() + (kin.rot * kin.contact.r).xy(),
            energy: inv.energy,
            work: y[state::WORK],
            normal_force,
            slip_speed: kin.slip.norm(),
            drift: 0.0,
            gap: kin.gap,
            mode,
            touching,
        };
        (sample, inv)
    }
}
