"""The five assembly errors have one table (beveloid.assembly_errors): the spec, the CLI flags,
the sweep's ranges and the JSON read it, in the generated kernels' order."""
import math

import numpy as np

from beveloid import assembly_errors as ae
from beveloid import cli, sweep, tca
from beveloid.generated import layouts
from beveloid.spec import KEY_DOCS


def test_one_table_in_the_kernels_order():
    assert tuple(e.field for e in ae.ERRORS) == layouts.AssemblyErrors._fields == tca.ERROR_NAMES
    assert tuple(KEY_DOCS["misalignment"]) == ae.KEYS
    for e in ae.ERRORS:
        d = KEY_DOCS["misalignment"][e.key]
        assert (d.lo, d.hi, d.unit) == (-e.limit, e.limit, e.unit)
    assert tuple(sweep.DEFAULT_RANGES) == ae.KEYS


def test_conversions_round_trip_in_the_users_units():
    user = {"dx_mm": 0.3, "dy_mm": -0.2, "dz_mm": 0.1, "vertical_deg": 0.25, "horizontal_deg": -0.04}
    v = ae.to_layout(user)
    assert np.allclose(v, [0.3, -0.2, 0.1, math.radians(0.25), math.radians(-0.04)], rtol=0, atol=1e-15)
    back = ae.from_layout(v)
    assert back.keys() == user.keys() and all(math.isclose(back[k], user[k], rel_tol=1e-14) for k in user)
    assert ae.label(user) == "dx=0.3 mm, dy=-0.2 mm, dz=0.1 mm, vertical=0.25 deg, horizontal=-0.04 deg"


def test_tca_flags_come_from_the_table():
    parser = cli.build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction").choices["tca"]
    flags = {s for a in sub._actions for s in a.option_strings}
    assert {e.flag for e in ae.ERRORS} <= flags
    args = sub.parse_args(["x.toml", "--vertical", "0.1", "--dx", "-0.5"])
    assert (args.vertical_deg, args.dx_mm, args.dz_mm) == (0.1, -0.5, None)
