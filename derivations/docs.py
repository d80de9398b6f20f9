"""docs/derivations.md, rendered from the symbolic models.

The page is generated (``beveloid derive``), never edited by hand.  Its content is a
pure function of the models and of their verification results: no timestamps, no
version strings, floats in a fixed format, so ``check_derivations_md`` can tell
whether the committed page is stale.

Verification takes a while (~15-20 s), so every entry point accepts the
``(equations, results)`` pair that ``registry.verify()`` returns and only runs the
check itself when given none.

    python -m beveloid.derivations.docs [PATH]          write the page
    python -m beveloid.derivations.docs --check [PATH]  exit 1 (and print a diff) if stale
"""
from __future__ import annotations

import difflib
import sys
from pathlib import Path

import sympy as sp

from . import registry
from .common import _as_list

_REPO = Path(__file__).resolve().parent.parent
# In a source checkout (editable install) the page lives in the repository; otherwise
# (installed into site-packages) default to docs/ under the current directory.
DEFAULT_PATH = (_REPO if (_REPO / "pyproject.toml").exists() else Path.cwd()) / "docs" / "derivations.md"
REGENERATE_HINT = "run `beveloid derive` to update (or `python -m beveloid.derivations.docs`)"

STATUS_TEXT = {
    "verified": "verified",
    "definition": "definition",
    "differs": "**DIFFERS**",
    "not applicable": "not applicable",
    "not checked": "not checked",
}


def _fmt_diff(x) -> str:
    return "-" if x is None else f"{x:.1e}"


def _cell(text: str) -> str:
    """Text safe inside a markdown table cell."""
    return str(text).replace("|", r"\|").replace("\n", " ")


# Symbols whose names sympy would typeset badly (phi2p -> "phi2p", Delta_x_q -> \Delta_{x q}).
SYMBOL_LATEX = {
    "phi1p": r"\varphi'_{1}",
    "phi2p": r"\varphi'_{2}",
    "Delta_x_q": r"\Delta x_{q}",
    "Delta_y_q": r"\Delta y_{q}",
    "Delta_z_q": r"\Delta z_{q}",
    "Delta_gamma_v": r"\Delta\gamma_{v}",
    "Delta_gamma_h": r"\Delta\gamma_{h}",
}


def _latex(expr) -> str:
    names = {x: SYMBOL_LATEX[x.name] for x in getattr(expr, "free_symbols", ()) if x.name in SYMBOL_LATEX}
    return sp.latex(expr, symbol_names=names)


def _math_block(expr) -> str:
    return "$$\n" + _latex(expr) + "\n$$"


def _summary_table(results) -> list[str]:
    lines = [
        "| Eq | what it is | how it was checked | status | max rel diff |",
        "|---:|---|---|---|---:|",
    ]
    for r in results:
        lines.append(
            f"| [{r.equation}](#eq-{r.equation}) | {_cell(r.title)} | {_cell(r.method)} "
            f"| {STATUS_TEXT.get(r.status, r.status)} | {_fmt_diff(r.max_rel_diff)} |"
        )
    n_ver = sum(r.status == "verified" for r in results)
    n_def = sum(r.status == "definition" for r in results)
    n_diff = sum(r.status == "differs" for r in results)
    lines += ["", f"{n_ver} verified, {n_def} definitions, {n_diff} differ (of {len(results)} equations)."]
    return lines


def _printed_section(eq) -> list[str]:
    items = _as_list(eq.printed)
    if not items:
        if eq.status == "definition":
            return ["No printed form is compared: the paper states this as a definition."]
        return ["No single printed expression is compared: the model checks the identities listed "
                "under *Check*."]
    lines = ["**Printed form, as compared** (the reference side of the check: normally the paper's print "
             "as typed in `derivations/paper.py`, rearranged where the check needs it):", ""]
    if len(items) == 1:
        lines.append(_math_block(items[0]))
    else:
        for k, item in enumerate(items, 1):
            if k > 1:
                lines.append("")
            lines += [f"Form {k} of {len(items)}:", "", _math_block(item)]
    return lines


def _equation_section(eq, result) -> list[str]:
    module = getattr(eq, "model", None)
    lines = [f'<a id="eq-{eq.number}"></a>', "", f"## Eq {eq.number} — {eq.title}", ""]
    if module:
        lines += [f"Model: `derivations/{module}.py` (`beveloid.derivations.{module}`)", ""]
    lines += _printed_section(eq)
    if eq.steps:
        lines += ["", "**Derivation**", ""]
        lines += [f"{k}. {step}" for k, step in enumerate(eq.steps, 1)]
    if result.status == "definition":
        lines += ["", f"**Check:** definition — stated by the paper, not derived; used by `{eq.used_by}`."]
    else:
        lines += ["", f"**Check:** {STATUS_TEXT.get(result.status, result.status)} — {result.method}; "
                      f"max rel diff {_fmt_diff(result.max_rel_diff)}"]
    labels = [label for label, _fn in eq.extra_checks]
    if labels:
        lines += ["", "Identities also checked:", ""]
        lines += [f"- `{label}`" for label in labels]
    if result.note:
        lines += ["", f"> **Note.** {result.note}"]
    return lines


def render_derivations_md(results=None) -> str:
    """The page as a string.

    ``results`` is the ``(equations, results)`` pair returned by ``registry.verify()``;
    when None the verification is run here.
    """
    eqs, checks = registry.verify() if results is None else results
    if len(eqs) != len(checks):
        raise ValueError(f"{len(eqs)} equations but {len(checks)} results")
    for e, r in zip(eqs, checks):
        if e.number != r.equation:
            raise ValueError(f"equation {e.number} paired with the result of {r.equation}")
    out = [
        "<!-- Generated by `beveloid derive` from derivations/*.py. Do not edit: changes are overwritten. -->",
        "",
        "# Derivations",
        "",
        "Zhu, Song, Lim, Peng, *Pitch cone design and influence of misalignments on tooth contact "
        "behaviors of crossed beveloid gears*, Mechanism and Machine Theory 59 (2013) 48–64: every "
        "numbered equation, derived by a symbolic model in `derivations/` and checked against the "
        "printed form typed into `derivations/paper.py`.",
        "",
        "This page is generated by `beveloid derive` (the page alone: `python -m beveloid.derivations.docs`); "
        "do not edit it by hand.",
        "",
        "How to read the checks: *symbolic* means the difference between the derived and the printed "
        "form expands to zero; *50-digit at N points* means both were evaluated in 50-digit arithmetic "
        "at N random points of the physical domain and agree to the relative difference shown "
        "(tolerance 1e-40). A *definition* is a statement the paper makes rather than derives; the "
        "models use it as stated (or as the note says).",
        "",
        "## Summary",
        "",
    ]
    out += _summary_table(checks)
    for e, r in zip(eqs, checks):
        out += [""] + _equation_section(e, r)
    out += [""] + _extra_section(registry.verify_extra())
    return "\n".join(out) + "\n"


def _extra_section(extra) -> list[str]:
    """Checks beyond the numbered equations (derivations/fpd_principal_directions.py)."""
    from . import fpd_principal_directions as fpd

    lines = ['<a id="beyond-the-print"></a>', "", "## Beyond the print: the FPD angle from the principal directions", "",
             "Model: `derivations/fpd_principal_directions.py`", ""]
    lines += [p.strip() for p in (fpd.__doc__ or "").split("\n\n")[1:] if p.strip()]
    lines += ["", "| check | how it was checked | status | max rel residual |", "|---|---|---|---:|"]
    for r in extra:
        lines.append(f"| {_cell(r.title)} | {_cell(r.method)} | {STATUS_TEXT.get(r.status, r.status)} "
                     f"| {_fmt_diff(r.max_rel_diff)} |")
    lines += [""] + [f"> **Note.** {r.note}" for r in extra if r.note]
    lines += ["", "The same crossing angle taken from the real surfaces' principal directions at the solved "
              "pitch-point contact (beveloid/curvature.py) is held against the designed xi over designs in "
              "tests/test_fpd_curvature.py; numbers in docs/validation.md."]
    return lines


def write_derivations_md(path=DEFAULT_PATH, results=None) -> Path:
    """Render and write the page; returns the path written."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(render_derivations_md(results), encoding="utf-8", newline="\n")
    return path


def check_derivations_md(path=DEFAULT_PATH, results=None) -> tuple[bool, str]:
    """(ok, unified diff from the file on disk to the freshly rendered page)."""
    path = Path(path)
    fresh = render_derivations_md(results)
    old = path.read_text(encoding="utf-8") if path.exists() else ""
    if old == fresh:
        return True, ""
    diff = "".join(difflib.unified_diff(
        old.splitlines(keepends=True), fresh.splitlines(keepends=True),
        fromfile=f"{path} (on disk)", tofile=f"{path} (from the models)"))
    return False, diff


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    check = "--check" in argv
    rest = [a for a in argv if a != "--check"]
    path = Path(rest[0]) if rest else DEFAULT_PATH
    if check:
        ok, diff = check_derivations_md(path)
        if not ok:
            sys.stdout.write(diff)
            print(f"{path} is stale: {REGENERATE_HINT}", file=sys.stderr)
        return 0 if ok else 1
    print(write_derivations_md(path))
    return 0


if __name__ == "__main__":
    sys.exit(main())
