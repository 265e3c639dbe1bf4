//! Two surfaces of the body in contact at once (docs/physics.md, "Contact spheres", "Two
//! contacts"), each sliding or sticking: the event-driven formulation of Pfeiffer &
//! Glocker (*Multibody Dynamics with Unilateral Contacts*, 1996) for a given active set.
//! The body's geometry (`kin`) is that of the first surface, so z_G = h_1(ζ); the second
//! surface's gap h_1(ζ) − h_2(ζ) stays zero.
//!
//! Body axes throughout. A sliding contact i carries F_i = N_i d_i, d_i = ζ − μ Rᵀŝ_i
//! (Coulomb; Coulomb–Contensou's over a contact disc, with its drilling torque per unit
//! N_i): one unknown. A sticking contact carries N_i ζ plus a horizontal force: three
//! unknowns. Each unknown x_k is a *pull*: force directions at the two contacts
//! (at_k,1, at_k,2) and a torque per unit t_k, so that
//! ```text
//!   a_G = Rᵀf/m − g ζ + Σ_k x_k (at_k,1 + at_k,2)/m,
//!   ω̇   = β + Σ_k x_k α_k,  α_k = I⁻¹(r_1 × at_k,1 + r_2 × at_k,2 + t_k),  β = I⁻¹(τ − ω × Iω).
//! ```
//! The material point at contact i accelerates at a_i = a_G + ω̇ × r_i + ω × (ω × r_i + ṙ_i)
//! (ṙ_i: the contact point moving over the surface, as for rolling), and each constrained
//! direction (the normal ζ at both contacts; the two horizontal axes at a sticking one) has
//! e·a_i = 0: a square linear system A x = b. Where both contacts stick, the pair of equal
//! and opposite forces along the line C_1C_2 (horizontal) moves nothing and is left
//! undetermined by the constraints: the law takes the least-norm forces, one unknown
//! L pulling along that line equally at both contacts and rows (a_1 + a_2)·ê/2 = 0.
//!
//! With a sliding contact, det A over its value without friction (d_i = ζ) is the law's
//! Painlevé denominator: 1 without friction, and ≤ 0 where the active set has no
//! consistent normal forces; with none it is infinite.

use nalgebra::{SMatrix, SVector, UnitQuaternion, Vector2, Vector3};

use super::contensou::ContactDisc;
use super::{ContactLaw, Kinematics, Response};
use crate::body::{Body, Surface};
use crate::effects::Wrench;
use crate::geometry::{self, Contact};
use crate::state::{self, State};

/// At most five unknowns: N_1, N_2 and three horizontal ones (both sticking).
const MOST: usize = 5;
type Matrix = SMatrix<f64, MOST, MOST>;
type Vector = SVector<f64, MOST>;

/// The two contacts, the body's surface in contact and `other`, each sliding or
/// sticking (`sticks`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoContacts {
    /// Coulomb coefficient μ (≥ 0; 0 is frictionless).
    pub friction: f64,
    /// The contact disc at each contact; `None` is a point contact.
    pub disc: Option<ContactDisc>,
    /// The second surface in contact.
    pub other: Surface,
    /// Whether each contact (the first, the second) sticks: its material point has no
    /// horizontal velocity.
    pub sticks: [bool; 2],
}

/// The contact forces of the active set at one state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Forces {
    /// N_1, N_2 \[N\].
    pub normal: [f64; 2],
    /// Each contact's horizontal force, world axes \[N\].
    pub tangential: [Vector2<f64>; 2],
    /// Each contact's slip, the horizontal velocity of its material point, world \[m/s\].
    pub slip: [Vector2<f64>; 2],
    /// The total contact force, world \[N\].
    pub force: Vector3<f64>,
    /// ω̇, body axes [rad/s²].
    pub omega_dot: Vector3<f64>,
    /// The Painlevé denominator (see the module docs).
    pub painleve: f64,
    /// The power of the contact forces, −Σ_i (F_i·v_Ci + t_i·ω) \[W\], a sticking
    /// contact's F_i·v_Ci taken as zero: its slip is the integration's drift (removed after
    /// every step by [`TwoContacts::impel`], which books the energy it takes), and the
    /// force's work on it, of either sign, would make W fall. With both sticking, t_i·ω is
    /// taken on ω's part along C_1C_2, the one turn the constraints leave: the rest is drift
    /// too (zero on the constraints), and a power that is zero there and positive at the
    /// stages off them would make W fall through the negative weights of the
    /// Runge–Kutta quadrature (a spin friction's, 2e-15 J a step).
    pub power: f64,
    /// With both contacts sticking, the unit vector along C_1C_2 (world, horizontal);
    /// else zero.
    pub line: Vector2<f64>,
}

/// What keeps a sticking contact sticking (docs/physics.md, "Two contacts").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Hold {
    /// Contact i's friction within its cone: μN_i − |F_h,i| ≥ 0, or, with both sticking,
    /// its part across the line C_1C_2, μN_i − |F_⊥,i| ≥ 0 (beyond, it slides across).
    Contact(usize),
    /// Both sticking: the force along C_1C_2, which the constraints leave to be shared
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
                let along = (self.tangential[0] + self.tangential[1]).dot(&self.line);
                left(0) + left(1) - along.abs()
            }
        }
    }
}

/// One unknown: its force direction at each contact (body axes, per unit), its torque per
/// unit, and the constraint row it pairs with (directions at each contact).
#[derive(Clone, Copy)]
struct Pull {
    at: [Vector3<f64>; 2],
    torque: Vector3<f64>,
    row: [Vector3<f64>; 2],
}

impl Pull {
    const NONE: Pull = Pull {
        at: [Vector3::new(0.0, 0.0, 0.0); 2],
        torque: Vector3::new(0.0, 0.0, 0.0),
        row: [Vector3::new(0.0, 0.0, 0.0); 2],
    };

    /// A force along `e` at contact `i` alone, paired with the row e·a_i.
    fn at(i: usize, e: Vector3<f64>, torque: Vector3<f64>) -> Pull {
        let mut at = [Vector3::zeros(); 2];
        at[i] = e;
        Pull {
            at,
            torque,
            row: at,
        }
    }
}

/// The two contacts' geometry at one state.
struct Pair {
    contact: [Contact; 2],
    slip: [Vector2<f64>; 2],
    rot: nalgebra::Matrix3<f64>,
    omega: Vector3<f64>,
}

impl TwoContacts {
    /// Each contact's kinematics: `kin` (the first's) and the second's, `kin` with the
    /// second contact's geometry and horizontal slip v_C2 = v_G + (ω × r_2)_h.
    #[inline]
    pub fn each(&self, body: &Body, kin: &Kinematics) -> [Kinematics; 2] {
        let contact = Contact::of(body, self.other, kin.contact.zeta, kin.omega);
        let slip = kin.v_g.xy() + (kin.rot * kin.omega.cross(&contact.r)).xy();
        [
            *kin,
            Kinematics {
                contact,
                slip,
                ..*kin
            },
        ]
    }

    fn pair(&self, body: &Body, kin: &Kinematics) -> Pair {
        let [_, second] = self.each(body, kin);
        Pair {
            contact: [kin.contact, second.contact],
            slip: [kin.slip, second.slip],
            rot: kin.rot,
            omega: kin.omega,
        }
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

    /// The unknowns of the active set and their number. `frictionless`: every sliding
    /// contact pushed along ζ alone (the Painlevé denominator's reference, and impulses).
    fn pulls(
        &self,
        p: &Pair,
        per_normal: Vector3<f64>,
        frictionless: bool,
    ) -> ([Pull; MOST], usize, Vector2<f64>) {
        let zeta = p.contact[0].zeta;
        let body_axis = |x: f64, y: f64| p.rot.tr_mul(&Vector3::new(x, y, 0.0));
        let mut pulls = [Pull::NONE; MOST];
        let mut n = 0;
        let mut line = Vector2::zeros();
        let mut push = |pull: Pull| {
            pulls[n] = pull;
            n += 1;
        };
        for i in 0..2 {
            let mut pull = Pull::at(i, zeta, per_normal);
            if !(self.sticks[i] || frictionless) {
                let (d, torque) = self.friction(p.slip[i], p.omega.dot(&zeta), zeta);
                pull.at[i] = p.rot.tr_mul(&d);
                pull.torque += torque;
            }
            push(pull);
        }
        if self.sticks == [true, true] {
            // The line C_1C_2 (horizontal): the force along it is shared by both contacts.
            let joint = (p.rot * (p.contact[1].r - p.contact[0].r)).xy();
            let e = if joint.norm() > 0.0 {
                joint.normalize()
            } else {
                Vector2::x()
            };
            line = e;
            let (along, across) = (body_axis(e.x, e.y), body_axis(-e.y, e.x));
            push(Pull {
                at: [along, along],
                torque: Vector3::zeros(),
                row: [along / 2.0, along / 2.0],
            });
            push(Pull::at(0, across, Vector3::zeros()));
            push(Pull::at(1, across, Vector3::zeros()));
        } else {
            for i in (0..2).filter(|&i| self.sticks[i]) {
                push(Pull::at(i, body_axis(1.0, 0.0), Vector3::zeros()));
                push(Pull::at(i, body_axis(0.0, 1.0), Vector3::zeros()));
            }
        }
        (pulls, n, line)
    }

    /// The matrix A of the rows' accelerations per unit of each pull (identity where
    /// there is no pull), with each pull's a_G (linear) and ω̇ (angular) per unit:
    /// A_rk = Σ_i row_r,i·(lin_k + α_k × r_i).
    fn matrix(
        body: &Body,
        p: &Pair,
        pulls: &[Pull; MOST],
        n: usize,
    ) -> (Matrix, [Vector3<f64>; MOST], [Vector3<f64>; MOST]) {
        let (m, i_inv) = (body.mass(), body.inertia_inv());
        let r = [p.contact[0].r, p.contact[1].r];
        let mut a = Matrix::identity();
        let mut lin = [Vector3::zeros(); MOST];
        let mut ang = [Vector3::zeros(); MOST];
        for k in 0..n {
            let pull = &pulls[k];
            lin[k] = (pull.at[0] + pull.at[1]) / m;
            ang[k] = i_inv * (r[0].cross(&pull.at[0]) + r[1].cross(&pull.at[1]) + pull.torque);
            for (row, other) in pulls.iter().enumerate().take(n) {
                a[(row, k)] = (0..2)
                    .map(|i| other.row[i].dot(&(lin[k] + ang[k].cross(&r[i]))))
                    .sum();
            }
        }
        (a, lin, ang)
    }

    /// The forces of the active set at `kin` (see the module docs).
    pub fn forces(&self, body: &Body, gravity: f64, kin: &Kinematics, load: &Wrench) -> Forces {
        let p = self.pair(body, kin);
        let per_normal = load.torque_per_normal;
        let (pulls, n, line) = self.pulls(&p, per_normal, false);
        let (a, _, ang) = Self::matrix(body, &p, &pulls, n);
        let zeta = p.contact[0].zeta;
        let w = p.omega;
        let beta = body.inertia_inv() * (load.torque - w.cross(&(body.inertia() * w)));
        let a0 = kin.rot.tr_mul(&load.force) / body.mass() - gravity * zeta;
        let bias =
            |c: &Contact| a0 + beta.cross(&c.r) + w.cross(&(w.cross(&c.r) + c.r_dot_surface));
        let biases = [bias(&p.contact[0]), bias(&p.contact[1])];
        let mut b = Vector::zeros();
        for (k, pull) in pulls.iter().enumerate().take(n) {
            b[k] = -(pull.row[0].dot(&biases[0]) + pull.row[1].dot(&biases[1]));
        }
        let lu = a.lu();
        let x = lu.solve(&b).unwrap_or(Vector::from_element(f64::NAN));
        let painleve = if self.sticks == [true, true] {
            f64::INFINITY
        } else if self.friction == 0.0 {
            1.0
        } else {
            let (plain, n0, _) = self.pulls(&p, per_normal, true);
            lu.determinant() / Self::matrix(body, &p, &plain, n0).0.determinant()
        };
        let mut at = [Vector3::zeros(); 2];
        let (mut omega_dot, mut torque) = (beta, Vector3::zeros());
        for k in 0..n {
            at[0] += x[k] * pulls[k].at[0];
            at[1] += x[k] * pulls[k].at[1];
            omega_dot += x[k] * ang[k];
            torque += x[k] * pulls[k].torque;
        }
        let tangential = [(kin.rot * at[0]).xy(), (kin.rot * at[1]).xy()];
        // Both sticking, the body can only turn about C_1C_2: the rest of ω is drift.
        let turn = if self.sticks == [true, true] {
            let e = kin.rot.tr_mul(&Vector3::new(line.x, line.y, 0.0));
            e * e.dot(&w)
        } else {
            w
        };
        Forces {
            normal: [at[0].dot(&zeta), at[1].dot(&zeta)],
            tangential,
            slip: p.slip,
            force: kin.rot * (at[0] + at[1]),
            omega_dot,
            painleve,
            power: -(0..2)
                .filter(|&i| !self.sticks[i])
                .map(|i| tangential[i].dot(&p.slip[i]))
                .sum::<f64>()
                - torque.dot(&turn),
            line,
        }
    }

    /// Impulses at the contacts that bring each constrained velocity — both normal
    /// velocities, and the horizontal ones of the sticking contacts — to its target:
    /// zero, or at contact i a slip `seed[i]` (world; where contact i sticks). The
    /// matrix is A's with sliding contacts pushed along ζ and no torque per unit (the
    /// Delassus matrix of the constrained directions, symmetric positive definite), and
    /// the kinetic energy the impulses change is booked in W, so E + W is unchanged.
    /// A sticking impact at both contacts where the state arrives with slip; the restoring
    /// step of the sticking constraint after every step; a seed of slip where a contact
    /// starts to slide.
    pub fn impel(&self, body: &Body, y: &mut State, seed: [Vector2<f64>; 2]) {
        let kin = Kinematics::new(body, y, false);
        let p = self.pair(body, &kin);
        let (pulls, n, _) = self.pulls(&p, Vector3::zeros(), true);
        let (a, lin, ang) = Self::matrix(body, &p, &pulls, n);
        let v_g = kin.rot.tr_mul(&kin.v_g);
        let v = [
            v_g + kin.omega.cross(&p.contact[0].r),
            v_g + kin.omega.cross(&p.contact[1].r),
        ];
        let target = [0, 1].map(|i| kin.rot.tr_mul(&Vector3::new(seed[i].x, seed[i].y, 0.0)));
        let mut b = Vector::zeros();
        for (k, pull) in pulls.iter().enumerate().take(n) {
            b[k] = (0..2).map(|i| pull.row[i].dot(&(target[i] - v[i]))).sum();
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

impl ContactLaw for TwoContacts {
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
            normal: f.normal[0] + f.normal[1],
            omega_dot: f.omega_dot,
            painleve: f.painleve,
            second_normal: f.normal[1],
            contact_power: Some(f.power),
        }
    }

    /// Restores the second contact on an accepted state: the attitude turned by the
    /// smallest rotation δφ (body axes) that makes the gap g = h_1(ζ) − h_2(ζ) zero
    /// (∇_ζ g = r_2 − r_1, and ζ turns by ζ × δφ), then ω corrected along the same axis so
    /// that ġ = (r_2 − r_1)·(ζ × ω) is zero (one Newton step each: the drift is of the
    /// size of the integration error); then, where a contact sticks, its slip brought
    /// back to zero ([`TwoContacts::impel`]).
    fn project(&self, body: &Body, y: &mut State) {
        let rot = state::rotation(y);
        let zeta = Vector3::new(rot[(2, 0)], rot[(2, 1)], rot[(2, 2)]);
        let surface = body.surface();
        let gap = geometry::height(body, surface, zeta) - geometry::height(body, self.other, zeta);
        let omega = state::omega(y);
        let dr = Contact::of(body, self.other, zeta, omega).r
            - Contact::of(body, surface, zeta, omega).r;
        // g changes by (r_2 − r_1)·(ζ × δφ) = δφ·((r_2 − r_1) × ζ) = δφ·axis.
        let axis = dr.cross(&zeta);
        let n2 = axis.norm_squared();
        if !(n2 > 0.0) {
            return;
        }
        let turn = -gap / n2 * axis;
        let q = UnitQuaternion::new_normalize(state::quaternion(y))
            * UnitQuaternion::from_scaled_axis(turn);
        state::set_quaternion(y, &q);
        // ġ = (r_2 − r_1)·(ζ × ω) = ω·axis.
        let correction = omega.dot(&axis) / n2 * axis;
        for i in 0..3 {
            y[state::OMEGA + i] -= correction[i];
        }
        if self.sticks != [false, false] {
            self.impel(body, y, [Vector2::zeros(); 2]);
        }
    }
}
