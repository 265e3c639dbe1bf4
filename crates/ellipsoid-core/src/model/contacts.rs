//! Several surfaces of the body in contact at once, two or three (docs/physics.md,
//! "Contact spheres", "Several contacts"), each sliding or sticking: the event-driven
//! formulation of Pfeiffer & Glocker (*Multibody Dynamics with Unilateral Contacts*, 1996)
//! for a given active set. The body's geometry (`kin`) is that of the first surface, so
//! z_G = h_1(ζ); each other surface's gap h_1(ζ) − h_k(ζ) stays zero.
//!
//! Body axes throughout. A sliding contact i carries F_i = N_i d_i, d_i = ζ − μ Rᵀŝ_i
//! (Coulomb; Coulomb–Contensou's over a contact disc, with its drilling torque per unit
//! N_i): one unknown. Each unknown x_k is a *pull*: force directions at the contacts
//! (at_k,i) and a torque per unit t_k, so that
//! ```text
//!   a_G = Rᵀf/m − g ζ + Σ_k x_k Σ_i at_k,i/m,
//!   ω̇   = β + Σ_k x_k α_k,  α_k = I⁻¹(Σ_i r_i × at_k,i + t_k),  β = I⁻¹(τ − ω × Iω).
//! ```
//! The material point at contact i accelerates at a_i = a_G + ω̇ × r_i + ω × (ω × r_i + ṙ_i)
//! (ṙ_i: the contact point moving over the surface, as for rolling), and each pull pairs
//! with a constraint row: the normal ζ at each contact, and the horizontal pulls of the
//! sticking contacts with rows along their own directions (Σ_i at_k,i·a_i = 0, the virtual
//! work of a rigid motion): a square linear system A x = b.
//!
//! The sticking contacts' horizontal forces: one sticking contact carries a horizontal
//! force of its own (two pulls). Two or more sticking contacts hold the body's horizontal
//! motion — the uniform translation and the turn about the vertical, the only horizontal
//! velocities a rigid body gives its contact points on the plane — and the forces that
//! do it are undetermined by the constraints beyond their resultant (F_x, F_y, M_z): a
//! pair along the line C_1C_2 moves nothing. The law takes the least-norm forces, three
//! pulls (x̂/s, ŷ/s at each of the s sticking contacts; ẑ × q_i / Σ_j|q_j|² at contact i,
//! q_i its horizontal position from their centroid).
//!
//! With a sliding contact, det A over its value without friction (d_i = ζ) is the law's
//! Painlevé denominator: 1 without friction, and ≤ 0 where the active set has no
//! consistent normal forces; with none it is infinite.

use nalgebra::{Matrix2, SMatrix, SVector, UnitQuaternion, Vector2, Vector3};

use super::contensou::ContactDisc;
use super::{ContactLaw, Response};
use crate::body::{Body, Surface};
use crate::effects::Wrench;
use crate::geometry::{self, Contact};
use crate::kinematics::Kinematics;
use crate::state::{self, State};

/// Most surfaces in contact at once that the law takes (the body's own and two others).
pub const MOST_CONTACTS: usize = 3;
/// At most six unknowns: the normal forces and three horizontal ones.
const MOST: usize = MOST_CONTACTS + 3;
type Matrix = SMatrix<f64, MOST, MOST>;
type Vector = SVector<f64, MOST>;

/// The contacts: the body's surface in contact, then `others[..count − 1]`, each sliding
/// or sticking (`sticks`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contacts {
    /// Coulomb coefficient μ (≥ 0; 0 is frictionless).
    pub friction: f64,
    /// The contact disc at each contact; `None` is a point contact.
    pub disc: Option<ContactDisc>,
    /// The other surfaces in contact, in order (`count − 1` of them; the rest unused).
    pub others: [Surface; MOST_CONTACTS - 1],
    /// How many surfaces are in contact: 2 or 3.
    pub count: usize,
    /// Whether each contact sticks: its material point has no horizontal velocity.
    pub sticks: [bool; MOST_CONTACTS],
}

/// The contact forces of the active set at one state (entries from `count` on are zero).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Forces {
    /// Each contact's normal force N_i \[N\].
    pub normal: [f64; MOST_CONTACTS],
    /// Each contact's horizontal force, world axes \[N\].
    pub tangential: [Vector2<f64>; MOST_CONTACTS],
    /// Each contact's slip, the horizontal velocity of its material point, world \[m/s\].
    pub slip: [Vector2<f64>; MOST_CONTACTS],
    /// The total contact force, world \[N\].
    pub force: Vector3<f64>,
    /// ω̇, body axes [rad/s²].
    pub omega_dot: Vector3<f64>,
    /// The Painlevé denominator (see the module docs).
    pub painleve: f64,
    /// The power of the contact forces, −Σ_i (F_i·v_Ci + t_i·ω) \[W\], a sticking
    /// contact's F_i·v_Ci taken as zero: its slip is the integration's drift (removed after
    /// every step by [`Contacts::impel`], which books the energy it takes), and the
    /// force's work on it, of either sign, would make W fall. With every contact sticking,
    /// t_i·ω is taken on the part of ω the constraints leave — along C_1C_2 for two, none
    /// for three: the rest is drift too (zero on the constraints), and a power that is zero
    /// there and positive at the stages off them would make W fall through the negative
    /// weights of the Runge–Kutta quadrature (a spin friction's, 2e-15 J a step).
    pub power: f64,
    /// With exactly two contacts sticking, the unit vector along their C_1C_2 (world,
    /// horizontal); else zero.
    pub line: Vector2<f64>,
    /// With exactly two contacts sticking, their indices; else [0, 0].
    pub pair: [usize; 2],
}

/// What keeps a sticking contact sticking (docs/physics.md, "Several contacts").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Hold {
    /// Contact i's friction within its cone: μN_i − |F_h,i| ≥ 0, or, with two sticking,
    /// its part across the line C_1C_2, μN_i − |F_⊥,i| ≥ 0 (beyond, it slides across).
    Contact(usize),
    /// Two sticking: the force along C_1C_2, which the constraints leave to be shared
    /// in any way, within what the two cones have left after their parts across,
    /// Σ_i √((μN_i)² − F_⊥,i²) − |Σ_i F_∥,i| ≥ 0 (beyond, both slide along the line:
    /// rigidity gives their material points the same velocity along it).
    Line,
}

impl Forces {
    /// The margin of `hold` with Coulomb coefficient `friction` \[N\]: ≥ 0 while it holds.
    pub fn margin(&self, hold: Hold, friction: f64) -> f64 {
        let across = |i: usize| {
            let t = self.tangential[i];
            t - t.dot(&self.line) * self.line
        };
        match hold {
            Hold::Contact(i) => friction * self.normal[i] - across(i).norm(),
            Hold::Line => {
                let left = |i: usize| {
                    ((friction * self.normal[i]).powi(2) - across(i).norm_squared())
                        .max(0.0)
                        .sqrt()
                };
                let [i, j] = self.pair;
                let along = (self.tangential[i] + self.tangential[j]).dot(&self.line);
                left(i) + left(j) - along.abs()
            }
        }
    }
}

/// One unknown: its force direction at each contact (body axes, per unit), its torque per
/// unit, and the constraint row it pairs with (directions at each contact).
#[derive(Clone, Copy)]
struct Pull {
    at: [Vector3<f64>; MOST_CONTACTS],
    torque: Vector3<f64>,
    row: [Vector3<f64>; MOST_CONTACTS],
}

impl Pull {
    const NONE: Pull = Pull {
        at: [Vector3::new(0.0, 0.0, 0.0); MOST_CONTACTS],
        torque: Vector3::new(0.0, 0.0, 0.0),
        row: [Vector3::new(0.0, 0.0, 0.0); MOST_CONTACTS],
    };

    /// A force along `e` at contact `i` alone, paired with the row e·a_i.
    fn at(i: usize, e: Vector3<f64>, torque: Vector3<f64>) -> Pull {
        Pull::spread(|k| if k == i { e } else { Vector3::zeros() }, torque)
    }

    /// Forces `at(i)` at each contact, paired with the row Σ_i at(i)·a_i.
    fn spread(at: impl Fn(usize) -> Vector3<f64>, torque: Vector3<f64>) -> Pull {
        let at = std::array::from_fn(at);
        Pull {
            at,
            torque,
            row: at,
        }
    }
}

/// The contacts' geometry at one state (entries from `count` on unused).
struct Active {
    contact: [Contact; MOST_CONTACTS],
    slip: [Vector2<f64>; MOST_CONTACTS],
    rot: nalgebra::Matrix3<f64>,
    omega: Vector3<f64>,
}

impl Contacts {
    /// Each contact's kinematics: `kin` (the first's) and the others', `kin` with their
    /// contact geometry and horizontal slip v_Ci = v_G + (ω × r_i)_h (entries from
    /// `count` on are `kin`).
    #[inline]
    pub fn each(&self, body: &Body, kin: &Kinematics) -> [Kinematics; MOST_CONTACTS] {
        std::array::from_fn(|i| {
            if i == 0 || i >= self.count {
                return *kin;
            }
            let contact = Contact::of(body, self.others[i - 1], kin.contact.zeta, kin.omega);
            let slip = kin.v_g.xy() + (kin.rot * kin.omega.cross(&contact.r)).xy();
            Kinematics {
                contact,
                slip,
                ..*kin
            }
        })
    }

    fn active(&self, body: &Body, kin: &Kinematics) -> Active {
        let each = self.each(body, kin);
        Active {
            contact: each.map(|k| k.contact),
            slip: each.map(|k| k.slip),
            rot: kin.rot,
            omega: kin.omega,
        }
    }

    /// The contacts that stick, as indices.
    fn sticking(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.count).filter(|&i| self.sticks[i])
    }

    /// Whether every contact sticks.
    pub fn all_stick(&self) -> bool {
        self.sticking().count() == self.count
    }

    /// The friction of a contact slipping at `slip` with spin ω_n = ω·ζ: the force
    /// direction d (world, d·e3 = 1) — Coulomb's d = e3 − μ v̂ (no friction where the
    /// slip is exactly zero), or the disc's — and the torque per unit N it adds (body).
    #[inline]
    fn friction(
        &self,
        slip: Vector2<f64>,
        spin: f64,
        zeta: Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let mu = self.friction;
        let (f, m) = match self.disc {
            Some(disc) => disc
                .law
                .traction(slip, spin, disc.radius)
                .unwrap_or((Vector2::zeros(), 0.0)),
            None => {
                let s = slip.norm();
                (if s > 0.0 { -slip / s } else { Vector2::zeros() }, 0.0)
            }
        };
        (Vector3::new(mu * f.x, mu * f.y, 1.0), (mu * m) * zeta)
    }

    /// The unknowns of the active set and their number, and with exactly two contacts
    /// sticking their line C_1C_2 (world unit vector) and indices. `frictionless`: every
    /// sliding contact pushed along ζ alone (the Painlevé denominator's reference, and
    /// impulses).
    fn pulls(
        &self,
        p: &Active,
        per_normal: Vector3<f64>,
        frictionless: bool,
    ) -> ([Pull; MOST], usize, Vector2<f64>, [usize; 2]) {
        let zeta = p.contact[0].zeta;
        let body_axis = |v: Vector2<f64>| p.rot.tr_mul(&Vector3::new(v.x, v.y, 0.0));
        let mut pulls = [Pull::NONE; MOST];
        let mut n = 0;
        let mut push = |pull: Pull| {
            pulls[n] = pull;
            n += 1;
        };
        for i in 0..self.count {
            let mut pull = Pull::at(i, zeta, per_normal);
            if !(self.sticks[i] || frictionless) {
                let (d, torque) = self.friction(p.slip[i], p.omega.dot(&zeta), zeta);
                pull.at[i] = p.rot.tr_mul(&d);
                pull.torque += torque;
            }
            push(pull);
        }
        let (mut line, mut pair) = (Vector2::zeros(), [0, 0]);
        let s = self.sticking().count();
        match s {
            0 => {}
            1 => {
                let i = self.sticking().next().unwrap_or(0);
                push(Pull::at(i, body_axis(Vector2::x()), Vector3::zeros()));
                push(Pull::at(i, body_axis(Vector2::y()), Vector3::zeros()));
            }
            _ => {
                // The horizontal positions of the sticking contacts from their centroid.
                let at = |i: usize| (p.rot * p.contact[i].r).xy();
                let centroid = self.sticking().map(at).sum::<Vector2<f64>>() / s as f64;
                let q = |i: usize| at(i) - centroid;
                let spread: f64 = self.sticking().map(|i| q(i).norm_squared()).sum();
                let on = |i: usize| self.sticks[i] && i < self.count;
                let share = 1.0 / s as f64;
                push(Pull::spread(
                    |i| {
                        if on(i) {
                            body_axis(Vector2::x() * share)
                        } else {
                            Vector3::zeros()
                        }
                    },
                    Vector3::zeros(),
                ));
                push(Pull::spread(
                    |i| {
                        if on(i) {
                            body_axis(Vector2::y() * share)
                        } else {
                            Vector3::zeros()
                        }
                    },
                    Vector3::zeros(),
                ));
                if spread > 0.0 {
                    push(Pull::spread(
                        |i| {
                            if on(i) {
                                let q = q(i);
                                body_axis(Vector2::new(-q.y, q.x) / spread)
                            } else {
                                Vector3::zeros()
                            }
                        },
                        Vector3::zeros(),
                    ));
                }
                if s == 2 {
                    let mut it = self.sticking();
                    pair = [it.next().unwrap_or(0), it.next().unwrap_or(1)];
                    let joint = at(pair[1]) - at(pair[0]);
                    line = if joint.norm() > 0.0 {
                        joint.normalize()
                    } else {
                        Vector2::x()
                    };
                }
            }
        }
        (pulls, n, line, pair)
    }

    /// The matrix A of the rows' accelerations per unit of each pull (identity where
    /// there is no pull), with each pull's a_G (linear) and ω̇ (angular) per unit:
    /// A_rk = Σ_i row_r,i·(lin_k + α_k × r_i).
    fn matrix(
        body: &Body,
        p: &Active,
        pulls: &[Pull; MOST],
        n: usize,
    ) -> (Matrix, [Vector3<f64>; MOST], [Vector3<f64>; MOST]) {
        let (m, i_inv) = (body.mass(), body.inertia_inv());
        let r = p.contact.map(|c| c.r);
        let mut a = Matrix::identity();
        let mut lin = [Vector3::zeros(); MOST];
        let mut ang = [Vector3::zeros(); MOST];
        for k in 0..n {
            let pull = &pulls[k];
            lin[k] = pull.at.iter().sum::<Vector3<f64>>() / m;
            let moment: Vector3<f64> = (0..MOST_CONTACTS).map(|i| r[i].cross(&pull.at[i])).sum();
            ang[k] = i_inv * (moment + pull.torque);
            for (row, other) in pulls.iter().enumerate().take(n) {
                a[(row, k)] = (0..MOST_CONTACTS)
                    .map(|i| other.row[i].dot(&(lin[k] + ang[k].cross(&r[i]))))
                    .sum();
            }
        }
        (a, lin, ang)
    }

    /// The forces of the active set at `kin` (see the module docs).
    pub fn forces(&self, body: &Body, gravity: f64, kin: &Kinematics, load: &Wrench) -> Forces {
        let p = self.active(body, kin);
        let per_normal = load.torque_per_normal;
        let (pulls, n, line, pair) = self.pulls(&p, per_normal, false);
        let (a, _, ang) = Self::matrix(body, &p, &pulls, n);
        let zeta = p.contact[0].zeta;
        let w = p.omega;
        let beta = body.inertia_inv() * (load.torque - w.cross(&(body.inertia() * w)));
        let a0 = kin.rot.tr_mul(&load.force) / body.mass() - gravity * zeta;
        let biases = p
            .contact
            .map(|c| a0 + beta.cross(&c.r) + w.cross(&(w.cross(&c.r) + c.r_dot_surface)));
        let mut b = Vector::zeros();
        for (k, pull) in pulls.iter().enumerate().take(n) {
            b[k] = -(0..MOST_CONTACTS)
                .map(|i| pull.row[i].dot(&biases[i]))
                .sum::<f64>();
        }
        let lu = a.lu();
        let x = lu.solve(&b).unwrap_or(Vector::from_element(f64::NAN));
        let all_stick = self.all_stick();
        let painleve = if all_stick {
            f64::INFINITY
        } else if self.friction == 0.0 {
            1.0
        } else {
            let (plain, n0, _, _) = self.pulls(&p, per_normal, true);
            lu.determinant() / Self::matrix(body, &p, &plain, n0).0.determinant()
        };
        let mut at = [Vector3::zeros(); MOST_CONTACTS];
        let (mut omega_dot, mut torque) = (beta, Vector3::zeros());
        for k in 0..n {
            for (at, pull) in at.iter_mut().zip(&pulls[k].at) {
                *at += x[k] * pull;
            }
            omega_dot += x[k] * ang[k];
            torque += x[k] * pulls[k].torque;
        }
        let tangential = at.map(|f| (kin.rot * f).xy());
        // Every contact sticking, the body can only turn about C_1C_2 (two) or not at all
        // (three): the rest of ω is drift.
        let turn = match (all_stick, self.count) {
            (false, _) => w,
            (true, 2) => {
                let e = kin.rot.tr_mul(&Vector3::new(line.x, line.y, 0.0));
                e * e.dot(&w)
            }
            (true, _) => Vector3::zeros(),
        };
        Forces {
            normal: at.map(|f| f.dot(&zeta)),
            tangential,
            slip: p.slip,
            force: kin.rot * at.iter().sum::<Vector3<f64>>(),
            omega_dot,
            painleve,
            power: -(0..self.count)
                .filter(|&i| !self.sticks[i])
                .map(|i| tangential[i].dot(&p.slip[i]))
                .sum::<f64>()
                - torque.dot(&turn),
            line,
            pair,
        }
    }

    /// Impulses at the contacts that bring each constrained velocity — the normal
    /// velocities, and the horizontal ones of the sticking contacts — to its target:
    /// zero, or at contact i a slip `seed[i]` (world; where contact i sticks; the seeds of
    /// two or more sticking contacts are met as far as a rigid motion can: their least-
    /// squares rigid horizontal motion). The matrix is A's with sliding contacts pushed
    /// along ζ and no torque per unit (the Delassus matrix of the constrained directions,
    /// symmetric positive definite), and the kinetic energy the impulses change is booked
    /// in W, so E + W is unchanged. A sticking impact where the state arrives with slip;
    /// the restoring step of the sticking constraints after every step; a seed of slip
    /// where a contact starts to slide.
    pub fn impel(&self, body: &Body, y: &mut State, seed: [Vector2<f64>; MOST_CONTACTS]) {
        let kin = Kinematics::new(body, y, false);
        let p = self.active(body, &kin);
        let (pulls, n, _, _) = self.pulls(&p, Vector3::zeros(), true);
        let (a, lin, ang) = Self::matrix(body, &p, &pulls, n);
        let v_g = kin.rot.tr_mul(&kin.v_g);
        let v = p.contact.map(|c| v_g + kin.omega.cross(&c.r));
        let target = seed.map(|s| kin.rot.tr_mul(&Vector3::new(s.x, s.y, 0.0)));
        let mut b = Vector::zeros();
        for (k, pull) in pulls.iter().enumerate().take(n) {
            b[k] = (0..self.count)
                .map(|i| pull.row[i].dot(&(target[i] - v[i])))
                .sum();
        }
        let Some(x) = a.lu().solve(&b) else {
            return;
        };
        let kinetic = |y: &State| {
            let kin = Kinematics::new(body, y, false);
            0.5 * (body.mass() * kin.v_g.norm_squared()
                + kin.omega.dot(&(body.inertia() * kin.omega)))
        };
        let before = kinetic(y);
        let (mut dv, mut dw) = (Vector3::zeros(), Vector3::zeros());
        for k in 0..n {
            dv += x[k] * lin[k];
            dw += x[k] * ang[k];
        }
        let dv = kin.rot * dv;
        y[state::VEL] += dv.x;
        y[state::VEL + 1] += dv.y;
        for i in 0..3 {
            y[state::OMEGA + i] += dw[i];
        }
        y[state::WORK] += before - kinetic(y);
    }
}

impl ContactLaw for Contacts {
    const ROLLING: bool = false;

    fn respond(
        &self,
        body: &Body,
        gravity: f64,
        kin: &Kinematics,
        _y: &State,
        load: &Wrench,
    ) -> Response {
        let f = self.forces(body, gravity, kin, load);
        Response {
            force: f.force,
            normal: f.normal.iter().sum(),
            omega_dot: f.omega_dot,
            painleve: f.painleve,
            other_normals: [f.normal[1], f.normal[2]],
            contact_power: Some(f.power),
        }
    }

    /// Restores the other contacts on an accepted state: the attitude turned by the
    /// smallest rotation δφ (body axes) that makes each gap g_k = h_1(ζ) − h_k(ζ) zero
    /// (∇_ζ g_k = r_k − r_1, and ζ turns by ζ × δφ, so g_k changes by δφ·a_k with
    /// a_k = (r_k − r_1) × ζ: δφ = Σ_k c_k a_k with the Gram system G c = −g), then ω
    /// corrected within the same axes so that each ġ_k = ω·a_k is zero (one Newton step
    /// each: the drift is of the size of the integration error); then, where a contact
    /// sticks, its slip brought back to zero ([`Contacts::impel`]).
    fn project(&self, body: &Body, y: &mut State) {
        let rot = state::rotation(y);
        let zeta = Vector3::new(rot[(2, 0)], rot[(2, 1)], rot[(2, 2)]);
        let omega = state::omega(y);
        let first = Contact::of(body, body.surface(), zeta, omega);
        let others = self.count - 1;
        let mut axes = [Vector3::zeros(); MOST_CONTACTS - 1];
        let mut gaps = Vector2::zeros();
        for k in 0..others {
            let other = self.others[k];
            axes[k] = (Contact::of(body, other, zeta, omega).r - first.r).cross(&zeta);
            gaps[k] = first.height - geometry::height(body, other, zeta);
        }
        // The Gram matrix of the axes (identity in the unused corner).
        let gram = Matrix2::from_fn(|i, j| {
            if i < others && j < others {
                axes[i].dot(&axes[j])
            } else if i == j {
                1.0
            } else {
                0.0
            }
        });
        let Some(inverse) = gram.try_inverse() else {
            return;
        };
        let combine = |c: Vector2<f64>| (0..others).map(|k| c[k] * axes[k]).sum::<Vector3<f64>>();
        let turn = combine(-(inverse * gaps));
        if !turn.iter().all(|x| x.is_finite()) {
            return;
        }
        let q = UnitQuaternion::new_normalize(state::quaternion(y))
            * UnitQuaternion::from_scaled_axis(turn);
        state::set_quaternion(y, &q);
        let rates = Vector2::from_fn(|k, _| if k < others { omega.dot(&axes[k]) } else { 0.0 });
        let correction = combine(inverse * rates);
        for i in 0..3 {
            y[state::OMEGA + i] -= correction[i];
        }
        if self.sticking().next().is_some() {
            self.impel(body, y, [Vector2::zeros(); MOST_CONTACTS]);
        }
    }
}
