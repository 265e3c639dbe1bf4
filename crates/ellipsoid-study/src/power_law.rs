//! The power law of a run's approach to a finite time t0, |y| ≈ A (t0 − t)^p, fitted by
//! least squares of ln|y| on ln(t0 − t) over a window of t0 − t (docs/physics.md,
//! "Dissipation of a rolling disc": the tilt and the precession rate of Euler's disk).
//! Shared by `ellipsoid power-law` and Python's `Trajectory.power_law`.

use ellipsoid_core::simulate::{EventKind, EventRecord};
use serde::Serialize;

/// Where t0 comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum T0 {
    /// The run's first flat landing (`None`: the run has none).
    Landing(Option<f64>),
    /// A given time \[s\].
    Given(f64),
    /// The time in \[lo, hi\] that makes ln|y| most nearly linear in ln(t0 − t) (golden
    /// section on the least-squares misfit) \[s\].
    Fitted(f64, f64),
}

/// A fitted power law |y| ≈ A (t0 − t)^p (SI units: A in the column's unit per s^p).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PowerLaw {
    /// The column fitted.
    pub column: String,
    /// p.
    pub exponent: f64,
    /// A.
    pub prefactor: f64,
    /// t0 \[s\].
    pub t0: f64,
    /// "landing", "given" or "fitted".
    pub t0_from: &'static str,
    /// The window of t0 − t \[s\].
    pub window: [f64; 2],
    /// The samples in the window.
    pub samples: usize,
    /// The root-mean-square residual of ln|y|.
    pub rms: f64,
}

/// The time of a run's first flat landing (the event `flat`) \[s\], t0 of [`T0::Landing`].
pub fn landing(events: &[EventRecord]) -> Option<f64> {
    (events.iter())
        .find(|e| matches!(e.kind, EventKind::Flat { .. }))
        .map(|e| e.t)
}

/// At most this many golden-section steps for a fitted t0 (the bracket shrinks by
/// 0.618 per step: 1e-21 of its width after 100).
const GOLDEN_STEPS: usize = 100;

/// Fits `column`'s values `y` at times `t` (equal lengths) over t0 − t in `window`,
/// using the samples there with y finite and nonzero.
pub fn fit(
    column: &str,
    t: &[f64],
    y: &[f64],
    window: (f64, f64),
    t0: T0,
) -> Result<PowerLaw, String> {
    let (lo, hi) = window;
    if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi > lo) {
        return Err(format!(
            "window = [{lo}, {hi}]: the window of t0 - t must satisfy 0 < lo < hi, finite (s)"
        ));
    }
    let points = |t0: f64| -> Vec<(f64, f64)> {
        t.iter()
            .zip(y)
            .filter(|&(&ti, &yi)| (lo..=hi).contains(&(t0 - ti)) && yi.is_finite() && yi != 0.0)
            .map(|(&ti, &yi)| ((t0 - ti).ln(), yi.abs().ln()))
            .collect()
    };
    let (t0, from) = match t0 {
        T0::Landing(Some(t)) => (t, "landing"),
        T0::Landing(None) => {
            return Err(
                "t0: the run has no flat landing to take t0 from; give t0 (s) or a bracket [lo, hi] to fit it in"
                    .to_owned(),
            );
        }
        T0::Given(t) if t.is_finite() => (t, "given"),
        T0::Given(t) => return Err(format!("t0 = {t}: must be finite (s)")),
        T0::Fitted(a, b) if a.is_finite() && b.is_finite() && a < b => {
            let misfit = |t0: f64| line(&points(t0)).map_or(f64::INFINITY, |l| l.2);
            (golden(misfit, a, b), "fitted")
        }
        T0::Fitted(a, b) => {
            return Err(format!(
                "t0 = [{a}, {b}]: a bracket to fit t0 in needs lo < hi, finite (s)"
            ));
        }
    };
    let p = points(t0);
    let (exponent, intercept, misfit) = line(&p).ok_or_else(|| {
        format!(
            "{column}: {} samples with t0 - t in [{lo}, {hi}] s (t0 = {t0} s) and a nonzero value; the fit needs at least 3 (widen the window or sample more densely)",
            p.len()
        )
    })?;
    Ok(PowerLaw {
        column: column.to_owned(),
        exponent,
        prefactor: intercept.exp(),
        t0,
        t0_from: from,
        window: [lo, hi],
        samples: p.len(),
        rms: (misfit / p.len() as f64).sqrt(),
    })
}

/// The least-squares line y = p x + c through at least 3 points with distinct x:
/// (p, c, the sum of squared residuals).
fn line(points: &[(f64, f64)]) -> Option<(f64, f64, f64)> {
    if points.len() < 3 {
        return None;
    }
    let n = points.len() as f64;
    let (mx, my) = (points.iter()).fold((0.0, 0.0), |(a, b), &(x, y)| (a + x / n, b + y / n));
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let misfit = (points.iter())
        .map(|&(x, y)| (y - intercept - slope * x).powi(2))
        .sum();
    Some((slope, intercept, misfit))
}

/// The minimum of `f` on [a, b] by golden-section search.
fn golden(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..GOLDEN_STEPS {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if f(c) < f(d) {
            b = d;
        } else {
            a = c;
        }
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An exact power law is recovered to round-off, t0 given or fitted.
    #[test]
    fn an_exact_power_law_is_recovered() {
        let (a, p, t0) = (0.02, 1.0 / 3.0, 5.0);
        let t: Vec<f64> = (0..4000).map(|i| i as f64 * 1e-3).collect();
        let y: Vec<f64> = t.iter().map(|&t| a * (t0 - t).powf(p)).collect();
        let given = fit("theta", &t, &y, (0.03, 3.0), T0::Given(t0)).unwrap();
        assert!((given.exponent - p).abs() < 1e-12 && (given.prefactor - a).abs() < 1e-12);
        assert_eq!(given.t0_from, "given");
        let fitted = fit("theta", &t, &y, (0.03, 3.0), T0::Fitted(4.5, 5.5)).unwrap();
        assert!((fitted.t0 - t0).abs() < 1e-6, "{}", fitted.t0);
        assert!((fitted.exponent - p).abs() < 1e-5);
        // Negative values are fitted by their size (a precession rate may be negative).
        let neg: Vec<f64> = y.iter().map(|v| -v).collect();
        let n = fit("phi_dot", &t, &neg, (0.03, 3.0), T0::Landing(Some(t0))).unwrap();
        assert!((n.exponent - p).abs() < 1e-12 && n.t0_from == "landing");
    }

    #[test]
    fn bad_requests_name_the_rule() {
        let t = [0.0, 1.0, 2.0];
        let y = [1.0, 1.0, 1.0];
        let err = |w, t0| fit("theta", &t, &y, w, t0).unwrap_err();
        assert!(err((0.0, 1.0), T0::Given(3.0)).contains("0 < lo < hi"));
        assert!(err((1.0, 0.5), T0::Given(3.0)).contains("0 < lo < hi"));
        assert!(err((0.5, 1.0), T0::Landing(None)).contains("no flat landing"));
        assert!(err((0.5, 1.0), T0::Given(f64::NAN)).contains("finite"));
        assert!(err((0.5, 1.0), T0::Fitted(2.0, 1.0)).contains("lo < hi"));
        assert!(err((0.5, 1.5), T0::Given(3.0)).contains("at least 3"));
    }
}
