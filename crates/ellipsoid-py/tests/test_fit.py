"""`ellipsoid.fit` (docs/fitting.md): the exact least-squares answer where the model is
linear in its parameters (free fall), known parameters recovered from noisy synthetic data
under every contact model, and bad input refused by name before any run."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

import ellipsoid

pytest.importorskip("scipy")

ROOT = os.path.join(os.path.dirname(__file__), "..", "..", "..")


def scenario(name: str, **changes: object) -> ellipsoid.Scenario:
    return ellipsoid.load(os.path.join(ROOT, "scenarios", f"{name}.toml")).replace(**changes)


def measured(scen: ellipsoid.Scenario, columns: list[str], t: np.ndarray, sigma: float, seed: int) -> dict[str, np.ndarray]:
    """The run of `scen` at times `t`, with seeded Gaussian noise of deviation `sigma`."""
    traj = ellipsoid.simulate(scen, t_eval=t)
    assert traj.success, traj.message
    rng = np.random.default_rng(seed)
    return {"t": t, **{c: traj[c] + sigma * rng.standard_normal(len(t)) for c in columns}}


def free_fall(height: float, gravity: float) -> ellipsoid.Scenario:
    """A ball in flight from rest: z_G(t) = r + height − g t²/2 until it lands at
    √(2 height / g) (a frictionless body that never touches within t_end)."""
    return ellipsoid.Scenario(
        body=dict(a=0.02, c=0.02, mass=0.1, inertia="uniform"),
        initial=dict(theta=0.3, height=height, velocity=[0.0, 0.0, 0.0]),
        contact=dict(model="frictionless"),
        effects=dict(gravity=gravity),
        solver=dict(method="dop853", rtol=1e-12, atol=1e-14),
        output=dict(t_end=0.25, dt=1e-2),
    )


@pytest.mark.parametrize("absolute", [True, False])
def test_free_fall_gives_the_linear_least_squares_estimates_and_errors(absolute: bool) -> None:
    # z = (r + h) − g t²/2 is linear in (h, g): the weighted least-squares estimates and
    # their covariance are those of the normal equations of the design [1, −t²/2].
    t = np.linspace(0.0, 0.25, 60)
    sigma = 2e-4
    data = measured(free_fall(0.5, 9.81), ["z"], t, sigma, seed=1)
    fit = ellipsoid.fit(free_fall(0.45, 9.0), data, {"initial.height": (0.3, 0.7), "effects.gravity": (5.0, 15.0)},
                        columns="z", sigma=sigma if absolute else None)
    design = np.column_stack([np.ones_like(t), -0.5 * t**2])
    coef, rss, *_ = np.linalg.lstsq(design, data["z"] - 0.02, rcond=None)
    cov = np.linalg.inv(design.T @ design) * (sigma**2 if absolute else float(rss[0]) / (len(t) - 2))
    assert fit.success, fit.message
    assert fit.params["initial.height"] == pytest.approx(coef[0], rel=1e-7)
    assert fit.params["effects.gravity"] == pytest.approx(coef[1], rel=1e-7)
    assert fit.stderr["initial.height"] == pytest.approx(math.sqrt(cov[0, 0]), rel=1e-5)
    assert fit.stderr["effects.gravity"] == pytest.approx(math.sqrt(cov[1, 1]), rel=1e-5)
    rho = cov[0, 1] / math.sqrt(cov[0, 0] * cov[1, 1])
    assert fit.correlation[0, 1] == pytest.approx(rho, rel=1e-5)
    assert fit.dof == len(t) - 2
    assert fit.chi2 == pytest.approx(float(rss[0]) / (sigma**2 if absolute else 1.0), rel=1e-6)
    assert not fit.warnings


# One case per contact model: the scenario (shortened), the true values, the start, the
# bounds, the measured column and its noise.
CASES = {
    "frictionless": ("nutation", {"output.t_end": 0.5}, {"body.com_offset": 0.003, "initial.psi_dot": 60.0},
                     {"body.com_offset": 0.0032, "initial.psi_dot": 57.0},
                     {"body.com_offset": (0.001, 0.006), "initial.psi_dot": (40.0, 80.0)}, "theta", 1e-3),
    "sliding": ("paper-sliding", {"output.t_end": 0.4}, {"contact.friction": 0.3},
                {"contact.friction": 0.25}, {"contact.friction": (0.05, 0.8)}, "theta", 1e-3),
    "rolling": ("disc", {"output.t_end": 0.5}, {"initial.psi_dot": 20.0, "initial.phi_dot": 3.0},
                {"initial.psi_dot": 21.0, "initial.phi_dot": 2.8},
                {"initial.psi_dot": (10.0, 30.0), "initial.phi_dot": (1.0, 5.0)}, "theta", 1e-3),
    "coulomb": ("tippe-top-disc", {"output.t_end": 1.2}, {"contact.friction": 0.3, "contact.contact_radius": 5e-4},
                {"contact.friction": 0.27, "contact.contact_radius": 6e-4},
                {"contact.friction": (0.05, 0.8), "contact.contact_radius": (1e-4, 2e-3)}, "theta", 5e-3),
}


@pytest.mark.parametrize("model", list(CASES))
def test_recovers_known_parameters_within_two_standard_errors(model: str) -> None:
    name, base, truth, start, bounds, column, sigma = CASES[model]
    true_scen = scenario(name, **base, **truth)
    assert true_scen.contact_model == model
    t = np.linspace(0.0, true_scen.t_end, 241)
    data = measured(true_scen, [column], t, sigma, seed=2)
    fit = ellipsoid.fit(scenario(name, **base, **start), data, bounds, columns=[column], sigma=sigma)
    assert fit.success, fit.message
    for key, value in truth.items():
        err = fit.stderr[key]
        # Not vacuous: the data determine each parameter to better than 5 %.
        assert 0 < err < 0.05 * abs(value), (key, err)
        assert abs(fit.params[key] - value) < 2 * err, (key, fit.params[key], value, err)
    # The residuals are the noise: χ² per degree of freedom near 1.
    assert 0.7 < fit.chi2 / fit.dof < 1.3
    assert fit.scenario.get(next(iter(truth))) == pytest.approx(fit.params[next(iter(truth))])


def test_standard_errors_match_the_scatter_over_noise_draws() -> None:
    # Over 30 draws of the noise, (estimate − truth) / stderr has a deviation near 1 if
    # the standard errors are right (0.75 to 1.35 holds with 99.9 % probability at 30
    # draws for a Gaussian), and a mean near 0 if the fit is unbiased.
    name, base, truth, start, bounds, column, sigma = CASES["frictionless"]
    true_scen = scenario(name, **base, **truth)
    t = np.linspace(0.0, true_scen.t_end, 121)
    z: dict[str, list[float]] = {k: [] for k in truth}
    for seed in range(30):
        fit = ellipsoid.fit(scenario(name, **base, **start), measured(true_scen, [column], t, sigma, seed=100 + seed),
                            bounds, columns=[column], sigma=sigma)
        for k, v in truth.items():
            z[k].append((fit.params[k] - v) / fit.stderr[k])
    for k, zs in z.items():
        assert 0.75 < np.std(zs) < 1.35, (k, np.std(zs))
        assert abs(np.mean(zs)) < 0.6, (k, np.mean(zs))


def test_noise_free_data_are_recovered_to_the_runs_accuracy() -> None:
    name, base, truth, start, bounds, column, _ = CASES["coulomb"]
    t = np.linspace(0.0, base["output.t_end"], 121)
    data = measured(scenario(name, **base, **truth), [column], t, 0.0, seed=0)
    fit = ellipsoid.fit(scenario(name, **base, **start), data, bounds, columns=column)
    for key, value in truth.items():
        assert fit.params[key] == pytest.approx(value, rel=1e-6), key


def test_csv_data_with_units_in_the_headers(tmp_path) -> None:
    t = np.linspace(0.0, 0.25, 40)
    data = measured(free_fall(0.5, 9.81), ["z", "theta"], t, 1e-4, seed=3)
    path = tmp_path / "measured.csv"
    with open(path, "w") as f:
        f.write("# a drop, filmed\nt [s],z [m],theta [rad]\n")
        for row in zip(data["t"], data["z"], data["theta"]):
            f.write(",".join(repr(float(v)) for v in row) + "\n")
    from_csv = ellipsoid.fit(free_fall(0.45, 9.81), str(path), {"initial.height": (0.3, 0.7)}, columns=["z"])
    from_dict = ellipsoid.fit(free_fall(0.45, 9.81), data, {"initial.height": (0.3, 0.7)}, columns=["z"])
    assert from_csv.params == from_dict.params
    pd = pytest.importorskip("pandas")
    frame = pd.DataFrame(data).set_index("t")
    from_frame = ellipsoid.fit(free_fall(0.45, 9.81), frame, {"initial.height": (0.3, 0.7)}, columns=["z"])
    assert from_frame.params == from_dict.params


def test_plot_shows_data_fit_and_residuals() -> None:
    plt = pytest.importorskip("matplotlib.pyplot")
    t = np.linspace(0.0, 0.25, 30)
    data = measured(free_fall(0.5, 9.81), ["z"], t, 1e-4, seed=4)
    fit = ellipsoid.fit(free_fall(0.45, 9.81), data, {"initial.height": (0.3, 0.7)})
    before = len(plt.get_fignums())
    axes = fit.plot()
    assert len(plt.get_fignums()) == before + 1
    assert axes.shape == (2,)
    assert np.allclose(axes[1].lines[0].get_ydata(), fit.residuals["z"])
    plt.close("all")


def test_a_changed_event_sequence_is_reported_not_hidden() -> None:
    # The ball lands at √(2 h / g) = 0.3193 s; the data end at 0.31935 s, so a step of g
    # by 1e-3 moves the landing across the data's end: no derivative there.
    scen = free_fall(0.5, 9.81).replace(output={"t_end": 0.32})
    t = np.linspace(0.0, 0.31935, 30)
    data = measured(scen, ["z"], t, 0.0, seed=0)
    with pytest.warns(RuntimeWarning, match="effects.gravity: the events"):
        fit = ellipsoid.fit(scen, data, {"effects.gravity": (5.0, 15.0)}, step=1e-3)
    assert fit.warnings and "not defined" in fit.warnings[0]


@pytest.mark.parametrize(
    ("change", "names"),
    [
        (dict(params={"contact.frictio": (0.1, 0.5)}), "contact.frictio"),
        (dict(params={"initial.theta": (0.0, 1.0)}), "initial.theta"),  # the file sets theta_deg
        (dict(params={"contact.friction": (0.5, 0.9)}), "outside the bounds"),
        (dict(params={"contact.friction": (0.9, 0.1)}), "low < high"),
        (dict(params={"contact.model": (0.0, 1.0)}), "not a number"),
        (dict(params={}), "params"),
        (dict(columns=["nope"]), "nope"),
        (dict(columns=["mode"]), "mode"),
        (dict(sigma={"theta": -1.0}), "sigma['theta']"),
        (dict(t=[0.0, 0.2, 0.1]), "row 2"),
        (dict(t=[0.0, 0.1, 11.0]), "outside the run's time span"),
        (dict(theta=[0.1, float("nan"), 0.2]), "row 1"),
        (dict(theta=[0.1, "x", 0.2]), "data['theta'] row 1"),
        (dict(theta=[0.1, 0.2]), "rows"),
        (dict(data="no-such-file.csv"), "no-such-file.csv"),
    ],
)
def test_bad_input_is_refused_by_name(change: dict, names: str) -> None:
    data = {"t": change.pop("t", [0.0, 0.1, 0.2]), "theta": change.pop("theta", [0.17, 0.18, 0.19])}
    if "data" in change:
        data = change.pop("data")
    if "columns" in change and change["columns"] == ["mode"]:
        data = {**data, "mode": ["rolling"] * 3}
    args = {"params": {"contact.friction": (0.1, 0.5)}, **change}
    with pytest.raises(ellipsoid.ScenarioError) as err:
        ellipsoid.fit(scenario("paper-sliding"), data, **args)
    assert names in str(err.value)
