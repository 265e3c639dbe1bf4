"""Robustness (issue #17): inputs that crashed the interpreter, exhausted memory or
threads, or raised outside the exception tree; and hypothesis over Scenario(...)."""

from __future__ import annotations

import math
import os
import re
import resource
import subprocess
import sys
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import ellipsoid
from conftest import REPO, oblate

NUTATION = REPO / "scenarios" / "nutation.toml"

# ------------------------------------------------------------- found by the campaign


def test_deep_nesting_is_a_scenario_error_not_a_crash() -> None:
    """A list (or dict) nested 16,000 deep used to overflow the stack (SIGSEGV). Run in a
    child, so that a regression fails this test instead of killing pytest."""
    code = """
import ellipsoid
for make in (lambda v: [v], lambda v: {"x": v}):
    v = 1.0
    for _ in range(16000):
        v = make(v)
    for call in (lambda: ellipsoid.Scenario(body={"a": v}), lambda: ellipsoid.load(NUTATION).replace(**{"body.a": v})):
        try:
            call()
        except ellipsoid.ScenarioError as e:
            assert "nested more than 32 deep" in str(e), e
        else:
            raise AssertionError("accepted")
cyclic = []
cyclic.append(cyclic)
try:
    ellipsoid.Scenario(body={"a": cyclic})
except ellipsoid.ScenarioError as e:
    assert "nested" in str(e)
print("ok")
"""
    out = subprocess.run([sys.executable, "-c", f"NUTATION = {str(NUTATION)!r}\n" + code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and out.stdout.strip() == "ok", (out.returncode, out.stderr[-2000:])


def test_a_long_list_as_a_change_takes_linear_memory() -> None:
    """replace(**{"output.times": [...]}) took memory quadratic in the list's length
    (10⁴ elements ≈ 0.5 GB). In a child with a 1 GB address-space limit, 10⁵ elements
    (before: ~50 GB) must go through."""
    text = "[body]\na = 0.025\nc = 0.0175\nmass = 0.05\ninertia = 'uniform'\n[contact]\nmodel = 'frictionless'\n[output]\nt_end = 1.0\ntimes = [0.0]\n"
    code = f"""
import resource
resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))
import ellipsoid
times = [i * 1e-5 for i in range(100_000)]
s = ellipsoid.Scenario.from_toml({text!r}).replace(**{{"output.times": times}})
assert len(s.sample_times) == 100_000
print("ok")
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr[-2000:]


def test_workers_are_capped() -> None:
    good = ellipsoid.load(NUTATION, output={"t_end": 0.01})
    cpus = os.cpu_count() or 1
    cap = max(4 * cpus, 8)
    assert len(ellipsoid.sweep([good, good], workers=cap)) == 2
    for bad in (cap + 1, 4000, 10**6, 2**64, 10**400, 0, -1):
        shown = str(bad) if len(str(bad)) <= 24 else f"an integer of {len(str(bad))} digits"
        with pytest.raises(ellipsoid.ScenarioError, match=rf"workers = {re.escape(shown)}: give 1 to {cap} worker threads") as info:
            ellipsoid.sweep([good], workers=bad)
        assert info.value.key == "workers"
    for bad_type in (1.5, "4", True):
        with pytest.raises(ellipsoid.ScenarioTypeError, match="workers: expected an integer"):
            ellipsoid.sweep([good], workers=bad_type)  # type: ignore[call-overload]


@pytest.mark.parametrize(
    ("call", "cls", "match"),
    [
        (lambda: oblate(body=dict(a=10**400, c=0.0175, mass=0.05, inertia="uniform")), ellipsoid.ScenarioError, r"body.a = an integer of 401 digits: beyond the range of a float"),
        (lambda: oblate(contact=dict(model="roll\udc80ing")), ellipsoid.ScenarioError, r"contact.model = .*not valid Unicode text"),
        (lambda: oblate(contact={"mo\udc80del": "rolling"}), ellipsoid.ScenarioError, r"not valid Unicode text"),
        (lambda: oblate().replace(**{"contact.model": "\ud800"}), ellipsoid.ScenarioError, r"not valid Unicode text"),
        (lambda: ellipsoid.Scenario.from_toml("x = 1\ud800"), ellipsoid.ScenarioError, r"text: not valid Unicode text"),
        (lambda: ellipsoid.sweep([oblate()], errors="x"), ellipsoid.ScenarioError, r"errors = 'x': expected \"raise\" or \"return\""),
        (lambda: ellipsoid.sweep([oblate()], summaries_only="yes"), ellipsoid.ScenarioTypeError, r"summaries_only: expected True or False"),
        (lambda: ellipsoid.sweep(42), ellipsoid.ScenarioTypeError, r"scenarios: expected an iterable"),
        (lambda: ellipsoid.simulate(42), ellipsoid.ScenarioTypeError, r"expected an ellipsoid.Scenario or the path"),
        (lambda: ellipsoid.load(3.5), ellipsoid.ScenarioTypeError, r"expected an ellipsoid.Scenario or the path"),
        (lambda: ellipsoid.Scenario(name=5), ellipsoid.ScenarioTypeError, r"name: expected a string"),
        (lambda: ellipsoid.Scenario(bdy={"a": 1}), ellipsoid.ScenarioError, r"bdy: unknown table at the top level; did you mean `body`\?"),
        (lambda: oblate(body=dict(a=Exploding(), c=0.0175, mass=0.05, inertia="uniform")), ellipsoid.ScenarioTypeError, r"body.a: __float__\(\) raised ZeroDivisionError"),
    ],
)
def test_every_input_error_is_in_the_tree(call: Any, cls: type, match: str) -> None:
    with pytest.raises(cls, match=match) as info:
        call()
    assert isinstance(info.value, ellipsoid.EllipsoidError)


class Exploding:
    def __float__(self) -> float:
        raise ZeroDivisionError("boom")


def test_several_errors_are_reported_at_once() -> None:
    with pytest.raises(ellipsoid.ScenarioError) as info:
        oblate(initial=dict(theta=0.1, psi_dott=60.0), contact=dict(modl="frictionless"))
    e = info.value
    assert len(e.errors) == 2 and e.errors[0] is not e
    assert [x.key for x in e.errors] == ["initial.psi_dott", "contact.modl"]
    assert e.key == "initial.psi_dott" and e.line < e.errors[1].line
    assert str(e).count("\n") == 1 and str(e).splitlines()[1] == str(e.errors[1])


# ------------------------------------------------------------------------ hypothesis

KEYS = {
    "body": ["a", "b", "c", "mass", "com_offset", "com_offset_vector", "inertia", "bogus"],
    "initial": ["theta", "theta_deg", "phi", "psi_dot", "omega_body", "rotation", "position", "velocity"],
    "contact": ["model", "friction", "contact_radius", "contact_law"],
    "effects": ["gravity", "rolling_resistance", "spin_friction", "air_drag"],
    "solver": ["method", "rtol", "atol", "step", "max_steps"],
    "output": ["t_end", "dt", "times"],
    "check": ["status", "energy"],
}

scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(2**80), max_value=2**80),
    st.integers(min_value=10**300, max_value=10**320),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=12),
    st.sampled_from(["uniform", "rolling", "coulomb", "rk4", "dop853", "x", "\udc80"]),
    st.binary(max_size=4),
    st.just(object()),
)
values = st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=4), st.tuples(inner, inner), st.dictionaries(st.one_of(st.text(max_size=6), st.integers()), inner, max_size=3)), max_leaves=12)
tables = st.one_of(values, st.fixed_dictionaries({}, optional={k: values for k in sum(KEYS.values(), [])}))


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.fixed_dictionaries({}, optional={name: tables for name in KEYS}))
def test_hypothesis_no_input_escapes_the_exception_tree(kwargs: dict[str, Any]) -> None:
    try:
        s = ellipsoid.Scenario(**kwargs)
    except ellipsoid.EllipsoidError as e:
        assert isinstance(e, ellipsoid.ScenarioError), type(e)
        assert "\n" not in str(e) or len(e.errors) > 1
        return
    assert math.isfinite(s.t_end) and len(s.sample_times) >= 1


@settings(max_examples=200, deadline=None)
@given(st.dictionaries(st.sampled_from([f"{t}.{k}" for t, ks in KEYS.items() for k in ks] + ["body", "x.y", "a..b", ""]), values, max_size=3))
def test_hypothesis_replace_stays_in_the_tree(changes: dict[str, Any]) -> None:
    try:
        oblate().replace(**changes)
    except ellipsoid.EllipsoidError as e:
        assert isinstance(e, ellipsoid.ScenarioError), type(e)


@settings(max_examples=60, deadline=None)
@given(st.one_of(st.none(), st.integers(), st.floats(), st.text(max_size=3), st.booleans()), st.one_of(st.none(), st.booleans(), st.integers()), st.one_of(st.none(), st.text(max_size=8), st.integers()))
def test_hypothesis_sweep_arguments_stay_in_the_tree(workers: Any, summaries_only: Any, errors: Any) -> None:
    base = oblate(output={"t_end": 0.001, "dt": 0.001})
    try:
        out = ellipsoid.sweep([base], workers=workers, summaries_only=summaries_only, errors=errors)
    except ellipsoid.EllipsoidError as e:
        assert isinstance(e, ellipsoid.ScenarioError), type(e)
        return
    assert len(out) == 1


def test_resource_module_is_available() -> None:
    """The memory test above limits a child's address space (POSIX only)."""
    assert resource.RLIMIT_AS is not None


# An argument of any type in any place of study(), Study's methods, Trajectory.plot /
# view / animate and sweep: an EllipsoidError or success, never a plain TypeError,
# ValueError, OverflowError or AttributeError (231 of 3,400 such calls escaped before).
arguments = st.one_of(
    scalars,
    st.sampled_from(["theta", "theta,path", "energy", "x.csv", "x.gif", "", -1, 2**64, 1.5, [], ["theta"], ("t",), {}]),
    st.lists(st.one_of(st.text(max_size=6), st.integers()), max_size=3),
)


def _tiny() -> ellipsoid.Scenario:
    return oblate(output={"t_end": 0.002, "dt": 0.001})


def _calls(tmp: Any) -> dict[str, Any]:
    traj = ellipsoid.simulate(_tiny())
    made = ellipsoid._ellipsoid.make_study(_tiny(), {"contact.friction": [0.2]})
    return {
        "study.axes": lambda v: ellipsoid.study(_tiny(), v),
        "study.outcomes": lambda v: ellipsoid.study(_tiny(), {"initial.psi_dot": [1.0]}, outcomes=v),
        "study.executor": lambda v: ellipsoid.study(_tiny(), {"initial.psi_dot": [1.0]}, v),
        "study.combine": lambda v: ellipsoid.study(_tiny(), {"initial.psi_dot": [1.0]}, combine=v),
        "study.workers": lambda v: ellipsoid.study(_tiny(), {"initial.psi_dot": [1.0]}, workers=v),
        "study.journal": lambda v: ellipsoid.study(_tiny(), {"initial.psi_dot": [1.0]}, journal=v if not isinstance(v, str) else os.path.join(tmp, v + "j")),
        "study.chunk_seconds": lambda v: ellipsoid.study(_tiny(), {"initial.psi_dot": [1.0]}, chunk_seconds=v),
        "study.out": lambda v: ellipsoid.study(_tiny(), {"initial.psi_dot": [1.0]}, out=v if not isinstance(v, str) else os.path.join(tmp, v)),
        "Study.run.start": lambda v: made.run(v),
        "Study.run.stop": lambda v: made.run(0, v),
        "Study.run.threads": lambda v: made.run(0, None, v),
        "Study.run.journal": lambda v: made.run(0, None, None, v if not isinstance(v, str) else os.path.join(tmp, v + "j")),
        "Study.point": lambda v: made.point(v),
        "Study.replace.base": lambda v: made.replace(base=v),
        "Study.replace.outcomes": lambda v: made.replace(outcomes=v),
        "Study.write.path": lambda v: made.write(v if not isinstance(v, str) else os.path.join(tmp, v), []),
        "Study.write.rows": lambda v: made.write(os.path.join(tmp, "w.csv"), v),
        "Study.write_bytes": lambda v: made.write_bytes(os.path.join(tmp, "b.parquet"), v),
        "Study.from_json": lambda v: type(made).from_json(v),
        "Study.load": lambda v: type(made).load(v),
        "plot.panels": lambda v: traj.plot(v),
        "plot.columns": lambda v: traj.plot(columns=v),
        "plot.ax": lambda v: traj.plot("theta", ax=v),
        "view.path": lambda v: traj.view(v if not isinstance(v, str) else os.path.join(tmp, v)),
        "view.title": lambda v: traj.view(title=v),
        "view.columns": lambda v: traj.view(columns=v),
        "animate.width": lambda v: traj.animate(os.path.join(tmp, "a.gif"), width=v, height=16, fps=1.0),
        "animate.fps": lambda v: traj.animate(os.path.join(tmp, "a.gif"), width=16, height=16, fps=v),
        "sweep.scenarios": lambda v: ellipsoid.sweep(v),
        "sweep.workers": lambda v: ellipsoid.sweep([_tiny()], v),
        "sweep.errors": lambda v: ellipsoid.sweep([_tiny()], errors=v),
    }


CALLS = [
    "study.axes", "study.outcomes", "study.executor", "study.combine", "study.workers", "study.journal",
    "study.chunk_seconds", "study.out", "Study.run.start", "Study.run.stop", "Study.run.threads",
    "Study.run.journal", "Study.point", "Study.replace.base", "Study.replace.outcomes", "Study.write.path",
    "Study.write.rows", "Study.write_bytes", "Study.from_json", "Study.load", "plot.panels", "plot.columns",
    "plot.ax", "view.path", "view.title", "view.columns", "animate.width", "animate.fps", "sweep.scenarios", "sweep.workers",
    "sweep.errors",
]


@pytest.fixture(scope="module")
def argument_calls(tmp_path_factory: Any) -> dict[str, Any]:
    pytest.importorskip("matplotlib")
    pytest.importorskip("pandas")
    calls = _calls(str(tmp_path_factory.mktemp("args")))
    assert sorted(calls) == sorted(CALLS)
    return calls


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(st.sampled_from(CALLS), arguments)
def test_hypothesis_argument_errors_are_ellipsoid_errors(argument_calls: dict[str, Any], call: str, value: Any) -> None:
    import matplotlib.pyplot as plt

    try:
        argument_calls[call](value)
    except ellipsoid.EllipsoidError:
        pass
    except Exception as e:  # noqa: BLE001 - the point of the test
        raise AssertionError(f"{call}({value!r}) raised {type(e).__name__}: {e}") from e
    finally:
        plt.close("all")


def test_numpy_integers_are_taken_wherever_an_integer_is(tmp_path: Any) -> None:
    """Every integer argument (an index, a count, a size) takes what `operator.index`
    takes — numpy's integers among them — as the same int would be; a bool (Python's or
    numpy's) and a float are still refused, naming the argument."""
    import numpy as np

    nutation = ellipsoid.load(REPO / "scenarios" / "nutation.toml", output={"t_end": 0.05, "dt": 0.01})
    egg = ellipsoid.Scenario(body={"a": 0.02, "c": 0.03, "mass": 0.06, "inertia": "uniform"},
                             initial={"theta": 0.0, "psi_dot": 100.0}, contact={"model": "frictionless"},
                             output={"t_end": 0.05, "dt": 0.01})
    res = ellipsoid.steady(egg, vary={"initial.psi_dot": np.linspace(40.0, 160.0, 5)})
    assert res.scenario(np.int32(0), 0.01, index=np.int64(3)) == res.scenario(0, 0.01, index=3)
    assert res.scenario("tilt", 0.01, index=np.uint8(4)) == res.scenario("tilt", 0.01, index=4)
    for bad in (True, np.bool_(True), 1.0, np.float64(1.0)):
        with pytest.raises(ellipsoid.ScenarioError, match="index = "):
            res.scenario(0, 0.01, index=bad)
    with pytest.raises(ellipsoid.ScenarioError, match=r"index = np.int64\(5\): must be a row number from 0 to 4"):
        res.scenario(0, 0.01, index=np.int64(5))
    assert len(ellipsoid.sweep([nutation, nutation], workers=np.int64(2))) == 2
    df = ellipsoid.study(nutation, {"initial.psi_dot": [40.0, 60.0, 80.0]}, workers=np.int64(2))
    assert len(df) == 3
    from ellipsoid._ellipsoid import make_study

    made = make_study(nutation, {"initial.psi_dot": [40.0, 60.0, 80.0]}, None, None)
    rows = made.run(np.int64(1), np.int32(3), np.int64(1))
    assert [r[0] for r in rows] == [1, 2]
    assert made.point(np.int64(2)) == made.point(2)
    traj = ellipsoid.simulate(nutation)
    frames = traj.animate(tmp_path / "a.gif", width=np.int64(64), height=np.int16(48), fps=np.int64(10))
    assert frames == traj.animate(tmp_path / "b.gif", width=64, height=48, fps=10)
    table = ellipsoid.precision(REPO / "scenarios" / "paper-sliding.toml", quick=True, t_end=0.05, repeats=np.int64(1))
    assert np.all(table.repeats >= 1)
    for call in (lambda v: ellipsoid.sweep([nutation], workers=v), lambda v: made.point(v),
                 lambda v: traj.animate(tmp_path / "c.gif", width=v)):
        for bad in (np.bool_(True), np.float64(2.0)):
            with pytest.raises(ellipsoid.ScenarioTypeError, match="expected an integer"):
                call(bad)


# ---------------------------------------------------------- issue 48, items 6 and 7


@pytest.mark.parametrize(
    ("call", "cls", "match"),
    [
        (lambda: ellipsoid.steady(oblate(), family=3), ellipsoid.ScenarioTypeError, r"family: expected a str, found int"),
        (lambda: ellipsoid.steady(oblate(), solve=None), ellipsoid.ScenarioTypeError, r"solve: expected a str, found NoneType"),
        (lambda: ellipsoid.steady(oblate(), vary={3: [1.0]}), ellipsoid.ScenarioTypeError, r"a key of vary is a dotted scenario key"),
        (lambda: ellipsoid.steady(oblate(), vary={"initial.psi_dot": ["fast"]}), ellipsoid.ScenarioTypeError, r"vary\['initial.psi_dot'\]: expected a 1-D array of numbers"),
        (lambda: ellipsoid.steady(oblate(), vary={"initial.psi_dot": [float("nan")]}), ellipsoid.ScenarioError, r"initial.psi_dot"),
        (lambda: ellipsoid.steady(oblate(), vary={"initial.bogus": [1.0]}), ellipsoid.ScenarioError, r"initial.bogus"),
        (lambda: ellipsoid.steady(oblate()).scenario(0, "small"), ellipsoid.ScenarioTypeError, r"eps: expected a number, found str"),
        (lambda: ellipsoid.steady(oblate()).scenario(-1, 1e-3), ellipsoid.ScenarioError, r"mode = -1"),
        (lambda: ellipsoid.linearize(oblate(), state="up"), ellipsoid.ScenarioTypeError, r"state: expected a sequence of 6 numbers"),
        (lambda: ellipsoid.linearize(oblate(), state=[0, 0, 1, 0, 0, "x"]), ellipsoid.ScenarioTypeError, r"state: expected a sequence of 6 numbers"),
        (lambda: ellipsoid.linearize(oblate(), state=[0.0, 0.0, 1e300, 0.0, 0.0, 0.0]), ellipsoid.ScenarioError, r"squared length"),
        (lambda: ellipsoid.linearize(oblate(), state=[0.0, 0.0, 1.0, 1e300, 0.0, 0.0]), ellipsoid.ScenarioError, r"analysed up to"),
        (lambda: ellipsoid.linearize(oblate(), state=[0.0, 0.0, 1.0, math.nan, 0.0, 0.0]), ellipsoid.ScenarioError, r"must be finite"),
        (lambda: ellipsoid.precision(oblate(), quick="yes"), ellipsoid.ScenarioTypeError, r"quick: expected True or False, found str"),
        (lambda: ellipsoid.precision(oblate(), quick=True, out=5), ellipsoid.ScenarioTypeError, r"out: expected a path"),
        (lambda: ellipsoid.simulate(oblate(output={"t_end": 0.01, "dt": 0.01}))[3], ellipsoid.ScenarioTypeError, r"a column is named by a str, found int"),
        (lambda: ellipsoid.simulate(oblate(output={"t_end": 0.01, "dt": 0.01}))["nope"], ellipsoid.ScenarioKeyError, r"nope.*not a column of this trajectory"),
        (lambda: ellipsoid.simulate(oblate(output={"t_end": 0.01, "dt": 0.01})).sol("soon"), ellipsoid.ScenarioTypeError, r"t: expected times"),
        (lambda: ellipsoid.simulate(oblate(output={"t_end": 0.01, "dt": 0.01})).to_csv(None), ellipsoid.ScenarioTypeError, r"path: expected a path"),
        (lambda: ellipsoid.simulate(oblate(output={"t_end": 0.01, "dt": 0.01})).to_hdf5(3.5), ellipsoid.ScenarioTypeError, r"path: expected a path"),
    ],
)
def test_argument_errors_are_in_the_tree(call: Any, cls: type, match: str) -> None:
    """Issue 48: some argument errors were pyo3's or numpy's plain TypeError, ValueError or
    KeyError. Each is now an EllipsoidError subclass that is also the built-in class it
    was (ScenarioError a ValueError, ScenarioTypeError a TypeError, ScenarioKeyError a
    KeyError), so `except ValueError` (TypeError, KeyError) goes on working."""
    with pytest.raises(cls, match=match) as info:
        call()
    assert isinstance(info.value, ellipsoid.EllipsoidError)
    builtin = {ellipsoid.ScenarioTypeError: TypeError, ellipsoid.ScenarioKeyError: KeyError}.get(cls, ValueError)
    assert isinstance(info.value, builtin)


def test_scenario_key_error_is_a_scenario_error_and_a_key_error() -> None:
    assert issubclass(ellipsoid.ScenarioKeyError, ellipsoid.ScenarioError)
    assert issubclass(ellipsoid.ScenarioKeyError, KeyError)
    traj = ellipsoid.simulate(oblate(output={"t_end": 0.01, "dt": 0.01}))
    with pytest.raises(KeyError):
        traj["normal_force_peg"]
    assert traj["theta"] is not None


def test_sections_and_spheres_are_bounded_at_validation() -> None:
    """Issue 48, items 6a and 7b, from Python: the sections keep at most 10⁶ points
    together; a contact sphere's radius and centre are bounded by the body's size."""
    section = lambda k: {"name": f"s{k}", "column": "theta", "crosses": 0.1, "max_points": 1_000_000}  # noqa: E731
    with pytest.raises(ellipsoid.ScenarioError, match=r"section\[1\]\.max_points = 1000000: the sections together keep at most 1000000 points") as info:
        oblate(section=[section(k) for k in range(16)])
    assert info.value.key == "section[1].max_points"
    sphere = {"name": "peg", "center": [0.0, 0.0, 0.02], "radius": 1e6}
    with pytest.raises(ellipsoid.ScenarioError, match=r"body\.sphere\[0\]\.radius = \S+: a sphere's radius must be from 1e-6 to 1e3 times") as info:
        oblate().replace(**{"body.sphere": [sphere]})
    assert info.value.key == "body.sphere[0].radius"


def test_animate_refuses_more_frames_than_it_draws(tmp_path: Any) -> None:
    """Issue 48, item 6c: a speed at which the run needs more than 2000 frames is a
    ScenarioError naming the speed that fits, nothing written (1e-300 wrote a GIF of no
    frame)."""
    traj = ellipsoid.simulate(oblate(output={"t_end": 0.5, "dt": 0.01}))
    for speed in (1e-300, 0.001):
        path = tmp_path / "a.gif"
        with pytest.raises(ellipsoid.ScenarioError, match=r"more than the 2000 an animation may have; give a speed of at least 0.00626"):
            traj.animate(path, width=16, height=16, speed=speed)
        assert not path.exists()
