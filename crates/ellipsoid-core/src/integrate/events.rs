//! Zero crossings of event functions: the sign test at step ends and Brent's method on
//! the dense output.

use super::Direction;

/// Whether g went from `g_prev` to `g_new` across zero in the wanted direction. A zero at
/// the start of the step (`g_prev == 0`, e.g. at t0 right after a mode switch) carries no
/// sign and never counts; landing exactly on zero at the end does.
#[inline]
pub(crate) fn crossed(direction: Direction, g_prev: f64, g_new: f64) -> bool {
    let rising = g_prev < 0.0 && g_new >= 0.0;
    let falling = g_prev > 0.0 && g_new <= 0.0;
    match direction {
        Direction::Rising => rising,
        Direction::Falling => falling,
        Direction::Either => rising || falling,
    }
}

/// Interior points of a step at which the event functions are evaluated on the dense
/// output when [`may_cross_inside`] says a crossing could hide between the step ends.
pub(crate) const SCAN_POINTS: usize = 8;

/// Whether g might cross zero inside a step although its values at the ends, g(t) =
/// `g_prev` and g(t_new) = `g_new`, do not show it (a dip shorter than the step), judged
/// from those values and g(t_before) = `g_before` at the start of the previous step
/// (`t_before` NaN on the first step). With σ = sign g(t) (the side a crossing in
/// `direction` starts from; no crossing can start from g(t) = 0), a = σ g(t), b = σ g(t_new),
/// it answers yes when
/// ```text
///   min(a, b) ≤ |b − a| + 2 dip
/// ```
/// where dip is how far the parabola through the three values falls below min(a, b)
/// inside the step: g is within one step's change of zero, or curving towards it by at
/// least half the way. A g that changes monotonically between positive ends cannot hide
/// a crossing, and far from zero (the usual case) the step costs nothing more; near zero
/// the step is scanned at [`SCAN_POINTS`] points. With a bound A of |g''| (`curvature`,
/// [`Event::curvature`](super::Event)) the answer is exact instead: yes when
/// min(a, b) ≤ A h²/8 ([`chord_gap`]), h = t_new − t.
#[inline]
pub(crate) fn may_cross_inside(
    direction: Direction,
    [t_before, t, t_new]: [f64; 3],
    [g_before, g_prev, g_new]: [f64; 3],
    curvature: Option<f64>,
) -> bool {
    let sigma = match direction {
        Direction::Falling if g_prev > 0.0 => 1.0,
        Direction::Rising if g_prev < 0.0 => -1.0,
        Direction::Either if g_prev != 0.0 => g_prev.signum(),
        _ => return false,
    };
    let (a, b) = (sigma * g_prev, sigma * g_new);
    let low = a.min(b);
    if low <= 0.0 {
        return true;
    }
    if let Some(bound) = curvature {
        return low <= chord_gap(bound, t_new - t);
    }
    let mut dip = 0.0;
    if t_before < t {
        let c = sigma * g_before;
        let (h_prev, h) = (t - t_before, t_new - t);
        // Newton form q(s) = c + d1 (s − t_b) + q2 (s − t_b)(s − t); vertex where q' = 0.
        let d1 = (a - c) / h_prev;
        let q2 = ((b - a) / h - d1) / (t_new - t_before);
        if q2 > 0.0 {
            let s = 0.5 * (t_before + t) - d1 / (2.0 * q2);
            if s > t && s < t_new {
                let q_min = c + d1 * (s - t_before) + q2 * (s - t_before) * (s - t);
                dip = (low - q_min).max(0.0);
            }
        }
    }
    low <= (b - a).abs() + 2.0 * dip
}

/// How far below the chord through its ends a function with |g''| ≤ `curvature` can fall
/// on an interval of length `h`: A h²/8 (the error bound of linear interpolation).
#[inline]
pub(crate) fn chord_gap(curvature: f64, h: f64) -> f64 {
    curvature * h * h / 8.0
}

/// Golden-section search (Kiefer 1953) for the minimum of f on [a, b], stopping as soon
/// as f ≤ 0 (a crossing is all the caller needs) or after 60 reductions of the interval
/// (0.618⁶⁰ ≈ 3e-13 of its length). Returns the lowest point seen and f there.
pub(crate) fn lowest(mut f: impl FnMut(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    const R: f64 = 0.618_033_988_749_894_9; // (√5 − 1)/2
    let (mut a, mut b) = (a, b);
    let mut x1 = b - R * (b - a);
    let mut x2 = a + R * (b - a);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..60 {
        if f1 <= 0.0 {
            return (x1, f1);
        }
        if f2 <= 0.0 {
            return (x2, f2);
        }
        if f1 < f2 {
            (b, x2, f2) = (x2, x1, f1);
            x1 = b - R * (b - a);
            f1 = f(x1);
        } else {
            (a, x1, f1) = (x1, x2, f2);
            x2 = a + R * (b - a);
            f2 = f(x2);
        }
    }
    if f1 < f2 { (x1, f1) } else { (x2, f2) }
}

/// Absolute time tolerance for locating a root in a step ending at `t` of length `h`.
#[inline]
pub(crate) fn time_tolerance(t: f64, h: f64) -> f64 {
    4.0 * f64::EPSILON * t.abs().max(h.abs())
}

/// Brent's root finder (R. P. Brent, *Algorithms for Minimization without Derivatives*,
/// 1973, ch. 4, procedure `zero`) on [a, b] with f(a) = fa, f(b) = fb of opposite signs
/// (fb may be 0). Returns the end of the final bracket (width ≤ ~2·tol) on the side of
/// `b`, i.e. a time at which g already has its post-crossing sign (or is zero).
pub(crate) fn locate(
    mut f: impl FnMut(f64) -> f64,
    a: f64,
    fa: f64,
    b: f64,
    fb: f64,
    tol: f64,
) -> f64 {
    if fb == 0.0 {
        return b;
    }
    let after = fb.signum();
    let (mut a, mut fa, mut b, mut fb) = (a, fa, b, fb);
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    // Bisection alone needs log2(h/tol) ≈ 60 iterations; Brent at most a few times that.
    for _ in 0..200 {
        if fb * (fc / fc.abs()) > 0.0 {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol1 = 2.0 * f64::EPSILON * b.abs() + 0.5 * tol;
        let xm = 0.5 * (c - b);
        if xm.abs() <= tol1 || fb == 0.0 {
            break;
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            // inverse quadratic interpolation, or secant when only two points are known
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * xm * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * xm * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            }
            p = p.abs();
            if 2.0 * p < (3.0 * xm * q - (tol1 * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol1 { d } else { tol1.copysign(xm) };
        fb = f(b);
    }
    if fb == 0.0 || fb.signum() == after {
        b
    } else {
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_finds_simple_roots_on_the_far_side() {
        let f = |t: f64| t * t - 2.0;
        let tol = time_tolerance(2.0, 1.0);
        let r = locate(f, 1.0, f(1.0), 2.0, f(2.0), tol);
        assert!((r - 2f64.sqrt()).abs() < 4.0 * tol, "{r}");
        assert!(f(r) >= 0.0, "returned point must be past the crossing");
        let g = |t: f64| 1.0 - t * t;
        let r = locate(g, 0.5, g(0.5), 3.0, g(3.0), tol);
        assert!((r - 1.0).abs() < 4.0 * tol && g(r) <= 0.0, "{r}");
    }

    #[test]
    fn crossing_rules() {
        assert!(crossed(Direction::Rising, -1.0, 1.0));
        assert!(!crossed(Direction::Falling, -1.0, 1.0));
        assert!(crossed(Direction::Either, 1.0, 0.0));
        assert!(
            !crossed(Direction::Either, 0.0, 1.0),
            "zero at the start is not an event"
        );
    }
}
