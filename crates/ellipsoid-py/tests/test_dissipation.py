"""The power law of Euler's disk's approach to t0 (`Trajectory.power_law`; docs/physics.md,
"Dissipation of a rolling disc"): the exponents the laws predict, measured on runs, and
bad requests refused by name."""

from __future__ import annotations

import math

import pytest
import ellipsoid

G = 9.81
MASS, RADIUS = 0.445, 0.0375


def disc(alpha0: float, effects: dict, t_end: float) -> ellipsoid.Scenario:
    """The thin uniform disc on its steady motion at tilt alpha0, rolling, under `effects`."""
    omega = math.sqrt(4 * G / (RADIUS * math.sin(alpha0)))
    i_t, i_a = MASS * RADIUS**2 / 4, MASS * RADIUS**2 / 2
    return ellipsoid.Scenario(
        body=dict(
            a=RADIUS, c=RADIUS / 10, mass=MASS, inertia=[i_t, i_t, i_a], ellipsoid_contact=False,
            rim=[dict(name="edge", center=[0.0, 0.0, 0.0], radius=RADIUS, edge=0.0)],
        ),
        initial=dict(theta=alpha0, phi_dot=omega, psi_dot=-omega * math.cos(alpha0)),
        contact=dict(model="rolling"),
        effects=dict(gravity=G, **effects),
        solver=dict(method="dop853", rtol=1e-11, atol=1e-13),
        output=dict(t_end=t_end, dt=1e-3),
    )


def test_rolling_friction_gives_the_tilt_two_thirds_and_the_precession_minus_one_third() -> None:
    """Rolling friction alone: α ∝ (t0 − t)^{2/3}, Ω ∝ (t0 − t)^{−1/3}, t0 the flat landing,
    within 2 % and 3 %; the landing is within 1 % of t0 = α0^{3/2}/(2 μ_r √(g/a))."""
    alpha0, mu_r = 0.05, 1e-4
    t0 = alpha0**1.5 / (2 * mu_r * math.sqrt(G / RADIUS))
    traj = ellipsoid.simulate(disc(alpha0, dict(rolling_friction=mu_r), t0 + 0.5))
    assert traj.success
    tilt = traj.power_law("theta", (0.03, 3.0))
    assert tilt["t0_from"] == "landing" and tilt["t0"] == traj.t_events["flat"][0]
    assert tilt["t0"] == pytest.approx(t0, rel=0.01)
    assert tilt["exponent"] == pytest.approx(2 / 3, rel=0.02), tilt
    rate = traj.power_law("phi_dot", (0.03, 3.0))
    assert rate["exponent"] == pytest.approx(-1 / 3, rel=0.03), rate
    assert tilt["samples"] > 2000 and tilt["rms"] < 0.05


def test_the_film_without_a_landing_fits_t0_in_a_bracket() -> None:
    """Moffatt's film alone never lands (the disc creeps past t0): t0 is given or fitted."""
    alpha0, mu = 0.05, 1.8e-5
    t0 = alpha0**3 * MASS / (2 * math.pi * mu * RADIUS)
    traj = ellipsoid.simulate(disc(alpha0, dict(air_film=dict(viscosity=mu)), t0 + 0.2))
    assert traj.success and len(traj.t_events["flat"]) == 0
    with pytest.raises(ellipsoid.ScenarioError, match="no flat landing"):
        traj.power_law("theta", (0.03, 3.0))
    fitted = traj.power_law("theta", (0.03, 3.0), t0=(0.9 * t0, 1.1 * t0))
    assert fitted["t0_from"] == "fitted" and fitted["t0"] == pytest.approx(t0, rel=0.01)
    assert fitted["exponent"] == pytest.approx(1 / 3, rel=0.02)
    given = traj.power_law("theta", (0.03, 3.0), t0=fitted["t0"])
    assert given["t0_from"] == "given" and given["exponent"] == pytest.approx(fitted["exponent"], rel=1e-9)


def test_bad_power_law_requests_are_refused_by_name() -> None:
    traj = ellipsoid.simulate(disc(0.3, dict(rolling_friction=1e-4), 0.1))
    with pytest.raises(ellipsoid.ScenarioKeyError, match="not a numeric column"):
        traj.power_law("tilt", (0.01, 0.1), t0=1.0)
    with pytest.raises(ellipsoid.ScenarioError, match="0 < lo < hi"):
        traj.power_law("theta", (0.1, 0.01), t0=1.0)
    with pytest.raises(ellipsoid.ScenarioError, match="at least 3"):
        traj.power_law("theta", (1.0, 2.0), t0=10.0)
    with pytest.raises(ellipsoid.ScenarioTypeError, match="t0 is None"):
        traj.power_law("theta", (0.01, 0.1), t0="soon")  # type: ignore[arg-type]
