"""ellipsoid.steady and ellipsoid.linearize against the analytic frictionless sleeping
criterion C²n² > 4 A m g (l − ρ) (docs/physics.md, "Steady motions and their stability")."""

from __future__ import annotations

import math

import numpy as np
import pytest

import ellipsoid

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
    with pytest.raises(ellipsoid.ScenarioError, match="not implemented"):
        ellipsoid.steady(egg(), family="precession")
    with pytest.raises(ellipsoid.ScenarioError, match="1-D"):
        ellipsoid.steady(egg(), vary={"initial.psi_dot": [[1.0, 2.0]]})
    with pytest.raises(ellipsoid.ScenarioError, match="sliding"):
        ellipsoid.steady(egg().replace(contact={"model": "sliding", "friction": 0.3}))
    with pytest.raises(ellipsoid.ScenarioError, match="state"):
        ellipsoid.linearize(egg(), state=[1.0, 2.0])
