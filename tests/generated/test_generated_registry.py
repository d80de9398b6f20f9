"""The generated kernels: a model variant through the registry (helpers: generated_support.py, fixtures: conftest.py)."""
from __future__ import annotations

import ast
import functools
import importlib
import inspect
import os
import re
import shutil
import subprocess
import sys
import tokenize
import types
import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from beveloid.derivations import codegen, kernels
from generated_support import *  # noqa: F401,F403  (the shared samplers and comparisons)


# One xdist worker runs these modules: their sympy models and renderings (~15 s) are built once per process.
pytestmark = pytest.mark.xdist_group("generated")

# ---------------------------------------------------------------------------------------
# 9. a model variant through the registry
# ---------------------------------------------------------------------------------------

SHIFT = np.array([0.1, -0.05, 0.2])
VARIANT_PACKAGE = "beveloid_variant_kernels"


def _shifted_surface_model():
    """The committed model with every point moved by the constant vector SHIFT (normals unchanged)."""
    original = kernels.SURFACE_MODELS[MODEL]

    def tooth_surface(sigma):
        point, normal, roll = original.tooth_surface(sigma)
        return point + sp.Matrix(SHIFT), normal, roll

    return types.SimpleNamespace(tooth_surface=tooth_surface, PARAMETERS=getattr(original, "PARAMETERS", ()),
                                 __name__="beveloid.derivations.shifted_surface")


@pytest.fixture(scope="module")
def variant(tmp_path_factory, specs, rendered, rendered_by):
    """The package `beveloid derive` writes with a "shifted" model registered next to MODEL,
    rendered through kernels.module_specs / kernels.glue_files and imported from a temp dir.

    The specs are kernels.module_specs(models)'s: its surface modules, one per model, then the
    modules that do not depend on the models (their builders take no registry), which are the
    session's own spec objects here, so their renderings are the session's (``rendered_by``)."""
    models = {MODEL: kernels.SURFACE_MODELS[MODEL], "shifted": _shifted_surface_model()}
    shared = list(specs.values())[len(kernels.SURFACE_MODELS):]
    variant_specs = [specs[f"surface_{MODEL}"], kernels.surface_module("shifted", models["shifted"]), *shared]
    files = codegen.generate(None, variant_specs, extra=kernels.glue_files(models), rendered_by=rendered_by)
    package = tmp_path_factory.mktemp("variant") / VARIANT_PACKAGE
    codegen.write(package, files)
    with pytest.MonkeyPatch.context() as mp:
        mp.syspath_prepend(str(package.parent))
        try:
            modules = ("surface_shifted", "tca_kernels", "tca_kernels_scalar")
            yield types.SimpleNamespace(files=files,
                                        **{m: importlib.import_module(f"{VARIANT_PACKAGE}.{m}") for m in modules})
        finally:
            for name in [n for n in sys.modules if n.split(".")[0] == VARIANT_PACKAGE]:
                del sys.modules[name]


def test_registry_variant_adds_its_surface_module(variant):
    """A registered model adds its surface module; only the registry-wide files change, and its
    kernels are the committed ones moved by SHIFT (same normals and derivatives)."""
    changed = sorted(n for n, text in variant.files.items()
                     if not (GENERATED / n).exists() or (GENERATED / n).read_text() != text)
    assert changed == sorted({"__init__.py", "layouts.py", "surface_shifted.py", "surface_shifted_scalar.py"}
                             | set(kernels.glue_files()))
    assert "class ShiftedSurfaceParams(typing.NamedTuple)" in variant.files["layouts.py"]
    committed = committed_module(f"surface_{MODEL}")
    for flank in FLANKS:
        values = sample(f"surface_{MODEL}", f"surface_{flank}", N_POINTS)
        for kind in ("surface", "surface_jet", "surface_second_derivatives"):
            new = getattr(variant.surface_shifted, f"{kind}_{flank}")(**values)
            old = getattr(committed, f"{kind}_{flank}")(**values)
            assert new._fields == old._fields
            for name, a, b in zip(new._fields, new, old):
                assert_close(a, b + SHIFT if name == "point" else b, RTOL, f"shifted {kind}_{flank}.{name}")


@pytest.mark.parametrize("flank", FLANKS)
def test_registry_variant_reaches_the_contact_system(variant, flank):
    """A pinion moved by SHIFT in S_1: the composed residual changes by exactly [L_f1 SHIFT, 0, 0]
    (normals unchanged), its pinion-angle derivative by [dL_f1/dphi'_1 SHIFT, 0, 0], nothing else;
    a gear moved by SHIFT in S_2 changes it by [-L_f2 SHIFT, 0, 0].  Numpy and scalar glue."""
    tk = variant.tca_kernels
    assert tk.MODELS == (MODEL, "shifted")
    values = sample_contact(N_POINTS)
    base = tk.contact_system(MODEL, MODEL, flank, **values)
    for name, a, b in zip(base._fields, base, committed_module("tca_kernels").contact_system(MODEL, MODEL, flank, **values)):
        assert_close(a, b, 0.0, f"{MODEL} pair through the variant glue: {name}")

    placement = committed_module("placement")
    at = dict(pinion_angle=values["pinion_angle"], pair=values["pair"])
    rotation = placement.pinion_placement(**at).rotation
    d_rotation, rtol = derivative(placement.pinion_placement, at, "pinion_angle", "rotation")
    zeros = np.zeros((N_POINTS, 2))
    change = {"residual": (np.concatenate([rotation @ SHIFT, zeros], axis=-1), RTOL),
              "residual_D_pinion_angle": (np.concatenate([d_rotation @ SHIFT, zeros], axis=-1), rtol),
              "pinion_point": (SHIFT, RTOL)}
    moved = tk.contact_system("shifted", MODEL, flank, **values)
    assert not np.allclose(moved.residual, base.residual)
    for name, a, b in zip(moved._fields, moved, base):
        delta, tol = change.get(name, (0.0, RTOL))
        assert_close(a, b + delta, tol, f"pinion shifted: {name}")
    gear_rotation = placement.gear_placement(values["x"][:, 4], values["errors"], values["pair"]).rotation
    gear_moved = tk.contact_system(MODEL, "shifted", flank, **values)
    assert_close(gear_moved.residual, base.residual - np.concatenate([gear_rotation @ SHIFT, zeros], axis=-1), RTOL,
                 "gear shifted: residual")
    assert_close(gear_moved.gear_point, base.gear_point + SHIFT, RTOL, "gear shifted: gear_point")

    for models, want in (((MODEL, "shifted"), gear_moved), (("shifted", MODEL), moved)):
        for i in range(3):
            got, _ = scalar_contact(tk, variant.tca_kernels_scalar, models, flank, values, i)
            for name, a, b in zip(want._fields, got, want):
                assert_close(a, b[i], RTOL, f"scalar glue {models}: {name}, point {i}")


def test_registry_variant_names_its_source_in_the_header():
    from beveloid.derivations.symbols import l, u

    flat = types.SimpleNamespace(tooth_surface=lambda sigma: (sp.Matrix([l, sigma * u, 0]), sp.Matrix([0, 0, 1]),
                                                              sp.Integer(0)),
                                 __name__="beveloid.derivations.flat_rack_variant")
    spec = kernels.surface_module("flat", flat)
    assert spec.module == "surface_flat"
    for text, template in ((codegen.render_module(spec), TEMPLATES[False]),
                           (codegen.render_scalar_module(spec), TEMPLATES[True])):
        assert text.startswith("# Generated by `beveloid derive` from derivations/flat_rack_variant.py "
                               f"with template {template}.\n")
    assert "(flat_rack_variant.py)" in codegen.render_layouts([spec])
    glue = kernels.glue_files({"flat": flat})
    assert "from . import surface_flat as _flat\n" in glue["tca_kernels.py"]
    assert "from .surface_flat_scalar import surface_jet_left_point" in glue["tca_kernels_scalar.py"]
