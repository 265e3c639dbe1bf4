#[path = "../../../tests/common/campaign.rs"]
mod campaign;
use campaign::Rng;
use ellipsoid_core::body::{Body, Sphere};
use ellipsoid_core::simulate::{ContactModel, Scene};
use nalgebra::{Matrix3, Vector3};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let seed: u64 = args[1].parse().unwrap();
    let count: usize = args[2].parse().unwrap();
    let show: Option<usize> = args.get(3).map(|s| s.parse().unwrap());
    let mut rng = Rng::new(seed);
    let mut bad = 0;
    let mut stats = std::collections::BTreeMap::new();
    for k in 0..count {
        let base = loop {
            if let Some(s) = campaign::scene(&mut rng, ellipsoid_core::integrate::Method::Dop853) {
                break s;
            }
        };
        let mut s: Scene = base.clone();
        s.contact = ContactModel::Frictionless;
        s.disc = None;
        let (a, c) = (0.0071, 0.0186);
        let m = rng.uniform(0.005, 0.1);
        let axes = Vector3::new(a, a, c);
        let u = ellipsoid_core::body::uniform_inertia(axes, m);
        let kk = rng.uniform(0.7, 1.3);
        let inertia = Matrix3::from_diagonal(&Vector3::new(
            u[(0, 0)] * kk,
            u[(0, 0)] * kk,
            u[(2, 2)] * rng.uniform(0.7, 1.3),
        ));
        let com = Vector3::new(0.0, 0.0, if rng.chance(0.5) { 0.0087 } else { -0.0087 });
        let n = 1 + rng.below(8);
        let spheres: Vec<Sphere> = (0..n)
            .map(|i| Sphere {
                name: format!("s{i}"),
                center: rng.vector(1.0).normalize() * rng.uniform(0.04, 0.048),
                radius: rng.uniform(0.00015, 0.0011),
            })
            .collect();
        let Ok(body) = Body::new(axes, m, inertia, com).and_then(|b| b.with_spheres(spheres))
        else {
            continue;
        };
        s.body = body;
        s.initial.angles.theta = 0.758;
        s.initial.omega_body = None;
        s.initial.angles.psi_dot = 210.0;
        s.initial.angles.phi_dot = rng.uniform(-5.0, 5.0);
        s.initial.angles.theta_dot = 0.0;
        s.initial.height = 0.0;
        s.initial.velocity = None;
        s.initial.velocity_z = None;
        s.effects = Default::default();
        s.gravity = 9.81;
        s.landing.restitution = rng.uniform(0.0, 1.0);
        if show.is_some() && show != Some(k) {
            continue;
        }
        let Ok(_) =
            ellipsoid_core::simulate::simulate(&s, &mut |_| std::ops::ControlFlow::Break(()))
        else {
            continue;
        };
        let r = campaign::run(&s);
        let layout = ellipsoid_core::columns::Layout::of(&s.body);
        let names = layout.numeric_columns();
        let gaps: Vec<usize> = (0..names.len())
            .filter(|&k| names[k].0.starts_with("gap_"))
            .collect();
        let mut worst = (0.0f64, 0.0, String::new());
        let mut row = Vec::new();
        for smp in &r.samples {
            row.clear();
            row.extend(ellipsoid_core::columns::values(smp));
            layout.surface_values(smp, &mut row);
            for &g in &gaps {
                if row[g] < worst.0 {
                    worst = (row[g], smp.t, names[g].0.to_string());
                }
            }
            if show.is_some() {
                let gs: Vec<String> = gaps.iter().map(|&g| format!("{:.2e}", row[g])).collect();
                println!(
                    "t={:.3} mode={:?} z={:.4e} {:?}",
                    smp.t, smp.mode, smp.position.z, gs
                );
            }
        }
        *stats
            .entry(
                format!("{:?}", r.outcome.status)
                    .split([' ', '{', '('])
                    .next()
                    .unwrap()
                    .to_string(),
            )
            .or_insert(0) += 1;
        if let Err(e) = campaign::check(&s, &r) {
            println!("scene {k}: check {e}");
        }
        if worst.0 < -1e-12 {
            bad += 1;
            println!(
                "scene {k}: status {:?}, worst gap {:.3e} at t={} ({}), m={m:.3} e={:.2} n={n} events={}",
                r.outcome.status,
                worst.0,
                worst.1,
                worst.2,
                s.landing.restitution,
                r.outcome.events.len()
            );
        }
        if show.is_some() {
            for e in &r.outcome.events {
                println!("{:.9} {:?}", e.t, e.kind);
            }
        }
    }
    println!("{stats:?}");
    println!("{bad} of {count} below the plane");
}
