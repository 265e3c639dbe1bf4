//! Steady motions and their stability (docs/physics.md, "Steady motions and their
//! stability"): the spectra against the analytic frictionless sleeping criterion, and
//! against runs of the simulator started on the steady motion (an independent path: the
//! integrator and the full state, not the reduced field's Jacobian).

mod common;

use common::{assert_spectrum, completed as run, crossing_frequency, first_reaching};

use nalgebra::{Complex, Vector3};
use rayon::prelude::*;

use ellipsoid_core::scenario;
use ellipsoid_core::simulate::{Sample, Scene};
use ellipsoid_core::steady::{self, Analysis, Family, ReducedField, reduce};

const G: f64 = 9.81;

/// The frictionless sleeping body's eigenvalues in body axes (docs/physics.md): with
/// k = m g (l − ρ), the world-frame tilt circles at σ solving A σ² − C n σ + k = 0, and
/// the body frame sees σ − n; each root gives a pair ±i(σ − n) (complex σ: a quartet).
fn sleeping_eigenvalues(big_a: f64, big_c: f64, k: f64, n: f64) -> Vec<Complex<f64>> {
    let disc = Complex::new(big_c * big_c * n * n - 4.0 * big_a * k, 0.0).sqrt();
    let mut out = Vec::new();
    for s in [1.0, -1.0] {
        let sigma = (Complex::new(big_c * n, 0.0) + disc * s) / (2.0 * big_a);
        let lambda = Complex::<f64>::i() * (sigma - n);
        out.push(lambda);
        out.push(-lambda);
    }
    out
}

#[derive(Clone, Copy)]
struct Case {
    name: &'static str,
    a: f64,
    c: f64,
    m: f64,
    big_a: f64,
    big_c: f64,
    d: f64,
    family: Family,
}

impl Case {
    /// l − ρ: G's height above the contact minus the pole's radius of curvature a²/c.
    fn l_minus_rho(&self) -> f64 {
        let l = match self.family {
            Family::Upright => self.c - self.d,
            _ => self.c + self.d,
        };
        l - self.a * self.a / self.c
    }
    /// The sleeping criterion's critical spin, 2 √(A m g (l − ρ)) / C (NaN if none).
    fn critical_spin(&self) -> f64 {
        2.0 * (self.big_a * self.m * G * self.l_minus_rho()).sqrt() / self.big_c
    }
    /// The body (a = b, c, mass m, inertia diag(A, A, C) about G, G a distance d below
    /// the centre on the axis) under `model`, spinning at `spin` about its axis (θ = 0).
    fn scene(&self, model: &str, spin: f64) -> Scene {
        self.scenario(model, spin).scene
    }
    /// [`Case::scene`]'s scenario.
    fn scenario(&self, model: &str, spin: f64) -> scenario::Scenario {
        let Case {
            a,
            c,
            m,
            big_a,
            big_c,
            d,
            ..
        } = *self;
        let text = format!(
            r#"
[body]
a = {a:e}
c = {c:e}
mass = {m:e}
com_offset = {d:e}
inertia = [[{big_a:e}, 0.0, 0.0], [0.0, {big_a:e}, 0.0], [0.0, 0.0, {big_c:e}]]
[initial]
theta_deg = 0.0
psi_dot = {spin:e}
[contact]
model = "{model}"
[effects]
gravity = {G:e}
[solver]
method = "dop853"
rtol = 1e-12
atol = 1e-15
[output]
t_end = 1.0
dt = 1e-3
"#
        );
        scenario::parse(&text, "test", &[] as &[&str]).unwrap()
    }
}

/// A homogeneous spheroid (a = b, c, mass m; A = m(a² + c²)/5, C = 2ma²/5 about its
/// centre), G a distance `d` below the centre, upright.
fn spheroid(name: &'static str, a: f64, c: f64, m: f64, d: f64) -> Case {
    Case {
        name,
        a,
        c,
        m,
        big_a: m * (a * a + c * c) / 5.0,
        big_c: 2.0 * m * a * a / 5.0,
        d,
        family: Family::Upright,
    }
}

fn oblate() -> Case {
    spheroid("oblate", 0.03, 0.01, 0.05, 0.002)
}

fn egg() -> Case {
    spheroid("egg on its end", 0.02, 0.03, 0.06, 0.0)
}

/// A tippe-top-like sphere, G 5 mm off the centre, standing on the pole G is far from.
fn offset_sphere() -> Case {
    Case {
        name: "offset-mass sphere, inverted",
        a: 0.02,
        c: 0.02,
        m: 0.015,
        big_a: 1.6e-6,
        big_c: 2.0e-6,
        d: 0.005,
        family: Family::Inverted,
    }
}

/// The frictionless sleeping criterion C²n² > 4 A m g (l − ρ): the spectrum equals the
/// analytic one to 1e-10 of its scale at spins on both sides of the critical spin, and
/// the verdict is stable exactly above it; an oblate body (l < ρ) is stable at every spin.
#[test]
fn val_frictionless_sleeping_criterion() {
    for case in [oblate(), egg(), offset_sphere()] {
        let k = case.m * G * case.l_minus_rho();
        let n_c = case.critical_spin();
        let spins: Vec<f64> = if n_c.is_nan() {
            assert!(case.l_minus_rho() < 0.0);
            vec![0.0, 1.0, 30.0, 300.0, -100.0]
        } else {
            [0.0, 0.5, 0.9, 0.999, 1.001, 1.1, 3.0, -2.0]
                .iter()
                .map(|f| f * n_c)
                .collect()
        };
        for n in spins {
            let scene = case.scene("frictionless", n);
            let an = steady::analyse(&scene, case.family).unwrap();
            // n is the spin about the upward vertical: the body's ψ̇ upright, −ψ̇ inverted.
            let spin = if case.family == Family::Upright {
                n
            } else {
                -n
            };
            assert_eq!(an.motion.spin, spin);
            let expected = sleeping_eigenvalues(case.big_a, case.big_c, k, spin);
            let what = format!("{} at n = {n}", case.name);
            assert_spectrum(&an.spectrum.eigenvalues(), &expected, 1e-10, &what);
            let stable = n_c.is_nan() || n.abs() > n_c;
            assert_eq!(an.spectrum.stable(), stable, "{what}: {:?}", an.spectrum);
            for mode in &an.spectrum.modes {
                assert_eq!(mode.name, "tilt", "{what}");
            }
        }
    }
}

/// ζ1 = sin θ sin ψ (world up in body axes) of a sample.
fn zeta1(s: &Sample) -> f64 {
    s.angles.theta.sin() * s.angles.psi.sin()
}

/// Starts a run on the steady motion displaced by 1e-6 along the unstable mode and fits
/// the growth of the tilt over a decade (1e-5 to 1e-4 rad): it must be the mode's Re λ
/// within 1e-6 (the issue asks 1 %; the nonlinear terms are ~θ² = 1e-8 there).
fn assert_growth(scene: &Scene, an: &Analysis, what: &str) {
    let mode = &an.spectrum.modes[0];
    let rate = mode.eigenvalue.re;
    assert!(rate > 0.0, "{what}: unstable");
    let delta = an.perturbation(0, 1e-6);
    let mut start = steady::started_at(scene, &an.motion.at, &delta);
    start.t_end = 16.0 / rate;
    start.sample_times = (0..=4000)
        .map(|i| i as f64 * start.t_end / 4000.0)
        .collect();
    let samples = run(&start);
    // The tilt's deviation from the motion's own (0 upright, π inverted).
    let t1 = first_reaching(&samples, an.motion.theta, 1e-5);
    let t2 = first_reaching(&samples, an.motion.theta, 1e-4);
    let fitted = 10f64.ln() / (t2 - t1);
    eprintln!("{what}: growth {fitted} against Re λ = {rate}");
    assert!(
        (fitted / rate - 1.0).abs() < 1e-6,
        "{what}: growth {fitted} against Re λ = {rate}"
    );
}

/// Starts a run displaced by 1e-6 along stable mode `k` and measures the angular
/// frequency of ζ1 from its zero crossings over 40 periods: it must be |Im λ| within 1e-6.
fn assert_frequency(scene: &Scene, an: &Analysis, k: usize, what: &str) {
    let lambda = an.spectrum.modes[k].eigenvalue;
    let omega = lambda.im.abs();
    let delta = an.perturbation(k, 1e-6);
    let mut start = steady::started_at(scene, &an.motion.at, &delta);
    let period = std::f64::consts::TAU / omega;
    start.t_end = 41.0 * period;
    let per_period = 400.0;
    let count = (41.0 * per_period) as usize;
    start.sample_times = (0..=count)
        .map(|i| i as f64 * start.t_end / count as f64)
        .collect();
    let samples = run(&start);
    let (measured, count) = crossing_frequency(&samples, zeta1);
    assert!(count >= 40, "{what}: {count} crossings");
    eprintln!(
        "{what}: {measured} against {omega}: {:.2e}",
        measured / omega - 1.0
    );
    assert!(
        (measured / omega - 1.0).abs() < 1e-6,
        "{what}: ζ1 oscillates at {measured} rad/s against |Im λ| = {omega} ({:.2e})",
        measured / omega - 1.0
    );
}

/// Independent path, frictionless egg on its end: below the critical spin a run grows
/// at the predicted rate, above it each mode oscillates at the predicted frequency.
#[test]
fn val_frictionless_egg_runs_follow_the_spectrum() {
    let case = egg();
    let n_c = case.critical_spin();
    for f in [0.3, 0.8] {
        let scene = case.scene("frictionless", f * n_c);
        let an = steady::analyse(&scene, Family::Upright).unwrap();
        assert_growth(&scene, &an, &format!("frictionless egg at {f} n_c"));
    }
    let scene = case.scene("frictionless", 2.0 * n_c);
    let an = steady::analyse(&scene, Family::Upright).unwrap();
    // Modes 0..4 come in conjugate pairs; one of each pair is enough.
    for k in [0, 2] {
        assert_frequency(
            &scene,
            &an,
            k,
            &format!("frictionless egg at 2 n_c, mode {k}"),
        );
    }
}

/// Independent path, rolling (no analytic value is asserted: rolling changes the
/// criterion): the egg on its end below the frictionless critical spin grows at the
/// predicted rate, the inverted offset-mass sphere at 3 n_c is stable and oscillates at
/// the predicted frequencies.
#[test]
fn val_rolling_runs_follow_the_spectrum() {
    let case = egg();
    let n_c = case.critical_spin();
    let slow = case.scene("rolling", 0.5 * n_c);
    let an = steady::analyse(&slow, Family::Upright).unwrap();
    assert_growth(&slow, &an, "rolling egg at 0.5 n_c");
    let sphere = offset_sphere();
    let scene = sphere.scene("rolling", 3.0 * sphere.critical_spin());
    let an = steady::analyse(&scene, Family::Inverted).unwrap();
    assert!(an.spectrum.stable(), "{:?}", an.spectrum);
    for k in [0, 2] {
        assert_frequency(&scene, &an, k, &format!("rolling sphere, mode {k}"));
    }
}

/// The bundled diagram of the egg on its end rolling (scripts/steady-diagrams.py: the body
/// of scenarios/egg.toml, Coulomb's rolling phase, which is the rolling law; critical spin
/// 49.18 rad/s) at two more spins than [`val_rolling_runs_follow_the_spectrum`]'s
/// 0.5 n_c = 40.7 rad/s: at 20 rad/s a run grows at Re λ, at 80 rad/s each pair's
/// frequency is |Im λ|.
#[test]
fn val_bundled_rolling_egg_runs_follow_the_spectrum() {
    let case = egg();
    let slow = case.scene("rolling", 20.0);
    let an = steady::analyse(&slow, Family::Upright).unwrap();
    assert_growth(&slow, &an, "rolling egg at 20 rad/s");
    let fast = case.scene("rolling", 80.0);
    let an = steady::analyse(&fast, Family::Upright).unwrap();
    assert!(an.spectrum.stable(), "{:?}", an.spectrum);
    for k in [0, 2] {
        assert_frequency(&fast, &an, k, &format!("rolling egg at 80 rad/s, mode {k}"));
    }
}

/// The reduction's premise: the model's angular acceleration depends on the state only
/// through ζ and ω — rotating the scene about the vertical (any yaw) and translating it
/// change it by round-off only — so the spectrum is the same for every yaw and position.
#[test]
fn inv_reduced_field_is_invariant_under_the_planes_symmetries() {
    let case = egg();
    let scene = case.scene("rolling", 5.0);
    let field = ReducedField::from_scene(&scene).unwrap();
    let ReducedField::Rolling(system, _) = &field else {
        panic!("rolling")
    };
    for k in 0..20 {
        let x = k as f64;
        let zeta = Vector3::new((1.3 * x).sin(), (0.7 * x).cos(), 2.0 + x.sin()).normalize();
        let omega = Vector3::new(
            3.0 * (0.4 * x).cos(),
            -2.0 * x.sin(),
            20.0 * (0.9 * x).sin(),
        );
        let reduced = field.rate(&reduce::join(&zeta, &omega));
        let mut angles = reduce::attitude(&zeta);
        angles.phi = 0.37 * x - 3.0;
        let mut y = reduce::full_state(&zeta, &omega);
        ellipsoid_core::state::set_quaternion(&mut y, &angles.rotation());
        y[ellipsoid_core::state::POS] = 12.0 * x.cos();
        y[ellipsoid_core::state::POS + 1] = -7.0 * x;
        let full = system.evaluate(&y).response.omega_dot;
        let dw = reduced.fixed_rows::<3>(3) - full;
        assert!(
            dw.norm() <= 1e-12 * full.norm().max(1.0),
            "yaw {}: {dw}",
            angles.phi
        );
    }
    let turned = |phi: f64| {
        let mut s = case.scene("rolling", 5.0);
        s.initial.angles.phi = phi;
        s.initial.position = nalgebra::Vector2::new(phi, -2.0 * phi);
        steady::analyse(&s, Family::Upright)
            .unwrap()
            .spectrum
            .eigenvalues()
    };
    let reference = turned(0.0);
    for phi in [0.5, 2.0, -2.5] {
        let other = turned(phi);
        assert_spectrum(&other, &reference, 1e-13, &format!("turned by {phi}"));
    }
}

/// The rattleback of `scenarios/rattleback.toml` under `model`, spinning at `spin` about
/// the vertical, with the product of inertia `product` (−2e-5 kg m² in the scenario).
fn rattleback(model: &str, spin: f64, product: f64) -> Scene {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/rattleback.toml");
    let sets = [
        format!("initial.omega_body=[0.0, 0.0, {spin:e}]"),
        format!("contact.model=\"{model}\""),
        format!(
            "body.inertia=[[2e-4, {product:e}, 0.0], [{product:e}, 1.6e-3, 0.0], [0.0, 0.0, 1.7e-3]]"
        ),
    ];
    scenario::load(&path, &sets).unwrap().scene
}

/// A triaxial body at rest in its rest attitude (no product of inertia): roll about the
/// long axis and pitch about the short one decouple, with ω² = m g (ρ − l)/I', ρ the
/// radius of curvature of the section (b²/c for roll, a²/c for pitch), l = c − d, and
/// I' = A or B (frictionless: G does not move sideways) or A + m l², B + m l² (rolling:
/// the body turns about the contact point). Asserted to 1e-10 of the scale (measured
/// 1e-15), with the modes named roll and pitch.
#[test]
fn val_triaxial_rest_attitude_roll_and_pitch() {
    let (a, b, c, d, m) = (0.20, 0.03, 0.02, 0.01, 1.0);
    let l = c - d;
    for (model, extra) in [("frictionless", 0.0), ("rolling", m * l * l)] {
        let scene = rattleback(model, 0.0, 0.0);
        let an = steady::analyse(&scene, Family::Upright).unwrap();
        let roll = (m * G * (b * b / c - l) / (2e-4 + extra)).sqrt();
        let pitch = (m * G * (a * a / c - l) / (1.6e-3 + extra)).sqrt();
        let i = Complex::<f64>::i();
        let expected = [i * pitch, -i * pitch, i * roll, -i * roll];
        assert_spectrum(&an.spectrum.eigenvalues(), &expected, 1e-10, model);
        for mode in &an.spectrum.modes {
            let name = if (mode.eigenvalue.im.abs() - roll).abs() < 1e-6 * roll {
                "roll"
            } else {
                "pitch"
            };
            assert_eq!(mode.name, name, "{model}: {mode:?}");
        }
    }
}

/// Least-squares slope of ln θ at its successive maxima (each refined by a parabola
/// through the three samples around it) between `from` and `to` rad: the growth rate of
/// an elliptic (non-circular) mode, whose tilt passes near zero twice a period.
fn envelope_growth(samples: &[Sample], from: f64, to: f64) -> f64 {
    let peaks: Vec<(f64, f64)> = samples
        .windows(3)
        .filter(|w| w[1].angles.theta > w[0].angles.theta && w[1].angles.theta >= w[2].angles.theta)
        .map(|w| {
            let (y0, y1, y2) = (w[0].angles.theta, w[1].angles.theta, w[2].angles.theta);
            let h = w[1].t - w[0].t;
            let curv = y0 - 2.0 * y1 + y2;
            let x = 0.5 * (y0 - y2) / curv;
            (w[1].t + x * h, y1 - 0.25 * (y0 - y2) * x)
        })
        .filter(|&(_, y)| y >= from && y <= to)
        .collect();
    assert!(peaks.len() >= 10, "{} peaks", peaks.len());
    let n = peaks.len() as f64;
    let (mt, my) = peaks
        .iter()
        .fold((0.0, 0.0), |(a, b), &(t, y)| (a + t / n, b + y.ln() / n));
    let (sxy, sxx) = peaks.iter().fold((0.0, 0.0), |(a, b), &(t, y)| {
        (a + (t - mt) * (y.ln() - my), b + (t - mt) * (t - mt))
    });
    sxy / sxx
}

/// The rattleback (rolling, with its product of inertia): time reversal (t, ω) → (−t, −ω)
/// maps the spin n to −n and the spectrum to its negative, so one wobble grows in each
/// direction of spin, at different rates. Runs started 1e-6 along each unstable mode grow
/// at its Re λ within 1e-5 (the issue asks 1 %; measured 3e-7), the tilt's envelope fitted
/// over a decade.
#[test]
fn val_rattleback_wobble_grows_in_each_direction_of_spin() {
    let product = -2e-5;
    let spectrum = |n: f64| {
        steady::analyse(&rattleback("rolling", n, product), Family::Upright)
            .unwrap()
            .spectrum
    };
    for n in [1.0, 5.0, 20.0] {
        let reversed: Vec<Complex<f64>> = spectrum(-n).eigenvalues().iter().map(|z| -z).collect();
        assert_spectrum(
            &spectrum(n).eigenvalues(),
            &reversed,
            1e-10,
            &format!("n = ±{n}"),
        );
    }
    for n in [5.0, -5.0, -8.0] {
        let scene = rattleback("rolling", n, product);
        let an = steady::analyse(&scene, Family::Upright).unwrap();
        let rate = an.spectrum.modes[0].eigenvalue.re;
        assert!(rate > 0.0 && !an.spectrum.stable());
        let delta = an.perturbation(0, 1e-6);
        let mut start = steady::started_at(&scene, &an.motion.at, &delta);
        start.t_end = 12.0 / rate;
        let period = std::f64::consts::TAU / an.spectrum.modes[0].eigenvalue.im.abs();
        let count = (start.t_end / period * 100.0) as usize;
        start.sample_times = (0..=count)
            .map(|i| (i as f64 * start.t_end / count as f64).min(start.t_end))
            .collect();
        let samples = run(&start);
        let fitted = envelope_growth(&samples, 1e-5, 1e-4);
        eprintln!("rattleback n = {n}: envelope growth {fitted} against Re λ = {rate}");
        assert!(
            (fitted / rate - 1.0).abs() < 1e-2,
            "n = {n}: {fitted} against {rate}"
        );
    }
}

/// A sweep of the spin locates the frictionless critical spin n_c = 2√(A m g (l − ρ))/C
/// as a collision to 1e-10 relative (upright egg: stable above; inverted sphere, whose
/// spin about the vertical is −ψ̇: stable below −n_c in ψ̇, and above +n_c).
#[test]
fn val_sweep_locates_the_critical_spin() {
    for case in [egg(), offset_sphere()] {
        let n_c = case.critical_spin();
        let base = case.scenario("frictionless", 0.0);
        let values: Vec<f64> = (0..=12)
            .map(|i| -2.0 * n_c + i as f64 * n_c / 3.0)
            .collect();
        let sw = steady::sweep(&base, case.family, "initial.psi_dot", &values).unwrap();
        assert!(sw.rows.iter().all(|r| r.is_ok()));
        assert_eq!(sw.critical.len(), 2, "{}: {:?}", case.name, sw.critical);
        for (crit, expected, above) in
            [(&sw.critical[0], -n_c, false), (&sw.critical[1], n_c, true)]
        {
            assert_eq!(crit.kind, steady::CriticalKind::Collision, "{}", case.name);
            assert_eq!(crit.stable_above, above, "{}", case.name);
            let err = (crit.value / expected - 1.0).abs();
            eprintln!(
                "{}: critical {} against {expected}: {err:.2e}",
                case.name, crit.value
            );
            assert!(
                err <= 1e-10,
                "{}: {} against {expected}",
                case.name,
                crit.value
            );
        }
    }
}

/// scenarios/rattleback.toml in its rest attitude (its initial tilt removed), spinning at
/// ψ̇ = 0 about the vertical: the text, for `--set initial.psi_dot=…`.
fn resting_rattleback() -> String {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/rattleback.toml");
    std::fs::read_to_string(path)
        .unwrap()
        .replace(
            "rotation = [{ axis = \"x\", angle_deg = 0.5 }, { axis = \"y\", angle_deg = 0.5 }]",
            "",
        )
        .replace("omega_body = [0.0, 0.0, -5.0]", "psi_dot = 0.0")
}

/// The rolling rattleback's spectrum is not symmetric about the imaginary axis: its
/// stability is lost transversally, a pair crossing alone (Re λ ∝ n), on both sides of
/// n = 0 where it is neutrally stable. A sweep through 0 finds two `hopf` critical values
/// next to 0 (within where Re λ = 1e-9 max |λ|: |n| < 1e-5 rad/s).
#[test]
fn val_rattleback_loses_stability_by_crossing_at_zero_spin() {
    let text = resting_rattleback();
    let base = scenario::parse(&text, "rattleback", &[] as &[&str]).unwrap();
    let sw = steady::sweep(&base, Family::Upright, "initial.psi_dot", &[-1.0, 0.0, 1.0]).unwrap();
    let stable: Vec<bool> = sw
        .rows
        .iter()
        .map(|r| r.as_ref().unwrap().spectrum.stable())
        .collect();
    assert_eq!(stable, [false, true, false]);
    assert_eq!(sw.critical.len(), 2, "{:?}", sw.critical);
    for (c, above) in sw.critical.iter().zip([true, false]) {
        assert_eq!(c.kind, steady::CriticalKind::Hopf, "{c:?}");
        assert_eq!(c.stable_above, above);
        assert!(c.value.abs() < 1e-5, "{c:?}");
    }
}

#[test]
fn a_scene_with_an_effect_is_refused_naming_every_effect_of_the_schema() {
    let text = "[body]\na = 0.02\nc = 0.03\nmass = 0.06\ninertia = [1.2e-5, 1.2e-5, 1.0e-5]\n\
                [initial]\npsi_dot = 50.0\n[contact]\nmodel = \"frictionless\"\n\
                [effects]\nair_drag = { linear = 0.1 }\n[output]\nt_end = 1.0\ndt = 1e-3\n";
    let scene = scenario::parse(text, "test", &[] as &[&str]).unwrap().scene;
    let e = steady::analyse(&scene, Family::Upright).unwrap_err();
    assert_eq!(
        e.to_string(),
        "effects = present: steady motions are analysed without effects \
         (air_boundary_layer, air_drag, air_film, rolling_friction, rolling_resistance, \
         spin_friction): remove them"
    );
}

// ------------------------------------------------------ under viscous sliding

use ellipsoid_core::steady::viscous;

/// The Leine–Glocker tippe top of `scenarios/tippe-top.toml` under viscous sliding,
/// μ_v = 1 s/m (the bundled diagram's), spun at 180 rad/s from θ = 0.1 rad as there: the
/// upright spin at n = 179.1 rad/s, the inverted one at −179.1 rad/s.
fn viscous_tippe_top() -> scenario::Scenario {
    tippe_top_viscous_with(&[])
}

/// [`viscous_tippe_top`] with the overrides `sets`.
fn tippe_top_viscous_with(sets: &[String]) -> scenario::Scenario {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/tippe-top.toml");
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("model = \"coulomb\"", "model = \"viscous\"")
        .replace("friction = 0.3", "viscous_friction = 1.0");
    scenario::parse_all(&text, "tippe-top-viscous.toml", sets).unwrap()
}

/// The rattleback of `scenarios/rattleback.toml` at rest in its rest attitude without a
/// product of inertia, under viscous sliding with coefficient `mu_v` [s/m].
fn viscous_rattleback(mu_v: f64) -> Scene {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/rattleback.toml");
    let sets = [
        "initial.omega_body=[0.0, 0.0, 0.0]".to_owned(),
        "contact.model=\"viscous\"".to_owned(),
        format!("contact.viscous_friction={mu_v:e}"),
        "body.inertia=[[2e-4, 0.0, 0.0], [0.0, 1.6e-3, 0.0], [0.0, 0.0, 1.7e-3]]".to_owned(),
    ];
    scenario::load(&path, &sets).unwrap().scene
}

/// Mode names under the viscous law where the answer is known.
/// - The tippe top's upright spin: the unstable pair is the axis' tilt (its eigenvector's
///   rotation carries the energy; the contact hardly slips), so is the slowly decaying
///   pair at |Im λ| ≈ n in which the tilted top rolls sideways (G moves, the contact point
///   does not slip), and the pair damped at ≈ 25 1/s is the slip's relaxation.
/// - The rattleback at rest without a product of inertia: roll and pitch decouple, and as
///   μ_v grows the law tends to rolling, so the two pairs tend to the rolling closed form
///   ω² = m g (ρ − l)/(I' + m l²) of `val_triaxial_rest_attitude_roll_and_pitch` (within
///   1e-6 at μ_v = 1e4 s/m; measured 3e-8): the pair at the roll frequency must be named
///   roll, the other pitch; the two real modes are the slip's relaxation, "slip", at
///   rates proportional to μ_v (×10 within 1e-3 from 1e3 to 1e4 s/m; measured 7e-6).
#[test]
fn val_viscous_modes_are_named_by_what_moves() {
    let top = viscous_tippe_top();
    let up = viscous::analyse(&top.scene, Family::Upright).unwrap();
    eprintln!(
        "tippe top upright: {:?} {:?}",
        up.eigenvalues,
        up.mode_names()
    );
    assert_eq!(
        up.mode_names(),
        ["tilt", "tilt", "tilt", "tilt", "slip", "slip"]
    );
    let (unstable, rolling, slip) = (up.eigenvalues[0], up.eigenvalues[2], up.eigenvalues[4]);
    assert!(unstable.re > 0.0 && !up.stable(), "{unstable}");
    assert!((rolling.im.abs() / up.spin - 1.0).abs() < 0.01 && rolling.re > -0.1);
    assert!(slip.re < -10.0, "{slip}");

    let (a, b, c, d, m) = (0.20, 0.03, 0.02, 0.01, 1.0);
    let l = c - d;
    let roll = (m * G * (b * b / c - l) / (2e-4 + m * l * l)).sqrt();
    let pitch = (m * G * (a * a / c - l) / (1.6e-3 + m * l * l)).sqrt();
    let slip_rates: Vec<Vec<f64>> = [1e3, 1e4]
        .iter()
        .map(|&mu_v| {
            let an = viscous::analyse(&viscous_rattleback(mu_v), Family::Upright).unwrap();
            let names = an.mode_names();
            eprintln!(
                "rattleback at rest, μ_v = {mu_v}: {:?} {names:?}",
                an.eigenvalues
            );
            let mut rates = Vec::new();
            for (lambda, name) in an.eigenvalues.iter().zip(&names) {
                if lambda.im == 0.0 {
                    assert_eq!(*name, "slip", "μ_v = {mu_v}: {lambda}");
                    rates.push(lambda.re);
                    continue;
                }
                let f = lambda.im.abs();
                let (expected, closed) = if (f / roll - 1.0).abs() < 0.01 {
                    ("roll", roll)
                } else {
                    ("pitch", pitch)
                };
                assert_eq!(*name, expected, "μ_v = {mu_v}: {lambda}");
                if mu_v == 1e4 {
                    assert!((f / closed - 1.0).abs() < 1e-6, "{f} against {closed}");
                }
            }
            assert_eq!(names.iter().filter(|n| **n == "roll").count(), 2);
            assert_eq!(names.iter().filter(|n| **n == "pitch").count(), 2);
            assert_eq!(rates.len(), 2);
            rates
        })
        .collect();
    for (low, high) in slip_rates[0].iter().zip(&slip_rates[1]) {
        assert!((high / low / 10.0 - 1.0).abs() < 1e-3, "{low} → {high}");
    }
}

/// `steady::perturbed` under the viscous law (the scenario `ellipsoid steady --perturb`
/// writes), read back and run: the tippe top's upright spin displaced 1e-6 along its
/// unstable tilt pair tilts from 1e-5 to 1e-4 rad at Re λ within 1 % (measured 6e-10);
/// the inverted spin displaced 1e-6 along its first tilt pair (the top rolling on its
/// tilted axis, damped at 0.013 1/s) makes ζ1 = sin θ sin ψ oscillate at |Im λ| within
/// 1e-6 over 10 periods (measured 1.3e-12).
#[test]
fn val_viscous_perturbed_scenarios_follow_the_spectrum() {
    let top = viscous_tippe_top();
    let up = viscous::analyse(&top.scene, Family::Upright).unwrap();
    let rate = up.eigenvalues[0].re;
    let start = steady::perturbed(&top, &up, 0, 1e-6).unwrap();
    let text = start.text.clone();
    assert!(
        text.contains("velocity = ["),
        "G's velocity is part of the start"
    );
    let mut scene = scenario::parse_all(&text, "start.toml", &[] as &[&str])
        .unwrap()
        .scene;
    scene.t_end = 16.0 / rate;
    scene.sample_times = (0..=8000)
        .map(|i| i as f64 * scene.t_end / 8000.0)
        .collect();
    let samples = run(&scene);
    assert!(
        samples[0].angles.theta < 2e-6,
        "{}",
        samples[0].angles.theta
    );
    let fitted =
        10f64.ln() / (first_reaching(&samples, 0.0, 1e-4) - first_reaching(&samples, 0.0, 1e-5));
    eprintln!("viscous upright, perturbed scenario: growth {fitted} against Re λ = {rate}");
    assert!(
        (fitted / rate - 1.0).abs() < 0.01,
        "{fitted} against {rate}"
    );

    let inverted = viscous::analyse(&top.scene, Family::Inverted).unwrap();
    assert!(inverted.stable());
    let k = inverted
        .mode_names()
        .iter()
        .position(|n| *n == "tilt")
        .expect("a tilt pair");
    let omega = inverted.eigenvalues[k].im.abs();
    let start = steady::perturbed(&top, &inverted, k, 1e-6).unwrap();
    let mut scene = scenario::parse_all(&start.text, "start.toml", &[] as &[&str])
        .unwrap()
        .scene;
    let periods = 10.0;
    scene.t_end = (periods + 1.0) * std::f64::consts::TAU / omega;
    let count = ((periods + 1.0) * 400.0) as usize;
    scene.sample_times = (0..=count)
        .map(|i| (i as f64 * scene.t_end / count as f64).min(scene.t_end))
        .collect();
    let samples = run(&scene);
    let (measured, crossings) = crossing_frequency(&samples, zeta1);
    let err = measured / omega - 1.0;
    eprintln!(
        "viscous inverted, perturbed scenario, mode {} ({}): {measured} against {omega}: {err:.2e}",
        k + 1,
        inverted.eigenvalues[k]
    );
    assert!(crossings as f64 >= periods, "{crossings} crossings");
    assert!(err.abs() < 1e-6, "{measured} against {omega} ({err:.2e})");
}

/// The steady verdicts against the tippe top's turn-over map (docs/studies.md, "The
/// tippe top's turn-over map": `studies/tippe-top-map.toml`, Coulomb friction μ = 0.3,
/// spun at 180 rad/s from θ = 0.1 rad, 8 s) on every point of its 40 × 40 grid
/// (1 600 runs with the study's settings, in parallel). The map's verdict at a point is clear where
/// - the top turns over: the run completes and θ reaches 2.5 rad (near inverted);
/// - the top stays up: θ never exceeds 0.2 rad, and either the upright spin is stable or
///   the contact slid long enough for the viscous growth rate to show,
///   Re λ_up · t_slip ≥ 3 (three e-folds; t_slip the last time the contact slid).
///
/// Not clear: a top that stayed up after its slip stopped sooner (the Coulomb contact
/// then rolls, which the viscous law never does: the band just inside 1 − α), a top that
/// rose part way (0.2 … 2.5 rad: every run's slip stops within about 1.3 s, and it then
/// rolls on at whatever tilt it had reached, so the map cannot tell "to its side" from
/// "turns over, interrupted"), and a run that did not complete. At every clear point the
/// steady verdict (the viscous law, μ_v = 1 s/m, at the run's spin) must be the map's:
/// turns over ⇔ upright unstable and inverted stable; stays up ⇔ upright stable
/// (measured: 635 clear points, all agreeing; 965 not clear).
#[test]
fn val_verdicts_agree_with_the_turn_over_map() {
    use ellipsoid_core::simulate::{Mode, Status};
    let map =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/tippe-top.toml");
    enum Verdict {
        Agrees,
        Unclear(String),
        Disagrees(String),
    }
    let point = |i: usize, j: usize| {
        let offset = 0.0005 + (0.009 - 0.0005) * i as f64 / 39.0;
        let inertia = 3.85e-7 + (1.12e-6 - 3.85e-7) * j as f64 / 39.0;
        let sets = vec![
            format!("body.com_offset={offset:e}"),
            format!("body.inertia[0]={inertia:e}"),
            format!("body.inertia[1]={inertia:e}"),
        ];
        let mut run_sets = sets.clone();
        run_sets.extend(
            [
                "solver.rtol=1e-8",
                "solver.atol=1e-10",
                "output.dt=0.01",
                "solver.max_steps=20000",
            ]
            .map(str::to_owned),
        );
        let scene = scenario::load(&map, &run_sets).unwrap().scene;
        let (out, samples) = common::run(&scene);
        let max_theta = samples.iter().map(|s| s.angles.theta).fold(0.0, f64::max);
        let t_slip = samples
            .iter()
            .filter(|s| s.mode == Mode::Sliding)
            .map(|s| s.t)
            .fold(0.0, f64::max);
        let top = tippe_top_viscous_with(&sets);
        let up = viscous::analyse(&top.scene, Family::Upright).unwrap();
        let down = viscous::analyse(&top.scene, Family::Inverted).unwrap();
        let steady = match (up.stable(), down.stable()) {
            (true, _) => "stays up",
            (false, true) => "turns over",
            (false, false) => "to its side",
        };
        let growth = up.max_real().max(0.0) * t_slip;
        let map_verdict = match out.status {
            Status::Completed if max_theta >= 2.5 => Some("turns over"),
            Status::Completed if max_theta < 0.2 && (up.stable() || growth >= 3.0) => {
                Some("stays up")
            }
            _ => None,
        };
        let what = format!(
            "α = {:.3}, I1/I3 = {:.3}: largest θ {max_theta:.2} rad, slid until {t_slip:.2} s, {:?}; steady: {steady} (Re λ_up = {:.3} 1/s)",
            offset / 0.015,
            inertia / 7e-7,
            out.status,
            up.max_real()
        );
        match map_verdict {
            Some(v) if v == steady => Verdict::Agrees,
            Some(v) => Verdict::Disagrees(format!("{what}; the map: {v}")),
            None => Verdict::Unclear(what),
        }
    };
    let verdicts: Vec<Verdict> = (0..40 * 40)
        .into_par_iter()
        .map(|k| point(k / 40, k % 40))
        .collect();
    let clear = verdicts
        .iter()
        .filter(|v| matches!(v, Verdict::Agrees))
        .count();
    let unclear: Vec<&String> = verdicts
        .iter()
        .filter_map(|v| match v {
            Verdict::Unclear(what) => Some(what),
            _ => None,
        })
        .collect();
    let disagree: Vec<&str> = verdicts
        .iter()
        .filter_map(|v| match v {
            Verdict::Disagrees(what) => Some(what.as_str()),
            _ => None,
        })
        .collect();
    eprintln!("{clear} clear points agree; not clear ({}):", unclear.len());
    for u in &unclear {
        eprintln!("  {u}");
    }
    assert!(disagree.is_empty(), "{}", disagree.join("\n"));
    assert!(clear >= 600, "{clear} clear points");
}

/// A disc-like lens (a = 0.03 m, c = 0.004 m, uniform, 0.05 kg) rolling, tilted 1.7 rad,
/// precessing at 1 rad/s (tests/cli_steady.rs's LENS).
const LENS: &str = r#"
[body]
a = 0.03
c = 0.004
mass = 0.05
inertia = "uniform"
[initial]
theta = 1.7
phi_dot = 1.0
psi_dot = 10.0
[contact]
model = "rolling"
[output]
t_end = 1.0
dt = 0.01
"#;

/// A prolate egg (a = b = 0.02 m, c = 0.03 m, uniform, 0.06 kg) upright without friction.
const EGG: &str = r#"
[body]
a = 0.02
c = 0.03
mass = 0.06
inertia = "uniform"
[initial]
theta = 0.0
psi_dot = 100.0
[contact]
model = "frictionless"
[output]
t_end = 1.0
dt = 0.01
"#;

fn parsed(text: &str, sets: &[&str]) -> scenario::Scenario {
    scenario::parse_all(text, "test.toml", sets).unwrap()
}

/// Issue 48: solved for θ at φ̇ = 0, the tilted families took F_n = φ̇ (…) = 0 as a
/// divisor; the family's tangents were NaN and the singular value decomposition panicked
/// ("Singular value was NaN"), killing a whole sweep. Issue 44: φ̇ = 0 now has its
/// motion, the lens on its edge (θ = π/2, where s = 0) rolling straight on or spinning
/// in place, whose tangents come from the null space of ∇F: a sweep through φ̇ = 0 has
/// three rows, each with a finite spectrum, the middle one at θ = π/2 to 1e-12.
#[test]
fn the_tilted_families_without_precession_stand_on_the_edge_and_do_not_panic() {
    use steady::Solve;
    for (family, model) in [
        (Family::RollingCircle, "contact.model=\"rolling\""),
        (Family::Precession, "contact.model=\"frictionless\""),
    ] {
        let base = parsed(LENS, &[model, "initial.phi_dot=0"]);
        let an = steady::analyse_solving(&base.scene, family, Solve::Theta).unwrap();
        assert!(
            (an.motion.theta - std::f64::consts::FRAC_PI_2).abs() < 1e-12,
            "{:?}",
            an.motion
        );
        assert_eq!(an.motion.precession, Some(0.0));
        let sw = steady::sweep_solving(
            &parsed(LENS, &[model]),
            family,
            Solve::Theta,
            "initial.phi_dot",
            &[-1.0, 0.0, 1.0],
            None,
        )
        .unwrap();
        for row in &sw.rows {
            let an = row.as_ref().unwrap();
            assert!(
                an.spectrum
                    .eigenvalues()
                    .iter()
                    .all(|l| l.re.is_finite() && l.im.is_finite())
            );
        }
        let middle = sw.rows[1].as_ref().unwrap();
        assert!(
            (middle.motion.theta - std::f64::consts::FRAC_PI_2).abs() < 1e-12,
            "{family:?}"
        );
    }
}

/// Issue 48: an egg spinning at 1e80 rad/s never returned (the Schur iteration of a
/// Jacobian of round-off does not converge, and had no bound), and at 1e40 the verdict was
/// round-off. Rates beyond `MAX_RATE_RATIO` √(g/c_max) are refused at once, naming the
/// quantity and the rule; a state too large for the Jacobian is refused by `linearize`.
#[test]
fn rates_beyond_what_doubles_resolve_are_refused_at_once() {
    use steady::Solve;
    let start = std::time::Instant::now();
    for spin in [1e7, 1e40, 1e80, 1e200, f64::MAX] {
        let set = format!("initial.psi_dot={spin:e}");
        let scene = parsed(EGG, &[set.as_str()]).scene;
        let e = steady::analyse(&scene, Family::Upright).unwrap_err();
        let text = e.to_string();
        assert!(
            text.starts_with("spin n = ") && text.contains("analysed up to 100000 √(g/c_max)"),
            "{text}"
        );
    }
    for (set, key) in [
        ("initial.phi_dot=1e10", "initial.phi_dot"),
        // A precession rate of 1e-300 asks for an infinite spin.
        ("initial.phi_dot=1e-300", "initial"),
    ] {
        let scene = parsed(LENS, &[set]).scene;
        let e = steady::analyse_solving(&scene, Family::RollingCircle, Solve::Spin).unwrap_err();
        assert_eq!(e.key(), key, "{set}: {e}");
    }
    let scene = parsed(EGG, &[]).scene;
    let huge = steady::Phase::new(0.0, 0.0, 1.0, 1e300, 1e300, 1e300);
    let e = steady::linearize_scene(&scene, Some(huge)).unwrap_err();
    assert_eq!(e.key(), "state", "{e}");
    assert!(start.elapsed() < std::time::Duration::from_secs(2));
}

/// Just below the rate bound the verdict is still the physics': Routh's rolling lens at
/// Ω = 0.9 of the bound (|ω0| ≈ 0.89 of it) is stable, its largest real part within a
/// fifth of the stability tolerance (measured 5e-11 of max |λ|; the round-off grows like
/// 6e-16 of the rate in units of √(g/c_max), the worst body measured).
#[test]
fn val_the_fastest_rolling_lens_analysed_is_stable_within_round_off() {
    let bound = steady::MAX_RATE_RATIO * (G / 0.03_f64).sqrt();
    let set = format!("initial.phi_dot={:e}", 0.9 * bound);
    let scene = parsed(LENS, &[set.as_str()]).scene;
    let an = steady::analyse(&scene, Family::RollingCircle).unwrap();
    let s = &an.spectrum;
    assert!(s.stable(), "{:?}", s.eigenvalues());
    assert!(
        s.max_real().abs() <= 0.2 * steady::STABLE_TOLERANCE * s.scale(),
        "{:?}",
        s.eigenvalues()
    );
}

/// Issue 48: hostile inputs to every steady entry point — the three given rates and the
/// tilt at zero, subnormal, huge, infinite-making and ordinary values, every family and
/// unknown, every contact law, sweeps, and `linearize` at hostile states. None may
/// panic or take 2 s; every analysis returned has finite eigenvalues, a rate within the
/// bound, and a verdict that its eigenvalues give (stable exactly when no real part is
/// above `STABLE_TOLERANCE` of the scale). The scenario parser's fuzzer
/// (`examples/fuzz_scenario.rs`) runs the same checks on the scenes it accepts.
#[test]
fn hostile_inputs_never_panic_hang_or_give_a_verdict_its_eigenvalues_contradict() {
    use std::panic::{AssertUnwindSafe, catch_unwind};
    use std::time::{Duration, Instant};
    use steady::Solve;
    const VALUES: [&str; 22] = [
        "0",
        "-0.0",
        "5e-324",
        "1e-300",
        "1e-9",
        "1e-3",
        "0.5",
        "1",
        "-1",
        "1.5707963267948966",
        "3.141592653589793",
        "3.1415926",
        "17",
        "-250",
        "1e4",
        "1e6",
        "2e6",
        "1e10",
        "1e40",
        "1e80",
        "1e300",
        "1.7976931348623157e308",
    ];
    const MODELS: [&str; 4] = [
        "contact.model=\"frictionless\"",
        "contact.model=\"rolling\"",
        "contact.friction=0.3",
        "contact.viscous_friction=1.0",
    ];
    const KEYS: [&str; 3] = ["initial.theta", "initial.phi_dot", "initial.psi_dot"];
    let mut rng: u64 = 0x2545_f491_4f6c_dd1d;
    let mut next = |n: usize| {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng % n as u64) as usize
    };
    let (mut analysed, mut refused) = (0, 0);
    for round in 0..1500 {
        let text = [LENS, EGG][next(2)];
        let mut sets: Vec<String> = vec![MODELS[next(4)].to_owned()];
        if sets[0].contains("friction=") {
            sets.insert(0, "contact.model=\"coulomb\"".into());
        }
        if sets.last().is_some_and(|s| s.contains("viscous_friction")) {
            sets.insert(0, "contact.model=\"viscous\"".into());
        }
        for key in KEYS {
            if next(3) > 0 {
                sets.push(format!("{key}={}", VALUES[next(VALUES.len())]));
            }
        }
        let Ok(base) = scenario::parse_all(text, "hostile.toml", &sets) else {
            continue;
        };
        let family = [
            Family::Upright,
            Family::Inverted,
            Family::Precession,
            Family::RollingCircle,
        ][next(4)];
        let solve = [Solve::Spin, Solve::PhiDot, Solve::Theta][next(3)];
        let what = format!("round {round}: {family:?} solving for {solve:?}, {sets:?}");
        let start = Instant::now();
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            let scene = &base.scene;
            let bound = steady::MAX_RATE_RATIO
                * (scene.gravity / scene.body.semi_axes().max()).sqrt()
                * (1.0 + 1e-12);
            let mut verdicts: Vec<(Vec<Complex<f64>>, bool, f64)> = Vec::new();
            match steady::analyse_solving(scene, family, solve) {
                Ok(an) => {
                    let w = an.motion.at.fixed_rows::<3>(3).norm();
                    assert!(w <= bound, "{what}: |ω0| = {w} beyond {bound}");
                    let s = &an.spectrum;
                    verdicts.push((s.eigenvalues(), s.stable(), s.scale()));
                }
                Err(e) => assert!(!e.to_string().is_empty()),
            }
            if let Ok(spin) = steady::viscous::analyse(scene, family) {
                verdicts.push((spin.eigenvalues.clone(), spin.stable(), spin.scale()));
            }
            let key = KEYS[next(3)];
            let values = [VALUES[next(22)], VALUES[next(22)], VALUES[next(22)]]
                .map(|v| v.parse::<f64>().unwrap());
            if let Ok(sw) = steady::sweep_solving(&base, family, solve, key, &values, None) {
                for an in sw.rows.iter().flatten() {
                    let s = &an.spectrum;
                    verdicts.push((s.eigenvalues(), s.stable(), s.scale()));
                }
            }
            let state = steady::Phase::from_fn(|_, _| VALUES[next(22)].parse::<f64>().unwrap());
            if let Ok(lin) = steady::linearize_scene(scene, Some(state)) {
                assert!(lin.jacobian.iter().all(|x| x.is_finite()), "{what}");
            }
            let _ = steady::linearize_scene(scene, None);
            verdicts
        }));
        let took = start.elapsed();
        assert!(took < Duration::from_secs(2), "{what}: took {took:?}");
        let verdicts = match outcome {
            Ok(v) => v,
            Err(p) => panic!(
                "{what}: panicked: {}",
                ellipsoid_core::error::panic_message(&*p)
            ),
        };
        if verdicts.is_empty() {
            refused += 1;
        }
        for (eigenvalues, stable, scale) in verdicts {
            analysed += 1;
            assert!(
                eigenvalues
                    .iter()
                    .all(|l| l.re.is_finite() && l.im.is_finite()),
                "{what}: {eigenvalues:?}"
            );
            let max_real = eigenvalues
                .iter()
                .map(|l| l.re)
                .fold(f64::NEG_INFINITY, f64::max);
            assert!(scale.is_finite(), "{what}: scale {scale}");
            assert_eq!(
                stable,
                max_real <= steady::STABLE_TOLERANCE * scale,
                "{what}: verdict against {eigenvalues:?}"
            );
        }
    }
    eprintln!("{analysed} analyses, {refused} inputs without one");
    assert!(analysed >= 300 && refused >= 300, "{analysed}, {refused}");
}

/// `linearize` refuses a state beyond what doubles analyse, as the steady families do
/// (issue 48: a state of 1e300 gave NaNs without an error): a ζ whose squared length
/// overflows or underflows (it cannot be normalised) and an |ω| above 10⁵ √(g/c_max) are
/// refused with the key `state` and the rule; every accepted state's Jacobian is finite.
#[test]
fn linearize_refuses_states_beyond_what_doubles_resolve() {
    let scene = parsed(EGG, &[]).scene;
    let bound = steady::MAX_RATE_RATIO * (G / 0.03_f64).sqrt();
    for (state, says) in [
        ([0.0, 0.0, 1e300, 0.0, 0.0, 0.0], "squared length"),
        ([1e300, 1e300, 1e300, 0.0, 0.0, 1.0], "squared length"),
        ([0.0, 0.0, 1e-160, 0.0, 0.0, 1.0], "squared length"),
        (
            [0.0, 0.0, 1.0, 1e140, 0.0, 0.0],
            "analysed up to 100000 √(g/c_max)",
        ),
        (
            [0.0, 0.0, 1.0, 0.0, 0.0, 1.01 * bound],
            "analysed up to 100000 √(g/c_max)",
        ),
        ([0.0, 0.0, 1.0, 0.0, 0.0, f64::NAN], "must be finite"),
    ] {
        let e = steady::linearize_scene(&scene, Some(steady::Phase::from_row_slice(&state)))
            .expect_err(&format!("{state:?}"));
        assert_eq!(e.key(), "state", "{e}");
        assert!(e.to_string().contains(says), "{state:?}: {e}");
    }
    for state in [
        [0.0, 0.0, 1.0, 0.0, 0.0, 0.99 * bound],
        [0.0, 0.0, 1e150, 0.0, 0.0, 10.0],
        [0.0, 1e-150, 0.0, 1.0, 2.0, 3.0],
    ] {
        let lin = steady::linearize_scene(&scene, Some(steady::Phase::from_row_slice(&state)))
            .unwrap_or_else(|e| panic!("{state:?}: {e}"));
        assert!(lin.jacobian.iter().all(|x| x.is_finite()), "{state:?}");
    }
}

/// Leine & Glocker's tippe top with its stem (scenarios/tippe-top-stem.toml) as a point
/// contact under `model`, spinning at ψ̇ = `spin` upright (θ = 0) or inverted (θ = π),
/// with or without the stem. SI units.
fn stemmed_top(model: &str, spin: f64, inverted: bool, stem: bool) -> scenario::Scenario {
    let theta = if inverted { 180.0 } else { 0.0 };
    let sphere = if stem {
        "[[body.sphere]]\nname = \"stem\"\ncenter = [0.0, 0.0, 0.013]\nradius = 0.005\n"
    } else {
        ""
    };
    let text = format!(
        "[body]\na = 0.015\nc = 0.015\nmass = 6e-3\ncom_offset = 0.003\n\
         inertia = [8e-7, 8e-7, 7e-7]\n{sphere}\
         [initial]\ntheta_deg = {theta:e}\npsi_dot = {spin:e}\n\
         [contact]\nmodel = \"{model}\"\n\
         [solver]\nmethod = \"dop853\"\nrtol = 1e-12\natol = 1e-15\n[output]\nt_end = 1.0\ndt = 0.01\n"
    );
    scenario::parse(&text, "stemmed", &[] as &[&str]).unwrap()
}

/// Issue 47: a body with contact spheres is analysed on the surface it rests on. The
/// inverted tippe top stands on its stem, a sphere of radius ρ = 5 mm whose centre is
/// l − ρ = 16 mm below G: frictionless, its spectrum is the sleeping criterion's with
/// k = m g (l − ρ) to 1e-10, stable exactly above n_c = 2√(A k)/C. Upright it rests on
/// its ball, and the stem (far above the plane) changes nothing: the spectrum is the
/// stemless top's.
#[test]
fn val_the_inverted_tippe_top_stands_on_its_stem_by_the_sleeping_criterion() {
    let (big_a, big_c, m) = (8e-7, 7e-7, 6e-3);
    let k = m * G * 0.016;
    let n_c = 2.0 * (big_a * k).sqrt() / big_c;
    for f in [0.0, 0.5, 0.999, 1.001, 3.0] {
        let an = steady::analyse(
            &stemmed_top("frictionless", f * n_c, true, true).scene,
            Family::Inverted,
        )
        .unwrap();
        let what = format!("inverted on the stem at {f} n_c");
        assert_eq!(
            an.motion.surface,
            ellipsoid_core::body::Surface::Sphere(0),
            "{what}"
        );
        // The spin about the upward vertical is −ψ̇ inverted.
        let expected = sleeping_eigenvalues(big_a, big_c, k, -f * n_c);
        assert_spectrum(&an.spectrum.eigenvalues(), &expected, 1e-10, &what);
        assert_eq!(an.spectrum.stable(), f > 1.0, "{what}: {:?}", an.spectrum);
        assert!(
            (an.motion.normal_force / (m * G) - 1.0).abs() < 1e-12,
            "{what}"
        );
    }
    for model in ["frictionless", "rolling"] {
        for spin in [0.0, 40.0, 180.0] {
            let with = steady::analyse(
                &stemmed_top(model, spin, false, true).scene,
                Family::Upright,
            )
            .unwrap();
            let without = steady::analyse(
                &stemmed_top(model, spin, false, false).scene,
                Family::Upright,
            )
            .unwrap();
            assert_eq!(
                with.motion.surface,
                ellipsoid_core::body::Surface::Ellipsoid
            );
            let what = format!("{model} upright on the ball at {spin} rad/s");
            assert_spectrum(
                &with.spectrum.eigenvalues(),
                &without.spectrum.eigenvalues(),
                1e-13,
                &what,
            );
        }
    }
}

/// Issue 47: the rolling inverted tippe top on its stem against an independent path, runs
/// of the simulator on the stem started 1e-6 along a mode: slower than the critical spin
/// (n = 40 rad/s) the tilt grows at Re λ, faster (200 rad/s) each pair oscillates at
/// |Im λ|, both to 1e-6. A sweep of the spin finds one critical spin, 85.67 rad/s
/// (docs/physics.md, "Bodies with contact spheres").
#[test]
fn val_the_rolling_top_on_its_stem_runs_as_its_spectrum_says() {
    let slow = stemmed_top("rolling", -40.0, true, true).scene;
    let an = steady::analyse(&slow, Family::Inverted).unwrap();
    assert_eq!(an.motion.surface, ellipsoid_core::body::Surface::Sphere(0));
    assert_growth(&slow, &an, "rolling on the stem at 40 rad/s");
    let fast = stemmed_top("rolling", -200.0, true, true).scene;
    let an = steady::analyse(&fast, Family::Inverted).unwrap();
    assert!(an.spectrum.stable(), "{:?}", an.spectrum);
    for k in [0, 2] {
        assert_frequency(
            &fast,
            &an,
            k,
            &format!("rolling on the stem at 200 rad/s, mode {k}"),
        );
    }
    let values: Vec<f64> = (0..=20).map(|i| -10.0 * i as f64).collect();
    let base = stemmed_top("rolling", 0.0, true, true);
    let sw = steady::sweep(&base, Family::Inverted, "initial.psi_dot", &values).unwrap();
    assert_eq!(sw.critical.len(), 1, "{:?}", sw.critical);
    let crit = &sw.critical[0];
    assert_eq!(crit.kind, steady::CriticalKind::Collision);
    assert!((crit.value + 85.67).abs() < 0.005, "{crit:?}");
}

/// Issue 47: along a sweep a mode keeps its name. The rattleback's raw names change with
/// the spin (at rest its modes are a pure pitch and a pure roll; spun at 30 rad/s both
/// pairs are named roll, in between one is a wobble); swept from −30 to 30 rad/s each
/// branch is named by its clearest member, the pure modes at rest: every row names two
/// pitch and two roll modes, the pitch pair being the one followed from the faster pair
/// at rest.
#[test]
fn val_a_mode_keeps_its_name_along_a_sweep() {
    let text = resting_rattleback();
    let base = scenario::parse(&text, "rattleback", &[] as &[&str]).unwrap();
    let raw = |spin: f64| {
        let scene = scenario::parse(&text, "rattleback", &[format!("initial.psi_dot={spin}")])
            .unwrap()
            .scene;
        let an = steady::analyse(&scene, Family::Upright).unwrap();
        let mut names: Vec<&str> = an.spectrum.modes.iter().map(|m| m.name).collect();
        names.sort_unstable();
        names
    };
    assert_eq!(raw(0.0), ["pitch", "pitch", "roll", "roll"]);
    assert_eq!(raw(30.0), ["roll", "roll", "roll", "roll"]);
    assert!(raw(3.0).contains(&"wobble"), "{:?}", raw(3.0));
    let values: Vec<f64> = (0..=60).map(|i| -30.0 + i as f64).collect();
    let sw = steady::sweep(&base, Family::Upright, "initial.psi_dot", &values).unwrap();
    for (v, row) in values.iter().zip(&sw.rows) {
        let an = row.as_ref().unwrap();
        let mut names: Vec<&str> = an.spectrum.modes.iter().map(|m| m.name).collect();
        names.sort_unstable();
        assert_eq!(names, ["pitch", "pitch", "roll", "roll"], "at ψ̇ = {v}");
        // The pitch pair is the faster one at rest, followed by continuity: at every spin
        // here it is still the pair of larger |Im λ|.
        let fastest = an
            .spectrum
            .modes
            .iter()
            .max_by(|a, b| a.eigenvalue.im.abs().total_cmp(&b.eigenvalue.im.abs()))
            .unwrap();
        assert_eq!(fastest.name, "pitch", "at ψ̇ = {v}: {:?}", an.spectrum.modes);
    }
}
