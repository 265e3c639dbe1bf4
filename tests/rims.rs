//! Rims (docs/physics.md, "Rims"): the torus's support point and gap against a brute-force
//! minimum over its surface, a sphere as the limit of a rim of small radius, a disc
//! spinning with its centre fixed at the precession rate of the exact steady relation
//! (Moffatt's Ω² = 4g/(R sin α) for a thin uniform disc, and its general form for a
//! rounded edge and G off the rim's plane), the upright rolling disc stable above
//! n² = g/(3R) and unstable below, and the conservation of energy on a rim.

mod common;

use common::{G, run};
use ellipsoid_core::body::{Body, Rim, Surface, uniform_inertia};
use ellipsoid_core::geometry::{self, Contact};
use ellipsoid_core::simulate::{EventKind, Sample, Status};
use nalgebra::{Matrix2, Vector2, Vector3};

/// The lowest point of the torus (circle of radius `ring` about body z centred at `c`, tube
/// radius `edge`) for world up `zeta`, by minimising ζ·q(u, v) over its parametrisation
/// q = c + (R + r cos v)(cos u, sin u, 0) + r sin v e3: the best of a 720 × 360 grid, then
/// Newton's method on (u, v) (on u alone for a sharp edge).
fn brute_force_lowest(c: Vector3<f64>, ring: f64, edge: f64, zeta: Vector3<f64>) -> Vector3<f64> {
    let q = |u: f64, v: f64| {
        c + Vector3::new(u.cos(), u.sin(), 0.0) * (ring + edge * v.cos())
            + Vector3::z() * (edge * v.sin())
    };
    let f = |u: f64, v: f64| zeta.dot(&q(u, v));
    let (mut u, mut v) = (0.0, 0.0);
    let mut best = f64::INFINITY;
    for i in 0..720 {
        for j in 0..360 {
            let (ui, vj) = (
                i as f64 * std::f64::consts::PI / 360.0,
                j as f64 * std::f64::consts::PI / 180.0,
            );
            if f(ui, vj) < best {
                (best, u, v) = (f(ui, vj), ui, vj);
            }
        }
    }
    for _ in 0..50 {
        let a = zeta.x * u.cos() + zeta.y * u.sin();
        let b = -zeta.x * u.sin() + zeta.y * u.cos();
        let w = ring + edge * v.cos();
        let grad = Vector2::new(w * b, -edge * v.sin() * a + edge * zeta.z * v.cos());
        let hess = Matrix2::new(
            -w * a,
            -edge * v.sin() * b,
            -edge * v.sin() * b,
            -edge * v.cos() * a - edge * zeta.z * v.sin(),
        );
        if edge == 0.0 {
            u -= grad.x / hess[(0, 0)];
        } else {
            let step = hess.try_inverse().expect("a regular minimum") * grad;
            u -= step.x;
            v -= step.y;
        }
    }
    q(u, v)
}

/// A thin disc body: its ellipsoid (a = R, c = R/10) carries the mass only; one rim.
fn disc(radius: f64, edge: f64, rim_z: f64, d2: f64, inertia: (f64, f64)) -> Body {
    let mass = 0.3;
    Body::of_revolution(radius, radius / 10.0, mass, inertia.0, inertia.1, d2)
        .unwrap()
        .with_rims(vec![Rim {
            name: "edge".into(),
            center: Vector3::new(0.0, 0.0, rim_z),
            radius,
            edge,
        }])
        .unwrap()
        .without_ellipsoid_contact()
        .unwrap()
}

#[test]
fn geo_the_rim_support_point_and_height_match_a_brute_force_minimum_over_the_torus() {
    let cases = [
        (0.05, 0.0, 0.0),
        (0.0375, 0.0016, 0.002),
        (0.01, 0.004, -0.003),
        (0.002, 0.01, 0.005),
    ];
    let zetas = [
        Vector3::new(0.3, -0.5, 0.8),
        Vector3::new(-0.9, 0.1, 0.2),
        Vector3::new(0.05, 0.02, -0.99),
        Vector3::new(0.7, 0.7, 0.1),
    ];
    for (ring, edge, z) in cases {
        let axes = Vector3::new(0.05, 0.05, 0.005);
        let body = Body::new(
            axes,
            0.3,
            uniform_inertia(axes, 0.3),
            Vector3::new(0.001, -0.002, 0.0),
        )
        .unwrap()
        .with_rims(vec![Rim {
            name: "rim".into(),
            center: Vector3::new(0.0, 0.0, z),
            radius: ring,
            edge,
        }])
        .unwrap();
        for zeta in zetas {
            let zeta = zeta.normalize();
            let contact = Contact::of(&body, Surface::Rim(0), zeta, Vector3::zeros());
            let lowest = brute_force_lowest(Vector3::new(0.0, 0.0, z), ring, edge, zeta);
            assert!(
                (contact.p_c - lowest).norm() < 1e-12,
                "R = {ring}, r = {edge}, ζ = {zeta:?}: p_c {:?} vs {lowest:?}",
                contact.p_c
            );
            // h = −ζ·p_c + ζ·g: the height of G when the lowest point touches.
            let h = -zeta.dot(&lowest) + zeta.dot(&body.com_offset());
            let height = geometry::height(&body, Surface::Rim(0), zeta);
            assert!(
                (height - h).abs() < 1e-14,
                "R = {ring}, r = {edge}: {height} vs {h}"
            );
            assert!((contact.height - h).abs() < 1e-14);
        }
    }
}

/// The Hessian of the rim's support (`r_dot_surface = −H ζ̇`) against finite differences of
/// its support point, away from the flat attitude.
#[test]
fn geo_the_rim_curvature_matches_finite_differences_of_its_support_point() {
    let body = disc(0.04, 0.003, 0.002, 0.001, (1.2e-4, 2.4e-4));
    let zeta = Vector3::new(0.4, -0.3, 0.85).normalize();
    let omega = Vector3::new(1.3, -0.7, 2.1);
    let c = Contact::of(&body, Surface::Rim(0), zeta, omega);
    // ṗ_c along ζ̇ = ζ × ω: −H ζ̇.
    let eps = 1e-6;
    let ahead = Contact::of(&body, Surface::Rim(0), zeta + c.zeta_dot * eps, omega);
    let behind = Contact::of(&body, Surface::Rim(0), zeta - c.zeta_dot * eps, omega);
    let rate = (ahead.p_c - behind.p_c) / (2.0 * eps);
    assert!(
        (rate - c.r_dot_surface).norm() < 1e-7 * rate.norm(),
        "{rate:?} vs {:?}",
        c.r_dot_surface
    );
}

/// A disc's TOML: uniform thin disc of radius R (m = 0.3 kg) unless `body` says otherwise.
fn scene(body: &str, initial: &str, model: &str, t_end: f64) -> ellipsoid_core::scenario::Scenario {
    let text = format!(
        "{body}\n[initial]\n{initial}\n[contact]\nmodel = \"{model}\"\n\
         [solver]\nmethod = \"dop853\"\nrtol = 1e-12\natol = 1e-14\n\
         [output]\nt_end = {t_end}\ndt = 0.01\n"
    );
    ellipsoid_core::scenario::parse(&text, "disc.toml", &[] as &[&str])
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn disc_toml(radius: f64, edge: f64, rim_z: f64, d2: f64, inertia: (f64, f64)) -> String {
    format!(
        "[body]\na = {radius}\nc = {}\nmass = 0.3\ncom_offset = {d2}\n\
         inertia = [{}, {}, {}]\nellipsoid_contact = false\n\
         [[body.rim]]\nname = \"edge\"\ncenter = [0.0, 0.0, {rim_z}]\nradius = {radius}\nedge = {edge}\n",
        radius / 10.0,
        inertia.0,
        inertia.0,
        inertia.1
    )
}

/// The largest |θ − θ0| and horizontal excursion of G over a run.
fn excursions(samples: &[Sample], theta0: f64) -> (f64, f64) {
    samples.iter().fold((0.0, 0.0), |(dt, dx), s| {
        (
            dt.max((s.angles.theta - theta0).abs()),
            dx.max(s.position.xy().norm()),
        )
    })
}

/// The steady precession of a rim rolling with G fixed (docs/physics.md, "Rims": "A disc
/// spinning with its centre fixed"): tilt α (the axis α from the vertical), edge r, rim
/// centre a distance d above G along the axis, transverse and axial moments I_t, I_a:
/// ψ̇ = −Ω (d sin α + R cos α)/(R + r sin α) and
/// Ω² = m g (d sin α + R cos α) / (sin α [I_t cos α − I_a sin α (r cos α − d)/(R + r sin α)]).
fn steady_rates(
    m: f64,
    radius: f64,
    edge: f64,
    d: f64,
    inertia: (f64, f64),
    alpha: f64,
) -> (f64, f64) {
    let (s, c) = alpha.sin_cos();
    let lever = d * s + radius * c;
    let denominator = s * (inertia.0 * c - inertia.1 * s * (edge * c - d) / (radius + edge * s));
    let omega = (m * G * lever / denominator).sqrt();
    (omega, -omega * lever / (radius + edge * s))
}

#[test]
fn moffatt_a_uniform_thin_disc_spinning_with_its_centre_fixed_keeps_its_tilt() {
    let radius = 0.05;
    let inertia = (0.3 * radius * radius / 4.0, 0.3 * radius * radius / 2.0);
    for alpha in [0.2, 0.7, 1.3] {
        let (omega, psi_dot) = steady_rates(0.3, radius, 0.0, 0.0, inertia, alpha);
        // Moffatt's exact relation for the thin uniform disc.
        assert!((omega * omega - 4.0 * G / (radius * alpha.sin())).abs() < 1e-9 * omega * omega);
        assert!((psi_dot + omega * alpha.cos()).abs() < 1e-12 * omega);
        let periods = 20.0 * std::f64::consts::TAU / omega;
        let body = disc_toml(radius, 0.0, 0.0, 0.0, inertia);
        for (factor, stays) in [(1.0, true), (1.01, false)] {
            let initial = format!(
                "theta = {alpha}\nphi_dot = {}\npsi_dot = {}",
                factor * omega,
                factor * psi_dot
            );
            let sc = scene(&body, &initial, "rolling", periods);
            let (out, samples) = run(&sc.scene);
            assert_eq!(out.status, Status::Completed);
            let (tilt, drift) = excursions(&samples, alpha);
            if stays {
                assert!(
                    tilt < 1e-9 && drift < 1e-9 * radius,
                    "α = {alpha}: Δθ {tilt:e}, G moved {drift:e} m"
                );
            } else {
                assert!(
                    tilt > 1e-4,
                    "α = {alpha}, Ω off by 1 %: Δθ {tilt:e} (the test must tell the rate apart)"
                );
            }
        }
    }
}

#[test]
fn moffatt_a_rounded_rim_off_the_plane_of_g_spins_steadily_at_the_general_rate() {
    // The Euler disk's proportions: R = 37.5 mm minus the fillet, fillet 1.6 mm; the rim
    // 4.9 mm below G (the disc's lower face), G on the axis.
    let (radius, edge, rim_z, d2) = (0.0359, 0.0016, -0.0049, 0.0);
    let inertia = (1.7e-4, 3.1e-4);
    for alpha in [0.15, 0.6, 1.2] {
        let (omega, psi_dot) = steady_rates(0.3, radius, edge, rim_z + d2, inertia, alpha);
        let periods = 20.0 * std::f64::consts::TAU / omega;
        let body = disc_toml(radius, edge, rim_z, d2, inertia);
        let initial = format!("theta = {alpha}\nphi_dot = {omega}\npsi_dot = {psi_dot}");
        let sc = scene(&body, &initial, "rolling", periods);
        let (out, samples) = run(&sc.scene);
        assert_eq!(out.status, Status::Completed);
        let (tilt, drift) = excursions(&samples, alpha);
        assert!(
            tilt < 1e-9 && drift < 1e-9 * radius,
            "α = {alpha}: Δθ {tilt:e}, G moved {drift:e} m"
        );
    }
}

/// The thin uniform disc rolling upright on its edge (θ = π/2) is stable for a spin
/// n² > g/(3R) (docs/physics.md, "Rims": m g R I_t / (I_a (I_a + m R²)) for any
/// axisymmetric thin wheel): started 0.1 mrad off upright, above 1.02 n_c its lean (which
/// the two nearly equal frequencies there amplify fifty-fold) stays below 0.01 rad and no
/// larger in the second 10 s than in the first, below 0.98 n_c it falls past 0.1 rad.
#[test]
fn the_upright_rolling_disc_is_stable_above_the_critical_spin_and_falls_below_it() {
    let radius = 0.05;
    let inertia = (0.3 * radius * radius / 4.0, 0.3 * radius * radius / 2.0);
    let critical = (G / (3.0 * radius)).sqrt();
    let body = disc_toml(radius, 0.0, 0.0, 0.0, inertia);
    for (factor, stable) in [(1.02, true), (0.98, false)] {
        let initial = format!(
            "theta = {}\npsi_dot = {}",
            std::f64::consts::FRAC_PI_2 - 1e-4,
            factor * critical
        );
        let sc = scene(&body, &initial, "rolling", 20.0);
        let (_, samples) = run(&sc.scene);
        let lean = |from: f64, to: f64| {
            (samples.iter().filter(|s| (from..=to).contains(&s.t)))
                .map(|s| (s.angles.theta - std::f64::consts::FRAC_PI_2).abs())
                .fold(0.0, f64::max)
        };
        let (first, second) = (lean(0.0, 10.0), lean(10.0, 20.0));
        let lean = first.max(second);
        if stable {
            assert!(
                lean < 0.01 && second <= 1.01 * first,
                "{factor} n_c: leaned {first} then {second} rad"
            );
        } else {
            assert!(lean > 0.1, "{factor} n_c: leaned only {lean} rad");
        }
    }
}

/// Rolling and frictionless rims conserve the energy (the run's relative drift), a
/// rounded rim tilted and spinning off any steady motion.
#[test]
fn rolling_and_frictionless_rims_conserve_energy() {
    let body = disc_toml(0.03, 0.004, -0.002, 0.001, (8e-5, 1.5e-4));
    for model in ["rolling", "frictionless"] {
        let sc = scene(
            &body,
            "theta = 0.9\nphi_dot = 3.0\npsi_dot = 25.0\ntheta_dot = 1.0",
            model,
            3.0,
        );
        let (out, samples) = run(&sc.scene);
        assert_eq!(out.status, Status::Completed, "{model}");
        let e0 = samples[0].energy;
        let worst = samples
            .iter()
            .map(|s| (s.energy - e0).abs())
            .fold(0.0, f64::max);
        assert!(
            worst < 1e-10 * e0.abs(),
            "{model}: E moved {worst:e} J of {e0} J"
        );
    }
}

/// A contact sphere is the rim of radius 0: rims of the smallest radii a scene takes,
/// R = 1e-6 L = 30 nm and twice that, trace the sphere's trajectory to within ten times R,
/// and the distance halves with R (first order in R, as the support R|Pζ| is).
#[test]
fn a_rim_of_vanishing_radius_moves_as_the_sphere_of_its_edge() {
    let base = "[body]\na = 0.02\nc = 0.03\nmass = 0.05\ncom_offset = 0.004\ninertia = [1.3e-5, 1.3e-5, 8e-6]\nellipsoid_contact = false\n";
    let sphere = format!(
        "{base}[[body.sphere]]\nname = \"tip\"\ncenter = [0.0, 0.0, -0.03]\nradius = 0.002\n"
    );
    let rim = |ring: f64| {
        format!(
            "{base}[[body.rim]]\nname = \"tip\"\ncenter = [0.0, 0.0, -0.03]\nradius = {ring}\nedge = 0.002\n"
        )
    };
    let initial = "theta = 0.4\npsi_dot = 60.0\nphi_dot = 2.0";
    let (_, a) = run(&scene(&sphere, initial, "frictionless", 1.0).scene);
    let apart = |ring: f64| {
        let (_, b) = run(&scene(&rim(ring), initial, "frictionless", 1.0).scene);
        assert_eq!(a.len(), b.len());
        a.iter()
            .zip(&b)
            .map(|(p, q)| (p.position - q.position).norm())
            .fold(0.0, f64::max)
    };
    let (small, double) = (apart(3e-8), apart(6e-8));
    assert!(small < 3e-7, "G apart by {small:e} m");
    assert!(
        (1.8..2.2).contains(&(double / small)),
        "{small:e} m, then {double:e} m at twice R"
    );
}

#[test]
fn rim_keys_and_their_errors_name_the_line_and_the_rule() {
    let body = "[body]\na = 0.05\nc = 0.005\nmass = 0.3\ninertia = [1.875e-4, 1.875e-4, 3.75e-4]\n";
    let err = |rims: &str| {
        let text = format!(
            "{body}{rims}[initial]\ntheta = 0.5\n[contact]\nmodel = \"rolling\"\n[output]\nt_end = 1.0\ndt = 0.1\n"
        );
        ellipsoid_core::scenario::parse(&text, "x.toml", &[] as &[&str])
            .unwrap_err()
            .to_string()
    };
    let off_axis = err(
        "[[body.rim]]\nname = \"edge\"\ncenter = [0.01, 0.0, 0.0]\nradius = 0.05\nedge = 0.0\n",
    );
    assert_eq!(
        off_axis,
        "x.toml:8:1: body.rim[0].center = [0.01, 0.0, 0.0]: a rim's centre lies on the body's symmetry axis: [0.0, 0.0, z]"
    );
    let negative = err(
        "[[body.rim]]\nname = \"edge\"\ncenter = [0.0, 0.0, 0.0]\nradius = 0.05\nedge = -0.001\n",
    );
    assert!(
        negative.starts_with(
            "x.toml:10:1: body.rim[0].edge = -0.001: an edge radius must be finite and at least 0"
        ),
        "{negative}"
    );
    let twin = err(
        "[[body.sphere]]\nname = \"edge\"\ncenter = [0.0, 0.0, 0.0]\nradius = 0.01\n[[body.rim]]\nname = \"edge\"\ncenter = [0.0, 0.0, 0.0]\nradius = 0.05\nedge = 0.0\n",
    );
    assert!(
        twin.contains(
            "body.rim[0].name = \"edge\": rim names must be unique among spheres and rims"
        ),
        "{twin}"
    );
    let alone = err("ellipsoid_contact = false\n");
    assert!(
        alone.contains("body.ellipsoid_contact")
            && alone.contains("needs a contact sphere or a rim"),
        "{alone}"
    );
}

/// A coin has no ellipsoid: the surfaces a body names are its spheres and rims only.
#[test]
fn a_body_without_ellipsoid_contact_touches_with_its_rims_only() {
    let body = disc(0.05, 0.0, 0.0, 0.0, (1.875e-4, 3.75e-4));
    assert_eq!(body.surfaces().collect::<Vec<_>>(), vec![Surface::Rim(0)]);
    // Tilted 0.5 rad the ellipsoid (a = R, c = R/10) would reach lower than the rim's
    // sharp edge does not: the lowest surface is still the rim.
    let zeta = Vector3::new(0.0, 0.5f64.sin(), 0.5f64.cos());
    assert_eq!(
        Contact::lowest(&body, zeta, Vector3::zeros()).surface,
        Surface::Rim(0)
    );
}

/// A coin: R = 12.13 mm, 1.75 mm thick (its rim's edge half that), 5.67 g, its moments
/// those of a solid cylinder.
fn coin_toml() -> String {
    "[body]\na = 0.01213\nc = 0.000875\nmass = 5.67e-3\ninertia = [2.10e-7, 2.10e-7, 4.17e-7]\n\
     ellipsoid_contact = false\n[[body.rim]]\nname = \"edge\"\ncenter = [0.0, 0.0, 0.0]\n\
     radius = 0.011255\nedge = 0.000875\n"
        .to_owned()
}

fn coin_scene(
    initial: &str,
    contact: &str,
    rtol: f64,
    t_end: f64,
) -> ellipsoid_core::scenario::Scenario {
    let text = format!(
        "{}[initial]\n{initial}\n[contact]\n{contact}\n[solver]\nmethod = \"dop853\"\nrtol = {rtol}\natol = {}\n\
         [output]\nt_end = {t_end}\ndt = 0.001\n",
        coin_toml(),
        rtol * 1e-2
    );
    ellipsoid_core::scenario::parse(&text, "coin.toml", &[] as &[&str])
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The times of a run's flat landings, with their energy losses.
fn flats(out: &ellipsoid_core::simulate::Outcome) -> Vec<(f64, f64)> {
    (out.events.iter())
        .filter_map(|e| match e.kind {
            EventKind::Flat { energy_loss, .. } => Some((e.t, energy_loss)),
            _ => None,
        })
        .collect()
}

/// A coin let go at 1.2 rad with friction tips over, lands flat once (the event located:
/// its time agrees between rtol 1e-10 and 1e-12 to 1e-9 s), slides on its face and comes
/// to rest: completed, E + W continuous across the landing, E never rising there.
#[test]
fn a_coin_tipping_over_lands_flat_once_and_comes_to_rest_on_its_face() {
    let contact = "model = \"coulomb\"\nfriction = 0.3";
    let (out, samples) = run(&coin_scene("theta = 1.2", contact, 1e-10, 0.5).scene);
    assert_eq!(out.status, Status::Completed);
    let landed = flats(&out);
    assert_eq!(landed.len(), 1, "{:?}", out.events);
    let (t_flat, loss) = landed[0];
    assert!(loss > 0.0, "the face's impact removes energy: {loss}");
    let (tight, _) = run(&coin_scene("theta = 1.2", contact, 1e-12, 0.5).scene);
    assert!(
        (flats(&tight)[0].0 - t_flat).abs() < 1e-9,
        "{t_flat} vs {:?}",
        flats(&tight)
    );
    // On its face from the landing on, at rest at the end.
    for s in samples.iter().filter(|s| s.t > t_flat) {
        assert_eq!(s.mode, ellipsoid_core::simulate::Mode::Face, "t = {}", s.t);
        // θ from the attitude to round-off: acos near 1 amplifies ε to √ε.
        assert!(s.angles.theta < 1e-7, "t = {}: θ = {}", s.t, s.angles.theta);
    }
    let last = samples.last().unwrap();
    assert_eq!((last.velocity.norm(), last.omega.norm()), (0.0, 0.0));
    assert!((last.position.z - 0.000875).abs() < 1e-15);
    // E + W continuous; E falls at the landing.
    let e0 = samples[0].energy + samples[0].work;
    for s in &samples {
        assert!(
            (s.energy + s.work - e0).abs() < 1e-9 * e0,
            "t = {}: E + W moved",
            s.t
        );
    }
    let before = samples.iter().rfind(|s| s.t < t_flat).unwrap();
    let after = samples.iter().find(|s| s.t > t_flat).unwrap();
    assert!(after.energy < before.energy);
}

/// `[contact] flat_tilt` moves the landing to a rougher face: the coin tipping over with
/// flat_tilt = 1e-4 lands where the default run's tilt passes sin θ = 1e-4 (that run's
/// observable on θ, an independent watch) to 1e-9 s, turned flat by at most that tilt, and
/// comes to rest on its face with E + W continuous. A flat tilt outside [1e-6, 1e-3] is
/// refused at its line.
#[test]
fn a_rougher_face_lands_the_coin_where_its_tilt_reaches_the_flat_tilt() {
    let contact = "model = \"coulomb\"\nfriction = 0.3";
    let alpha = 1e-4f64.asin();
    let observed = format!(
        "{contact}\n[[observe]]\nname = \"rough\"\ncolumn = \"theta\"\ncrosses = {alpha:e}\ndirection = \"down\""
    );
    let (default, _) = run(&coin_scene("theta = 1.2", &observed, 1e-11, 0.5).scene);
    let crossing = (default.events.iter())
        .find(|e| matches!(e.kind, EventKind::Observed { .. }))
        .expect("the default run passes sin θ = 1e-4")
        .t;
    let rough = format!("{contact}\nflat_tilt = 1e-4");
    let (out, samples) = run(&coin_scene("theta = 1.2", &rough, 1e-11, 0.5).scene);
    assert_eq!(out.status, Status::Completed);
    let landed = flats(&out);
    assert_eq!(landed.len(), 1, "{:?}", out.events);
    assert!(
        (landed[0].0 - crossing).abs() < 1e-9,
        "landed at {} s, the tilt passed 1e-4 at {crossing} s",
        landed[0].0
    );
    assert!(landed[0].0 < flats(&default)[0].0);
    let e0 = samples[0].energy + samples[0].work;
    for s in &samples {
        assert!((s.energy + s.work - e0).abs() < 1e-9 * e0, "t = {}", s.t);
    }
    let last = samples.last().unwrap();
    assert_eq!(last.mode, ellipsoid_core::simulate::Mode::Face);
    assert_eq!((last.velocity.norm(), last.omega.norm()), (0.0, 0.0));
    for bad in ["1e-7", "0.01", "nan"] {
        let text = format!(
            "{}[initial]\ntheta = 1.2\n[contact]\n{contact}\nflat_tilt = {bad}\n[output]\nt_end = 0.1\ndt = 0.01\n",
            coin_toml()
        );
        let err = ellipsoid_core::scenario::parse(&text, "coin.toml", &[] as &[&str])
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with(&format!(
                "coin.toml:17:1: contact.flat_tilt = {bad}: the flat tilt must lie in [1e-6, 1e-3]"
            )),
            "{err}"
        );
    }
}

/// Without friction the plane's force is vertical: the angular momentum about the
/// vertical through G, L_z, is kept through the fall, the face's impact and the spin on
/// the face, where Ω = L_z/I_zz and v_G stay constant. (Its axial spin ω₃ is kept too, so
/// the coin reaches flat only where L_z = I_a ω₃: ψ̇ = φ̇ (I_t (1 + cos θ)/I_a − cos θ).)
#[test]
fn a_frictionless_coin_keeps_its_vertical_angular_momentum_through_the_flat_landing() {
    let (i_t, i_a) = disc_body_for_lz();
    let (theta, phi_dot) = (1.0f64, 3.0);
    let psi_dot = phi_dot * (i_t * (1.0 + theta.cos()) / i_a - theta.cos());
    let initial = format!("theta = {theta}\nphi_dot = {phi_dot}\npsi_dot = {psi_dot}");
    let (out, samples) = run(&coin_scene(&initial, "model = \"frictionless\"", 1e-11, 0.6).scene);
    assert_eq!(out.status, Status::Completed);
    assert_eq!(flats(&out).len(), 1, "{:?}", out.events);
    let lz = |s: &Sample| {
        let body = disc_body_for_lz();
        let w = s.omega_world;
        // L_z = e3·(R I Rᵀ) ω with R from the body's ζ: the body is axisymmetric, so
        // L_z = I_t ω_z + (I_a − I_t)(n·ω) n_z, n the axis in world axes.
        let (st, ct) = s.angles.theta.sin_cos();
        let (sp, cp) = s.angles.phi.sin_cos();
        let n = Vector3::new(st * sp, -st * cp, ct);
        body.0 * w.z + (body.1 - body.0) * n.dot(&w) * n.z
    };
    let l0 = lz(&samples[0]);
    for s in &samples {
        assert!(
            (lz(s) - l0).abs() < 1e-9 * l0.abs(),
            "t = {}: L_z {} vs {l0}",
            s.t,
            lz(s)
        );
    }
    let face: Vec<&Sample> = samples
        .iter()
        .filter(|s| s.mode == ellipsoid_core::simulate::Mode::Face)
        .collect();
    assert!(face.len() > 100);
    let (first, last) = (face[0], face[face.len() - 1]);
    assert!((last.omega_world.z - first.omega_world.z).abs() < 1e-12 * first.omega_world.z.abs());
    assert!((last.velocity - first.velocity).norm() < 1e-15);
}

/// The coin's (I_t, I_a).
fn disc_body_for_lz() -> (f64, f64) {
    (2.10e-7, 4.17e-7)
}

/// A coin dropped flat from 5 cm lands on its face at t = √(2h/g) (a touchdown and a flat
/// landing), which stops it dead without friction: the energy lost is m g h, and it lies
/// at z_G = r.
#[test]
fn a_coin_dropped_flat_lands_on_its_face() {
    let h = 0.05;
    let (out, samples) = run(&coin_scene(
        &format!("theta = 0.0\nheight = {h}"),
        "model = \"frictionless\"",
        1e-11,
        0.3,
    )
    .scene);
    assert_eq!(out.status, Status::Completed);
    let landed = flats(&out);
    assert_eq!(landed.len(), 1, "{:?}", out.events);
    assert!(
        (landed[0].0 - (2.0 * h / G).sqrt()).abs() < 1e-9,
        "{landed:?}"
    );
    assert!(
        (landed[0].1 - 5.67e-3 * G * h).abs() < 1e-9 * 5.67e-3 * G * h,
        "{landed:?}"
    );
    let last = samples.last().unwrap();
    assert!((last.position.z - 0.000875).abs() < 1e-15 && last.velocity.norm() == 0.0);
}

/// A coin started lying flat (θ = 0) is on its face from t = 0.
#[test]
fn a_coin_started_flat_lies_on_its_face() {
    let scene = coin_scene(
        "theta = 0.0\nphi_dot = 10.0\nvelocity = [0.1, 0.0]",
        "model = \"sliding\"\nfriction = 0.2\ncontact_radius = 1e-4",
        1e-10,
        1.0,
    )
    .scene;
    let (out, samples) = run(&scene);
    assert_eq!(out.status, Status::Completed, "{:?}", out.events);
    assert!(
        samples
            .iter()
            .all(|s| s.mode == ellipsoid_core::simulate::Mode::Face)
    );
    // The face's friction acts at its centre, on the vertical through G (the axis stands
    // vertical): the contact columns and the rim's own are that point and its speed |v_G|
    // (ω is vertical), however the rim's support point falls at zero tilt.
    let layout = ellipsoid_core::columns::Layout::of(&scene.body);
    for s in &samples {
        assert!((s.contact - s.position.xy()).norm() < 1e-15, "t = {}", s.t);
        assert!(
            (s.slip_speed - s.velocity.xy().norm()).abs() < 1e-15,
            "t = {}",
            s.t
        );
        let mut rim = Vec::new();
        layout.surface_values(s, &mut rim);
        let speed = s.velocity.xy().norm();
        let want = [s.normal_force, speed, 0.0, s.position.x, s.position.y];
        assert!(
            rim.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-15),
            "t = {}: {rim:?} vs {want:?}",
            s.t
        );
    }
    // Coulomb–Contensou: slip and spin stop together, within the run.
    let last = samples.last().unwrap();
    assert_eq!((last.velocity.norm(), last.omega.norm()), (0.0, 0.0));
}

/// The steady circular rolling of a thin uniform disc (docs/physics.md, "Rims": "Rolling
/// in a circle"): leaning with its axis θ from the vertical, its contact point on a circle
/// of radius ρ_c = x_G + R cos θ about the vertical through O, G at x_G from it, the disc
/// precesses at Ω² sin θ [I_t cos θ + x_G (I_a/R + m R)] = m g R cos θ and spins at
/// ψ̇ = −Ω (x_G/R + cos θ). The disc of Le Saux, Leine & Glocker (2005), m = 0.3048 kg,
/// R = 0.05 m, leaning 5° on a circle of 10 R, keeps θ to 1e-9 rad for five turns, its
/// contact point on the circle to 1e-9 R; 1 % off Ω, θ moves by more than 1e-4 rad.
#[test]
fn a_thin_disc_rolls_steadily_on_a_circle_at_the_derived_rates() {
    let (m, radius) = (0.3048, 0.05);
    let (i_t, i_a) = (m * radius * radius / 4.0, m * radius * radius / 2.0);
    let theta = 85f64.to_radians();
    let (s, c) = theta.sin_cos();
    let x_g = 10.0 * radius - radius * c;
    let omega = (m * G * radius * c / (s * (i_t * c + x_g * (i_a / radius + m * radius)))).sqrt();
    let psi_dot = -omega * (x_g / radius + c);
    let body = format!(
        "[body]\na = {radius}\nc = 0.002\nmass = {m}\ninertia = [{i_t}, {i_t}, {i_a}]\nellipsoid_contact = false\n\
         [[body.rim]]\nname = \"edge\"\ncenter = [0.0, 0.0, 0.0]\nradius = {radius}\nedge = 0.0\n"
    );
    let turns = 5.0 * std::f64::consts::TAU / omega;
    for (factor, steady) in [(1.0, true), (1.01, false)] {
        let initial = format!(
            "theta = {theta}\nphi = {}\nphi_dot = {}\npsi_dot = {}",
            std::f64::consts::FRAC_PI_2,
            factor * omega,
            factor * psi_dot
        );
        let sc = scene(&body, &initial, "rolling", turns);
        let (out, samples) = run(&sc.scene);
        assert_eq!(out.status, Status::Completed);
        let tilt = samples
            .iter()
            .map(|s| (s.angles.theta - theta).abs())
            .fold(0.0, f64::max);
        if steady {
            // O lies x_G from G against the axis's horizontal direction (−x at φ = π/2).
            let centre = samples[0].position.xy() - nalgebra::Vector2::new(x_g, 0.0);
            let off = (samples.iter())
                .map(|s| ((s.contact - centre).norm() - 10.0 * radius).abs())
                .fold(0.0, f64::max);
            assert!(
                tilt < 1e-9 && off < 1e-9 * radius,
                "Δθ {tilt:e}, contact off the circle by {off:e} m"
            );
        } else {
            assert!(tilt > 1e-4, "Ω off by 1 %: Δθ {tilt:e}");
        }
    }
}

/// A sharp cylinder (two rims, edge 0, at ±h) laid on its side touches with both rims:
/// two contacts from the start; with friction its slip stops and it rolls straight on both
/// edges (docs/hard-cases.md, row 35).
#[test]
fn a_sharp_cylinder_on_its_side_rolls_on_both_rims() {
    let body = "[body]\na = 0.02\nc = 0.03\nmass = 0.3\ninertia = [9.75e-5, 9.75e-5, 6.0e-5]\nellipsoid_contact = false\n\
                [[body.rim]]\nname = \"bottom\"\ncenter = [0.0, 0.0, -0.03]\nradius = 0.02\nedge = 0.0\n\
                [[body.rim]]\nname = \"top\"\ncenter = [0.0, 0.0, 0.03]\nradius = 0.02\nedge = 0.0\n";
    let text = format!(
        "{body}[initial]\ntheta_deg = 90.0\npsi_dot = 20.0\n[contact]\nmodel = \"coulomb\"\nfriction = 0.5\n\
         [solver]\nmethod = \"dop853\"\nrtol = 1e-11\natol = 1e-13\n[output]\nt_end = 2.0\ndt = 0.001\n"
    );
    let sc = ellipsoid_core::scenario::parse(&text, "cylinder.toml", &[] as &[&str]).unwrap();
    let (out, samples) = run(&sc.scene);
    assert_eq!(out.status, Status::Completed);
    let last = samples.last().unwrap();
    assert_eq!(last.mode, ellipsoid_core::simulate::Mode::TwoContacts);
    assert!(
        samples
            .iter()
            .skip(1)
            .all(|s| s.mode == ellipsoid_core::simulate::Mode::TwoContacts)
    );
    // Rolling straight along x (the axis along y at φ = 0), at R ψ̇'s speed after the grip.
    assert!(
        last.position.y.abs() < 1e-8,
        "lateral drift {} m",
        last.position.y
    );
    assert!(last.position.x.abs() > 0.1);
    let e0 = samples[0].energy + samples[0].work;
    assert!((last.energy + last.work - e0).abs() < 1e-12 * e0);
}

/// λ² of the straight upright rolling of a body of revolution at spin n (docs/physics.md,
/// "Rims": "Rolling upright"), derived independently with Kane's method
/// (scripts/derive-upright-rolling.py): on a parallel at distance ρ from G (G in its
/// plane) whose meridian has radius of curvature r,
/// A (A + m ρ²) λ² = A m g (ρ − r) − C (C + m ρ²) n²; the other two eigenvalues are
/// zero (the family's spin and its turn into circles).
fn upright_rolling_lambda2(m: f64, (a, c): (f64, f64), rho: f64, r: f64, n: f64) -> f64 {
    (a * m * G * (rho - r) - c * (c + m * rho * rho) * n * n) / (a * (a + m * rho * rho))
}

/// A rolling scenario of `body` (its TOML) started at `initial` (the `[initial]` table's
/// lines), for the steady analysis.
fn rolling_text(body: &str, initial: &str) -> String {
    format!(
        "{body}\n[initial]\n{initial}\n[contact]\nmodel = \"rolling\"\n[output]\nt_end = 1.0\ndt = 0.1\n"
    )
}

/// The steady analysis of a scenario text at its initial state.
fn steady_of(
    text: &str,
    family: ellipsoid_core::steady::Family,
    sets: &[String],
) -> Result<ellipsoid_core::steady::Analysis, ellipsoid_core::error::ModelError> {
    let scene = ellipsoid_core::scenario::parse(text, "disc.toml", sets)
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
        .scene;
    ellipsoid_core::steady::analyse(&scene, family)
}

/// Rims rolling straight on, upright (θ = π/2, φ̇ = 0, the rolling-circle family at its
/// infinite radius): the spectrum equals the closed form of Kane's method to 1e-9 at
/// spins from 0.5 to 2 times the critical one, for a sharp thin disc (n_c² = g/(3R)), a
/// rounded rim (ρ = R + r) and an ellipsoid on its equator (ρ = a, r = c²/a, the same
/// formula through a different support map); a sweep of the spin finds ±n_c to 1e-9.
#[test]
fn steady_upright_rolling_of_a_rim_has_the_closed_form_spectrum() {
    use ellipsoid_core::steady::{Family, sweep};
    let m = 0.3;
    let lens = "[body]\na = 0.03\nc = 0.004\nmass = 0.3\ninertia = \"uniform\"\n";
    let lens_inertia = (
        m * (0.03f64.powi(2) + 0.004f64.powi(2)) / 5.0,
        m * 0.0009 * 0.4,
    );
    let cases = [
        // name, body text, (A, C), ρ, r
        (
            "thin disc",
            disc_toml(0.05, 0.0, 0.0, 0.0, (m * 0.0025 / 4.0, m * 0.0025 / 2.0)),
            (m * 0.0025 / 4.0, m * 0.0025 / 2.0),
            0.05,
            0.0,
        ),
        (
            "rounded rim",
            disc_toml(0.03, 0.004, 0.0, 0.0, (8e-5, 1.5e-4)),
            (8e-5, 1.5e-4),
            0.034,
            0.004,
        ),
        (
            "ellipsoid",
            lens.to_string(),
            lens_inertia,
            0.03,
            0.004 * 0.004 / 0.03,
        ),
    ];
    for (name, body, inertia, rho, r) in cases {
        let critical =
            (inertia.0 * m * G * (rho - r) / (inertia.1 * (inertia.1 + m * rho * rho))).sqrt();
        if name == "thin disc" {
            assert!((critical / (G / 0.15).sqrt() - 1.0).abs() < 1e-14);
        }
        let text = rolling_text(
            &body,
            &format!(
                "theta = {}\nphi_dot = 0.0\npsi_dot = 1.0",
                std::f64::consts::FRAC_PI_2
            ),
        );
        for factor in [0.5, 0.9, 1.1, 2.0] {
            let n = factor * critical;
            let an = steady_of(
                &text,
                Family::RollingCircle,
                &[format!("initial.psi_dot={n}")],
            )
            .unwrap_or_else(|e| panic!("{name}: {e}"));
            let circles = an.motion.circles.unwrap();
            assert!(circles.center.is_infinite() && circles.contact.is_infinite());
            assert_eq!(an.motion.precession, Some(0.0));
            let lambda2 = upright_rolling_lambda2(m, inertia, rho, r, n);
            let scale = lambda2.abs().sqrt();
            let values = an.spectrum.eigenvalues();
            assert_eq!(values.len(), 2, "{name}: {values:?}");
            for l in &values {
                let (along, across) = if lambda2 > 0.0 {
                    (l.re.abs(), l.im.abs())
                } else {
                    (l.im.abs(), l.re.abs())
                };
                let err = (along - scale).abs().max(across) / scale;
                eprintln!("{name} at {factor} n_c: λ = {l} against λ² = {lambda2}: {err:.1e}");
                assert!(
                    err < 1e-9,
                    "{name} at {factor} n_c: {values:?} against λ² = {lambda2}"
                );
            }
            assert_eq!(an.spectrum.stable(), factor > 1.0, "{name} at {factor} n_c");
        }
        let base = ellipsoid_core::scenario::parse(&text, "disc.toml", &[] as &[&str]).unwrap();
        let values: Vec<f64> = (0..=8)
            .map(|i| critical * (-2.0 + 0.5 * i as f64))
            .collect();
        let sw = sweep(&base, Family::RollingCircle, "initial.psi_dot", &values).unwrap();
        assert_eq!(sw.critical.len(), 2, "{name}: {:?}", sw.critical);
        for (crit, expected) in sw.critical.iter().zip([-critical, critical]) {
            eprintln!("{name}: critical spin {} against {expected}", crit.value);
            assert!(
                (crit.value / expected - 1.0).abs() < 1e-9,
                "{name}: {crit:?}"
            );
        }
    }
}

/// The rolling-circle family of a rim holds Moffatt's disc spinning with its centre
/// fixed: at its tilt α and Ω of the general relation (`steady_rates`), the spin solved
/// for is the relation's n = Ω cos α + ψ̇ to 1e-9 (0 for the thin uniform disc) and G's
/// circle has radius below 1e-9 R, for a thin disc and a rounded rim off G's plane.
#[test]
fn steady_rolling_circle_of_a_rim_holds_the_disc_spinning_with_its_centre_fixed() {
    use ellipsoid_core::steady::Family;
    let thin = (0.05, 0.0, 0.0, (0.3 * 0.0025 / 4.0, 0.3 * 0.0025 / 2.0));
    let rounded = (0.0359, 0.0016, -0.0049, (1.7e-4, 3.1e-4));
    for (radius, edge, rim_z, inertia) in [thin, rounded] {
        for alpha in [0.2f64, 0.7, 1.3] {
            let (omega, psi_dot) = steady_rates(0.3, radius, edge, rim_z, inertia, alpha);
            let n = omega * alpha.cos() + psi_dot;
            let text = rolling_text(
                &disc_toml(radius, edge, rim_z, 0.0, inertia),
                &format!("theta = {alpha}\nphi_dot = {omega}"),
            );
            let an = steady_of(&text, Family::RollingCircle, &[]).unwrap();
            let m = &an.motion;
            eprintln!(
                "R {radius}, α {alpha}: n {} against {n}, G's circle {:e} m",
                m.spin,
                m.circles.unwrap().center
            );
            assert!((m.spin - n).abs() < 1e-9 * omega, "{m:?} against n = {n}");
            assert!(m.circles.unwrap().center < 1e-9 * radius, "{m:?}");
        }
    }
}

/// A rim with its axis vertical lies on its face: the upright and inverted families,
/// which start there, are refused naming the rim; at φ̇ = 0 off the edge (s ≠ 0) no
/// spin is steady, and the error says where the contact point is.
#[test]
fn steady_motions_a_rim_has_not_are_refused_by_name() {
    use ellipsoid_core::steady::Family;
    let body = disc_toml(
        0.05,
        0.0,
        0.0,
        0.0,
        (0.3 * 0.0025 / 4.0, 0.3 * 0.0025 / 2.0),
    );
    let text = rolling_text(&body, "theta = 0.0\npsi_dot = 10.0");
    for family in [Family::Upright, Family::Inverted] {
        let e = steady_of(&text, family, &[]).unwrap_err();
        assert_eq!(e.key(), "body.rim", "{e}");
        assert!(e.to_string().contains("flat on its face"), "{e}");
    }
    let e = steady_of(&text, Family::RollingCircle, &["initial.theta=1.2".into()]).unwrap_err();
    assert_eq!(e.key(), "initial.theta", "{e}");
    assert!(e.to_string().contains("straight below G"), "{e}");
}
