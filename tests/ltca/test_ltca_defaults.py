"""The LTCA at its defaults on designs unlike case 1: Hertz, continuity over the cycle, the
convergence indicator, validity, short requests.  Each check is a physical property or a contract."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from beveloid import curvature, ltca
from beveloid.ltca.mechanics import hertz
from beveloid.pair import Pair


def _spec(**changes):
    """case 1 with ``section__key`` changes (a mapping as tomllib gives it)."""
    import tomllib
    from pathlib import Path

    d = tomllib.loads((Path(__file__).resolve().parents[2] / "examples" / "case1.toml").read_text())
    for key, value in changes.items():
        section, name = key.split("__")
        d[section][name] = value
    return d


DESIGNS = {
    # m_n 3, z 26/60, shaft angle 28.4 deg, offset 160.4 mm, cone angles 3.48/0.57 deg (issue's ranges)
    "m3 short ellipse": dict(pair__normal_module_mm=3.0, pair__shaft_angle_deg=28.4, pair__offset_mm=160.4,
                             pinion__teeth=26, pinion__cone_angle_deg=3.48, pinion__helix_angle_deg=-16.0,
                             pinion__profile_shift=0.3, gear__teeth=60, gear__cone_angle_deg=0.57),
    "m2 small module": dict(pair__normal_module_mm=2.0, pair__offset_mm=229.0 / 3),
    "m10 large module": dict(pair__normal_module_mm=10.0, pair__offset_mm=229.0 * 10 / 6),
}


@pytest.mark.parametrize("name, flank", [("m3 short ellipse", "left"), ("m2 small module", "left"),
                                         ("m10 large module", "left"), ("m10 large module", "right")])
def test_default_grid_holds_hertz(name, flank):
    """p_max of every loaded pair clear of the flank edges within 5 % of Hertz (the pair's own load and
    the relative curvature at its tangency) at the default grid, and the indicator says converged."""
    pair = Pair.from_spec(_spec(**DESIGNS[name]))
    torque = 100.0 * (pair.geometry.normal_module_mm / 6) ** 2
    r = ltca.analyze(pair, ltca.LoadCase(torque), ltca.Options(flank=flank, positions=5, tooth_model="plate"))
    checked = 0
    for j in range(5):
        for k in range(3):
            load = r.pair_load_n[j, k]
            if not load > 0 or np.isfinite(r.pair_edge_max_pressure_mpa[j, k]):
                continue
            rc = curvature.relative_curvature(pair.geometry, flank, r.tangency_unknowns[j, k],
                                              r.pair_pinion_angle[j, k], pair.errors)
            a_small, a_large = np.linalg.eigvalsh(rc.H) / 2
            ref = hertz.hertz_point_contact(a_small, a_large, float(load), ltca.Material().e_star_mpa)
            assert abs(r.pair_surface_max_pressure_mpa[j, k] / ref.max_pressure_mpa - 1) < 0.05, (j, k)
            assert r.pair_max_pressure_mpa[j, k] == r.pair_surface_max_pressure_mpa[j, k]
            assert abs(r.pair_hertz_max_pressure_mpa[j, k] / ref.max_pressure_mpa - 1) < 1e-9  # what the JSON says
            checked += 1
    assert checked >= 2
    ok = np.isfinite(r.convergence.load_change)
    assert ok.any() and np.all(r.convergence.load_change[ok] < 0.01)


def test_pair_loads_continuous_over_the_cycle():
    """Crowned case 1 at 200 N m: no pair's load drops to 0 and back between neighbouring positions.
    Here the rigid TCA once left one loaded pair's tangency unsolved (FAILED after the path's repeated
    angle, tests/solver/test_solver_repeated_angle.py) and the cycle interpolated its neighbours; it now
    solves every pair at every position."""
    d = _spec(pinion__profile_crowning_um=10.0, pinion__lead_crowning_um=10.0, gear__profile_crowning_um=10.0,
              gear__lead_crowning_um=10.0)
    pair = Pair.from_spec(d)
    r = ltca.analyze(pair, ltca.LoadCase(200.0), ltca.Options(positions=12, tooth_model="plate"))
    assert all(s == "ok" for s in r.status)
    from beveloid.ltca.passes.cycle import Setup
    from beveloid.solver import Solver

    setup = Setup(pair.geometry, "right", pair.errors, 12, 3, Solver())
    assert setup.solved.all() and not setup.interpolated.any()
    F = r.pair_load_n
    total = F.sum(axis=1)
    for k in range(F.shape[1]):
        for j in range(1, F.shape[0] - 1):
            dropped = F[j, k] < 0.2 * min(F[j - 1, k], F[j + 1, k])
            assert not dropped, (j, k, F[j - 1:j + 2, k])
    # the largest step of a pair's load between neighbouring positions is a fraction of the total
    assert np.max(np.abs(np.diff(F, axis=0))) < 0.6 * total.max()


def test_one_and_two_positions_accepted(capsys):
    from beveloid import cli

    pair = Pair.example("case1")
    r = ltca.analyze(pair, ltca.LoadCase(50.0), ltca.Options(positions=1, tooth_model="plate"))
    assert r.status == ("ok",) and math.isnan(r.loaded_te_peak_to_peak)
    from pathlib import Path

    case1 = Path(__file__).resolve().parents[2] / "examples" / "case1.toml"
    rc = cli.main(["ltca", str(case1), "--torque-nm", "50", "--positions", "2", "--json", "--tooth-model", "plate"])
    out, err = capsys.readouterr()
    import json

    data = json.loads(out)
    assert rc == 0 and data["loaded_transmission_error_peak_to_peak_urad"] is None
    assert "not available" in data["statistics_note"]


def test_extreme_torque_leaves_the_models_validity():
    r = ltca.analyze(Pair.example("case1"), ltca.LoadCase(1e6), ltca.Options(positions=1, tooth_model="plate"))
    assert r.validity[0] is not None and "elastic" in r.validity[0]
    assert any("validity" in w for w in r.warnings())
    low = ltca.analyze(Pair.example("case1"), ltca.LoadCase(50.0), ltca.Options(positions=1, tooth_model="plate"))
    assert low.validity == (None,)
    # a reason shared by positions that leave for different sets of reasons is named once
    mixed = dataclasses.replace(low, validity=(r.validity[0], r.validity[0].split("; ")[0]))
    line = next(w for w in mixed.warnings() if "validity" in w)
    for why in r.validity[0].split("; "):
        assert line.count(why) == 1, line


@pytest.mark.parametrize("kwargs, needle", [
    (dict(positions=0), "positions = 0: must be"),
    (dict(pairs=4), "pairs = 4: must be an odd"),
    (dict(grid=(2, 40)), "grid = (2, 40): must be"),
    (dict(flank="top"), "flank = 'top': must be"),
])
def test_options_validate_themselves(kwargs, needle):
    with pytest.raises(ValueError, match=None) as exc:
        ltca.Options(**kwargs)
    assert needle in str(exc.value) and "\n" not in str(exc.value)


@pytest.mark.parametrize("kwargs, needle", [
    (dict(torque_nm=0.0), "torque_nm = 0.0: must be"),
    (dict(torque_nm=[100.0, -5.0]), "torque_nm = "),
    (dict(torque_nm=10.0, errors=(0.0, 0.0)), "errors = (0.0, 0.0): must be"),
    (dict(torque_nm=10.0, errors=(0.0, 0.0, float("nan"), 0.0, 0.0)), "errors = "),
])
def test_the_load_case_validates_itself(kwargs, needle):
    from beveloid.errors import OptionError

    with pytest.raises(OptionError) as exc:
        ltca.LoadCase(**kwargs)
    assert needle in str(exc.value) and "\n" not in str(exc.value)


def test_the_load_case_is_one_torque_or_a_map_and_its_errors_default_to_the_pairs():
    from beveloid.pair import Pair

    pair = Pair.example("case1")
    one = ltca.LoadCase(200)
    assert one.torque_nm == 200.0 and not one.is_map and one.torques_nm == (200.0,)
    assert np.array_equal(one.error_sets(pair), pair.errors[None, :])
    tmap = ltca.LoadCase([50, 100], errors=(0.01, 0, 0, 0, 0))
    assert tmap.is_map and tmap.torques_nm == (50.0, 100.0) and tmap.errors == (0.01, 0.0, 0.0, 0.0, 0.0)
    box = ltca.LoadCase(100.0, errors=[(0, 0, 0, 0, 0), (0.02, 0, 0, 0, 0)])
    assert box.is_map and box.error_sets(pair).shape == (2, 5)
    with pytest.raises(TypeError):
        ltca.analyze(pair, ltca.Options())  # the options in place of the load case
    with pytest.raises(TypeError):
        ltca.Options(torque_nm=10.0)  # the load is no option any more


def test_memory_estimate_refuses_what_does_not_fit():
    big = ltca.Options(grid=(201, 201), positions=3)
    assert big.memory_bytes() > 3e10  # three dense 40401-cell blocks
    with pytest.raises(ValueError, match="needs about"):
        big.check_memory(available=16e9)
    ltca.Options().check_memory(available=2e9)


def test_the_grid_warning_names_each_change_or_says_it_was_not_compared():
    """A position not converged on its grid because of a pair's load, where the surface peak was not
    compared (an edge peak): the warning gives the load change and says the peak was not compared,
    no "up to - %"."""
    from types import SimpleNamespace

    from beveloid.ltca.results.result import Convergence, LTCAResult

    fake = SimpleNamespace(convergence=Convergence(np.array([np.nan, 0.01, np.nan]), np.array([0.013, 0.0, 0.002])),
                           converged=np.array([True, True, True]), status=("ok",) * 3, validity=(None,) * 3,
                           pair_edge_max_pressure_mpa=np.full((3, 3), np.nan))
    (line,) = LTCAResult.warnings(fake)
    assert "grid not converged at 1 of 3 positions" in line
    assert "peak pressure not compared there" in line and "pair load change up to 1.3 % (tolerance 1 %)" in line
    assert "- %" not in line
