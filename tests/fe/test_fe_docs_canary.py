"""The FE numbers the docs quote (docs/loaded_contact.md 9.7, docs/validation.md 10) are recorded in
docs/numbers.json by ``python docs/readme_numbers.py --record fe_tooth,rating`` (minutes: the default FE
mesh); each record holds a canary, the same analyses on the coarse FE tooth (``fe_canary``).  Here the
canary is recomputed from the session's coarse FE data: a change of the code that moves the FE tooth,
the LTCA or the rating fails this test until the numbers are recorded again (tests/docs checks that
the pages quote the record)."""
from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

from beveloid.fe import cache

pytestmark = pytest.mark.xdist_group(name="fe_case1")

REPO = Path(__file__).resolve().parents[2]


def _numbers():
    spec = importlib.util.spec_from_file_location("readme_numbers", REPO / "docs" / "readme_numbers.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_recorded_fe_numbers_are_the_codes(coarse_teeth, monkeypatch):
    numbers = _numbers()
    # the session's coarse FE data (tests/fe/conftest.py, every size x 3) is the canary's FE tooth
    monkeypatch.setattr(cache, "cached_tooth_data", lambda pair, member, *a, **k: (coarse_teeth[member], "hit"))
    now = numbers.fe_canary()
    rec = json.loads((REPO / "docs" / "numbers.json").read_text())
    for group in ("fe_tooth", "rating"):
        stale = {k: (v, now[k]) for k, v in rec[group]["canary"].items() if v != pytest.approx(now[k], rel=5e-3)}
        assert set(rec[group]["canary"]) == set(now) and not stale, (
            f"docs/numbers.json's {group} numbers were made by other code (recorded, now: {stale}): rerun "
            f"`python docs/readme_numbers.py --record {group}` and paste what `--print` shows")
