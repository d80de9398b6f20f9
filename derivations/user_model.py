"""``beveloid derive --model FILE --name NAME``: one tooth-surface model into a model folder.

The derivation module states what a built-in model states (derivations/kernels.py's docstring):
``tooth_surface(sigma)`` (or ``tooth_surface_late`` / ``tooth_surface_staged``), ``PARAMETERS``,
``KEYS``, optionally ``CHOICE_KEYS`` and ``SELECTED_BY``.  It is imported (it is code: this is the
only place that runs it) as ``beveloid.derivations.<its file name>``, so it may import the
built-in models absolutely (``from beveloid.derivations import eq04_07_tooth_surface``) or, like a
module of derivations/, relatively.

What is written (beveloid/models/discovery.py reads it): ``<out>/<name>/`` with the numpy kernels
``surface_<name>.py``, their scalar twins ``surface_<name>_scalar.py`` (what the compiled solver
runs), the parameter layout ``layout.py`` and ``model.json`` (interface, glue entry, hashes,
checks).  Everything is generated and checked in a staging folder first; a model that fails a
check is not written.  The checks (:func:`kernel_checks`, :func:`runtime_checks`) apply to any
model: unit normal, normal orthogonal to the surface and outward, first and second derivatives
against complex-step differences of the generated kernels, scalar twins equal to the numpy
kernels, and the meshing condition: Eq 38 solved at the pitch point of the paper's case 1 with
both members on the model, through the runtime's own model loading and solver.
"""
from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
import time
import types
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from beveloid.errors import UserCodeError

from . import codegen, kernels
from .interface import Field


class ModelError(ValueError):
    """A derivation module that does not state a usable model (one line: what and how to fix)."""


@dataclass(frozen=True)
class Check:
    name: str
    passed: bool
    detail: str


@dataclass(frozen=True)
class Derived:
    folder: Path
    files: tuple
    checks: tuple
    keys: tuple  # (name, unit, default, lo, hi, doc)
    seconds: float


def load_module(path: Path, name: str):
    """Import the derivation module at ``path`` (this runs it).  Its failure is the user's:
    UserCodeError (the file, the line, the frames in the file)."""
    stem = path.stem if path.stem.isidentifier() else f"user_model_{name}"
    modname = f"{__package__}.{stem}"
    if modname in sys.modules or importlib.util.find_spec(modname) is not None:
        modname = f"{__package__}.user_model_{name}"
    spec = importlib.util.spec_from_file_location(modname, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[modname] = module
    try:
        spec.loader.exec_module(module)
    except Exception as exc:
        del sys.modules[modname]
        raise (UserCodeError.from_exception(exc, [path], "while importing the model")
               or ModelError(f"{path.name}: importing it failed: {type(exc).__name__}: {exc}")) from exc
    return module


def generation_error(exc: Exception, path: Path, module) -> UserCodeError | ModelError:
    """What to tell of ``exc``, raised while the kernels of the model ``module`` (at ``path``) were
    derived and printed: the frames in the model's file when it raised there (its tooth_surface),
    else which function of the model sympy could not derive and what failed."""
    function = kernels.surface_function(module)
    err = UserCodeError.from_exception(exc, [path], f"while deriving {function}")
    if err is not None:
        return err
    if isinstance(exc, codegen.GenerationError):  # names the kernel: surface_jet_left, ...
        return ModelError(f"{path.name}: {function} cannot be derived: {exc}")
    doing = "; ".join(getattr(exc, "__notes__", ()))  # "generating surface_left" (codegen)
    return ModelError(f"{path.name}: {function} cannot be derived{f' ({doing})' if doing else ''}:"
                      f" {type(exc).__name__}: {exc}")


def evaluation_failure(exc: Exception) -> Check | None:
    """A failed check for ``exc`` raised inside a generated kernel of the model during the checks
    (a square root of a negative, a division by zero at the checked points); None when no
    generated kernel raised it."""
    import traceback

    frames = [f for f in traceback.extract_tb(exc.__traceback__) if f.filename.startswith("<surface_")]
    if not frames:
        return None
    where = f"{frames[-1].filename.strip('<>')}.{frames[-1].name}"
    return Check("kernels evaluate", False, f"{where} raised {type(exc).__name__}: {exc} (case 1's pinion, the keys"
                 " at a quarter of their range)")


def interface_problem(module, name: str, member_values: dict, builtin_keys: dict) -> str | None:
    """What the module lacks or states wrongly (None when its interface is usable).

    ``member_values``: the quantities the runtime fills by name (PairGeometry.surface_values);
    ``builtin_keys``: {key: KeyDoc} of a member section (no user key may shadow one)."""
    from beveloid.models.discovery import name_problem

    if name_problem(name):
        return f"--name {name}: {name_problem(name)}"
    if name in kernels.SURFACE_MODELS:
        return f"--name {name}: a built-in model has this name; choose another"
    if not any(hasattr(module, f) for f in ("tooth_surface", "tooth_surface_late", "tooth_surface_staged")):
        return "the module defines no tooth_surface(sigma) returning (point, unit outward normal, roll angle)"
    params = tuple(getattr(module, "PARAMETERS", ()))
    rack = {f.name for f in kernels.RACK_FIELDS}
    seen = set()
    for f in params:
        if not isinstance(f, Field):
            return f"PARAMETERS holds {f!r}: each entry must be a beveloid.derivations.interface.Field"
        if f.name in rack or f.name in seen:
            return f"PARAMETERS: {f.name} is given twice (or is one of the rack's own fields {sorted(rack)})"
        seen.add(f.name)
    keys, choices = dict(getattr(module, "KEYS", {})), dict(getattr(module, "CHOICE_KEYS", {}))
    for key, rule in keys.items():
        if key not in seen:
            return f"KEYS: {key} is not a field of PARAMETERS"
        try:
            default, lo, hi = (float(v) for v in rule)
        except (TypeError, ValueError):
            return f"KEYS: {key} = {rule!r}: must be (default, lowest, highest)"
        if not lo < hi or not lo <= default <= hi:
            return f"KEYS: {key} = {rule!r}: needs lowest < highest and the default between them"
    for key in choices:
        if key not in seen:
            return f"CHOICE_KEYS: {key} is not a field of PARAMETERS"
    for key in getattr(module, "SELECTED_BY", ()):
        if key not in keys:
            return f"SELECTED_BY: {key} is not one of KEYS"
    for f in params:
        if f.name not in keys and f.name not in choices and f.name not in member_values:
            return (f"PARAMETERS: {f.name} is neither an input key (KEYS, CHOICE_KEYS) nor a quantity the runtime"
                    f" fills ({', '.join(sorted(set(member_values) - rack))})")
    units = {f.name: f.unit for f in params}
    for key in (*keys, *choices):
        doc = builtin_keys.get(key)
        if doc is None or doc.model == name:
            continue
        if doc.model is None or key in choices or (doc.unit, doc.default, doc.lo, doc.hi) != (
                units[key], *(float(v) for v in keys[key])):
            return (f"KEYS: {key} is already a key of a member section ({doc.description}); name yours apart "
                    "(or give it exactly the same unit, default and range)")
    return None


def _module_from_text(name: str, text: str):
    mod = types.ModuleType(name)
    exec(compile(text, f"<{name}>", "exec"), mod.__dict__)  # generated code, just rendered
    return mod


def test_values(entry: dict) -> dict:
    """The model's keys at a quarter of the way from their default towards the far end of the range
    (non-zero, so that the checks see the modification), choices at their default."""
    out = {}
    for k in entry["input_keys"]:
        far = k["hi"] if k["hi"] > k["default"] else k["lo"]
        out[k["name"]] = k["default"] + 0.25 * (far - k["default"])
    for k in entry["choice_keys"]:
        out[k["name"]] = next(c["value"] for c in k["choices"] if c["name"] == k["default"])
    return out


def _rel(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


def kernel_checks(numpy_text, scalar_text, layout_text, entry, member_values) -> list[Check]:
    """The checks of the generated kernels themselves (case 1's pinion data, the keys at test_values)."""
    from beveloid.generated import layouts, surface_involute

    lay = getattr(_module_from_text("layout", layout_text), entry["layout"])
    kern = _module_from_text(entry["module"], numpy_text)
    twin = _module_from_text(entry["module"] + "_scalar", scalar_text)
    values = dict(member_values, **test_values(entry))
    params = np.asarray(lay.pack(values), dtype=float)
    base = np.asarray(layouts.InvoluteSurfaceParams.pack(member_values), dtype=float)
    mn, width = member_values["normal_module_mm"], member_values["face_width_mm"]
    L, U = np.meshgrid(np.linspace(0.3, 2.0, 4) * mn, np.linspace(-0.4, 0.4, 5) * width)
    L, U = L.ravel(), U.ravel()
    worst = {"point_D_lu": 0.0, "normal_D_lu": 0.0, "point_D2_lu": 0.0, "forms": 0.0, "twins": 0.0}
    unit, ortho, outward = 0.0, 0.0, 1.0
    method = "complex step (h = 1e-30 mm)"
    for flank in ("left", "right"):
        s = getattr(kern, f"surface_{flank}")(L, U, params)
        jet = getattr(kern, f"surface_jet_{flank}")(L, U, params)
        d2 = getattr(kern, f"surface_second_derivatives_{flank}")(L, U, params).point_D2_lu
        forms = getattr(kern, f"surface_fundamental_forms_{flank}")(L, U, params)
        n = s.normal
        unit = max(unit, float(np.max(np.abs(np.linalg.norm(n, axis=-1) - 1.0))))
        for c in range(2):
            t = jet.point_D_lu[..., c]
            ortho = max(ortho, float(np.max(np.abs(np.einsum("...i,...i", n, t)) / np.linalg.norm(t, axis=-1))))
        n0 = surface_involute.__dict__[f"surface_{flank}"](L, U, base).normal
        outward = min(outward, float(np.min(np.einsum("...i,...i", n, n0))))
        # first derivatives of point and normal, second of the point: complex-step differences
        try:
            h = 1e-30
            with np.errstate(all="raise"):
                dl = getattr(kern, f"surface_{flank}")(L + 1j * h, U, params)
                du = getattr(kern, f"surface_{flank}")(L, U + 1j * h, params)
                jl = getattr(kern, f"surface_jet_{flank}")(L + 1j * h, U, params).point_D_lu
                ju = getattr(kern, f"surface_jet_{flank}")(L, U + 1j * h, params).point_D_lu
            num_p = np.stack([dl.point.imag / h, du.point.imag / h], axis=-1)
            num_n = np.stack([dl.normal.imag / h, du.normal.imag / h], axis=-1)
            num_d2 = np.stack([jl[..., 0].imag / h, jl[..., 1].imag / h, ju[..., 1].imag / h], axis=-1)
            if not all(np.all(np.isfinite(a)) for a in (num_p, num_n, num_d2)):
                raise FloatingPointError("not finite")
        except (TypeError, FloatingPointError, ValueError) as exc:  # a kernel that takes no complex values
            method = f"central differences (complex step not applicable: {exc})"
            num_p, num_n, num_d2 = _central(kern, flank, L, U, params, mn)
        worst["point_D_lu"] = max(worst["point_D_lu"], _rel(jet.point_D_lu, num_p))
        worst["normal_D_lu"] = max(worst["normal_D_lu"], _rel(jet.normal_D_lu, num_n))
        worst["point_D2_lu"] = max(worst["point_D2_lu"], _rel(d2, num_d2))
        J = jet.point_D_lu
        first = np.einsum("...ia,...ib->...ab", J, J)
        second = np.einsum("...ik,...i->...k", d2, n)[..., [0, 1, 1, 2]].reshape(second_shape(d2))
        worst["forms"] = max(worst["forms"], _rel(forms.first_form, first), _rel(forms.second_form, second))
        worst["twins"] = max(worst["twins"], _twin_difference(twin, flank, L, U, params, s, jet, d2))
    tol = 1e-8 if method.startswith("complex") else 1e-5
    return [
        Check("unit normal", unit < 1e-12, f"max | |n| - 1 | = {unit:.1e} (limit 1e-12)"),
        Check("normal orthogonal to the surface", ortho < 1e-10,
              f"max |n . R_l| / |R_l|, |n . R_u| / |R_u| = {ortho:.1e} (limit 1e-10)"),
        Check("normal outward", outward > 0.5, f"smallest cosine to the involute flank's outward normal {outward:.4f}"
              " (must be > 0.5)"),
        Check("first derivatives", max(worst["point_D_lu"], worst["normal_D_lu"]) < tol,
              f"dR/d(l, u) and dn/d(l, u) against {method}: relative {worst['point_D_lu']:.1e}, "
              f"{worst['normal_D_lu']:.1e} (limit {tol:g})"),
        Check("second derivatives", worst["point_D2_lu"] < tol,
              f"d2R/d(l, u)2 against {method} of dR/d(l, u): relative {worst['point_D2_lu']:.1e} (limit {tol:g})"),
        Check("fundamental forms", worst["forms"] < 1e-12,
              f"first and second forms against R_l, R_u, R_ll, R_lu, R_uu and n: relative {worst['forms']:.1e}"),
        Check("scalar twins", worst["twins"] < 1e-12,
              f"the compiled solver's one-point kernels against the numpy kernels: relative {worst['twins']:.1e}"),
    ]


def second_shape(d2):
    return d2.shape[:-2] + (2, 2)


def _central(kern, flank, L, U, params, mn):
    h = 1e-4 * mn
    f = getattr(kern, f"surface_{flank}")
    g = getattr(kern, f"surface_jet_{flank}")

    def diff(fn, attr, dl, du):
        a = [getattr(fn(L + k * dl, U + k * du, params), attr) for k in (-2, -1, 1, 2)]
        return (a[0] - 8 * a[1] + 8 * a[2] - a[3]) / (12 * h)

    p = np.stack([diff(f, "point", h, 0), diff(f, "point", 0, h)], axis=-1)
    n = np.stack([diff(f, "normal", h, 0), diff(f, "normal", 0, h)], axis=-1)
    jl, ju = diff(g, "point_D_lu", h, 0), diff(g, "point_D_lu", 0, h)
    return p, n, np.stack([jl[..., 0], jl[..., 1], ju[..., 1]], axis=-1)


def _twin_difference(twin, flank, L, U, params, s, jet, d2):
    worst = 0.0
    p, nrm, ph = np.empty(3), np.empty(3), np.empty(1)
    dp, dn, dd = np.empty((3, 2)), np.empty((3, 2)), np.empty((3, 3))
    for k in range(L.size):
        getattr(twin, f"surface_{flank}_point")(L[k], U[k], params, p, nrm, ph)
        getattr(twin, f"surface_jet_{flank}_point")(L[k], U[k], params, p, nrm, dp, dn)
        getattr(twin, f"surface_second_derivatives_{flank}_point")(L[k], U[k], params, dd)
        worst = max(worst, _rel(p, s.point[k]), _rel(nrm, s.normal[k]), _rel(ph, s.roll_angle[k]),
                    _rel(dp, jet.point_D_lu[k]), _rel(dn, jet.normal_D_lu[k]), _rel(dd, d2[k]))
    return worst


RUNTIME_CHECK = r"""
import json, sys, tomllib
from beveloid.models import catalog
from beveloid.pair import Pair
from beveloid.spec import example_text
from beveloid.tca.reference import reference_contact
name, values = sys.argv[1], json.loads(sys.argv[2])
cat = catalog()
if name not in [m.name for m in cat.user]:
    print(json.dumps({"error": cat.problem(name)})); sys.exit(0)
spec = tomllib.loads(example_text("case1"))
for member in ("pinion", "gear"):
    spec[member].update(values, tooth_surface=name)
geom = Pair.from_spec(spec).geometry
out = {}
for flank in ("left", "right"):
    try:
        out[flank] = list(map(float, reference_contact(geom, flank).x))
    except Exception as exc:
        out[flank] = str(exc)
print(json.dumps({"contacts": out}))
"""


def runtime_checks(root: Path, name: str, values: dict) -> list[Check]:
    """Through the runtime, in a fresh process that sees only ``root`` as its model folder: the model
    loads by name, and the aligned pair of case 1 with both members on it meshes (Eq 38 solved at
    the pitch point of both flanks by the solver core)."""
    env = dict(os.environ, BEVELOID_MODELS_DIR=str(root))
    proc = subprocess.run([sys.executable, "-c", RUNTIME_CHECK, name, json.dumps(values)], env=env,
                          capture_output=True, text=True, timeout=600)
    if proc.returncode != 0:
        last = (proc.stderr.strip().splitlines() or ["(no message)"])[-1]
        return [Check("loads at run time", False, last)]
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    if "error" in out:
        return [Check("loads at run time", False, out["error"])]
    checks = [Check("loads at run time", True, f"tooth_surface = \"{name}\" in a spec (the keys at {values})")]
    for flank, x in out["contacts"].items():
        ok = isinstance(x, list)
        checks.append(Check(f"meshing, {flank} flank", ok,
                            "Eq 38 (R_f1 = R_f2, n_f1 = -n_f2) solved at the pitch point of case 1 with both members on"
                            " the model" if ok else x))
    return checks


def _outside_packages(out: Path) -> str | None:
    import site

    from beveloid.models.discovery import package_folder

    resolved = out.resolve()
    forbidden = [package_folder("generated").parent.resolve(), *(Path(p).resolve() for p in site.getsitepackages())]
    for f in forbidden:
        if resolved == f or f in resolved.parents:
            return f"--out {out}: inside {f}; user models go to a folder of their own (default: the user data folder)"
    return None


def check_builtin_glue(base: dict, builtin: list) -> None:
    """The runtime composes the glue with the built-in models first: rendered alone, they must give
    the committed glue byte for byte (else generated/ is stale: `beveloid derive` first)."""
    from beveloid.models import render_glue
    from beveloid.models.discovery import package_folder

    texts = render_glue(dict(base, models=builtin))
    for name, text in texts.items():
        if (package_folder("generated") / f"{name}.py").read_text() != text:
            raise ModelError(f"generated/{name}.py differs from what the derivations render: the package's generated/"
                             " is stale; run `beveloid derive` in the checkout first")


def derive_model(path, name: str, out=None, progress=None) -> Derived:
    """Generate, check and write the model of the derivation module ``path`` as ``name`` into
    ``out`` (default: the user model folder).  Raises ModelError (nothing written) for a bad
    module or destination; returns the checks (nothing written when one failed)."""
    from beveloid.models import models_dir, package_stamp
    from beveloid.models.discovery import INTERFACE, file_sha256
    from beveloid.pair import Pair
    from beveloid.spec import KEY_DOCS

    t0 = time.perf_counter()
    path = Path(path).expanduser().resolve()
    root = Path(out).expanduser() if out else models_dir()
    problem = _outside_packages(root)
    if problem:
        raise ModelError(problem)
    if not path.is_file():
        raise ModelError(f"--model {path}: no such file")
    member_values = Pair.example("case1").geometry.surface_values("pinion")
    module = load_module(path, name)
    problem = interface_problem(module, name, member_values, KEY_DOCS["pinion"])
    if problem:
        raise ModelError(f"{path.name}: {problem}")
    base, builtin = kernels.glue_base(), [kernels.model_entry(k, m) for k, m in kernels.SURFACE_MODELS.items()]
    check_builtin_glue(base, builtin)
    entry = kernels.model_entry(name, module)
    if progress:
        progress(entry["module"])
    try:  # runs the model's tooth_surface, then sympy on what it returned
        spec = kernels.surface_module(name, module)
        reduced_by = {}  # the two files share the symbolic reduction (codegen.render_function)
        texts = {f"{spec.module}.py": codegen.render_module(spec, reduced_by=reduced_by),
                 f"{spec.module}_scalar.py": codegen.render_scalar_module(spec, reduced_by=reduced_by),
                 "layout.py": codegen.render_layouts([spec])}
    except Exception as exc:
        raise generation_error(exc, path, module) from exc
    try:
        checks = kernel_checks(texts[f"{spec.module}.py"], texts[f"{spec.module}_scalar.py"], texts["layout.py"],
                               entry, member_values)
    except Exception as exc:
        failed = evaluation_failure(exc)
        if failed is None:
            raise
        checks = [failed]
    try:
        root.mkdir(parents=True, exist_ok=True)
        staging = root / f".staging-{name}-{os.getpid()}"
        folder = staging / name
        folder.mkdir(parents=True)
    except OSError as exc:
        raise ModelError(f"--out {root}: cannot be written ({exc.strerror})") from None
    try:
        for fname, text in texts.items():
            (folder / fname).write_text(text)
        face = dict(format=1, name=name, beveloid_version=_version(), package_stamp=package_stamp(),
                    doc=(module.__doc__ or "").strip().split("\n\n")[0],
                    source=dict(path=str(path), sha256=file_sha256(path)),
                    parameters=[dict(name=f.name, unit=f.unit, doc=f.doc) for f in getattr(module, "PARAMETERS", ())],
                    glue=dict(base=base, builtin=builtin, model=entry),
                    files={fname: file_sha256(folder / fname) for fname in texts})
        (folder / INTERFACE).write_text(json.dumps(dict(face, checks=[]), indent=1) + "\n")
        if all(c.passed for c in checks):
            if progress:
                progress("checking at run time (a fresh process: the model by name, Eq 38 at the pitch point) ...")
            checks += runtime_checks(staging, name, test_values(entry))
        face["checks"] = [dict(name=c.name, passed=c.passed, detail=c.detail) for c in checks]
        (folder / INTERFACE).write_text(json.dumps(face, indent=1) + "\n")
        final = root / name
        if all(c.passed for c in checks):
            if final.exists():
                old = staging / f".old-{name}"
                os.replace(final, old)
            os.replace(folder, final)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    keys = tuple((k["name"], k["unit"], k["default"], k["lo"], k["hi"], k["doc"]) for k in entry["input_keys"])
    return Derived(root / name, tuple(sorted([*texts, INTERFACE])), tuple(checks), keys, time.perf_counter() - t0)


def _version():
    from beveloid import __version__

    return __version__
