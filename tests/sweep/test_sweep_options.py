"""The sweep has the shape of the other analyses: a frozen, self-validating Options, analyze(pair, options)
returning a frozen result with to_json(); its chunks are drawn and solved on their own
(sweep.solve_chunk, a NamedTuple back) and give the same numbers however they are run."""
from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from beveloid import parallel, sweep
from beveloid.errors import OptionError
from beveloid.solver import Solver

TIMING = ("seconds", "seconds_total", "us_per_point", "us_per_point_total")


@pytest.mark.parametrize("changes, needle", [
    ({"flank": "middle"}, "flank = 'middle': must be one of left, right"),
    ({"samples": 0}, "samples = 0"),
    ({"positions": 1}, "positions = 1"),
    ({"seed": -1}, "seed = -1: must be an integer from 0"),
    ({"chunk": 0}, "chunk = 0: must be an integer from 1"),
    ({"ranges": {"dx_mm": -0.1}}, "ranges.dx_mm = -0.1: must be >= 0"),
    ({"ranges": {"tilt_deg": 0.1}}, "ranges.tilt_deg = 0.1: not an error"),
    ({"ranges": {"dx_mm": 6.0}, "nominal": {"dx_mm": 5.0}}, "|nominal| + half-width must be <= 10"),
])
def test_options_refuse_bad_values_in_one_line(changes, needle):
    with pytest.raises(ValueError) as info:
        sweep.Options(**changes)
    assert needle in str(info.value) and "\n" not in str(info.value)
    if "samples" not in changes and "positions" not in changes:
        assert isinstance(info.value, OptionError)


def test_options_are_frozen_and_complete():
    o = sweep.Options(ranges={"dz_mm": 0.1}, nominal={"dx_mm": 0.2})
    assert o.ranges == dict(sweep.DEFAULT_RANGES, dz_mm=0.1)
    assert o.nominal == {k: (0.2 if k == "dx_mm" else 0.0) for k in sweep.DEFAULT_RANGES}
    with pytest.raises(dataclasses.FrozenInstanceError):
        o.samples = 3


def test_analyze_is_the_sweep_and_runs_anywhere_the_same(pair1):
    options = sweep.Options(samples=9, positions=6, seed=3, ranges={"dx_mm": 0.2}, chunk=4)
    serial = sweep.analyze(pair1, options)
    with pytest.raises(dataclasses.FrozenInstanceError):
        serial.samples = 1
    with parallel.executor(workers=1) as ex:  # the chunks through an executor: drawn on their own
        chunked = sweep.analyze(pair1, options, executor=ex)
    direct = sweep.analyze(pair1, sweep.Options(flank="right", samples=9, positions=6, seed=3, ranges={"dx_mm": 0.2}, chunk=9))
    for other in (chunked, direct):
        np.testing.assert_array_equal(other.errors, serial.errors)
        np.testing.assert_array_equal(other.status_codes, serial.status_codes)
        np.testing.assert_array_equal(other.te_peak_to_peak, serial.te_peak_to_peak)
    a = {k: v for k, v in json.loads(json.dumps(serial.to_json(), allow_nan=False)).items() if k not in TIMING}
    b = {k: v for k, v in chunked.to_json().items() if k not in TIMING}
    assert a == json.loads(json.dumps(b))


def test_a_chunk_is_a_named_record_of_its_own_sets(pair1):
    options = sweep.Options(samples=5, positions=4, seed=8)
    whole = sweep.analyze(pair1, options)
    grid, aligned = sweep.aligned_path(pair1.geometry, "right", 4)
    np.testing.assert_array_equal(grid, whole.pinion_angles)
    task = sweep.ChunkTask(pair1.geometry, "right", 2, 5, options.ranges, 8, options.nominal, grid, Solver(), aligned)
    part = sweep.solve_chunk(task)
    assert isinstance(part, sweep.ChunkSolution)
    np.testing.assert_array_equal(part.errors, whole.errors[2:5])
    np.testing.assert_array_equal(part.status, whole.status_codes[2:5])
    np.testing.assert_array_equal(part.te_peak_to_peak, whole.te_peak_to_peak[2:5])
    np.testing.assert_array_equal(part.pinion_shift_mm, whole.pinion_shift_mm[2:5])


def test_progress_is_the_one_protocol(pair1):
    """The sweep reports progress(done, total, what), the shape of every long computation (beveloid.progress)."""
    from beveloid.progress import Bar, Lines

    calls = []
    sweep.analyze(pair1, sweep.Options(samples=6, positions=5, chunk=2), progress=lambda *a: calls.append(a))
    assert [c[:2] for c in calls] == [(2, 6), (4, 6), (6, 6)] and {c[2] for c in calls} == {"error sets"}
    import io

    out = io.StringIO()
    bar, lines = Bar(out), Lines(out, prefix="x: ", counts=True)
    bar(3, 6, "error sets"), bar(6, 6, "error sets"), lines(1, 3, "meshing"), lines(5, None, "ccx: a line")
    text = out.getvalue()
    assert "3/6 error sets" in text and "6/6 error sets" in text and "x: [1/3] meshing\nx: ccx: a line\n" in text
