"""The Python example is true: every ```python block of README.md and docs/api.md (found by its
fence, wherever the page puts it) runs as written, and what its comments promise holds."""
from __future__ import annotations

import dataclasses
import json
import re
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
#: one worker runs the module: its examples run once (the module-scoped namespace), not once a worker
pytestmark = pytest.mark.xdist_group(name="readme_api")


def python_blocks(text: str) -> list[str]:
    """The bodies of the ```python fenced blocks of a markdown text, in order."""
    return re.findall(r"^```python[ \t]*\n(.*?)^```[ \t]*$", text, flags=re.M | re.S)


def test_python_blocks_are_found_by_their_fence_alone():
    text = "# T\n\n```python\nx = 1\n```\n\n## Anywhere\n```bash\nls\n```\n```python\ny = 2\n```\n"
    assert python_blocks(text) == ["x = 1\n", "y = 2\n"]


@pytest.fixture(scope="module")
def readme_namespace(tmp_path_factory):
    pages = ("README.md", "docs/api.md")  # the README links the API page
    blocks = [b for page in pages for b in python_blocks((REPO / page).read_text(encoding="utf-8"))]
    assert blocks, "neither README.md nor docs/api.md has a ```python block"
    ns: dict = {}
    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(tmp_path_factory.mktemp("readme"))  # runs from any working directory
        for i, block in enumerate(blocks):
            exec(compile(block, f"python block {i + 1}", "exec"), ns)
    return ns


def test_the_readme_example_runs_and_its_result_carries_what_the_comments_say(readme_namespace):
    from beveloid import tca

    ns = readme_namespace
    res = ns["res"]
    assert isinstance(res, tca.TCAResult)
    # "both flanks, backlash, contact ellipses": on the result as returned, not added later
    assert set(res.flanks) == set(tca.FLANKS) and res.backlash_um is not None
    ce = ns["ce"]
    assert ce is ns["right"].contact_ellipse is not None
    ok = [s == "ellipse" for s in ce.status]
    assert sum(ok) > 0 and np.all(np.asarray(ce.semi_axes_mm)[ok] > 0)
    # the result is immutable and has its JSON as a method (strict JSON: no NaN)
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.notes = ()
    with pytest.raises(dataclasses.FrozenInstanceError):
        ce.status = []
    doc = json.loads(json.dumps(res.to_json(), allow_nan=False))
    assert "contact_ellipse_semi_axes_mm" in doc["flanks"]["right"]
    # the errors named in the example are the errors analysed
    assert list(res.errors) == pytest.approx(list(ns["errors"]))


def test_the_rest_of_the_example_holds(readme_namespace):
    """The design, the indirect design, the misalignment, the curvature and the sweep lines."""
    ns = readme_namespace
    assert ns["mc"].contact_points_solved == 2_000 * 20
    assert abs(ns["back"].offset_mm - ns["d"].offset_mm) < 1e-9 * ns["d"].offset_mm
    assert ns["d"] is ns["pair"].design and ns["geom"] is ns["pair"].geometry
    assert list(ns["shifted"].errors) == [0.5, 0.0, 0.0, 0.0, 0.0]
    assert ns["right"].status.count("ok") > 0 and ns["k"].k1 >= ns["k"].k2


def test_the_contract_example_runs_each_analysis(readme_namespace):
    """docs/api.md's contract block: every analysis called as it shows, each result a Result."""
    from beveloid import ltca, rating, sweep, tca, tooth
    from beveloid.result import Result

    ns = readme_namespace
    for name, kind in (("t", tca.TCAResult), ("swept", sweep.SweepResult), ("whole", tooth.ToothResult),
                       ("loaded", ltca.LTCAResult), ("rated", rating.RatingResult)):
        assert isinstance(ns[name], kind) and isinstance(ns[name], Result)
    assert 0 < ns["share"] <= 1 and isinstance(ns["refused"].requirement, str) and ns["refused"].key == "positions"


def slow_blocks(text: str) -> list[str]:
    """The bodies of the ```python slow blocks (what needs minutes or CalculiX)."""
    return re.findall(r"^```python slow[ \t]*\n(.*?)^```[ \t]*$", text, flags=re.M | re.S)


def test_slow_blocks_are_found_apart_from_the_others():
    text = "```python\nx = 1\n```\n```python slow\ny = 2\n```\n"
    assert python_blocks(text) == ["x = 1\n"] and slow_blocks(text) == ["y = 2\n"]


@pytest.mark.slow
def test_the_slow_examples_run(readme_namespace):
    """docs/api.md's FE check, run as written after the other blocks (CalculiX, minutes)."""
    ns = dict(readme_namespace)
    for i, block in enumerate(slow_blocks((REPO / "docs" / "api.md").read_text(encoding="utf-8"))):
        exec(compile(block, f"slow python block {i + 1}", "exec"), ns)
    assert ns["check"].pair is ns["case1"]
    json.dumps(ns["check"].to_json(), allow_nan=False)


def test_the_loaded_example_takes_a_load_case_apart_from_its_options(readme_namespace):
    """docs/api.md's loaded block (issue 56): one torque gives an LTCAResult, a torque list a Batch with a
    torque map, the tolerance box one row per error set, the rating its options' LTCA."""
    from beveloid import ltca, rating

    ns = readme_namespace
    assert isinstance(ns["at200"], ltca.LTCAResult) and ns["at200"].torque_nm == 200.0
    assert isinstance(ns["tmap"], ltca.Batch) and ns["tmap"].te_peak_to_peak_urad.shape == (1, 2)
    assert [r.torque_nm for r in ns["tmap"].results[0]] == [100.0, 300.0]
    assert len(ns["box"]) == 2 and len(ns["box"][0]) == 1
    assert isinstance(ns["rated800"], rating.RatingResult) and ns["rated800"].options.ltca == ns["quick"]
