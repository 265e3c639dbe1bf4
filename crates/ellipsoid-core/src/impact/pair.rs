//! Impact at two contacts at once (docs/physics.md, "Contact spheres", "Impact at two
//! contacts"; the hybrid machine's `transition::pair_touchdown`): Newton's law at each contact with
//! Coulomb friction, the event-driven impact of Pfeiffer & Glocker (*Multibody Dynamics
//! with Unilateral Contacts*, 1996, ch. 7), in world axes, with impulses P_i = (P_t,i, Λ_i) at the contact points C_i:
//! ```text
//!   v_i⁺ = v_i⁻ + Σ_j W_ij P_j,    W_ij = 𝟙/m − [r_i]× I⁻¹ [r_j]×
//!   ξ_i  = v_i⁺ + e min(v_n,i⁻, 0) e3                          (normal restitution only)
//!   P_i ∈ C_i = {|P_t| ≤ μ Λ},   −(ξ_i + μ|ξ_t,i| e3) ∈ N_{C_i}(P_i)   (De Saxcé)
//! ```
//! i.e. Λ_i ≥ 0, ξ_n,i ≥ 0, Λ_i ξ_n,i = 0, and at each contact either stick (ξ_t = 0,
//! |P_t| ≤ μΛ) or slide (P_t = −μΛ ξ̂_t). Solved as the fixed point
//! P_i = proj_{C_i}(P_i − ρ_i (ξ_i + μ|ξ_t,i| e3)) by block Gauss–Seidel,
//! ρ_i = 1/λ_max(W_ii).
//!
//! Energy: T⁺ − T⁻ = Σ_i P_i·(v_i⁻ + v_i⁺)/2. For e = 0 (Moreau's law) it is
//! P·v⁺ − ½ PᵀWP ≤ 0, since Λ_i v_n,i⁺ = 0 and P_t,i·v_t,i⁺ = −μΛ_i|v_t,i⁺| ≤ 0;
//! frictionless, with one e at both contacts, it is −(1 − e)/(2(1 + e)) ΛᵀWΛ ≤ 0. With
//! friction and e > 0 Newton's law can add energy (Kane's paradox; Glocker, Multibody
//! Syst. Dyn. 2013): where it would, the impact is taken with e = 0.
//!
//! The no-slip law (the rolling model) is the limit μ → ∞: a contact either separates
//! (P_i = 0, ξ_n,i ≥ 0) or stays and sticks (ξ_i = 0, Λ_i ≥ 0, P_t,i free). Its active set
//! S is found by trying each (the struck one, the pressed one, both), solving
//! W_SS P_S = −ξ⁻_S by the least-norm solution (with both stuck W_SS is singular: the
//! equal and opposite tangential pair along C_1C_2 does nothing, as in the two-contact
//! phase), and keeping the first whose conditions hold. The law can have two solutions
//! (a separating contact's tangential velocity is free, so the problem is not monotone):
//! a contact that separates with no impulse, and the same contact held sticking by a
//! tangential impulse larger than its normal one. The smaller set is taken: it is a
//! solution of Coulomb's law at every μ above the other contact's need, the other only
//! above |P_t|/Λ at the held contact. For e = 0 the energy change is −½PᵀWP ≤ 0. No set
//! holds where sticking the struck contact would take a pulling normal impulse (Λ < 0)
//! and the other is driven in if it takes none: there Coulomb's solution slides at the
//! struck contact with a tangential impulse that grows with μ, and the law has no limit
//! (`None`).

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::{Approach, Tangential};

type Vector6 = SVector<f64, 6>;
type Matrix6 = SMatrix<f64, 6, 6>;

/// Most block Gauss–Seidel sweeps; the iteration converges linearly at a rate set by
/// W's coupling of the two contacts: medians of about 140 and at most 18,893 sweeps in
/// two sets of 300 random impacts (the module's test and a milder one).
const MAX_SWEEPS: u32 = 200_000;

/// The fixed point is reached where a sweep moves P by less than this, relative to the
/// impulse scale |v⁻| max_i ρ_i.
const CONVERGED: f64 = 1e-15;

/// The outcome of [`resolve_pair`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairImpact {
    /// Post-impact velocity of G, world \[m/s\].
    pub v_g: Vector3<f64>,
    /// Post-impact angular velocity, world \[rad/s\].
    pub omega: Vector3<f64>,
    /// The impulse at each contact, world \[N·s\].
    pub impulse: [Vector3<f64>; 2],
    /// v_n = e3·v_C at each contact, before and after \[m/s\].
    pub normal_velocity: [(f64, f64); 2],
    /// Kinetic energy before − after \[J\], ≥ 0.
    pub energy_loss: f64,
    /// Whether each contact's tangential velocity is zero after the impact.
    pub stuck: [bool; 2],
    /// The restitution the impact was taken with: the scene's e, or 0 where Newton's law
    /// with e would have added energy.
    pub restitution: f64,
    /// Gauss–Seidel sweeps spent.
    pub sweeps: u32,
}

/// The two contacts' velocities as a linear function of their impulses, v = v⁻ + W P.
struct Pair {
    w: Matrix6,
    v0: Vector6,
    /// ρ_i = 1/λ_max(W_ii).
    rho: [f64; 2],
}

impl Pair {
    fn new(body: &Approach, second: &Vector3<f64>) -> Self {
        let r = [body.r, *second];
        let mut w = Matrix6::zeros();
        let mut v0 = Vector6::zeros();
        for (i, ri) in r.iter().enumerate() {
            for (j, rj) in r.iter().enumerate() {
                let block = Matrix3::identity() / body.mass
                    - ri.cross_matrix() * body.inertia_inv * rj.cross_matrix();
                w.fixed_view_mut::<3, 3>(3 * i, 3 * j).copy_from(&block);
            }
            let v = body.v_g + body.omega.cross(ri);
            v0.fixed_rows_mut::<3>(3 * i).copy_from(&v);
        }
        let w = (w + w.transpose()) * 0.5;
        let rho = [0, 1].map(|i| {
            let block = w.fixed_view::<3, 3>(3 * i, 3 * i).into_owned();
            1.0 / block.symmetric_eigenvalues().max()
        });
        Pair { w, v0, rho }
    }

    fn velocity(&self, p: &Vector6) -> Vector6 {
        self.v0 + self.w * p
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

/// Resolves the impact of `body` on the plane at two contacts at once, the first at
/// `body.r`, the second at lever arm `second` (world), with Newton's restitution e at
/// both and the tangential law (see the module docs). `None` where the iteration does not
/// converge or, for the no-slip law, no active set satisfies its conditions.
pub fn resolve_pair(
    body: &Approach,
    second: Vector3<f64>,
    tangential: Tangential,
    restitution: f64,
) -> Option<PairImpact> {
    let pair = Pair::new(body, &second);
    let e = restitution.clamp(0.0, 1.0);
    let law = |e| match tangential {
        Tangential::Frictionless => solve(body, &pair, &second, 0.0, e),
        Tangential::Coulomb { friction } => solve(body, &pair, &second, friction.max(0.0), e),
        Tangential::NoSlip => stick(body, &pair, &second, e),
    };
    let hit = law(e)?;
    // Only friction can make Newton's law add energy (the module docs).
    if e > 0.0 && hit.energy_loss < 0.0 && tangential != Tangential::Frictionless {
        return law(0.0);
    }
    Some(hit)
}

/// The fixed point of the module docs with restitution `e`.
fn solve(
    body: &Approach,
    pair: &Pair,
    second: &Vector3<f64>,
    mu: f64,
    e: f64,
) -> Option<PairImpact> {
    let shift = Vector6::new(
        0.0,
        0.0,
        e * pair.v0[2].min(0.0),
        0.0,
        0.0,
        e * pair.v0[5].min(0.0),
    );
    // The impulse scale: what stops the faster contact point through the softer block.
    let scale = pair.v0.norm() * pair.rho[0].max(pair.rho[1]);
    let mut p = Vector6::zeros();
    let mut sweeps = 0;
    loop {
        sweeps += 1;
        let mut moved: f64 = 0.0;
        for i in 0..2 {
            let xi = (pair.velocity(&p) + shift)
                .fixed_rows::<3>(3 * i)
                .into_owned();
            let xi_hat = xi + Vector3::z() * (mu * xi.xy().norm());
            let old = p.fixed_rows::<3>(3 * i).into_owned();
            let new = project_cone(old - pair.rho[i] * xi_hat, mu);
            moved = moved.max((new - old).norm());
            p.fixed_rows_mut::<3>(3 * i).copy_from(&new);
        }
        if !p.iter().all(|x| x.is_finite()) {
            return None;
        }
        if moved <= CONVERGED * scale {
            break;
        }
        if sweeps >= MAX_SWEEPS {
            return None;
        }
    }
    Some(outcome(body, pair, second, p, e, sweeps))
}

/// The no-slip law of the module docs with restitution `e`: the first active set whose
/// least-norm impulses satisfy its conditions (Λ_i ≥ 0 where a contact stays, ξ_n,j ≥ 0
/// where it separates), to [`STICK_TOL`] of the velocity and impulse scales. The sets
/// are tried smallest first: where a contact can separate with no impulse, it does.
fn stick(body: &Approach, pair: &Pair, second: &Vector3<f64>, e: f64) -> Option<PairImpact> {
    let target = |i: usize| -e * pair.v0[3 * i + 2].min(0.0);
    let scale = pair.v0.norm();
    let tol = STICK_TOL * scale;
    // Rows of a contact that separates are the identity on its (zero) impulse, scaled as
    // W so that the least-norm cut-off treats both blocks alike.
    let unit = pair.w.norm() / 6.0_f64.sqrt();
    [[true, false], [false, true], [true, true]]
        .into_iter()
        .find_map(|stays| {
            let (mut a, mut rhs) = (Matrix6::identity() * unit, Vector6::zeros());
            for i in (0..2).filter(|&i| stays[i]) {
                for j in (0..2).filter(|&j| stays[j]) {
                    let block = pair.w.fixed_view::<3, 3>(3 * i, 3 * j).into_owned();
                    a.fixed_view_mut::<3, 3>(3 * i, 3 * j).copy_from(&block);
                }
                let xi = pair.v0.fixed_rows::<3>(3 * i) - Vector3::z() * target(i);
                rhs.fixed_rows_mut::<3>(3 * i).copy_from(&(-xi));
            }
            let p = a.svd(true, true).solve(&rhs, STICK_TOL * unit).ok()?;
            let v = pair.velocity(&p);
            let holds = (0..2).all(|i| {
                if stays[i] {
                    let xi = v.fixed_rows::<3>(3 * i) - Vector3::z() * target(i);
                    p[3 * i + 2] >= -tol * pair.rho[i] && xi.norm() <= tol
                } else {
                    v[3 * i + 2] >= target(i) - tol
                }
            });
            holds.then(|| outcome(body, pair, second, p, e, 0))
        })
}

/// Most relative residual of the no-slip law's conditions (its least-norm solve is exact
/// to a few ulps of the velocity scale times W's conditioning).
const STICK_TOL: f64 = 1e-10;

/// The impact with impulses `p` (both contacts, world): the velocities after, the loss
/// −P·(v⁻ + v⁺)/2 (a negative value within its round-off bound reported as 0), and which
/// contacts are left not slipping.
fn outcome(
    body: &Approach,
    pair: &Pair,
    second: &Vector3<f64>,
    p: Vector6,
    e: f64,
    sweeps: u32,
) -> PairImpact {
    let v_after = pair.velocity(&p);
    let loss = -p.dot(&(pair.v0 + v_after)) * 0.5;
    let round_off = 64.0 * f64::EPSILON * p.norm() * (pair.v0.norm() + v_after.norm());
    let loss = if loss < 0.0 && loss > -round_off {
        0.0
    } else {
        loss
    };
    let impulse = [0, 1].map(|i| p.fixed_rows::<3>(3 * i).into_owned());
    let total = impulse[0] + impulse[1];
    let moment = body.r.cross(&impulse[0]) + second.cross(&impulse[1]);
    let slip_tol = super::SLIP_TOL * pair.v0.norm();
    PairImpact {
        v_g: body.v_g + total / body.mass,
        omega: body.omega + body.inertia_inv * moment,
        impulse,
        normal_velocity: [0, 1].map(|i| (pair.v0[3 * i + 2], v_after[3 * i + 2])),
        energy_loss: loss,
        stuck: [0, 1].map(|i| v_after.fixed_rows::<2>(3 * i).norm() <= slip_tol),
        restitution: e,
        sweeps,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::impact::resolve;

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
    fn assert_law(body: &Approach, second: Vector3<f64>, hit: &PairImpact, mu: f64, tol: f64) {
        let r = [body.r, second];
        let scale = body.v_g.norm() + body.omega.norm() * 0.2;
        for (i, ri) in r.iter().enumerate() {
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
    }

    #[test]
    fn frictionless_pair_dissipates_exactly_the_newton_amount() {
        // Falling flat (both contacts approach), with a turn: both take impulse.
        let (body, second) = rod(Vector3::new(0.0, 0.0, -1.0), Vector3::new(0.3, 2.0, 0.0));
        for e in [0.0, 0.5, 1.0] {
            let hit = resolve_pair(&body, second, Tangential::Frictionless, e).unwrap();
            assert_law(&body, second, &hit, 0.0, 1e-12);
            // ΔT = −(1 − e)/(2(1 + e)) ΛᵀWΛ.
            let pair = Pair::new(&body, &second);
            let mut p = Vector6::zeros();
            p.fixed_rows_mut::<3>(0).copy_from(&hit.impulse[0]);
            p.fixed_rows_mut::<3>(3).copy_from(&hit.impulse[1]);
            let expected = (1.0 - e) / (2.0 * (1.0 + e)) * p.dot(&(pair.w * p));
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
        let pair = resolve_pair(&body, second, Tangential::Frictionless, 0.7).unwrap();
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
            let hit = resolve_pair(&body, second, Tangential::Coulomb { friction: mu }, e)
                .expect("converges");
            assert_law(&body, second, &hit, mu, 1e-9);
            let before = kinetic(&body, &body.v_g, &body.omega);
            let after = kinetic(&body, &hit.v_g, &hit.omega);
            assert!(
                after <= before * (1.0 + 1e-12),
                "energy rose {before} → {after}"
            );
            assert!((before - after - hit.energy_loss).abs() <= 1e-10 * before);
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
                resolve_pair(&body, second, Tangential::Coulomb { friction: mu }, e)
            };
            let Some(hit) = resolve_pair(&body, second, Tangential::NoSlip, e) else {
                // Sticking the struck contact would pull; Coulomb's solution slides there,
                // its tangential impulse growing with μ.
                let grip = |mu: f64| coulomb(mu, e).map(|c| c.impulse[0].xy().norm());
                if let (Some(p3), Some(p10)) = (grip(3.0), grip(10.0)) {
                    assert!(p10 > 1.5 * p3, "{p3} {p10}");
                }
                none += 1;
                continue;
            };
            let before = kinetic(&body, &body.v_g, &body.omega);
            let after = kinetic(&body, &hit.v_g, &hit.omega);
            assert!(
                after <= before * (1.0 + 1e-12),
                "energy rose {before} → {after}"
            );
            assert!((before - after - hit.energy_loss).abs() <= 1e-10 * before);
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
}
