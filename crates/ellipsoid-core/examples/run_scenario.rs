//! Runs one scenario's simulation (no output files): for instruction counts under
//! callgrind, e.g. `valgrind --tool=callgrind target/release/examples/run_scenario scenarios/egg.toml`.
use std::ops::ControlFlow;
fn main() {
    let path = std::env::args().nth(1).expect("a scenario path");
    let s = ellipsoid_core::scenario::load(std::path::Path::new(&path), &[] as &[&str]).unwrap();
    let mut rows = 0u64;
    let out = ellipsoid_core::simulate::simulate(&s.scene, &mut |_| {
        rows += 1;
        ControlFlow::Continue(())
    })
    .unwrap();
    println!("{rows} rows, {} rhs evaluations", out.stats.rhs_evals);
}
