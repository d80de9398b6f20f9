"""The loaded analysis' options are declared once (issue 56): no option of ``ltca.Options`` is declared a
second time in rating/, optimize/, fecheck/ or cli/ (an options class that copies its fields, a command line
flag declared by hand); every command that takes them (ltca, rating, optimize, fe-check, and paper's tooth)
gets them from the one declaration in cli/common.py, and they work there as in ``beveloid ltca``."""
from __future__ import annotations

import ast
import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from beveloid import ltca
from beveloid.cli import build_parser, main
from beveloid.cli.common import LTCA_FLAGS

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "beveloid"
SCOPE = ("rating", "optimize", "fecheck", "cli")
#: the fields of ltca.Options (material: the pair's, never a flag; angles: the rating's refinement between
#: positions, never a flag)
FIELDS = {f.name for f in dataclasses.fields(ltca.Options)} - {"angles"}
#: the flags of ltca.Options' fields (those a command line sets)
FLAGS = {flag: key for key, flag, _, _ in LTCA_FLAGS}
#: commands with a flag of the same name for another analysis' option (tca.Options, sweep.Options): not
#: ltca.Options, so not a second declaration of it
OTHER_ANALYSES = {"--flank": ("tca.py", "sweep.py"), "--positions": ("tca.py", "sweep.py", "paper.py"),
                  "--pairs": ("tca.py",)}
#: the commands whose loaded analysis is an ltca.Options, and the fields each takes
TAKERS = {"ltca": FIELDS - {"material"}, "rating": FIELDS - {"material"}, "optimize": FIELDS - {"material"},
          "fe-check": FIELDS - {"material"}, "paper": {"tooth_model"}}


def _files():
    for folder in SCOPE:
        for path in sorted((PACKAGE / folder).rglob("*.py")):
            yield path.relative_to(ROOT).as_posix(), ast.parse(path.read_text(encoding="utf-8"))


def test_every_field_a_command_line_sets_has_one_flag():
    assert set(FLAGS.values()) == FIELDS - {"material"}, "a field of ltca.Options without a flag in LTCA_FLAGS"
    assert len(FLAGS) == len(LTCA_FLAGS)


def test_no_options_class_copies_the_fields_of_ltca_options():
    """rating.Options, fecheck.Options and optimize.Request hold an ltca.Options (their ``ltca`` field)."""
    found = []
    for rel, tree in _files():
        for cls in ast.walk(tree):
            if not (isinstance(cls, ast.ClassDef) and (cls.name.endswith("Options") or cls.name == "Request")):
                continue
            for node in cls.body:
                if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name) and node.target.id in FIELDS:
                    found.append(f"{rel}:{node.lineno} {cls.name}.{node.target.id}")
    assert not found, f"a field of ltca.Options declared again (hold an ltca.Options instead): {found}"


def test_no_flag_of_ltca_options_is_declared_by_hand():
    """Outside cli/common.py's LTCA_FLAGS no add_argument names a flag of ltca.Options (tca's and sweep's
    own --flank / --positions / --pairs are theirs: another analysis' options)."""
    found = []
    for rel, tree in _files():
        if rel == "beveloid/cli/common.py":
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.Call) and getattr(node.func, "attr", None) == "add_argument":
                for arg in node.args:
                    if isinstance(arg, ast.Constant) and arg.value in FLAGS:
                        if Path(rel).name in OTHER_ANALYSES.get(arg.value, ()):
                            continue
                        found.append(f"{rel}:{node.lineno} {arg.value}")
    assert not found, f"declare these with cli.common.add_ltca_flags: {found}"


def test_every_command_that_takes_them_has_the_one_declaration():
    commands = next(a for a in build_parser()._actions if a.dest == "command").choices
    for name, fields in TAKERS.items():
        actions = {a.dest: a for a in commands[name]._actions}
        for key, flag, kwargs, text in LTCA_FLAGS:
            if key not in fields:
                continue
            a = actions[key]
            assert a.option_strings == [flag], (name, key)
            assert a.help == text(a.default), (name, key)  # the shared help, with the command's default
            assert a.choices == kwargs.get("choices") and a.type == kwargs.get("type"), (name, key)


def test_rating_takes_the_grid_and_the_positions_as_ltca_does(tmp_path, capsys):
    """`rating --grid --positions --pairs` reach its LTCA: the command's numbers are the library's with those
    options, and another grid gives other numbers."""
    from beveloid import rating
    from beveloid.pair import Pair

    case1 = str(ROOT / "examples" / "case1.toml")
    flags = ["--torque-nm", "800", "--positions", "3", "--pairs", "1", "--tooth-model", "plate", "--json"]
    assert main(["rating", case1, *flags, "--grid", "5x7"]) in rating.EXIT_STATUS.values()  # the verdict's status
    coarse = json.loads(capsys.readouterr().out)
    lib = rating.analyze(Pair.example("case1"), ltca.LoadCase(800.0),
                         rating.Options(ltca.Options(positions=3, pairs=1, grid=(5, 7), tooth_model="plate")))
    assert coarse["pinion"]["contact_pressure_max_mpa"] == lib.members["pinion"].contact_pressure_max_mpa
    assert main(["rating", case1, *flags, "--grid", "9x11"]) in rating.EXIT_STATUS.values()
    fine = json.loads(capsys.readouterr().out)
    assert not np.isclose(fine["pinion"]["contact_pressure_max_mpa"], coarse["pinion"]["contact_pressure_max_mpa"],
                          rtol=1e-9)


@pytest.mark.parametrize("argv, words", [
    (["rating", "--grid", "2x40"], "--grid = 2x40: must be"),
    (["rating", "--positions", "0"], "--positions = 0: must be"),
    (["rating", "--pairs", "2"], "--pairs = 2: must be an odd"),
    (["fe-check", "--fe-refinement", "9"], "--fe-refinement = 9: must be"),
    (["rating", "--torque-nm", "-3"], "--torque-nm = -3.0: must be"),
])
def test_a_bad_value_names_the_flag_in_every_command(capsys, argv, words):
    case1 = str(ROOT / "examples" / "case1.toml")
    command, *rest = argv
    args = [command, case1, *(rest if "--torque-nm" in rest else ["--torque-nm", "100", *rest])]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert words in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err
