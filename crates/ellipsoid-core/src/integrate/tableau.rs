//! Butcher tableaux, embedded error weights and dense-output weights, as published.
//!
//! Sources:
//! - HNW: E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I:
//!   Nonstiff Problems*, 2nd ed., Springer 1993: RK4 (Sect. II.1), DOPRI5 and DOP853
//!   (Sect. II.5, and the codes' description in the appendix).
//! - Hairer's Fortran codes `dopri5.f` and `dop853.f`: the same digits,
//!   plus the dense-output coefficients d1..d7 of DOPRI5 (Shampine's 4th-order extension)
//!   and the three extra stages and the D coefficients of DOP853's 7th-order extension.
//!   The DOP853 digits below are copied from SciPy's transcription of `dop853.f`
//!   (`scipy/integrate/_ivp/dop853_coefficients.py`) and checked equal to it bit for bit.
//!
//! The unit tests at the bottom check the Runge–Kutta order conditions (one per rooted
//! tree, HNW Sect. II.2; continuous versions Sect. II.6) for every tableau and every
//! continuous extension, so a mistyped digit fails loudly.

#![allow(clippy::excessive_precision)] // digits kept exactly as published, for checking

/// An explicit Runge–Kutta tableau with `S` stages (`a` strictly lower triangular).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tableau<const S: usize> {
    /// Nodes c_i.
    pub c: [f64; S],
    /// Coupling coefficients a_ij (j < i).
    pub a: [[f64; S]; S],
    /// Weights b_i of the propagated solution.
    pub b: [f64; S],
}

/// The classical 4th-order Runge–Kutta method (HNW Sect. II.1).
#[rustfmt::skip]
pub const RK4: Tableau<4> = Tableau {
    c: [0.0, 0.5, 0.5, 1.0],
    a: [
        [0.0, 0.0, 0.0, 0.0],
        [0.5, 0.0, 0.0, 0.0],
        [0.0, 0.5, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ],
    b: [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
};

/// Weights b_i(θ) of RK4's 3rd-order continuous extension (HNW Sect. II.6, the dense
/// output of the classical method): y(t + θh) ≈ y + h Σ b_i(θ) k_i, with b_i(1) = b_i.
#[inline]
pub fn rk4_dense_weights(theta: f64) -> [f64; 4] {
    let t2 = theta * theta;
    let t3 = t2 * theta;
    let b1 = theta - 1.5 * t2 + (2.0 / 3.0) * t3;
    let b23 = t2 - (2.0 / 3.0) * t3;
    let b4 = -0.5 * t2 + (2.0 / 3.0) * t3;
    [b1, b23, b23, b4]
}

/// Dormand–Prince 5(4) (HNW Sect. II.5; `dopri5.f`, coefficients c2..a76). FSAL: the
/// last row of `a` equals `b`, so stage 7 is f(t + h, y₁).
#[rustfmt::skip]
pub const DOPRI5: Tableau<7> = Tableau {
    c: [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0],
    a: [
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0, 0.0],
        [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0, 0.0],
        [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0, 0.0],
        [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0, 0.0],
    ],
    b: [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0, 0.0],
};

/// DOPRI5 error weights e_i = b_i − b̂_i (`dopri5.f`, e1..e7); the local error estimate is
/// h Σ e_i k_i.
#[rustfmt::skip]
pub const DOPRI5_E: [f64; 7] = [
    71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0,
    -1.0 / 40.0,
];

/// DOPRI5 dense-output coefficients d1..d7 (`dopri5.f`; Shampine's 4th-order continuous
/// extension, HNW Sect. II.6). The interpolant is
/// y(θ) = y₀ + θ(Δ + (1−θ)(B + θ(Δ − h k₇ − B + (1−θ) h Σ d_i k_i))),
/// with Δ = y₁ − y₀ and B = h k₁ − Δ.
#[rustfmt::skip]
pub const DOPRI5_D: [f64; 7] = [
    -12715105075.0 / 11282082432.0, 0.0, 87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0, 701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0, 69997945.0 / 29380423.0,
];

/// Dormand–Prince 8(5,3) (HNW Sect. II.5; `dop853.f`, c2..a1211 and b1..b12). Twelve
/// stages; f(t + h, y₁) is evaluated separately after an accepted step and serves as the
/// first stage of the next one.
#[rustfmt::skip]
pub const DOP853: Tableau<12> = Tableau {
    c: [0.0, 0.526001519587677318785587544488e-01, 0.789002279381515978178381316732e-01, 0.118350341907227396726757197510, 0.281649658092772603273242802490, 0.333333333333333333333333333333, 0.25, 0.307692307692307692307692307692, 0.651282051282051282051282051282, 0.6, 0.857142857142857142857142857142, 1.0],
    a: [
        
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [5.26001519587677318785587544488e-2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [1.97250569845378994544595329183e-2, 5.91751709536136983633785987549e-2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [2.95875854768068491816892993775e-2, 0.0, 8.87627564304205475450678981324e-2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [2.41365134159266685502369798665e-1, 0.0, -8.84549479328286085344864962717e-1, 9.24834003261792003115737966543e-1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.7037037037037037037037037037e-2, 0.0, 0.0, 1.70828608729473871279604482173e-1, 1.25467687566822425016691814123e-1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.7109375e-2, 0.0, 0.0, 1.70252211019544039314978060272e-1, 6.02165389804559606850219397283e-2, -1.7578125e-2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.70920001185047927108779319836e-2, 0.0, 0.0, 1.70383925712239993810214054705e-1, 1.07262030446373284651809199168e-1, -1.53194377486244017527936158236e-2, 8.27378916381402288758473766002e-3, 0.0, 0.0, 0.0, 0.0, 0.0],
        [6.24110958716075717114429577812e-1, 0.0, 0.0, -3.36089262944694129406857109825, -8.68219346841726006818189891453e-1, 2.75920996994467083049415600797e1, 2.01540675504778934086186788979e1, -4.34898841810699588477366255144e1, 0.0, 0.0, 0.0, 0.0],
        [4.77662536438264365890433908527e-1, 0.0, 0.0, -2.48811461997166764192642586468, -5.90290826836842996371446475743e-1, 2.12300514481811942347288949897e1, 1.52792336328824235832596922938e1, -3.32882109689848629194453265587e1, -2.03312017085086261358222928593e-2, 0.0, 0.0, 0.0],
        [-9.3714243008598732571704021658e-1, 0.0, 0.0, 5.18637242884406370830023853209, 1.09143734899672957818500254654, -8.14978701074692612513997267357, -1.85200656599969598641566180701e1, 2.27394870993505042818970056734e1, 2.49360555267965238987089396762, -3.0467644718982195003823669022, 0.0, 0.0],
        [2.27331014751653820792359768449, 0.0, 0.0, -1.05344954667372501984066689879e1, -2.00087205822486249909675718444, -1.79589318631187989172765950534e1, 2.79488845294199600508499808837e1, -2.85899827713502369474065508674, -8.87285693353062954433549289258, 1.23605671757943030647266201528e1, 6.43392746015763530355970484046e-1, 0.0],
    ],
    b: [5.42937341165687622380535766363e-2, 0.0, 0.0, 0.0, 0.0, 4.45031289275240888144113950566, 1.89151789931450038304281599044, -5.8012039600105847814672114227, 3.1116436695781989440891606237e-1, -1.52160949662516078556178806805e-1, 2.01365400804030348374776537501e-1, 4.47106157277725905176885569043e-2],
};

/// DOP853 5th-order error weights er1..er12 (`dop853.f`): err₅ = h Σ er_i k_i.
#[rustfmt::skip]
pub const DOP853_E5: [f64; 12] = [0.1312004499419488073250102996e-1, 0.0, 0.0, 0.0, 0.0, -0.1225156446376204440720569753e1, -0.4957589496572501915214079952, 0.1664377182454986536961530415e1, -0.3503288487499736816886487290, 0.3341791187130174790297318841, 0.8192320648511571246570742613e-1, -0.2235530786388629525884427845e-1];

/// DOP853 3rd-order estimator weights bhh1, bhh2, bhh3 (`dop853.f`), applied to stages 1,
/// 9 and 12: err₃ = h (Σ b_i k_i − bhh1 k₁ − bhh2 k₉ − bhh3 k₁₂).
pub const DOP853_BHH: [f64; 3] = [
    0.244094488188976377952755905512,
    0.733846688281611857341361741547,
    0.220588235294117647058823529412e-1,
];

/// Nodes c14, c15, c16 of DOP853's three extra dense-output stages (`dop853.f`).
pub const DOP853_C_EXTRA: [f64; 3] = [0.1, 0.2, 0.777777777777777777777777777778];

/// Couplings of the extra stages 14–16 (`dop853.f`, a141..a1615), over the extended stage
/// list k₁..k₁₂, k₁₃ = f(t + h, y₁), k₁₄, k₁₅ (zero-based columns 0..15).
#[rustfmt::skip]
pub const DOP853_A_EXTRA: [[f64; 16]; 3] = [
    
    [5.61675022830479523392909219681e-2, 0.0, 0.0, 0.0, 0.0, 0.0, 2.53500210216624811088794765333e-1, -2.46239037470802489917441475441e-1, -1.24191423263816360469010140626e-1, 1.5329179827876569731206322685e-1, 8.20105229563468988491666602057e-3, 7.56789766054569976138603589584e-3, -8.298e-3, 0.0, 0.0, 0.0],
    [3.18346481635021405060768473261e-2, 0.0, 0.0, 0.0, 0.0, 2.83009096723667755288322961402e-2, 5.35419883074385676223797384372e-2, -5.49237485713909884646569340306e-2, 0.0, 0.0, -1.08347328697249322858509316994e-4, 3.82571090835658412954920192323e-4, -3.40465008687404560802977114492e-4, 1.41312443674632500278074618366e-1, 0.0, 0.0],
    [-4.28896301583791923408573538692e-1, 0.0, 0.0, 0.0, 0.0, -4.69762141536116384314449447206, 7.68342119606259904184240953878, 4.06898981839711007970213554331, 3.56727187455281109270669543021e-1, 0.0, 0.0, 0.0, -1.39902416515901462129418009734e-3, 2.9475147891527723389556272149, -9.15095847217987001081870187138, 0.0],
];

/// DOP853 dense-output coefficients d4..d7 (`dop853.f`, rows d41..d716) over the same
/// extended stage list. The interpolant is
/// y(θ) = y₀ + θ(Δ + (1−θ)(B + θ(Δ − h k₁₃ − B + (1−θ)(P₄ + θ(P₅ + (1−θ)(P₆ + θ P₇)))))),
/// with P_r = h Σ d_{r,i} k_i.
#[rustfmt::skip]
pub const DOP853_D: [[f64; 16]; 4] = [
    
    [-0.84289382761090128651353491142e1, 0.0, 0.0, 0.0, 0.0, 0.56671495351937776962531783590, -0.30689499459498916912797304727e1, 0.23846676565120698287728149680e1, 0.21170345824450282767155149946e1, -0.87139158377797299206789907490, 0.22404374302607882758541771650e1, 0.63157877876946881815570249290, -0.88990336451333310820698117400e-1, 0.18148505520854727256656404962e2, -0.91946323924783554000451984436e1, -0.44360363875948939664310572000e1],
    [0.10427508642579134603413151009e2, 0.0, 0.0, 0.0, 0.0, 0.24228349177525818288430175319e3, 0.16520045171727028198505394887e3, -0.37454675472269020279518312152e3, -0.22113666853125306036270938578e2, 0.77334326684722638389603898808e1, -0.30674084731089398182061213626e2, -0.93321305264302278729567221706e1, 0.15697238121770843886131091075e2, -0.31139403219565177677282850411e2, -0.93529243588444783865713862664e1, 0.35816841486394083752465898540e2],
    [0.19985053242002433820987653617e2, 0.0, 0.0, 0.0, 0.0, -0.38703730874935176555105901742e3, -0.18917813819516756882830838328e3, 0.52780815920542364900561016686e3, -0.11573902539959630126141871134e2, 0.68812326946963000169666922661e1, -0.10006050966910838403183860980e1, 0.77771377980534432092869265740, -0.27782057523535084065932004339e1, -0.60196695231264120758267380846e2, 0.84320405506677161018159903784e2, 0.11992291136182789328035130030e2],
    [-0.25693933462703749003312586129e2, 0.0, 0.0, 0.0, 0.0, -0.15418974869023643374053993627e3, -0.23152937917604549567536039109e3, 0.35763911791061412378285349910e3, 0.93405324183624310003907691704e2, -0.37458323136451633156875139351e2, 0.10409964950896230045147246184e3, 0.29840293426660503123344363579e2, -0.43533456590011143754432175058e2, 0.96324553959188282948394950600e2, -0.39177261675615439165231486172e2, -0.14972683625798562581422125276e3],
];

#[cfg(test)]
mod tests {
    //! Order conditions (HNW Sect. II.2): a method with weights w is of order p iff
    //! Σ_i w_i Φ_i(τ) = 1/γ(τ) for every rooted tree τ with |τ| ≤ p, where Φ_i(τ) is the
    //! product over the subtrees τ_k of (A Φ(τ_k))_i. A continuous extension with weights
    //! w(θ) is of order q iff Σ_i w_i(θ) Φ_i(τ) = θ^|τ|/γ(τ) for |τ| ≤ q (Sect. II.6).

    use super::*;

    /// A rooted tree as the (sorted) indices of its subtrees in the generated list.
    struct Tree {
        order: usize,
        children: Vec<usize>,
        gamma: f64,
    }

    /// All rooted trees up to `max_order` (1, 1, 2, 4, 9, 20, 48, 115 of orders 1..8).
    fn trees(max_order: usize) -> Vec<Tree> {
        let mut all: Vec<Tree> = vec![Tree {
            order: 1,
            children: vec![],
            gamma: 1.0,
        }];
        for n in 2..=max_order {
            // multisets of existing trees (non-increasing index) with orders summing to n-1
            let mut found = Vec::new();
            fn extend(
                all: &[Tree],
                remaining: usize,
                max_idx: usize,
                cur: &mut Vec<usize>,
                out: &mut Vec<Vec<usize>>,
            ) {
                if remaining == 0 {
                    out.push(cur.clone());
                    return;
                }
                for i in (0..=max_idx).rev() {
                    if all[i].order <= remaining {
                        cur.push(i);
                        extend(all, remaining - all[i].order, i, cur, out);
                        cur.pop();
                    }
                }
            }
            extend(&all, n - 1, all.len() - 1, &mut Vec::new(), &mut found);
            for children in found {
                let gamma = n as f64 * children.iter().map(|&c| all[c].gamma).product::<f64>();
                all.push(Tree {
                    order: n,
                    children,
                    gamma,
                });
            }
        }
        all
    }

    /// Φ_i(τ) for every tree, for an S-stage coupling matrix.
    fn elementary_weights<const S: usize>(a: &[[f64; S]; S], trees: &[Tree]) -> Vec<[f64; S]> {
        let mut phi: Vec<[f64; S]> = Vec::with_capacity(trees.len());
        for tree in trees {
            let mut p = [1.0; S];
            for &child in &tree.children {
                for i in 0..S {
                    p[i] *= (0..S).map(|j| a[i][j] * phi[child][j]).sum::<f64>();
                }
            }
            phi.push(p);
        }
        phi
    }

    /// Largest defect |Σ w_i Φ_i(τ) − θ^|τ|/γ(τ)| over the trees of exactly `order`.
    fn defect<const S: usize>(a: &[[f64; S]; S], w: &[f64; S], theta: f64, order: usize) -> f64 {
        let trees = trees(order);
        let phi = elementary_weights(a, &trees);
        trees
            .iter()
            .zip(&phi)
            .filter(|(t, _)| t.order == order)
            .map(|(t, p)| {
                let lhs: f64 = (0..S).map(|i| w[i] * p[i]).sum();
                (lhs - theta.powi(order as i32) / t.gamma).abs()
            })
            .fold(0.0, f64::max)
    }

    fn assert_order<const S: usize>(
        name: &str,
        a: &[[f64; S]; S],
        w: &[f64; S],
        theta: f64,
        p: usize,
        tol: f64,
    ) {
        for q in 1..=p {
            let d = defect(a, w, theta, q);
            assert!(
                d < tol,
                "{name}: order-{q} conditions violated by {d:e} (θ = {theta})"
            );
        }
    }

    fn assert_not_order<const S: usize>(name: &str, a: &[[f64; S]; S], w: &[f64; S], p: usize) {
        let d = defect(a, w, 1.0, p);
        assert!(
            d > 1e-6,
            "{name}: unexpectedly satisfies the order-{p} conditions"
        );
    }

    fn assert_row_sums<const S: usize>(name: &str, t: &Tableau<S>) {
        for i in 0..S {
            let s: f64 = t.a[i].iter().sum();
            assert!(
                (s - t.c[i]).abs() < 1e-14,
                "{name}: row {i} sums to {s}, c = {}",
                t.c[i]
            );
        }
    }

    #[test]
    fn tree_counts_match_oeis_a000081() {
        let t = trees(8);
        let counts: Vec<usize> = (1..=8)
            .map(|n| t.iter().filter(|x| x.order == n).count())
            .collect();
        assert_eq!(counts, [1, 1, 2, 4, 9, 20, 48, 115]);
    }

    #[test]
    fn rk4_is_order_4_with_order_3_dense_output() {
        assert_row_sums("RK4", &RK4);
        assert_order("RK4", &RK4.a, &RK4.b, 1.0, 4, 1e-15);
        assert_not_order("RK4", &RK4.a, &RK4.b, 5);
        for (w, b) in rk4_dense_weights(1.0).iter().zip(RK4.b) {
            assert!(
                (w - b).abs() < 1e-15,
                "RK4 dense output must end on the step"
            );
        }
        for theta in [0.1, 0.37, 0.5, 0.9] {
            assert_order(
                "RK4 dense",
                &RK4.a,
                &rk4_dense_weights(theta),
                theta,
                3,
                1e-15,
            );
        }
    }

    #[test]
    fn dopri5_is_order_5_embedded_4_dense_4() {
        assert_row_sums("DOPRI5", &DOPRI5);
        assert_eq!(DOPRI5.a[6], DOPRI5.b, "FSAL");
        assert_order("DOPRI5", &DOPRI5.a, &DOPRI5.b, 1.0, 5, 1e-15);
        assert_not_order("DOPRI5", &DOPRI5.a, &DOPRI5.b, 6);
        let b_hat: [f64; 7] = std::array::from_fn(|i| DOPRI5.b[i] - DOPRI5_E[i]);
        assert_order("DOPRI5 embedded", &DOPRI5.a, &b_hat, 1.0, 4, 1e-15);
        assert_not_order("DOPRI5 embedded", &DOPRI5.a, &b_hat, 5);
        for theta in [0.1, 0.37, 0.5, 0.9] {
            assert_order(
                "DOPRI5 dense",
                &DOPRI5.a,
                &dopri5_dense_weights(theta),
                theta,
                4,
                1e-14,
            );
        }
    }

    /// Weights of Hairer's DOPRI5 interpolant (see [`DOPRI5_D`]) per stage, divided by h.
    fn dopri5_dense_weights(theta: f64) -> [f64; 7] {
        let s1 = 1.0 - theta;
        std::array::from_fn(|j| {
            let delta = DOPRI5.b[j];
            let bspl = if j == 0 { 1.0 } else { 0.0 } - delta;
            let cont4 = delta - if j == 6 { 1.0 } else { 0.0 } - bspl;
            theta * (delta + s1 * (bspl + theta * (cont4 + s1 * DOPRI5_D[j])))
        })
    }

    /// DOP853's tableau extended by k₁₃ = f(t + h, y₁) and the three dense stages.
    fn dop853_extended() -> [[f64; 16]; 16] {
        let mut a = [[0.0; 16]; 16];
        for (row, src) in a.iter_mut().zip(DOP853.a) {
            row[..12].copy_from_slice(&src);
        }
        a[12][..12].copy_from_slice(&DOP853.b);
        a[13..16].copy_from_slice(&DOP853_A_EXTRA);
        a
    }

    #[test]
    fn dop853_is_order_8_with_5_and_3_estimators() {
        assert_row_sums("DOP853", &DOP853);
        assert_order("DOP853", &DOP853.a, &DOP853.b, 1.0, 8, 1e-13);
        assert_not_order("DOP853", &DOP853.a, &DOP853.b, 9);
        let b5: [f64; 12] = std::array::from_fn(|i| DOP853.b[i] - DOP853_E5[i]);
        assert_order("DOP853 5th-order estimator", &DOP853.a, &b5, 1.0, 5, 1e-13);
        let mut b3 = [0.0; 12];
        b3[0] = DOP853_BHH[0];
        b3[8] = DOP853_BHH[1];
        b3[11] = DOP853_BHH[2];
        assert_order("DOP853 3rd-order estimator", &DOP853.a, &b3, 1.0, 3, 1e-13);
    }

    /// Extra stage 14 + r couples only the stages before it (`Dop853::extra_stage` sums a
    /// row over all 16 stages).
    #[test]
    fn dop853_extra_stages_couple_only_earlier_stages() {
        for (r, row) in DOP853_A_EXTRA.iter().enumerate() {
            assert!(row[13 + r..].iter().all(|&a| a == 0.0), "row {r}: {row:?}");
        }
    }

    #[test]
    fn dop853_dense_output_is_order_7() {
        let a = dop853_extended();
        let c: [f64; 16] = std::array::from_fn(|i| match i {
            0..12 => DOP853.c[i],
            12 => 1.0,
            _ => DOP853_C_EXTRA[i - 13],
        });
        for i in 0..16 {
            let s: f64 = a[i].iter().sum();
            assert!(
                (s - c[i]).abs() < 1e-13,
                "extended row {i} sums to {s}, c = {}",
                c[i]
            );
        }
        for theta in [0.1, 0.37, 0.5, 0.9] {
            let s1 = 1.0 - theta;
            let w: [f64; 16] = std::array::from_fn(|j| {
                let delta = if j < 12 { DOP853.b[j] } else { 0.0 };
                let bspl = if j == 0 { 1.0 } else { 0.0 } - delta;
                let cont4 = delta - if j == 12 { 1.0 } else { 0.0 } - bspl;
                let d = |r: usize| DOP853_D[r][j];
                let par = d(0) + theta * (d(1) + s1 * (d(2) + theta * d(3)));
                theta * (delta + s1 * (bspl + theta * (cont4 + s1 * par)))
            });
            assert_order("DOP853 dense", &a, &w, theta, 7, 1e-12);
        }
    }
}
