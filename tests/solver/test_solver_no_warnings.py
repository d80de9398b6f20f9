"""The interpreted core (numpy backend, or numba with NUMBA_DISABLE_JIT=1) raises no numpy
RuntimeWarning where a Newton iterate diverges on relieved flanks: the point's status says so."""
from __future__ import annotations

import re
import warnings
from pathlib import Path

import pytest

from beveloid import tca
from beveloid.pair import Pair
from beveloid.solver import Solver
from beveloid.spec import spec_from_toml_bytes

ROOT = Path(__file__).resolve().parents[2]
RELIEFS = ('tip_relief_um = 20.0\ntip_relief_height_mm = 2.0\ntip_relief_shape = "linear"\nend_relief_um = 15.0\n'
           'end_relief_length_mm = 8.0\nlead_crowning_um = 10.0\n')


@pytest.mark.slow
def test_numpy_backend_on_relieved_flanks_is_silent():
    text = (ROOT / "examples" / "case1.toml").read_text()
    for member in ("pinion", "gear"):
        text = re.sub(rf"^\[{member}\][^\n]*\n", lambda m: m.group(0) + RELIEFS, text, count=1, flags=re.M)
    pair = Pair.from_spec(spec_from_toml_bytes(text.encode()))
    with warnings.catch_warnings(record=True) as caught:
        # before: ~90 overflow / invalid-value warnings from the kernels, at 10 positions as at 20
        warnings.simplefilter("always")
        result = tca.analyze(pair, tca.Options(positions=10), solver=Solver("numpy"))
    assert [str(w.message) for w in caught] == []
    statuses = {s for fr in result.flanks.values() for s in fr.status}
    assert "ok" in statuses, statuses
