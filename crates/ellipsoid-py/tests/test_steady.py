"""ellipsoid.steady and ellipsoid.linearize against the analytic frictionless sleeping
criterion C²n² > 4 A m g (l − ρ) (docs/physics.md, "Steady motions and their stability")."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import ellipsoid

REPO = Path(__file__).resolve().parents[3]
G = 9.81
A_SEMI, C_SEMI, MASS = 0.02, 0.03, 0.06  # a prolate egg on its end
BIG_A = MASS * (A_SEMI**2 + C_SEMI**2) / 5
BIG_C = 2 * MASS * A_SEMI**2 / 5
L_MINUS_RHO = C_SEMI - A_SEMI**2 / C_SEMI
N_C = 2 * math.sqrt(BIG_A * MASS * G * L_MINUS_RHO) / BIG_C


def egg(psi_dot: float = 0.0) -> ellipsoid.Scenario:
    return ellipsoid.Scenario(
        body=dict(a=A_SEMI, c=C_SEMI, mass=MASS, inertia="uniform"),
        initial=dict(theta=0.0, psi_dot=psi_dot),
        contact=dict(model="frictionless"),
        effects=dict(gravity=G),
        output=dict(t_end=1.0, dt=0.01),
    )


def test_sweep_finds_the_critical_spin_and_the_analytic_eigenvalues() -> None:
    values = np.linspace(0.5 * N_C, 2.0 * N_C, 30)  # never exactly N_C (a defective double eigenvalue there)
    res = ellipsoid.steady(egg(), family="upright", vary={"initial.psi_dot": values})
    assert np.array_equal(res.values, values)
    assert res.eigenvalues.shape == (30, 4) and res.eigenvalues.dtype == np.complex128
    # Each row sorted by decreasing real part.
    assert np.all(np.diff(res.eigenvalues.real, axis=1) <= 0)
    for n, row in zip(values, res.eigenvalues):
        k = MASS * G * L_MINUS_RHO
        disc = np.sqrt(complex(BIG_C**2 * n**2 - 4 * BIG_A * k))
        sigma = [(BIG_C * n + s * disc) / (2 * BIG_A) for s in (1, -1)]
        expected = [1j * (x - n) for x in sigma] + [-1j * (x - n) for x in sigma]
        scale = max(abs(z) for z in expected)
        for e in expected:
            assert np.min(np.abs(row - e)) <= 1e-10 * scale
    assert len(res.critical) == 1
    crit = res.critical[0]
    assert crit["kind"] == "collision" and crit["stable_side"] == "above"
    assert abs(crit["value"] / N_C - 1) <= 1e-10
    assert list(res.stable) == [bool(v > N_C) for v in values]
    assert res.states.shape == (30, 6)
    assert np.allclose(res.states[:, 5], values, rtol=0, atol=1e-12 * N_C)
    table = res.to_pandas()
    assert list(table.columns[:6]) == ["initial.psi_dot", "spin", "theta", "normal_force", "stable", "max_real"]
    assert len(table) == 30 and (table["mode1"] == "tilt").all()


def test_single_motion_and_linearize() -> None:
    res = ellipsoid.steady(egg(2 * N_C))
    assert res.values.shape == (1,) and res.values[0] == pytest.approx(2 * N_C, rel=1e-15)
    assert res.stable[0] and res.critical == []
    jac, names = ellipsoid.linearize(egg(2 * N_C))
    assert names == ["zeta_t1", "zeta_t2", "omega1", "omega2", "omega3"]
    assert jac.shape == (5, 5)
    # The family's zero removed, the same eigenvalues as the 4×4 block of the Jacobian
    # (at the upright spin the ω3 row and column decouple).
    block = np.linalg.eigvals(jac[:4, :4])
    for z in res.eigenvalues[0]:
        assert np.min(np.abs(block - z)) <= 1e-9 * np.max(np.abs(block))
    jac2, _ = ellipsoid.linearize(egg(), state=[0.0, 0.0, 1.0, 0.0, 0.0, 2 * N_C])
    assert np.allclose(jac, jac2, rtol=0, atol=1e-9 * np.max(np.abs(jac)))


def test_bad_input_names_the_field() -> None:
    with pytest.raises(ellipsoid.ScenarioError, match="family"):
        ellipsoid.steady(egg(), family="sideways")
    with pytest.raises(ellipsoid.ScenarioError, match="initial.theta"):
        ellipsoid.steady(egg(), family="precession")
    with pytest.raises(ellipsoid.ScenarioError, match="contact.model"):
        ellipsoid.steady(egg().replace(**{"initial.theta": 0.5}), family="rolling-circle")
    with pytest.raises(ellipsoid.ScenarioError, match="1-D"):
        ellipsoid.steady(egg(), vary={"initial.psi_dot": [[1.0, 2.0]]})
    with pytest.raises(ellipsoid.ScenarioError, match="sliding"):
        ellipsoid.steady(egg().replace(contact={"model": "sliding", "friction": 0.3}))
    with pytest.raises(ellipsoid.ScenarioError, match="state"):
        ellipsoid.linearize(egg(), state=[1.0, 2.0])


# A sphere with G 5 mm below its centre (a tippe top's ball), rolling tilted.
R_BALL, D_OFF, M_BALL, A_BALL, C_BALL = 0.02, 0.005, 0.015, 1.6e-6, 2.0e-6


def ball(theta: float, phi_dot: float) -> ellipsoid.Scenario:
    inertia = [[A_BALL, 0.0, 0.0], [0.0, A_BALL, 0.0], [0.0, 0.0, C_BALL]]
    return ellipsoid.Scenario(
        body=dict(a=R_BALL, c=R_BALL, mass=M_BALL, inertia=inertia, com_offset=D_OFF),
        initial=dict(theta=theta, phi_dot=phi_dot),
        contact=dict(model="rolling"),
        effects=dict(gravity=G),
        output=dict(t_end=1.0, dt=0.01),
    )


def routh_spin(theta: float, omega: float) -> float:
    """Routh's steady rolling of the ball from the Newton–Euler balance about G in world
    axes (axis k tilted towards +x; every vector turns at Ω e3): dH/dt = Ω e3 × H equals
    r × (m a_G + m g e3), v_G = −ω × r, a_G = Ω e3 × v_G; affine in n, solved along e3 × k."""
    e3 = np.array([0.0, 0.0, 1.0])
    k = np.array([math.sin(theta), 0.0, math.cos(theta)])
    r = -R_BALL * e3 + D_OFF * k

    def residual(n: float) -> np.ndarray:
        w = omega * e3 + (n - omega * math.cos(theta)) * k
        h = A_BALL * w + (C_BALL - A_BALL) * np.dot(w, k) * k
        v_g = -np.cross(w, r)
        force = M_BALL * omega * np.cross(e3, v_g) + M_BALL * G * e3
        return omega * np.cross(e3, h) - np.cross(r, force)

    j = np.cross(e3, k) / math.sin(theta)
    r0, r1 = residual(0.0), residual(1.0)
    return float(-np.dot(r0, j) / np.dot(r1 - r0, j))


def test_rolling_circle_solves_routh_relation_along_the_family() -> None:
    thetas = np.linspace(0.3, 2.5, 12)
    res = ellipsoid.steady(ball(0.3, -5.0), family="rolling-circle", vary={"initial.theta": thetas})
    assert res.family == "rolling-circle"
    assert res.eigenvalues.shape == (12, 2) and res.eigenvalues.dtype == np.complex128
    assert np.allclose(res.theta, thetas, rtol=0, atol=1e-15)
    assert res.phi_dot is not None and np.all(res.phi_dot == -5.0)
    expected = np.array([routh_spin(t, -5.0) for t in thetas])
    assert np.max(np.abs(res.spin - expected) / np.abs(expected)) <= 1e-12
    assert all(row == ["nutation", "nutation"] for row in res.modes)
    # Frictionless and rolling spectra are symmetric about the imaginary axis: ±λ.
    assert np.allclose(res.eigenvalues[:, 0], -res.eigenvalues[:, 1], rtol=0, atol=1e-9 * np.abs(res.eigenvalues).max())
    table = res.to_pandas()
    assert list(table.columns[:9]) == [
        "initial.theta", "spin", "theta", "normal_force", "phi_dot", "radius_g", "radius_contact", "stable", "max_real",
    ]
    one = ellipsoid.steady(ball(1.2, 20.0), family="rolling-circle")
    assert one.spin[0] == pytest.approx(routh_spin(1.2, 20.0), rel=1e-12)
    with pytest.raises(ellipsoid.ScenarioError, match="solves for spin here"):
        ellipsoid.steady(ball(1.2, 20.0), family="rolling-circle", vary={"initial.psi_dot": [1.0, 2.0]})


def test_precession_given_two_of_theta_phi_dot_and_spin() -> None:
    frictionless = ball(1.1, -15.0).replace(**{"contact.model": "frictionless"})
    spin = ellipsoid.steady(frictionless, family="precession").spin[0]
    # The spin φ̇ cos θ + ψ̇ of a scenario whose φ̇ is 10 % off: solve="phi_dot" finds Ω.
    guess = frictionless.replace(
        **{"initial.phi_dot": -16.5, "initial.psi_dot": spin + 16.5 * math.cos(1.1)}
    )
    res = ellipsoid.steady(guess, family="precession", solve="phi_dot")
    assert res.phi_dot is not None and res.phi_dot[0] == pytest.approx(-15.0, rel=1e-12)
    assert res.circles is not None and res.circles[0, 0] == 0.0  # G fixed
    assert res.spin[0] == pytest.approx(spin, rel=1e-15)
    with pytest.raises(ellipsoid.ScenarioError, match="solve"):
        ellipsoid.steady(frictionless, family="precession", solve="psi")


def lens(phi_dot: float, model: str = "rolling") -> ellipsoid.Scenario:
    """A disc-like lens (a = 0.03 m, c = 0.004 m) tilted 1.7 rad, spinning at 10 rad/s."""
    return ellipsoid.Scenario(
        body=dict(a=0.03, c=0.004, mass=0.05, inertia="uniform"),
        initial=dict(theta=1.7, phi_dot=phi_dot, psi_dot=10.0),
        contact=dict(model=model),
        output=dict(t_end=1.0, dt=0.01),
    )


@pytest.mark.parametrize(("family", "model"), [("rolling-circle", "rolling"), ("precession", "frictionless")])
def test_a_tilted_family_at_zero_precession_stands_on_the_edge(family: str, model: str) -> None:
    # Issue 48: solved for θ at φ̇ = 0 this was a PanicException ("Singular value was NaN");
    # issue 44: φ̇ = 0 has its motion, the lens on its edge (θ = π/2) rolling straight on
    # (infinite circles) or spinning in place (G fixed).
    res = ellipsoid.steady(lens(0.0, model), family=family, solve="theta")
    assert res.theta[0] == pytest.approx(math.pi / 2, abs=1e-12)
    assert res.phi_dot[0] == 0.0
    radius_g = res.circles[0, 0]
    assert math.isinf(radius_g) if model == "rolling" else radius_g == 0.0
    sweep = ellipsoid.steady(lens(1.0, model), family=family, solve="theta", vary={"initial.phi_dot": [-1.0, 0.0, 1.0]})
    assert np.isfinite(sweep.eigenvalues).all()


def test_a_disc_rolling_upright_is_stable_above_its_critical_spin() -> None:
    """Issue 44: a rim's steady motions. The thin uniform disc of scenarios/rolling-disc.toml
    rolling upright (θ = π/2, φ̇ = 0) is stable above n² = g/(3R); its upright family
    (flat on its face) is refused naming the rim."""
    disc = ellipsoid.load(str(REPO / "scenarios/rolling-disc.toml")).replace(
        **{"initial.theta": math.pi / 2, "initial.phi_dot": 0.0, "initial.psi_dot": 1.0}
    )
    n_c = math.sqrt(G / (3 * 0.05))
    res = ellipsoid.steady(disc, family="rolling-circle", vary={"initial.psi_dot": np.linspace(0.0, 2 * n_c, 9)})
    (crit,) = res.critical
    assert crit["value"] == pytest.approx(n_c, rel=1e-9)
    assert crit["stable_side"] == "above"
    assert res.surface == ["edge"] * 9
    with pytest.raises(ellipsoid.ScenarioError, match='body.rim = "edge": the upright spin rests on this rim'):
        ellipsoid.steady(disc, family="upright")


def test_rates_beyond_what_doubles_resolve_are_refused_at_once() -> None:
    # Issue 48: 1e80 rad/s never returned; now refused naming the quantity and the rule.
    for spin in (1e40, 1e80, 1e300):
        with pytest.raises(ellipsoid.ScenarioError, match=r"spin n = .*analysed up to 100000"):
            ellipsoid.steady(egg(spin))


def test_vary_over_a_key_the_scenario_refuses_names_it() -> None:
    for key, values in (("body.colour", [1.0, 2.0]), ("body.mass", [-1.0, 1.0])):
        with pytest.raises(ellipsoid.ScenarioError, match=rf"{key} = .*the scenario refuses this value"):
            ellipsoid.steady(egg(100.0), vary={key: values})


def test_ctrl_c_interrupts_a_long_sweep() -> None:
    from conftest import INTERRUPT_MAIN, interrupt_inside

    from ellipsoid._ellipsoid import steady_raw

    # 10⁵ spins: seconds of work, stopped before the next value. The sweep is called in
    # Rust directly: `ellipsoid.steady` is Python, whose own frame the watcher would see
    # instead of this one's (`interrupt_inside`).
    values = [float(v) for v in np.linspace(-200.0, 200.0, 100_000)]
    interrupt_inside(INTERRUPT_MAIN, steady_raw, egg(), "upright", "initial.psi_dot", values, "spin")


def test_a_body_with_a_stem_stands_on_it_inverted() -> None:
    """Issue 47: a body with contact spheres is analysed on the surface it rests on. The
    inverted tippe top of Leine & Glocker stands on its stem, a sphere of 5 mm whose centre
    is l − ρ = 16 mm from G: without friction its critical spin is the sleeping
    criterion's 2√(A m g (l − ρ))/C; upright it rests on its ball."""
    top = ellipsoid.Scenario(
        body=dict(a=0.015, c=0.015, mass=6e-3, com_offset=0.003, inertia=[8e-7, 8e-7, 7e-7],
                  sphere=[dict(name="stem", center=[0.0, 0.0, 0.013], radius=0.005)]),
        initial=dict(theta=math.pi, psi_dot=0.0),
        contact=dict(model="frictionless"),
        effects=dict(gravity=G),
        output=dict(t_end=1.0, dt=0.01),
    )
    n_c = 2 * math.sqrt(8e-7 * 6e-3 * G * 0.016) / 7e-7
    values = np.linspace(-2 * n_c, 0.0, 21)
    res = ellipsoid.steady(top, family="inverted", vary={"initial.psi_dot": values})
    assert res.surface == ["stem"] * 21
    (crit,) = res.critical
    assert crit["value"] == pytest.approx(-n_c, rel=1e-9)
    assert ellipsoid.steady(top, family="upright").surface == ["ellipsoid"]
