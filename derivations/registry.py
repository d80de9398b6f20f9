"""Which model derives which equations (verification), and what is generated from which model."""
from __future__ import annotations

import importlib
import json

from .common import check

MODEL_MODULES = (
    "eq01_03_rack_cutter",
    "eq04_07_tooth_surface",
    "eq08_17_pitch_cones",
    "eq18_21_line_contact",
    "eq22_27_working_data",
    "eq28_38_meshing_model",
)


def model(name):
    return importlib.import_module(f"{__package__}.{name}")


def all_equations():
    eqs = []
    for name in MODEL_MODULES:
        for e in model(name).equations():
            e.model = name
            eqs.append(e)
    numbers = sorted(e.number for e in eqs)
    assert numbers == list(range(1, 39)), f"equations registered: {numbers}"
    return sorted(eqs, key=lambda e: e.number)


def verify(progress=None):
    """Check every equation; returns (equations, results)."""
    eqs = all_equations()
    results = []
    for e in eqs:
        if progress:
            progress(e)
        results.append(check(e))
    return eqs, results


_EXTRA = {}


def verify_extra():
    """Checks beyond the numbered equations (labels that are not "1".."38"), computed once per process."""
    if "results" not in _EXTRA:
        from . import fpd_principal_directions

        _EXTRA["results"] = fpd_principal_directions.check()
    return list(_EXTRA["results"])


def results_json(results) -> str:
    out = []
    for r in results:
        out.append({
            "equation": str(r.equation),
            "title": r.title,
            "status": r.status,
            "method": r.method,
            "max_rel_diff": r.max_rel_diff,
            "note": r.note,
        })
    return json.dumps(out, indent=2)


def extra_summary(extra) -> str:
    """One line on the checks beyond the print: how many were applicable and how many of those hold."""
    n_na = sum(r.status == "not applicable" for r in extra)
    applicable = len(extra) - n_na
    n_ver = sum(r.status == "verified" for r in extra)
    check = "check" if applicable == 1 else "checks"
    line = f"beyond the print: {n_ver} of {applicable} applicable {check} verified"
    if n_ver != applicable:
        line += f", {applicable - n_ver} differ"
    return line + (f" ({n_na} not applicable)" if n_na else "")


def results_table(results) -> str:
    rows = [("Eq", "what it is", "how it was checked", "status", "max rel diff")]
    for r in results:
        rows.append((str(r.equation), r.title, r.method, r.status,
                     "-" if r.max_rel_diff is None else f"{r.max_rel_diff:.1e}"))
    widths = [max(len(row[i]) for row in rows) for i in range(5)]
    lines = ["  ".join(c.ljust(w) for c, w in zip(row, widths)).rstrip() for row in rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    numbered = [r for r in results if str(r.equation).isdigit()]
    extra = [r for r in results if not str(r.equation).isdigit()]
    n_ver = sum(r.status == "verified" for r in numbered)
    n_def = sum(r.status == "definition" for r in numbered)
    n_diff = sum(r.status == "differs" for r in numbered)
    lines.append("")
    lines.append(f"{n_ver} verified, {n_def} definitions, {n_diff} differ (of {len(numbered)} equations)")
    if extra:
        lines.append(extra_summary(extra))
    return "\n".join(lines)
