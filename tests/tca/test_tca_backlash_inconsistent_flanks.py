"""The backlash where the two flanks' reference contacts open the gear the same way (one of them is no contact
of this tooth space): a failed backlash with its reason, not an exception.  Found by the slow tier's
rotating-seed CLI fuzz (seed 18508): `beveloid tca` crashed with "both flanks open in the same direction";
that spec is tests/tca/test_tca_reference_continuation.py's FAR_ROOT."""
from __future__ import annotations

import importlib
import tomllib

from beveloid import tca
from beveloid.pair import Pair
from beveloid.spec import example_text


def test_flanks_that_open_the_same_way_give_a_failed_backlash(monkeypatch):
    module = importlib.import_module("beveloid.tca.backlash")  # the module (tca.backlash is its function)
    geom = Pair.from_spec(tomllib.loads(example_text("case1"))).geometry
    monkeypatch.setattr(module, "first_touch_sign", lambda geom, flank: 1.0)
    module.whole_pitches.cache_clear()
    try:
        b = tca.backlash(geom)
    finally:
        module.whole_pitches.cache_clear()
    assert b.um is None and b.status == "failed" and "two-flank contact" in b.reason
