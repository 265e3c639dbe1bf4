//! The hybrid machine's random-scene campaign at any size (tests/common/campaign.rs; the
//! test `tests/campaign.rs` runs 200 scenes at seed 24):
//!
//! ```text
//! cargo run --release -p ellipsoid-core --example campaign -- --seed 24 --count 2000 [--show N] [--spheres]
//! ```
//! prints, per method, how many runs ended with each status and how many broke a check,
//! the scenes whose DOP853 run took an impact at three contacts at once, and those whose
//! DOP853 run stopped `several_contacts` (contact model, time, status), then each failing
//! scene; `--show N` prints scene N's two runs in detail; `--spheres`
//! gives each body one or two random contact spheres (`campaign::with_spheres`); `--stems`
//! draws frictionless bodies with small far-out spheres instead
//! (`campaign::frictionless_with_stems`, docs/hard-cases.md row 33).

#[path = "../../../tests/common/campaign.rs"]
mod campaign;

use std::collections::BTreeMap;

use campaign::{Rng, distance, run, with};
use ellipsoid_core::integrate::Method;
use ellipsoid_core::simulate::Status;

fn main() {
    let mut seed = 24u64;
    let mut count = 200usize;
    let mut show = None;
    let mut spheres = false;
    let mut stems = false;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < args.len() {
        let value = |i: usize| {
            args.get(i + 1)
                .and_then(|v| v.parse::<u64>().ok())
                .unwrap_or_else(|| {
                    eprintln!("{} takes a whole number", args[i]);
                    std::process::exit(2)
                })
        };
        if args[i] == "--spheres" || args[i] == "--stems" {
            spheres |= args[i] == "--spheres";
            stems |= args[i] == "--stems";
            i += 1;
            continue;
        }
        match args[i].as_str() {
            "--seed" => seed = value(i),
            "--count" => count = value(i).min(1_000_000) as usize,
            "--show" => show = Some(value(i) as usize),
            other => {
                eprintln!(
                    "unknown argument {other}: --seed N, --count N, --show N, --spheres, --stems"
                );
                std::process::exit(2)
            }
        }
        i += 2;
    }
    let mut rng = Rng::new(seed);
    let mut scenes = Vec::new();
    while scenes.len() < count {
        let scene = if stems {
            campaign::frictionless_with_stems(&mut rng)
        } else {
            campaign::scene(&mut rng, Method::Dop853)
        };
        let scene = if spheres {
            scene.and_then(|s| campaign::with_spheres(&s, &mut rng))
        } else {
            scene
        };
        if let Some(s) = scene {
            scenes.push(s);
        }
    }
    let mut table: BTreeMap<(&str, &str), usize> = BTreeMap::new();
    let mut failures = Vec::new();
    let mut three = Vec::new();
    let mut several = Vec::new();
    for (i, scene) in scenes.iter().enumerate() {
        if show.is_some_and(|s| s != i) {
            continue;
        }
        let r853 = run(scene);
        if campaign::impact_at_three(&r853.outcome.events) {
            three.push(i);
        }
        if let Status::SeveralContacts { .. } = r853.outcome.status {
            several.push(format!(
                "scene {i} ({:?}) at t = {}: {:?}",
                scene.contact, r853.outcome.final_sample.t, r853.outcome.status
            ));
        }
        let r5 = run(&with(scene, Method::Dopri5, campaign::RTOL));
        for (name, r) in [("dop853", &r853), ("dopri5", &r5)] {
            *table.entry((name, r.outcome.status.name())).or_default() += 1;
            if let Err(e) = campaign::check(scene, r) {
                failures.push(format!("scene {i} {name}: {e}"));
            }
        }
        let d = distance(scene, &r853.outcome.final_sample, &r5.outcome.final_sample);
        let verdict = match campaign::agree(scene, &r853, &r5, || {
            run(&with(scene, Method::Dop853, 1e-12))
        }) {
            Ok(()) if d <= 1e-6 => "agree",
            Ok(()) => "agree (sensitive)",
            Err(e) => {
                failures.push(format!("scene {i}: {e}"));
                "disagree"
            }
        };
        *table.entry(("methods", verdict)).or_default() += 1;
        if show == Some(i) {
            println!("{scene:#?}");
            for (name, r) in [("dop853", &r853), ("dopri5", &r5)] {
                let o = &r.outcome;
                println!(
                    "{name}: {:?} at t = {}, {} steps, {} events",
                    o.status,
                    o.final_sample.t,
                    o.stats.accepted + o.stats.rejected,
                    o.events.len()
                );
                for e in o.events.iter().rev().take(8).rev() {
                    println!("  {:.12} {:?}", e.t, e.kind);
                }
            }
        }
    }
    println!("seed {seed}, {count} scenes, rtol {:e}", campaign::RTOL);
    for ((method, status), n) in &table {
        println!("{method:8} {status:22} {n}");
    }
    println!("impact at three contacts (dop853): scenes {three:?}");
    for s in &several {
        println!("several_contacts (dop853): {s}");
    }
    println!("{} failures", failures.len());
    for f in &failures {
        println!("{f}");
    }
}
