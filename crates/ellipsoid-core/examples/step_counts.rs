//! Prints, as CSV, the work of DOPRI5 and DOP853 on the reference problems at several
//! tolerances: accepted and rejected steps, right-hand-side calls and the error at the
//! end where the exact solution is known. `benches/scipy_compare.py` runs this and puts
//! SciPy's counts beside it.
//!
//! `cargo run --release -p ellipsoid-core --example step_counts`

use std::f64::consts::TAU;
use std::ops::ControlFlow;

use ellipsoid_core::integrate::problems::{Arenstorf, ExpSinSquared, Kepler, VanDerPol};
use ellipsoid_core::integrate::{Method, OdeSystem, Options, integrate};
use nalgebra::{SVector, Vector2};

/// One line of output; `exact` is the known final state, if any.
fn report<S: OdeSystem<N>, const N: usize>(
    problem: &str,
    system: &S,
    y0: SVector<f64, N>,
    t_end: f64,
    exact: Option<SVector<f64, N>>,
) {
    for method in [Method::Dopri5, Method::Dop853] {
        for tol in [1e-4, 1e-6, 1e-8, 1e-10] {
            let options = Options::new(tol, tol);
            let sol = integrate(
                method,
                system,
                0.0,
                y0,
                t_end,
                &options,
                &[],
                &[],
                &mut |_, _| ControlFlow::Continue(()),
            )
            .expect("valid input");
            let err = exact.map_or(f64::NAN, |e| (sol.y - e).amax());
            println!(
                "{problem},{},{tol:e},{tol:e},{},{},{},{err:.3e}",
                method.name(),
                sol.stats.accepted,
                sol.stats.rejected,
                sol.stats.rhs_evals
            );
        }
    }
}

fn main() {
    println!("problem,method,rtol,atol,accepted,rejected,rhs_evals,error");
    report(
        "arenstorf",
        &Arenstorf,
        Arenstorf::y0(),
        Arenstorf::PERIOD,
        Some(Arenstorf::y0()),
    );
    let kepler = Kepler { e: 0.5 };
    report(
        "kepler_e0.5",
        &kepler,
        kepler.y0(),
        2.0 * TAU,
        Some(kepler.exact(2.0 * TAU)),
    );
    report(
        "expsin",
        &ExpSinSquared,
        ExpSinSquared::exact(0.0),
        2.0,
        Some(ExpSinSquared::exact(2.0)),
    );
    report(
        "vanderpol_mu5",
        &VanDerPol::standard(5.0),
        Vector2::new(2.0, 0.0),
        20.0,
        None,
    );
}
