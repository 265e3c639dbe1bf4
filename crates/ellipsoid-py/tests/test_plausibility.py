"""Plausibility warnings (docs/scenarios.md, "Plausibility warnings"): a valid value that is
likely a unit slip is an `ellipsoid.PlausibilityWarning` (a UserWarning) with the command
line's message; the run goes on; `warnings.filterwarnings` silences it or makes it raise.
No bundled scenario warns."""

from __future__ import annotations

import warnings
from typing import Any

import pytest

import ellipsoid
from conftest import BUNDLED, scenario_id


def egg(body: dict[str, Any] | None = None, initial: dict[str, Any] | None = None) -> ellipsoid.Scenario:
    """The issue's egg (a = b = 2 cm, c = 3 cm, 60 g, laid at 80°, 135 rad/s), a short run."""
    return ellipsoid.Scenario(
        body=dict(a=0.02, c=0.03, mass=0.06, inertia="uniform") | (body or {}),
        initial=(initial or dict(theta_deg=80.0, phi_dot=135.0)),
        contact=dict(model="sliding", friction=0.3),
        output=dict(t_end=0.01, dt=0.005),
    )


def caught(call: Any) -> tuple[Any, list[warnings.WarningMessage]]:
    """`call()`'s result and every warning it issued (all shown, none filtered)."""
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        result = call()
    return result, list(seen)


def test_the_category_is_a_user_warning_of_the_package() -> None:
    assert issubclass(ellipsoid.PlausibilityWarning, UserWarning)
    assert not issubclass(ellipsoid.PlausibilityWarning, ellipsoid.EllipsoidError)
    assert ellipsoid.PlausibilityWarning.__module__ == "ellipsoid"
    assert "PlausibilityWarning" in ellipsoid.__all__


def test_the_issues_three_slips_warn_and_the_run_goes_on() -> None:
    slips = egg(body=dict(mass=60), initial=dict(theta=80, phi_dot=1600))
    traj, seen = caught(lambda: ellipsoid.simulate(slips))
    assert traj.success, traj.message
    assert [w.category for w in seen] == [ellipsoid.PlausibilityWarning] * 3
    lines = [str(w.message) for w in seen]
    assert "warning: initial.theta = 80: 80 rad is more than 2π (12.7 turns): degrees? use theta_deg = 80" in lines[0]
    assert "warning: body.mass = 60: the density mass / ((4/3)π a b c) is 1.19e6 kg/m³" in lines[1]
    assert "grams? 60 g is mass = 0.06" in lines[1]
    assert "warning: initial.phi_dot = 1600: the initial spin energy" in lines[2]
    assert lines[2].endswith("rpm typed as rad/s? 1600 rpm is 168 rad/s")
    # Attributed to the caller's line, not to the package.
    assert all(w.filename == __file__ for w in seen), [w.filename for w in seen]


def test_a_plausible_scenario_does_not_warn() -> None:
    _, seen = caught(lambda: ellipsoid.simulate(egg()))
    assert seen == []


def test_filterwarnings_silences_them_or_makes_them_raise() -> None:
    slip = egg(body=dict(mass=60))
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        warnings.filterwarnings("ignore", category=ellipsoid.PlausibilityWarning)
        assert ellipsoid.simulate(slip).success
    assert list(seen) == []
    with warnings.catch_warnings():
        warnings.filterwarnings("error", category=ellipsoid.PlausibilityWarning)
        with pytest.raises(ellipsoid.PlausibilityWarning, match="body.mass = 60"):
            ellipsoid.simulate(slip)
    with pytest.warns(ellipsoid.PlausibilityWarning, match="body.mass = 60"):
        ellipsoid.simulate(slip)


def test_changes_and_every_entry_point_warn() -> None:
    # A change by keyword names its override; sweep and check warn too.
    _, seen = caught(lambda: ellipsoid.simulate(egg(), **{"initial.phi_dot": 1600}))
    assert len(seen) == 1 and "initial.phi_dot = 1600" in str(seen[0].message), seen
    _, seen = caught(lambda: ellipsoid.sweep([egg(), egg(body=dict(mass=60))]))
    assert [("body.mass = 60" in str(w.message)) for w in seen] == [True]
    _, seen = caught(lambda: ellipsoid.check(egg(initial=dict(theta=80, phi_dot=1.0))))
    assert len(seen) == 1 and "initial.theta = 80" in str(seen[0].message), seen


@pytest.mark.parametrize("path", BUNDLED, ids=scenario_id)
def test_no_bundled_scenario_warns(path: Any) -> None:
    with warnings.catch_warnings():
        warnings.filterwarnings("error", category=ellipsoid.PlausibilityWarning)
        ellipsoid.check(path)


def test_a_study_warns_once_for_each_slip_among_its_points() -> None:
    """Issue 47: `ellipsoid.study` warns before it runs, each distinct slip once: here θ
    typed in degrees at two of an axis's values (80 and 60 rad), and the mass in grams on
    the other axis, whatever the number of points that carry them; a plausible study
    does not warn."""
    base = egg(initial=dict(theta=0.5, phi_dot=10.0))
    axes = {"initial.theta": [0.5, 80.0, 60.0, 80.0], "body.mass": [0.06, 60.0]}
    df, seen = caught(lambda: ellipsoid.study(base, axes, workers=1))
    assert len(df) == 8 and set(df["status"]) <= {"completed", "slip_stopped"}
    texts = [str(w.message) for w in seen if w.category is ellipsoid.PlausibilityWarning]
    assert len(texts) == 3, texts
    assert sum("initial.theta = 80" in t for t in texts) == 1
    assert sum("initial.theta = 60" in t for t in texts) == 1
    assert sum("body.mass = 60" in t for t in texts) == 1
    _, seen = caught(lambda: ellipsoid.study(base, {"initial.theta": [0.5, 0.6]}, workers=1))
    assert not [w for w in seen if w.category is ellipsoid.PlausibilityWarning]
