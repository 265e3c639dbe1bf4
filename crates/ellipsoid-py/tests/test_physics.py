"""val_* (against an independent reference) and inv_* (conserved quantities), run from Python."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import ellipsoid
from conftest import A, BUNDLED, C, D2, I1, I3, M, oblate, scenario_id

G = 9.81


@pytest.mark.parametrize("path", BUNDLED, ids=scenario_id)
def test_inv_bundled_scenario_meets_its_check_table(path: Path) -> None:
    """Each bundled scenario's [check] table (expected status, largest relative drifts)."""
    traj = ellipsoid.simulate(path)
    checks = traj.summary["checks"]
    assert checks, f"{path.name} has no [check] table"
    failed = {k: v for k, v in checks.items() if not v["passed"]}
    assert not failed, failed
    # Recomputed from the columns (energy and dissipated work), independently of the
    # summary's bookkeeping: max |(E + W) - (E0 + W0)| / |E0 + W0| over the samples, which
    # include the final state, must be the summary's figure (not merely below it: a
    # summary that reported 0, or measured over other samples, fails) ...
    drift = traj.summary["drift"]
    assert traj.t[-1] == traj.summary["final"]["t"], "the last sample is the final state"
    e_w = traj.energy + traj.work
    recomputed = np.max(np.abs(e_w - e_w[0])) / abs(e_w[0])
    assert recomputed == pytest.approx(drift["energy_plus_work"], rel=1e-9, abs=1e-17)
    # ... and must meet a physical bound: the scenario's tolerance, else 1e-9 (every
    # bundled scene runs at rtol <= 1e-10; E + W is conserved by every model).
    bound = checks.get("energy_plus_work", {}).get("expected", 1e-9)
    assert recomputed <= bound, (recomputed, bound)
    if drift["energy"] is not None:
        # A conservative scene: E alone is conserved, W stays 0.
        e = traj.energy
        assert np.max(np.abs(e - e[0])) / abs(e[0]) == pytest.approx(drift["energy"], rel=1e-9, abs=1e-17)
        assert np.all(traj.work == 0.0)
    else:
        # A dissipative one: the work done against friction and drag never decreases
        # and has taken energy out by the end.
        assert np.all(np.diff(traj.work) >= 0.0)
        assert traj.work[-1] > 0.0 and traj.energy[-1] < traj.energy[0]


def test_inv_frictionless_run_conserves_energy_momentum_and_axial_spin() -> None:
    traj = ellipsoid.simulate(oblate(output=dict(t_end=2.0, dt=1e-3)))
    assert traj.completed and set(traj.mode) == {"frictionless"}
    assert np.ptp(traj.energy) / abs(traj.energy[0]) < 1e-9
    # No horizontal force: v_G stays 0 (the body starts with no horizontal velocity).
    assert np.max(np.abs(traj.vx)) < 1e-12 and np.max(np.abs(traj.vy)) < 1e-12
    # ω3 = ψ̇ + φ̇ cos θ is constant for a body of revolution on a frictionless plane.
    assert np.ptp(traj.omega_z) / abs(traj.omega_z[0]) < 1e-9
    drift = traj.summary["drift"]
    assert drift["energy"] < 1e-9 and drift["angular_momentum_z"] < 1e-9 and drift["axial_spin"] < 1e-9


def nutation_period(theta0: float, psi_dot0: float) -> float:
    """The nutation period of the oblate body on a frictionless plane, by quadrature.

    Reduced to one degree of freedom (L_z = I3 n cos θ0 and n = ω3 are conserved; the body
    starts at rest but for the spin, so θ̇0 = φ̇0 = 0 and θ0 is a turning point):
        ½(I + m h'(θ)²) θ̇² + (L_z − I3 n cos θ)² / (2 I sin²θ) + m g h(θ) = E,
        h(θ) = √(a² sin²θ + c² cos²θ) − D2 cos θ.
    T = 2 ∫ dθ/θ̇ between the turning points, with θ = mid + half·sin χ, which removes the
    inverse-square-root singularities at the ends.

    E − U(θ) is written as −sin((θ − θ0)/2)·K(θ) with K free of cancellation (differences
    of cosines and of square roots as products), so that the integrand keeps full
    precision next to the turning points, where both θ̇ and cos χ vanish.
    """
    scipy_integrate = pytest.importorskip("scipy.integrate")
    optimize = pytest.importorskip("scipy.optimize")
    n = psi_dot0
    p0 = np.sqrt(A**2 * np.sin(theta0) ** 2 + C**2 * np.cos(theta0) ** 2)

    def k(th: float) -> float:
        d2 = (th - theta0) / 2
        s = np.sin((th + theta0) / 2)  # cos θ0 − cos θ = 2 s sin(d/2)
        p = np.sqrt(A**2 * np.sin(th) ** 2 + C**2 * np.cos(th) ** 2)
        # (L_z − I3 n cos θ)² / (2 I sin²θ) = (I3 n)² 4 s² sin²(d/2) / (2 I sin²θ)
        spin = (I3 * n) ** 2 * 4 * s**2 * np.sin(d2) / (2 * I1 * np.sin(th) ** 2)
        # h(θ) − h(θ0) = (a² − c²) sin(θ − θ0) sin(θ + θ0) / (p + p0) + 2 D2 s sin(d/2)
        height = (A**2 - C**2) * 2 * np.cos(d2) * np.sin(th + theta0) / (p + p0) + 2 * D2 * s
        return spin + M * G * height

    def dh(th: float) -> float:
        p = np.sqrt(A**2 * np.sin(th) ** 2 + C**2 * np.cos(th) ** 2)
        return (A**2 - C**2) * np.sin(th) * np.cos(th) / p + D2 * np.sin(th)

    # E − U > 0 where sin(d/2) and K have opposite signs: K(θ0) says which way θ moves.
    side = -np.sign(k(theta0))
    th = theta0
    while np.sign(k(th + side * 1e-3)) == np.sign(k(theta0)):
        th += side * 1e-3
    other = optimize.brentq(k, th, th + side * 1e-3, xtol=1e-16, rtol=4 * np.finfo(float).eps)
    lo, hi = sorted((theta0, other))
    mid, half = (lo + hi) / 2, (hi - lo) / 2

    def integrand(chi: float) -> float:
        th = mid + half * np.sin(chi)
        # θ − θ0 without cancellation: half (1 ± sin χ) = 2 half sin²((π/2 ± χ)/2).
        d = 2 * half * np.sin((np.pi / 2 + chi) / 2) ** 2 if theta0 == lo else -2 * half * np.sin((np.pi / 2 - chi) / 2) ** 2
        kinetic = -np.sin(d / 2) * k(th)
        mass = I1 + M * dh(th) ** 2
        return half * np.cos(chi) / np.sqrt(2 * kinetic / mass)

    value, _ = scipy_integrate.quad(integrand, -np.pi / 2, np.pi / 2, epsabs=0, epsrel=1e-13, limit=200)
    # Cross-check with a Gauss–Legendre rule (the integrand is smooth). They agree to
    # ~1e-12: K still loses digits next to the far turning point, where its two terms
    # cancel, and more nodes there only sample that round-off; 1e-10 is ample for a
    # reference used at 1e-6.
    nodes, weights = np.polynomial.legendre.leggauss(100)
    gl = sum(w * integrand(x * np.pi / 2) for x, w in zip(nodes, weights)) * np.pi / 2
    assert abs(gl - value) < 1e-10 * value, (gl, value)
    return 2 * value


def measured_period(traj: ellipsoid.Trajectory) -> float:
    """Mean spacing of θ's maxima, each located by a parabola through the three samples
    around it (error O(dt³) relative to the curvature, far below 1e-6 here)."""
    th, t = traj.theta, traj.t
    k = np.where((th[1:-1] > th[:-2]) & (th[1:-1] >= th[2:]))[0] + 1
    peaks = []
    for i in k:
        y0, y1, y2 = th[i - 1], th[i], th[i + 1]
        dt = t[i + 1] - t[i]
        denom = y0 - 2 * y1 + y2
        peaks.append(t[i] + 0.5 * dt * (y0 - y2) / denom)
    peaks_arr = np.array(peaks)
    assert len(peaks_arr) >= 3
    return float((peaks_arr[-1] - peaks_arr[0]) / (len(peaks_arr) - 1))


def test_val_frictionless_nutation_period_matches_quadrature() -> None:
    theta0, psi_dot0 = 0.1745, 60.0
    expected = nutation_period(theta0, psi_dot0)
    # Sample finely enough for the parabolic peak fit; run over several periods.
    traj = ellipsoid.simulate(oblate(output=dict(t_end=min(40 * expected, 10.0), dt=expected / 400)))
    got = measured_period(traj)
    # The issue asks for 1e-6; the run and the reference agree to ~1e-13.
    assert abs(got - expected) / expected < 1e-9, (got, expected)


def test_observe_reports_the_tippe_top_passing_the_horizontal() -> None:
    """`simulate(..., observe=[...])`: the crossing of θ = π/2 is an event with its name
    and full state, θ there is π/2, and a terminal observable ends the run there."""
    import math

    scenarios = Path(__file__).resolve().parents[3] / "scenarios"
    obs = {"name": "horizontal", "column": "theta", "crosses": math.pi / 2, "direction": "up"}
    traj = ellipsoid.simulate(scenarios / "tippe-top.toml", observe=[obs])
    events = [e for e in traj.events if e["kind"] == "observed"]
    assert len(events) == 1 and events[0]["name"] == "horizontal"
    t = events[0]["t"]
    assert abs(t - 0.750628) < 1e-6
    assert abs(events[0]["state"]["theta"] - math.pi / 2) < 1e-9
    stopped = ellipsoid.simulate(scenarios / "tippe-top.toml", observe=[dict(obs, terminal=True)])
    assert stopped.status == "observed" and stopped.t[-1] == t
    # omega_world_z is the vertical spin φ̇ + ψ̇ cos θ (Euler's kinematics)
    vertical = traj.phi_dot + traj.psi_dot * np.cos(traj.theta)
    ok = np.sin(traj.theta) > 1e-6
    assert np.max(np.abs(traj.omega_world_z - vertical)[ok]) < 1e-9 * np.max(np.abs(traj.omega_z))
    with pytest.raises(ellipsoid.ScenarioError, match="theta"):
        ellipsoid.simulate(scenarios / "tippe-top.toml", observe=[dict(obs, column="thetta")])


def test_the_slip_columns_say_which_contact_sticks() -> None:
    """Issue 47: the point-contact tippe top with its stem (scenarios/tippe-top-jump-stem.toml)
    ends on ball and stem. Which contact sticks is in its per-surface slip columns,
    computed from the state (the material point's horizontal speed), and it agrees with
    an independent path, the machine's `grip` events: between two grip events a surface
    that gripped has slip_speed_S below 1e-12 m/s at every sample, one that let go more
    than 1e-4 m/s a little after (docs/physics.md, "With point contacts the stemmed top
    ends on ball and stem")."""
    traj = ellipsoid.simulate(Path(__file__).parents[3] / "scenarios" / "tippe-top-jump-stem.toml")
    grips = [e for e in traj.summary["events"] if e["kind"] == "grip"]
    assert [(e["surface"], e["sticks"]) for e in grips][-3:] == [("stem", True), ("stem", False), ("ellipsoid", True)]
    assert traj.mode[-1] == "two_contacts@ellipsoid+stem"
    ends = [e["t"] for e in grips[1:]] + [traj.t[-1] + 1.0]
    for e, end in zip(grips[-3:], ends[-3:]):
        slip = traj[f"slip_speed_{e['surface']}"]
        during = (traj.t > e["t"] + 1e-6) & (traj.t < end)
        assert during.sum() > 10, e
        if e["sticks"]:
            assert np.all(slip[during] < 1e-12), (e, slip[during].max())
        else:
            later = during & (traj.t > e["t"] + 0.01)
            assert np.all(slip[later] > 1e-4), (e, slip[later].min())
    # At the end the ball sticks and the stem slides.
    assert traj["slip_speed_ellipsoid"][-1] < 1e-12 < 0.1 < traj["slip_speed_stem"][-1]
