"""Scenarios from Python: keyword tables, `replace`, `load`, and their errors."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import ellipsoid
from conftest import I1, REPO, oblate

NUTATION = REPO / "scenarios" / "nutation.toml"


def same_run(a: ellipsoid.Trajectory, b: ellipsoid.Trajectory) -> None:
    assert len(a) == len(b)
    for name in ellipsoid.COLUMNS:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


def test_keyword_tables_build_the_same_scene_as_the_file() -> None:
    """nutation.toml written as keyword arguments (degrees, integers, numpy values)."""
    built = ellipsoid.Scenario(
        body=dict(a=0.025, c=0.0175, mass=0.05, com_offset=0.003, inertia=np.array([9.3125e-6, 9.3125e-6, 1.25e-5])),
        initial=dict(theta_deg=np.float32(10.0).item(), psi_dot=np.int64(60)),
        contact=dict(model="frictionless"),
        solver=dict(method="dop853", rtol=1e-11, atol=1e-13),
        output=dict(t_end=0.5, dt=1e-3),
        check=dict(status="completed", energy=1e-9),
        name="nutation-py",
    )
    assert built.source == "nutation-py" and built.stem == "nutation-py"
    assert "[body]" in built.text and "theta_deg = 10" in built.text
    same_run(ellipsoid.simulate(built), ellipsoid.simulate(NUTATION, output={"t_end": 0.5}))
    assert built.t_end == 0.5 and built.contact_model == "frictionless"
    assert len(built.sample_times) == 501 and built.sample_times[-1] == 0.5


def test_contact_spheres_from_keyword_tables() -> None:
    """`[[body.sphere]]` as `body=dict(..., sphere=[dict(name=..., center=..., radius=...)])`:
    the same run as the bundled file, the stem's touchdown named in the events, and a bad
    radius an EllipsoidError naming the sphere's key."""
    stem = REPO / "scenarios" / "tippe-top-stem.toml"
    body = dict(
        a=0.015,
        c=0.015,
        mass=6e-3,
        com_offset=0.003,
        inertia=[8e-7, 8e-7, 7e-7],
        sphere=[dict(name="stem", center=np.array([0.0, 0.0, 0.013]), radius=0.005)],
    )
    built = ellipsoid.Scenario(
        body=body,
        initial=dict(theta=0.1, psi_dot=180.0, velocity=[0.0, 0.0]),
        contact=dict(model="coulomb", friction=0.3, contact_radius=5e-4, contact_law="exact"),
        solver=dict(method="dop853", rtol=1e-11, atol=1e-13),
        output=dict(t_end=1.5, dt=1e-3),
    )
    a = ellipsoid.simulate(built)
    b = ellipsoid.simulate(stem, output={"t_end": 1.5})
    same_run(a, b)
    changes = [e for e in a.events if e["kind"] == "contact_surface"]
    assert changes and (changes[0]["from"], changes[0]["to"]) == ("ellipsoid", "stem")
    bad = dict(body, sphere=[dict(name="stem", center=[0.0, 0.0, 0.013], radius=-1.0)])
    with pytest.raises(ellipsoid.EllipsoidError, match=r"body\.sphere\[0\]\.radius = -1"):
        ellipsoid.Scenario(body=bad, contact=dict(model="frictionless"), output=dict(t_end=1.0))


def test_replace_merges_tables_and_accepts_dotted_keys() -> None:
    base = ellipsoid.load(NUTATION)
    a = base.replace(contact={"model": "coulomb", "friction": 0.2}, output={"t_end": 0.2})
    b = base.replace(**{"contact.model": "coulomb", "contact.friction": 0.2, "output.t_end": 0.2})
    c = ellipsoid.load(NUTATION, contact={"model": "coulomb", "friction": 0.2}, output={"t_end": 0.2})
    assert a == b == c and a != base
    assert a.overrides == ['contact.model="coulomb"', "contact.friction=0.2", "output.t_end=0.2"]
    assert base.overrides == [] and base.t_end == 10.0, "replace leaves the original alone"
    # Only the keys given change: dt and the solver settings stay.
    assert len(a.sample_times) == 201
    same_run(ellipsoid.simulate(a), ellipsoid.simulate(NUTATION, **{"contact.model": "coulomb", "contact.friction": 0.2, "output.t_end": 0.2}))
    # Nested inline tables and arrays of tables.
    d = base.replace(effects={"air_drag": {"linear": 1e-3}}, initial={"position": (0.5, 0.25)}, output={"t_end": 0.1})
    assert d.overrides[:2] == ["effects.air_drag.linear=0.001", "initial.position=[0.5, 0.25]"]
    traj = ellipsoid.simulate(d)
    assert traj.x[0] == 0.5 and traj.y[0] == 0.25


def test_a_change_replaces_its_twin_key() -> None:
    # nutation.toml gives theta_deg = 10: a change of theta replaces it (issue 47), and the
    # scenario reads back the change, not the twin.
    base = ellipsoid.load(NUTATION)
    changed = base.replace(**{"initial.theta": 0.2})
    assert changed.get("initial.theta") == 0.2 and changed.get("initial.theta_deg") is None
    assert base.get("initial.theta_deg") == 10.0
    assert ellipsoid.simulate(changed, output={"t_end": 0.01}).theta[0] == pytest.approx(0.2, abs=1e-15)
    back = changed.replace(initial={"theta_deg": 10.0})
    assert ellipsoid.simulate(back, output={"t_end": 0.01}).theta[0] == pytest.approx(math.radians(10.0), abs=1e-15)


def test_from_toml_and_paths() -> None:
    text = NUTATION.read_text()
    s = ellipsoid.Scenario.from_toml(text, name="inline", output={"t_end": 0.1})
    assert s.source == "inline" and s.overrides == ["output.t_end=0.1"]
    same_run(ellipsoid.simulate(s), ellipsoid.simulate(str(NUTATION), output={"t_end": 0.1}))
    assert ellipsoid.load(Path(NUTATION)) == ellipsoid.load(str(NUTATION))
    assert "nutation.toml" in repr(ellipsoid.load(NUTATION))


@pytest.mark.parametrize(
    ("make", "key", "kind", "message"),
    [
        (lambda: oblate(body=dict(a=0.025, c=0.0175, mass=-0.05, inertia="uniform")), "body.mass", "invalid", "body.mass = -0.05: the mass must be positive and finite (kg)"),
        (lambda: oblate(body=dict(a=0.025, c=0.0175, mas=0.05, inertia="uniform")), "body.mas", "unknown_key", "unknown key in [body]; did you mean `mass`?"),
        (lambda: oblate(contact=dict(model="sliding")), "contact.friction", "missing", "contact.friction is missing: the sliding model needs μ"),
        (lambda: oblate(contact=dict(model="frictionles")), "contact.model", "invalid", 'did you mean "frictionless"?'),
        (lambda: oblate(output=dict(t_end="long", dt=1e-3)), "output.t_end", "type", 'output.t_end = "long": expected a number'),
        (lambda: oblate(output=dict(t_end=1.0)), "output.dt", "missing", "output.dt is missing"),
        (lambda: oblate().replace(**{"body.mass": -1}), "body.mass", "invalid", "the change body.mass=-1: body.mass = -1: the mass must be positive"),
        (lambda: oblate().replace(solver={"rtol": 0.0}), "solver.rtol", "invalid", "the change solver.rtol=0.0: solver.rtol = 0: the relative tolerance must lie between 10·EPS"),
        (lambda: oblate().replace(body={"mass": {"x": 1}}), "body.mass", "override", "body.mass: is not a table, so body.mass.x cannot be set"),
        # A file holding both twins (a change of one replaces the other: see below).
        (lambda: ellipsoid.Scenario.from_toml(NUTATION.read_text().replace("theta_deg = 10.0", "theta = 0.1\ntheta_deg = 10.0")), "initial.theta_deg", "conflict", "give either initial.theta or initial.theta_deg, not both"),
        (lambda: ellipsoid.load("/nonexistent/x.toml"), None, "io", "/nonexistent/x.toml: cannot read the scenario file"),
        (lambda: ellipsoid.Scenario.from_toml("[body\n", name="bad.toml"), None, "syntax", "bad.toml:1:6: TOML syntax error"),
    ],
)
def test_bad_input_raises_scenario_error_naming_the_key(make, key, kind, message) -> None:
    with pytest.raises(ellipsoid.ScenarioError) as info:
        make()
    err = info.value
    assert isinstance(err, ValueError) and isinstance(err, ellipsoid.EllipsoidError)
    assert message in str(err), str(err)
    assert err.key == key and err.kind == kind
    if key is not None:
        assert key in str(err)


def test_scenario_error_carries_its_location(tmp_path: Path) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text(NUTATION.read_text().replace("mass = 0.05", "mass = -0.05"))
    with pytest.raises(ellipsoid.ScenarioError) as info:
        ellipsoid.load(bad)
    e = info.value
    assert (e.source, e.key, e.value, e.override) == (str(bad), "body.mass", "-0.05", None)
    assert e.line == 17 and e.column == 1, (e.line, e.column)
    assert str(e) == f"{bad}:17:1: body.mass = -0.05: the mass must be positive and finite (kg)"


def test_physics_rejected_at_t0_is_a_scenario_error() -> None:
    """N ≤ 0 at t = 0 (a fast spin about a steep axis) is found by the simulation, and
    placed in the scenario like the CLI does (with on_lift_off = "stop"; by default the
    body flies from t = 0)."""
    s = oblate(initial=dict(theta=1.2, phi_dot=3000.0), contact=dict(model="frictionless", on_lift_off="stop"))
    assert ellipsoid.simulate(oblate(initial=dict(theta=1.2, phi_dot=3000.0)), output={"t_end": 0.01}).mode[0] == "flight"
    with pytest.raises(ellipsoid.ScenarioError, match=r"initial normal force N = -.*N > 0") as info:
        ellipsoid.simulate(s)
    assert info.value.key == "initial normal force N"


def test_python_values_that_toml_cannot_hold_are_type_errors() -> None:
    with pytest.raises(TypeError, match=r"body.a: a value of type object"):
        oblate(body=dict(a=object(), c=0.0175, mass=0.05, inertia="uniform"))
    with pytest.raises(TypeError, match=r"contact.friction = None: None cannot be given"):
        oblate().replace(contact={"friction": None})
    with pytest.raises(TypeError, match="keys must be strings"):
        oblate(body={1: 2})
    with pytest.raises(TypeError, match="expected an ellipsoid.Scenario or the path"):
        ellipsoid.simulate(42)  # type: ignore[arg-type]


def test_replace_sets_elements_of_arrays_by_index() -> None:
    """A key path with [i] indexes (the grammar of --set and of a study's axes) changes one
    element of an array, of numbers or of tables; the rest stays, and a bad index is an
    error naming the change."""
    base = oblate()
    s = base.replace(**{"body.inertia[2]": 1.5e-5, "initial.position": [0.5, 0.25]}).replace(**{"initial.position[1]": 2.0})
    whole = base.replace(body={"inertia": [I1, I1, 1.5e-5]}, initial={"position": [0.5, 2.0]})
    same_run(ellipsoid.simulate(s, output={"t_end": 0.05}), ellipsoid.simulate(whole, output={"t_end": 0.05}))
    assert s.overrides[0] == "body.inertia[2]=0.000015" and s.overrides[-1] == "initial.position[1]=2.0"
    stem = ellipsoid.load(REPO / "scenarios" / "tippe-top-stem.toml")
    bigger = stem.replace(**{"body.sphere[0].radius": 0.004})
    assert bigger == ellipsoid.load(REPO / "scenarios" / "tippe-top-stem.toml", **{"body.sphere[0].radius": 0.004})
    assert bigger != stem and "body.sphere[0].radius=0.004" in bigger.overrides
    with pytest.raises(ellipsoid.ScenarioError, match=r"body\.sphere: has 1 element\(s\), no index 1, so body\.sphere\[1\]\.radius cannot be set") as info:
        stem.replace(**{"body.sphere[1].radius": 0.004})
    assert info.value.kind == "override"
    with pytest.raises(ellipsoid.ScenarioError, match=r"body\.inertia\[2\] = -1|principal moments"):
        base.replace(**{"body.inertia[2]": -1.0})


def test_rims_from_keyword_tables() -> None:
    """`[[body.rim]]` and `ellipsoid_contact` as `body=dict(..., ellipsoid_contact=False,
    rim=[dict(name=..., center=..., radius=..., edge=...)])`: the same run as the bundled
    coin, which lands flat once and ends on its face; an off-axis centre an EllipsoidError
    naming the rim's key."""
    coin = REPO / "scenarios" / "coin.toml"
    base = ellipsoid.load(coin)
    body = dict(
        a=0.01213,
        c=0.000875,
        mass=5.67e-3,
        inertia=[2.10e-7, 2.10e-7, 4.17e-7],
        ellipsoid_contact=False,
        rim=[dict(name="edge", center=[0.0, 0.0, 0.0], radius=0.011255, edge=0.000875)],
    )
    built = base.replace(body=body)
    a = ellipsoid.simulate(built)
    b = ellipsoid.simulate(coin)
    same_run(a, b)
    flats = [e for e in a.events if e["kind"] == "flat"]
    assert len(flats) == 1 and flats[0]["surface"] == "edge" and flats[0]["energy_loss"] > 0.0
    assert a["mode"][-1] == "face@edge"
    bad = dict(body, rim=[dict(name="edge", center=[0.01, 0.0, 0.0], radius=0.011255, edge=0.0)])
    with pytest.raises(ellipsoid.EllipsoidError, match=r"body\.rim\[0\]\.center = \[0\.01, 0(\.0)?, 0(\.0)?\]: a rim's centre lies on the body's symmetry axis"):
        base.replace(body=bad)
