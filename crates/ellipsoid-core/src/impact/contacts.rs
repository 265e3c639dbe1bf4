//! Impact at several contacts at once, the struck one and up to [`MOST_CONTACTS`] − 1
//! others (docs/physics.md, "Contact spheres", "Impact at two contacts"; the hybrid
//! machine's `transition::pair_touchdown`): Newton's law at each contact with Coulomb
//! friction, the event-driven impact of Pfeiffer & Glocker (*Multibody Dynamics with
//! Unilateral Contacts*, 1996, ch. 7), in world axes, with impulses P_i = (P_t,i, Λ_i) at
//! the contact points C_i:
//! ```text
//!   v_i⁺ = v_i⁻ + Σ_j W_ij P_j,    W_ij = 𝟙/m − [r_i]× I⁻¹ [r_j]×
//!   ξ_i  = v_i⁺ + e min(v_n,i⁻, 0) e3                          (normal restitution only)
//!   P_i ∈ C_i = {|P_t| ≤ μ Λ},   −(ξ_i + μ|ξ_t,i| e3) ∈ N_{C_i}(P_i)   (De Saxcé)
//! ```
//! i.e. Λ_i ≥ 0, ξ_n,i ≥ 0, Λ_i ξ_n,i = 0, and at each contact either stick (ξ_t = 0,
//! |P_t| ≤ μΛ) or slide (P_t = −μΛ ξ̂_t). Solved as the fixed point
//! P_i = proj_{C_i}(P_i − ρ_i (ξ_i + μ|ξ_t,i| e3)) by block Gauss–Seidel,
//! ρ_i = 1/λ_max(W_ii). W is kept as a fixed 3·[`MOST_CONTACTS`]-square matrix, its blocks
//! of absent contacts zero: no heap allocation.
//!
//! Energy: T⁺ − T⁻ = Σ_i P_i·(v_i⁻ + v_i⁺)/2. For e = 0 (Moreau's law) it is
//! P·v⁺ − ½ PᵀWP ≤ 0, since Λ_i v_n,i⁺ = 0 and P_t,i·v_t,i⁺ = −μΛ_i|v_t,i⁺| ≤ 0;
//! frictionless, with one e at every contact and every contact that takes impulse
//! approaching (v_n,i⁻ ≤ 0), it is −(1 − e)/(2(1 + e)) ΛᵀWΛ ≤ 0. With e > 0 Newton's law
//! can add energy: with friction (Kane's paradox; Glocker, Multibody Syst. Dyn. 2013),
//! and, frictionless too, where an impulse holds a contact that was leaving
//! (v_n,i⁻ > 0, Λ_i > 0, v_n,i⁺ = 0; for e = 1 the change is Σ Λ_i v_n,i⁻/2 over those).
//! Where it would, the impact is taken with e = 0.
//!
//! The impulses need not be unique where the velocities are: W = J M⁻¹ Jᵀ has the rank of
//! the body's six velocities at most, so it is singular for three contacts, and for two an
//! equal and opposite tangential pair along C_1C_2 does nothing (Jᵀ P = 0: no change of
//! v_G, ω or the energy). The iteration is therefore taken as converged where a sweep no
//! longer changes the contacts' velocities: its impulses can drift along W's null space
//! without end (measured: an impulse split creeping by 4e-14 of its scale a sweep for
//! 200,000 sweeps, a two-contact impact of the campaign with contact spheres, seed 7
//! scene 24, whose velocities had converged at sweep 146). Where the iteration does not
//! converge (the friction law is not monotone, so it may cycle), it gives `None`.
//!
//! The no-slip law (the rolling model) is the limit μ → ∞: a contact either separates
//! (P_i = 0, ξ_n,i ≥ 0) or stays and sticks (ξ_i = 0, Λ_i ≥ 0, P_t,i free). Its active set
//! S of staying contacts is found by trying each non-empty one, solving W_SS P_S = −ξ⁻_S by
//! the least-norm solution (with two or more stuck W_SS is singular: an equal and opposite
//! tangential pair along C_iC_j does nothing, as in the two-contact phase; with three
//! non-collinear contacts stuck it has rank 6 and, for e = 0, leaves the body at rest), and
//! keeping the first whose conditions hold. The law can have several solutions (a
//! separating contact's tangential velocity is free, so the problem is not monotone): a
//! contact that separates with no impulse, and the same contact held sticking by a
//! tangential impulse larger than its normal one. The sets are tried
//! - smallest first: a contact that can separate with no impulse does. That solution
//!   solves Coulomb's law at every μ above what the other contacts need, the one that holds
//!   the contact only above |P_t|/Λ there;
//! - among sets of one size, those with the struck contact (index 0) first, then by the
//!   others' indices (lexicographic order of the sets' contacts): the impact is the struck
//!   contact's, and where it alone suffices it is the one-contact no-slip impact.
//!
//! For two contacts the order is the struck one, the other, both. For e = 0 the energy
//! change is −½PᵀWP ≤ 0. No set holds where sticking the struck contact would take a
//! pulling normal impulse (Λ < 0) and another is driven in if it takes none: there
//! Coulomb's solution slides at the struck contact with a tangential impulse that grows
//! with μ, and the law has no limit (`None`).

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::{Approach, Tangential};
use crate::model::MOST_CONTACTS;

/// The impulses (or velocities) of every contact, three rows a contact.
type Stacked = SVector<f64, { 3 * MOST_CONTACTS }>;
type Coupling = SMatrix<f64, { 3 * MOST_CONTACTS }, { 3 * MOST_CONTACTS }>;

/// Most block Gauss–Seidel sweeps; the iteration converges linearly at a rate set by
/// W's coupling of the contacts: medians of about 140 and at most 18,893 sweeps in two
/// sets of 300 random two-contact impacts (the module's test and a milder one), a median
/// of 94 in 600 random three-contact ones (the module's test), all but one within 3,452
/// sweeps and that one (Coulomb, μ = 0.83, e = 0) within 189,576.
const MAX_SWEEPS: u32 = 200_000;

/// The fixed point is reached where a sweep changes the contacts' velocities
/// v = v⁻ + W P by less than this, relative to |v⁻|.
const CONVERGED: f64 = 1e-15;

/// The outcome of [`resolve_contacts`]; entries at index ≥ `count` are zero (false).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactsImpact {
    /// Post-impact velocity of G, world \[m/s\].
    pub v_g: Vector3<f64>,
    /// Post-impact angular velocity, world \[rad/s\].
    pub omega: Vector3<f64>,
    /// The impulse at each contact, world \[N·s\].
    pub impulse: [Vector3<f64>; MOST_CONTACTS],
    /// v_n = e3·v_C at each contact, before and after \[m/s\].
    pub normal_velocity: [(f64, f64); MOST_CONTACTS],
    /// Kinetic energy before − after \[J\], ≥ 0.
    pub energy_loss: f64,
    /// Whether each contact's tangential velocity is zero after the impact.
    pub stuck: [bool; MOST_CONTACTS],
    /// The restitution the impact was taken with: the scene's e, or 0 where Newton's law
    /// with e would have added energy.
    pub restitution: f64,
    /// Gauss–Seidel sweeps spent (0 for the no-slip law).
    pub sweeps: u32,
    /// Contacts of the impact, the struck one included.
    pub count: usize,
}

/// The contacts' velocities as a linear function of their impulses, v = v⁻ + W P.
struct Contacts {
    w: Coupling,
    v0: Stacked,
    /// ρ_i = 1/λ_max(W_ii).
    rho: [f64; MOST_CONTACTS],
    /// Lever arms r_i = C_i − G, world.
    levers: [Vector3<f64>; MOST_CONTACTS],
    count: usize,
}

impl Contacts {
    fn new(body: &Approach, others: &[Vector3<f64>]) -> Self {
        let count = 1 + others.len();
        let mut levers = [Vector3::zeros(); MOST_CONTACTS];
        levers[0] = body.r;
        levers[1..count].copy_from_slice(others);
        let mut w = Coupling::zeros();
        let mut v0 = Stacked::zeros();
        for (i, ri) in levers[..count].iter().enumerate() {
            for (j, rj) in levers[..count].iter().enumerate() {
                let block = Matrix3::identity() / body.mass
                    - ri.cross_matrix() * body.inertia_inv * rj.cross_matrix();
                w.fixed_view_mut::<3, 3>(3 * i, 3 * j).copy_from(&block);
            }
            let v = body.v_g + body.omega.cross(ri);
            v0.fixed_rows_mut::<3>(3 * i).copy_from(&v);
        }
        let w = (w + w.transpose()) * 0.5;
        let rho = std::array::from_fn(|i| {
            if i < count {
                let block = w.fixed_view::<3, 3>(3 * i, 3 * i).into_owned();
                1.0 / block.symmetric_eigenvalues().max()
            } else {
                0.0
            }
        });
        Contacts {
            w,
            v0,
            rho,
            levers,
            count,
        }
    }

    fn velocity(&self, p: &Stacked) -> Stacked {
        self.v0 + self.w * p
    }

    /// v_i = v_i⁻ + Σ_j W_ij P_j, contact i's rows of [`Contacts::velocity`].
    fn velocity_at(&self, i: usize, p: &Stacked) -> Vector3<f64> {
        self.v0.fixed_rows::<3>(3 * i) + self.w.fixed_rows::<3>(3 * i) * p
    }
}

/// Projection onto the friction cone {|P_t| ≤ μ Λ} (the half-line Λ ≥ 0 for μ = 0).
fn project_cone(p: Vector3<f64>, mu: f64) -> Vector3<f64> {
    let t = p.xy().norm();
    let n = p.z;
    if t <= mu * n {
        return p;
    }
    if mu * t <= -n {
        return Vector3::zeros();
    }
    let lambda = (mu * t + n) / (mu * mu + 1.0);
    let pt = if t > 0.0 {
        p.xy() * (mu * lambda / t)
    } else {
        nalgebra::Vector2::zeros()
    };
    Vector3::new(pt.x, pt.y, lambda)
}

/// Resolves the impact of `body` on the plane at several contacts at once: index 0 the
/// struck one at `body.r`, then one at each lever arm of `others` (world), with Newton's
/// restitution e at all and the tangential law (see the module docs). `None` where the
/// iteration does not converge or, for the no-slip law, no active set satisfies its
/// conditions.
///
/// # Panics
/// Unless `others` holds 1 to [`MOST_CONTACTS`] − 1 lever arms.
pub fn resolve_contacts(
    body: &Approach,
    others: &[Vector3<f64>],
    tangential: Tangential,
    restitution: f64,
) -> Option<ContactsImpact> {
    assert!(
        (1..MOST_CONTACTS).contains(&others.len()),
        "{} other contacts",
        others.len()
    );
    let contacts = Contacts::new(body, others);
    let e = restitution.clamp(0.0, 1.0);
    let law = |e| match tangential {
        Tangential::Frictionless => solve(body, &contacts, 0.0, e),
        Tangential::Coulomb { friction } => solve(body, &contacts, friction.max(0.0), e),
        Tangential::NoSlip => stick(body, &contacts, e),
    };
    let hit = law(e)?;
    // Where Newton's law adds energy (the module docs), Moreau's (e = 0) cannot.
    if e > 0.0 && hit.energy_loss < 0.0 {
        return law(0.0);
    }
    Some(hit)
}

/// The fixed point of the module docs with restitution `e`.
fn solve(body: &Approach, contacts: &Contacts, mu: f64, e: f64) -> Option<ContactsImpact> {
    let mut shift = Stacked::zeros();
    for i in 0..contacts.count {
        shift[3 * i + 2] = e * contacts.v0[3 * i + 2].min(0.0);
    }
    let scale = contacts.v0.norm();
    let mut p = Stacked::zeros();
    let mut sweeps = 0;
    loop {
        sweeps += 1;
        let before = p;
        for i in 0..contacts.count {
            let xi = contacts.velocity_at(i, &p) + shift.fixed_rows::<3>(3 * i);
            let xi_hat = xi + Vector3::z() * (mu * xi.xy().norm());
            let old = p.fixed_rows::<3>(3 * i).into_owned();
            let new = project_cone(old - contacts.rho[i] * xi_hat, mu);
            p.fixed_rows_mut::<3>(3 * i).copy_from(&new);
        }
        if !p.iter().all(|x| x.is_finite()) {
            return None;
        }
        // The sweep's change of the contacts' velocities: they (and v_G⁺, ω⁺) are what
        // converges; the impulses need not, where W is singular (module docs).
        if (contacts.w * (p - before)).norm() <= CONVERGED * scale {
            break;
        }
        if sweeps >= MAX_SWEEPS {
            return None;
        }
    }
    Some(outcome(body, contacts, p, e, sweeps))
}

/// The non-empty sets of `count` contacts (`true` where a contact stays) in the order the
/// no-slip law tries them (the module docs): by size, then lexicographically by their
/// contacts. With contact i as bit `count − 1 − i`, the descending bit patterns of one
/// size are that lexicographic order.
fn active_sets(count: usize) -> impl Iterator<Item = [bool; MOST_CONTACTS]> {
    (1..=count).flat_map(move |size| {
        (1..1_usize << count).rev().filter_map(move |bits: usize| {
            let set = std::array::from_fn(|i| i < count && (bits >> (count - 1 - i)) & 1 == 1);
            (bits.count_ones() as usize == size).then_some(set)
        })
    })
}

/// The no-slip law of the module docs with restitution `e`: the first active set (in the
/// order of [`active_sets`]) whose least-norm impulses satisfy its conditions (Λ_i ≥ 0
/// where a contact stays, ξ_n,j ≥ 0 where it separates), to [`STICK_TOL`] of the velocity
/// and impulse scales.
fn stick(body: &Approach, contacts: &Contacts, e: f64) -> Option<ContactsImpact> {
    let count = contacts.count;
    let target = |i: usize| -e * contacts.v0[3 * i + 2].min(0.0);
    let scale = contacts.v0.norm();
    let tol = STICK_TOL * scale;
    // Rows of a contact that separates (or is absent) are the identity on its (zero)
    // impulse, scaled as W so that the least-norm cut-off treats all blocks alike.
    let unit = contacts.w.norm() / ((3 * count) as f64).sqrt();
    active_sets(count).find_map(|stays| {
        let (mut a, mut rhs) = (Coupling::identity() * unit, Stacked::zeros());
        for i in (0..count).filter(|&i| stays[i]) {
            for j in (0..count).filter(|&j| stays[j]) {
                let block = contacts.w.fixed_view::<3, 3>(3 * i, 3 * j).into_owned();
                a.fixed_view_mut::<3, 3>(3 * i, 3 * j).copy_from(&block);
            }
            let xi = contacts.v0.fixed_rows::<3>(3 * i) - Vector3::z() * target(i);
            rhs.fixed_rows_mut::<3>(3 * i).copy_from(&(-xi));
        }
        // One step of refinement on the residual takes the least-norm solve from its
        // round-off times A's conditioning to that of A itself.
        let svd = a.svd(true, true);
        let mut p = svd.solve(&rhs, STICK_TOL * unit).ok()?;
        p += svd.solve(&(rhs - a * p), STICK_TOL * unit).ok()?;
        // A separating contact's impulse is zero (not the solve's round-off about it).
        for i in (0..MOST_CONTACTS).filter(|&i| !stays[i]) {
            p.fixed_rows_mut::<3>(3 * i).fill(0.0);
        }
        let v = contacts.velocity(&p);
        let holds = (0..count).all(|i| {
            if stays[i] {
                let xi = v.fixed_rows::<3>(3 * i) - Vector3::z() * target(i);
                p[3 * i + 2] >= -tol * contacts.rho[i] && xi.norm() <= tol
            } else {
                v[3 * i + 2] >= target(i) - tol
            }
        });
        holds.then(|| outcome(body, contacts, p, e, 0))
    })
}

/// Most relative residual of the no-slip law's conditions (its least-norm solve is exact
/// to a few ulps of the velocity scale times W's conditioning).
const STICK_TOL: f64 = 1e-10;

/// The impact with impulses `p` (every contact, world): the velocities after, the loss
/// −P·(v⁻ + v⁺)/2 (a negative value within its round-off bound reported as 0), and which
/// contacts are left not slipping.
fn outcome(
    body: &Approach,
    contacts: &Contacts,
    p: Stacked,
    e: f64,
    sweeps: u32,
) -> ContactsImpact {
    let count = contacts.count;
    let v_after = contacts.velocity(&p);
    let loss = -p.dot(&(contacts.v0 + v_after)) * 0.5;
    let round_off = 64.0 * f64::EPSILON * p.norm() * (contacts.v0.norm() + v_after.norm());
    let loss = if loss < 0.0 && loss > -round_off {
        0.0
    } else {
        loss
    };
    let impulse: [Vector3<f64>; MOST_CONTACTS] =
        std::array::from_fn(|i| p.fixed_rows::<3>(3 * i).into_owned());
    let total: Vector3<f64> = impulse.iter().sum();
    let moment: Vector3<f64> = (contacts.levers.iter().zip(&impulse))
        .map(|(r, p)| r.cross(p))
        .sum();
    let slip_tol = super::SLIP_TOL * contacts.v0.norm();
    ContactsImpact {
        v_g: body.v_g + total / body.mass,
        omega: body.omega + body.inertia_inv * moment,
        impulse,
        normal_velocity: std::array::from_fn(|i| (contacts.v0[3 * i + 2], v_after[3 * i + 2])),
        energy_loss: loss,
        stuck: std::array::from_fn(|i| {
            i < count && v_after.fixed_rows::<2>(3 * i).norm() <= slip_tol
        }),
        restitution: e,
        sweeps,
        count,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::impact::resolve;
    use nalgebra::Rotation3;

    /// A rod-like body: G at the origin, contacts at ±0.1 m along x, 0.05 m below.
    fn rod(v_g: Vector3<f64>, omega: Vector3<f64>) -> (Approach, Vector3<f64>) {
        let inertia = Matrix3::from_diagonal(&Vector3::new(2e-4, 1e-3, 1.1e-3));
        let body = Approach {
            mass: 0.3,
            inertia_inv: inertia.try_inverse().unwrap(),
            r: Vector3::new(0.1, 0.0, -0.05),
            v_g,
            omega,
        };
        (body, Vector3::new(-0.12, 0.01, -0.05))
    }

    /// Uniform numbers in [−1, 1) from a xorshift generator seeded with `seed`.
    fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    fn kinetic(body: &Approach, v_g: &Vector3<f64>, omega: &Vector3<f64>) -> f64 {
        let inertia = body.inertia_inv.try_inverse().unwrap();
        0.5 * body.mass * v_g.norm_squared() + 0.5 * omega.dot(&(inertia * omega))
    }

    /// The law's conditions at each contact, to `tol` of the velocity scale: Λ ≥ 0,
    /// ξ_n ≥ 0, Λ ξ_n = 0, and stick or slide against the slip within the cone.
    fn assert_law(
        body: &Approach,
        others: &[Vector3<f64>],
        hit: &ContactsImpact,
        mu: f64,
        tol: f64,
    ) {
        let levers: Vec<_> = std::iter::once(body.r)
            .chain(others.iter().copied())
            .collect();
        let reach = levers.iter().map(|r| r.norm()).fold(0.0, f64::max);
        let scale = body.v_g.norm() + body.omega.norm() * 2.0 * reach;
        assert_eq!(hit.count, levers.len());
        for (i, ri) in levers.iter().enumerate() {
            let v = hit.v_g + hit.omega.cross(ri);
            let p = hit.impulse[i];
            let v_before = body.v_g + body.omega.cross(ri);
            let xi_n = v.z + hit.restitution * v_before.z.min(0.0);
            assert!(p.z >= 0.0, "Λ_{i} = {}", p.z);
            assert!(xi_n >= -tol * scale, "ξ_n,{i} = {xi_n}");
            assert!(
                p.z * xi_n <= tol * scale * p.norm(),
                "Λ ξ_n = {}",
                p.z * xi_n
            );
            assert!(p.xy().norm() <= mu * p.z * (1.0 + 1e-12) + 1e-18);
            let slip = v.xy().norm();
            if slip > tol * scale {
                let opposed = p.xy() + mu * p.z * v.xy() / slip;
                assert!(
                    opposed.norm() <= tol * p.norm(),
                    "friction not against the slip at {i}"
                );
            }
        }
        for i in levers.len()..MOST_CONTACTS {
            assert_eq!(hit.impulse[i], Vector3::zeros());
            assert!(!hit.stuck[i] && hit.normal_velocity[i] == (0.0, 0.0));
        }
    }

    #[test]
    fn frictionless_pair_dissipates_exactly_the_newton_amount() {
        // Falling flat (both contacts approach), with a turn: both take impulse.
        let (body, second) = rod(Vector3::new(0.0, 0.0, -1.0), Vector3::new(0.3, 2.0, 0.0));
        for e in [0.0, 0.5, 1.0] {
            let hit = resolve_contacts(&body, &[second], Tangential::Frictionless, e).unwrap();
            assert_law(&body, &[second], &hit, 0.0, 1e-12);
            // ΔT = −(1 − e)/(2(1 + e)) ΛᵀWΛ.
            let contacts = Contacts::new(&body, &[second]);
            let p = Stacked::from_fn(|k, _| hit.impulse[k / 3][k % 3]);
            let expected = (1.0 - e) / (2.0 * (1.0 + e)) * p.dot(&(contacts.w * p));
            let before = kinetic(&body, &body.v_g, &body.omega);
            let after = kinetic(&body, &hit.v_g, &hit.omega);
            assert!(
                ((before - after) - expected).abs() <= 1e-12 * before,
                "e = {e}"
            );
            assert!((hit.energy_loss - expected).abs() <= 1e-12 * before);
            if e == 1.0 {
                assert!(hit.energy_loss.abs() <= 1e-12 * before);
            }
        }
    }

    #[test]
    fn a_pair_with_one_idle_contact_is_the_single_contact_impact() {
        // Only the first contact approaches and the second separates under its impulse:
        // Λ_2 = 0, and the first is the one-contact law (frictionless: Newton = Stronge).
        // The second contact beside the first, rising: the first's impulse lifts it too.
        let (body, _) = rod(Vector3::new(0.0, 0.0, -1.0), Vector3::new(60.0, 0.0, 0.0));
        let second = Vector3::new(0.08, 0.02, -0.05);
        let pair = resolve_contacts(&body, &[second], Tangential::Frictionless, 0.7).unwrap();
        let single = resolve(&body, Tangential::Frictionless, 0.7);
        assert_eq!(pair.impulse[1], Vector3::zeros());
        assert!((pair.impulse[0] - single.impulse).norm() <= 1e-13 * single.impulse.norm());
        assert!((pair.v_g - single.v_g).norm() <= 1e-13);
    }

    #[test]
    fn coulomb_pair_obeys_the_law_and_never_adds_energy() {
        // Random approaches, half of them elastic (e = 1).
        let mut uniform = uniform(0x2545_f491_4f6c_dd1d);
        let (mut slid, mut plastic) = (0, 0);
        for _ in 0..300 {
            let v = Vector3::new(uniform(), uniform(), -1.0 - uniform().abs());
            let w = Vector3::new(3.0 * uniform(), 3.0 * uniform(), 30.0 * uniform());
            let (body, second) = rod(v, w);
            let mu = 0.1 + 2.0 * uniform().abs();
            let e = if uniform() > 0.0 {
                1.0
            } else {
                uniform().abs()
            };
            let hit = resolve_contacts(&body, &[second], Tangential::Coulomb { friction: mu }, e)
                .expect("converges");
            assert_law(&body, &[second], &hit, mu, 1e-9);
            assert_energy(&body, &hit);
            slid += hit.stuck.iter().filter(|s| !**s).count();
            plastic += usize::from(hit.restitution != e);
        }
        assert!(
            slid > 50,
            "the cases should include sliding contacts: {slid}"
        );
        // Elastic impacts with friction include Kane's paradox, taken plastic.
        assert!(plastic > 0, "no case of Kane's paradox was met");
    }

    /// The no-slip law against an independent path, the Gauss–Seidel Coulomb solve at a
    /// friction high enough that it leaves every contact that stays sticking inside its
    /// cone (where it does, and with the same contacts taking impulse, the two laws
    /// coincide): the same velocities after; and the law's own conditions, with the energy
    /// never rising, in every case. As in the rolling model, the second contact is at rest
    /// (rolling) and the first strikes.
    #[test]
    fn no_slip_pair_is_coulomb_with_enough_friction() {
        let mut uniform = uniform(0x9e37_79b9_7f4a_7c15);
        let [mut compared, mut both, mut one, mut none] = [0; 4];
        for _ in 0..300 {
            let w = Vector3::new(10.0 * uniform(), 10.0 * uniform(), 30.0 * uniform());
            let (body, second) = rod(Vector3::zeros(), w);
            let strike = w.cross(&(body.r - second)).z;
            let w = if strike < 0.0 { w } else { -w };
            let (body, second) = rod(-w.cross(&second), w);
            let e = uniform().abs();
            let coulomb = |mu: f64, e: f64| {
                resolve_contacts(&body, &[second], Tangential::Coulomb { friction: mu }, e)
            };
            let Some(hit) = resolve_contacts(&body, &[second], Tangential::NoSlip, e) else {
                // Sticking the struck contact would pull; Coulomb's solution slides there,
                // its tangential impulse growing with μ.
                let grip = |mu: f64| coulomb(mu, e).map(|c| c.impulse[0].xy().norm());
                if let (Some(p3), Some(p10)) = (grip(3.0), grip(10.0)) {
                    assert!(p10 > 1.5 * p3, "{p3} {p10}");
                }
                none += 1;
                continue;
            };
            assert_energy(&body, &hit);
            let scale = w.norm() * 0.2;
            for (i, ri) in [body.r, second].iter().enumerate() {
                let v = hit.v_g + hit.omega.cross(ri);
                let target = -hit.restitution * (body.v_g + body.omega.cross(ri)).z.min(0.0);
                let p = hit.impulse[i];
                assert!(p.z >= -1e-12, "Λ_{i} = {}", p.z);
                if p == Vector3::zeros() {
                    assert!(v.z >= target - 1e-10 * scale, "ξ_n,{i} = {}", v.z - target);
                } else {
                    assert!((v - Vector3::z() * target).norm() <= 1e-10 * scale, "ξ_{i}");
                }
            }
            match hit.impulse.iter().filter(|p| p.z > 0.0).count() {
                2 => both += 1,
                _ => one += 1,
            }
            let Some(slid) = coulomb(3.0, hit.restitution) else {
                continue;
            };
            let inside = (0..2).all(|i| {
                let p = slid.impulse[i];
                p.xy().norm() < 3.0 * p.z * (1.0 - 1e-6) || p == Vector3::zeros()
            });
            let same_set = (0..2).all(|i| (slid.impulse[i].z > 0.0) == (hit.impulse[i].z > 0.0));
            if inside && same_set && slid.restitution == hit.restitution {
                compared += 1;
                assert!((slid.v_g - hit.v_g).norm() <= 1e-8 * scale, "v_G");
                assert!((slid.omega - hit.omega).norm() <= 1e-8 * scale / 0.2, "ω");
            }
        }
        assert!(
            compared > 200 && both > 200 && one > 10 && none < 10,
            "{compared} {both} {one} {none}"
        );
    }

    #[test]
    fn the_no_slip_sets_are_tried_by_size_then_struck_first() {
        let order = |count| -> Vec<Vec<usize>> {
            active_sets(count)
                .map(|set| (0..MOST_CONTACTS).filter(|&i| set[i]).collect())
                .collect()
        };
        assert_eq!(order(2), [vec![0], vec![1], vec![0, 1]]);
        let three = [
            vec![0],
            vec![1],
            vec![2],
            vec![0, 1],
            vec![0, 2],
            vec![1, 2],
            vec![0, 1, 2],
        ];
        assert_eq!(order(3), three);
    }

    /// A random body on three contacts on the plane, below G at angles 2πi/3 + `spread`·u about its
    /// vertical (u uniform in [−1, 1)), so non-collinear for `spread` < π/3, and G over
    /// their triangle for `spread` < π/6. Its tangential velocity of G and spin about the
    /// vertical are random, scaled by `tangential`, and its vertical velocity and tilting
    /// spin give the contacts the normal velocities `normal`:
    /// v_n,i = v_z + ω_x r_i,y − ω_y r_i,x.
    fn tripod(
        uniform: &mut impl FnMut() -> f64,
        spread: f64,
        tangential: f64,
        normal: [f64; 3],
    ) -> (Approach, [Vector3<f64>; 3]) {
        let mass = 0.05 + uniform().abs();
        let axes = Vector3::from_fn(|_, _| 0.02 + 0.08 * uniform().abs()).map(|a| a * a);
        let principal =
            Vector3::new(axes.y + axes.z, axes.z + axes.x, axes.x + axes.y) * mass / 5.0;
        let turn = Rotation3::from_scaled_axis(Vector3::from_fn(|_, _| 3.0 * uniform()));
        let inertia =
            turn.matrix() * Matrix3::from_diagonal(&principal) * turn.matrix().transpose();
        let depth = 0.01 + 0.07 * uniform().abs();
        let levers: [Vector3<f64>; 3] = std::array::from_fn(|i| {
            let angle = std::f64::consts::TAU * i as f64 / 3.0 + spread * uniform();
            let reach = 0.02 + 0.08 * uniform().abs();
            Vector3::new(reach * angle.cos(), reach * angle.sin(), -depth)
        });
        let tilt = Matrix3::from_fn(|i, k| [1.0, levers[i].y, -levers[i].x][k]);
        let x = tilt.lu().solve(&Vector3::from(normal)).unwrap();
        let body = Approach {
            mass,
            inertia_inv: inertia.try_inverse().unwrap(),
            r: levers[0],
            v_g: Vector3::new(tangential * uniform(), tangential * uniform(), x[0]),
            omega: Vector3::new(x[1], x[2], 30.0 * tangential * uniform()),
        };
        (body, levers)
    }

    /// The velocity scale of `body` on `levers`: |v_G| + |ω| 2 max|r_i|.
    fn speed(body: &Approach, levers: &[Vector3<f64>]) -> f64 {
        let reach = levers.iter().map(|r| r.norm()).fold(0.0, f64::max);
        body.v_g.norm() + body.omega.norm() * 2.0 * reach
    }

    /// The no-slip law's conditions, to `tol` of the velocity scale: a contact that stays
    /// has ξ = 0 and Λ ≥ 0, one that separates P = 0 and ξ_n ≥ 0.
    fn assert_no_slip(body: &Approach, levers: &[Vector3<f64>], hit: &ContactsImpact, tol: f64) {
        let scale = speed(body, levers);
        for (i, ri) in levers.iter().enumerate() {
            let v = hit.v_g + hit.omega.cross(ri);
            let target = -hit.restitution * (body.v_g + body.omega.cross(ri)).z.min(0.0);
            let p = hit.impulse[i];
            if p == Vector3::zeros() {
                assert!(v.z >= target - tol * scale, "ξ_n,{i} = {}", v.z - target);
            } else {
                assert!(p.z >= -tol * body.mass * scale, "Λ_{i} = {}", p.z);
                assert!((v - Vector3::z() * target).norm() <= tol * scale, "ξ_{i}");
            }
        }
    }

    /// Kinetic energy never rises, and the reported loss is the kinetic energy's fall.
    fn assert_energy(body: &Approach, hit: &ContactsImpact) {
        let before = kinetic(body, &body.v_g, &body.omega);
        let after = kinetic(body, &hit.v_g, &hit.omega);
        assert!(
            after <= before * (1.0 + 1e-12),
            "energy rose {before} → {after}"
        );
        assert!((before - after - hit.energy_loss).abs() <= 1e-10 * before);
    }

    /// Three contacts at 120° about G's vertical, equal levers, isotropic inertia, a
    /// straight drop: by symmetry v_G⁺ = (0, 0, e v), ω⁺ = 0 and Λ_i = m(1 + e)v/3, with or
    /// without friction.
    #[test]
    fn a_symmetric_drop_on_three_contacts_rebounds_straight() {
        let (mass, reach, depth, v) = (0.2, 0.05, 0.03, 1.5);
        let levers: [Vector3<f64>; 3] = std::array::from_fn(|i| {
            let angle = 0.3 + std::f64::consts::TAU * i as f64 / 3.0;
            Vector3::new(reach * angle.cos(), reach * angle.sin(), -depth)
        });
        let body = Approach {
            mass,
            inertia_inv: Matrix3::identity() / 4e-4,
            r: levers[0],
            v_g: Vector3::new(0.0, 0.0, -v),
            omega: Vector3::zeros(),
        };
        for e in [0.0, 0.5, 1.0] {
            for (law, mu) in [
                (Tangential::Frictionless, 0.0),
                (Tangential::Coulomb { friction: 0.3 }, 0.3),
            ] {
                let hit = resolve_contacts(&body, &levers[1..], law, e).unwrap();
                assert_law(&body, &levers[1..], &hit, mu, 1e-12);
                assert_eq!(hit.restitution, e);
                assert!((hit.v_g - Vector3::new(0.0, 0.0, e * v)).norm() <= 1e-12 * v);
                assert!(hit.omega.norm() * reach <= 1e-12 * v, "ω⁺ = {}", hit.omega);
                let lambda = mass * (1.0 + e) * v / 3.0;
                for p in hit.impulse {
                    assert!(
                        (p.z - lambda).abs() <= 1e-12 * lambda,
                        "{law:?} e = {e}: Λ = {}",
                        p.z
                    );
                }
            }
        }
    }

    /// A third contact that rises fast enough to stay separating changes nothing: the
    /// impact at three contacts is the one at the first two, for every law.
    #[test]
    fn a_separating_third_contact_leaves_the_two_contact_impact() {
        let mut uniform = uniform(0xd1b5_4a32_d192_ed03);
        let laws = [
            Tangential::Frictionless,
            Tangential::Coulomb { friction: 0.3 },
            Tangential::NoSlip,
        ];
        let mut compared = [0; 3];
        for _ in 0..300 {
            let normal = [-0.1 - uniform().abs(), uniform(), 5.0];
            let (body, levers) = tripod(&mut uniform, 0.8, 0.2, normal);
            let e = uniform().abs();
            let scale = speed(&body, &levers);
            for (k, law) in laws.into_iter().enumerate() {
                let two = resolve_contacts(&body, &levers[1..2], law, e);
                let three = resolve_contacts(&body, &levers[1..], law, e);
                let (two, three) = match (two, three) {
                    (None, None) => continue,
                    (Some(two), Some(three)) => (two, three),
                    (two, three) => panic!("{law:?}: {two:?} but {three:?}"),
                };
                // The third contact separates after the two-contact impact.
                assert!((two.v_g + two.omega.cross(&levers[2])).z > 0.0);
                assert_eq!(three.impulse[2], Vector3::zeros());
                assert!((three.v_g - two.v_g).norm() <= 1e-12 * scale, "{law:?} v_G");
                let turn = (three.omega - two.omega).norm() * 0.2;
                assert!(turn <= 1e-12 * scale, "{law:?} ω");
                for i in 0..2 {
                    let gap = (three.impulse[i] - two.impulse[i]).norm();
                    assert!(gap <= 1e-12 * body.mass * scale, "{law:?} P_{i}");
                }
                assert_eq!(three.restitution, two.restitution);
                compared[k] += 1;
            }
        }
        assert!(
            compared[0] == 300 && compared[1] == 300 && compared[2] > 100,
            "{compared:?}"
        );
    }

    /// Random impacts at three contacts, the struck one approaching, the others approaching
    /// or leaving: every law's conditions hold at every contact and the energy never rises.
    /// Prints the Gauss–Seidel sweeps (median, most) and how often each law has no solution.
    #[test]
    fn random_three_contact_impacts_obey_their_laws() {
        let mut uniform = uniform(0x6a09_e667_f3bc_c909);
        let mut sweeps = Vec::new();
        let (mut none, mut plastic, mut stalled) = ([0; 2], 0, 0);
        let mut staying = [[0; 4]; 2];
        for _ in 0..300 {
            let normal = [
                -0.1 - 2.0 * uniform().abs(),
                2.0 * uniform(),
                2.0 * uniform(),
            ];
            let (body, levers) = tripod(&mut uniform, 0.8, 0.2, normal);
            let others = &levers[1..];
            let e = if uniform() > 0.0 {
                1.0
            } else {
                uniform().abs()
            };
            let mu = 0.1 + 1.5 * uniform().abs();
            for (law, mu) in [
                (Tangential::Frictionless, 0.0),
                (Tangential::Coulomb { friction: mu }, mu),
            ] {
                let Some(hit) = resolve_contacts(&body, others, law, e) else {
                    stalled += 1;
                    continue;
                };
                assert_law(&body, others, &hit, mu, 1e-9);
                assert_energy(&body, &hit);
                sweeps.push(hit.sweeps);
                plastic += usize::from(hit.restitution != e);
            }
            // The no-slip law on this draw, and on the rolling model's: the body rolling
            // on contacts 1 and 2 (at rest, turning about C_1C_2), contact 0 striking.
            let axis = (levers[2] - levers[1]).normalize();
            let spin = 10.0 * uniform();
            let strike = spin * axis.cross(&(levers[0] - levers[1])).z;
            let omega = axis * if strike < 0.0 { spin } else { -spin };
            let rolling = Approach {
                v_g: -omega.cross(&levers[1]),
                omega,
                ..body
            };
            for (k, body) in [body, rolling].iter().enumerate() {
                let Some(hit) = resolve_contacts(body, others, Tangential::NoSlip, e) else {
                    none[k] += 1;
                    continue;
                };
                assert_no_slip(body, &levers, &hit, 1e-10);
                assert_energy(body, &hit);
                staying[k][hit
                    .impulse
                    .iter()
                    .filter(|p| **p != Vector3::zeros())
                    .count()] += 1;
            }
        }
        sweeps.sort_unstable();
        eprintln!(
            "Gauss–Seidel sweeps: median {}, max {}, {stalled} of 600 not converging; \
             {plastic} taken plastic; no-slip without a solution: {} of 300 random, {} of \
             300 rolling; staying sets of 1, 2, 3 contacts: {:?} random, {:?} rolling",
            sweeps[sweeps.len() / 2],
            sweeps[sweeps.len() - 1],
            none[0],
            none[1],
            &staying[0][1..],
            &staying[1][1..],
        );
        assert!(stalled == 0, "{stalled} of 600 did not converge");
        assert!(plastic > 0, "no impact was taken plastic");
        assert!(none[1] < 30, "{none:?}");
        assert!(
            staying[1][1] > 10 && staying[1][2] > 10 && staying[1][3] > 10,
            "{staying:?}"
        );
    }

    /// Without rebound, three non-collinear contacts that all stay and stick are three
    /// points of the rigid body at rest: v_G⁺ = 0, ω⁺ = 0, and the whole kinetic energy
    /// is lost.
    #[test]
    fn three_sticking_contacts_without_rebound_stop_the_body() {
        let mut uniform = uniform(0xbb67_ae85_84ca_a73b);
        for _ in 0..100 {
            let normal = [0; 3].map(|_| -1.0 - 0.2 * uniform());
            let (body, levers) = tripod(&mut uniform, 0.4, 0.1, normal);
            let hit = resolve_contacts(&body, &levers[1..], Tangential::NoSlip, 0.0).unwrap();
            assert!(
                hit.impulse.iter().all(|p| p.z > 0.0),
                "all stay: {:?}",
                hit.impulse
            );
            let scale = speed(&body, &levers);
            assert!(hit.v_g.norm() <= 1e-12 * scale, "v_G⁺ = {}", hit.v_g);
            assert!(
                hit.omega.norm() * 0.2 <= 1e-12 * scale,
                "ω⁺ = {}",
                hit.omega
            );
            let before = kinetic(&body, &body.v_g, &body.omega);
            assert!((hit.energy_loss - before).abs() <= 1e-12 * before);
            assert!(hit.stuck.iter().all(|s| *s));
        }
    }
}
