"""``beveloid fe-check``: a very coarse check of case 1 through the command line (CalculiX), and its
one-line refusals (no ccx, bad flags) that need no CalculiX."""
from __future__ import annotations

import json

import pytest

from beveloid import cli
from beveloid.fecheck import ccx_path

CASE1 = "beveloid/data/case1.toml"
COARSEN = 2.0  #: refinement 1's sizes x 2 (the FE tooth's x 6)
STRIP_CAP = 4000  #: with COARSEN: about 11 800 elements (seven-tooth sectors), ~45 s of CalculiX CPU


def test_missing_ccx_is_one_line_naming_the_package(monkeypatch, capsys, tmp_path):
    monkeypatch.setenv("BEVELOID_CCX", str(tmp_path / "no-such-ccx"))
    assert cli.main(["fe-check", CASE1, "--torque-nm", "100"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "calculix-ccx" in err and "Traceback" not in err


@pytest.mark.parametrize("argv, key", [(["--refinement", "9"], "--refinement"), (["--position", "20"], "--position"),
                                       (["--torque-nm", "-1"], "--torque-nm"),
                                       (["--contact-size-um", "1"], "--contact-size-um"),
                                       (["--coarsen", "0"], "--coarsen"),
                                       (["--max-strip-elements", "10"], "--max-strip-elements")])
def test_bad_flags_are_one_line_naming_the_flag(capsys, argv, key):
    base = ["fe-check", CASE1, "--torque-nm", "100"]
    assert cli.main(base + argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and key in err


def test_fine_fillets_reaches_the_options_and_a_non_bool_is_refused(monkeypatch, tmp_path):
    """--fine-fillets sets fecheck.Options.fine_fillets (off by default); a value that is not a bool names the key."""
    from beveloid import fecheck
    from beveloid.errors import OptionError

    from beveloid.errors import UserError

    seen = []

    def stop(pair, load, options, **k):  # the options the CLI made, and no LTCA nor CalculiX
        seen.append(options)
        raise UserError("stopped by the test")

    monkeypatch.setenv("BEVELOID_CCX", "/bin/true")
    monkeypatch.setattr(fecheck, "analyze", stop)
    for extra in ([], ["--fine-fillets"]):
        assert cli.main(["fe-check", CASE1, "--torque-nm", "100"] + extra) == 2
    assert [o.fine_fillets for o in seen] == [False, True]
    with pytest.raises(OptionError, match="fine_fillets"):
        fecheck.Options(fine_fillets="yes")


@pytest.mark.slow
@pytest.mark.long_running
@pytest.mark.skipif(ccx_path() is None, reason="needs CalculiX (ccx, Debian package calculix-ccx)")
def test_coarse_fe_check_of_case1_agrees_with_the_ltca(tmp_path):
    """A very coarse model (every element size x 3 of refinement 1, a low strip cap, 5 LTCA positions, the
    LTCA's plate tooth: cheaper than its FE tooth, which tests/fe checks): the loads share the torque like
    the LTCA's, the pinion lags like the LTCA's, and the files are kept."""
    from beveloid import fecheck, ltca
    from beveloid.pair import Pair

    result = fecheck.analyze(Pair.example("case1"), ltca.LoadCase(200.0),
                             fecheck.Options(ltca=ltca.Options(flank="right", positions=5, tooth_model="plate"),
                                             out_dir=str(tmp_path), coarsen=COARSEN, max_strip_elements=STRIP_CAP),
                      progress=None)
    out = result.to_json()
    json.dumps(out, allow_nan=False)
    assert result.load.torque_nm == out["torque_nm"] == 200.0 and result.pair.spec.source == "case1.toml"
    assert not result.calculix.pair_normal_load_n.flags.writeable
    fe, lt = out["calculix"], out["ltca"]
    # (the moment of the contact forces equals the torque in any converged solution: it checks nothing, and
    # is not asserted; the model is checked by the cantilever, the Hertz block and docs/validation.md 11)
    assert len(fe["pair_normal_load_n"]) == len(lt["pair_normal_load_n"]) == len(out["tooth_pairs"])
    # (nor is the sum of the pair loads: both balance the same torque through lever arms a few percent apart)
    # the pair the LTCA loads most (4.5 x either side pair's load) is the one the FE loads most
    fe_loads, lt_loads = ([v or 0.0 for v in b["pair_normal_load_n"]] for b in (fe, lt))
    assert fe_loads.index(max(fe_loads)) == lt_loads.index(max(lt_loads))
    # the pinion's lag under load.  Upper bound: at refinement 1 (sizes half of these) the FE lags 0.99 x the
    # FE-tooth LTCA's (docs/validation.md 11.1), whose lag is 3.5 % below the plate's (docs/loaded_contact.md
    # 9.7), and a coarser displacement-based mesh is only stiffer; lower bound: strips 20 contact
    # half-widths wide miss most of the contact's own approach, about a quarter of the lag (measured 0.75)
    unloaded = out["unloaded_transmission_error_urad"]
    fe_lag = fe["loaded_transmission_error_urad"] - unloaded
    lt_lag = lt["loaded_transmission_error_urad"] - unloaded
    assert 0.65 < fe_lag / lt_lag < 1.05
    assert fe["root_stress_max_mpa"]["pinion"] > 0 and fe["root_stress_max_mpa"]["gear"] > 0
    # a mesh this coarse does not resolve the contacts' widths, and says so per refined pair
    unresolved = [n for n in out["notes"] if "peak pressure and contact area are not resolved" in n]
    assert len(unresolved) == len(out["local_refinement"]) > 0
    for key in ("deck", "frd", "dat", "vtu"):
        assert (tmp_path / out["files"][key].split("/")[-1]).exists()


def test_a_pair_meshed_coarser_than_its_contact_width_is_named_in_the_notes():
    from beveloid.fecheck.check import PEAK_RESOLVED_PER_SEMI_AXIS, _resolution_notes

    fine = {"tooth_pair": 0, "semi_axes_mm": [0.2, 5.0], "pinion_element_mm": 0.1, "gear_element_mm": 0.2}
    coarse = dict(fine, tooth_pair=1, gear_element_mm=0.2 * PEAK_RESOLVED_PER_SEMI_AXIS * 1.01)
    notes = _resolution_notes([fine, coarse])
    assert len(notes) == 1 and notes[0].startswith("tooth pair 1: elements of 0.222 mm") and "1.1 x" in notes[0]
    assert "not resolved" in _resolution_notes(None)[0]


def test_api_out_dir_with_a_missing_parent_is_refused_before_any_work(tmp_path, monkeypatch):
    """fecheck.analyze()'s out_dir keeps the one output rule (beveloid/outputs.py): a missing tree is refused
    in one line before the LTCA runs, whether or not CalculiX is installed."""
    from beveloid import fecheck, ltca
    from beveloid.outputs import OutputError
    from beveloid.pair import Pair

    monkeypatch.setattr(ltca, "analyze", lambda *a, **k: pytest.fail("the LTCA ran before the output was checked"))
    target = tmp_path / "no" / "such" / "dir"
    with pytest.raises(OutputError, match=r"^out_dir = .*: the folder .* does not exist; create it first"):
        fecheck.analyze(Pair.example("case1"), ltca.LoadCase(100.0), fecheck.Options(out_dir=str(target)),
                        progress=None)
    assert not (tmp_path / "no").exists()


#: a stand-in for CalculiX: writes the empty files ccx starts with, then the user presses Ctrl-C
_INTERRUPTING_CCX = """#!/bin/sh
touch fe_check.dat fe_check.sta fe_check.cvg spooles.out
echo "ccx: started"
sleep 0.5  # the line is printed whole first (a SIGINT inside print() cut it before its newline)
kill -INT $PPID
sleep 60
"""


@pytest.mark.parametrize("made_here", [False, True])
def test_ctrl_c_while_calculix_runs_keeps_nothing_and_says_so(tmp_path, made_here):
    """Interrupted while ccx runs: the deck and CalculiX's partial files (spooles.out too: issue 60) are
    removed from --out, the folder's other files stay, and one line says what was removed
    (docs/commands.md, Outputs); a folder the run made is removed."""
    import os
    import signal
    import subprocess
    import sys

    ccx = tmp_path / "ccx"
    ccx.write_text(_INTERRUPTING_CCX)
    ccx.chmod(0o755)
    out = tmp_path / "out"
    if not made_here:
        out.mkdir()
        (out / "mine.txt").write_text("kept\n")
    # the check up to CalculiX: its deck written into --out, then ccx run by the real runner (the LTCA and
    # the meshes before it are the coarse test's above: here they would cost seconds and change nothing)
    code = ("import sys; from pathlib import Path; from beveloid import cli; from beveloid.fecheck import check, run\n"
            "def analyze(pair, load, options, progress=None):\n"
            "    deck = Path(options.out_dir) / 'fe_check.inp'\n"
            "    deck.write_text('*HEADING\\n')\n"
            "    run.run_ccx(deck, progress)\n"
            "import beveloid.fecheck as face; face.analyze = check.analyze = analyze\n"
            "sys.exit(cli.main())")
    proc = subprocess.run([sys.executable, "-c", code, "fe-check", os.path.abspath(CASE1), "--torque-nm", "200",
                           "--out", str(out)],
                          capture_output=True, text=True, timeout=600, env=dict(os.environ, BEVELOID_CCX=str(ccx)))
    assert proc.returncode in (130, -signal.SIGINT), proc.stderr
    assert "Traceback" not in proc.stderr, proc.stderr
    note = [line for line in proc.stderr.splitlines() if line.startswith("beveloid fe-check: --out")]
    assert len(note) == 1 and "fe_check.inp" in note[0] and "spooles.out" in note[0], proc.stderr
    if made_here:
        assert "the folder, made by this run, is removed" in note[0] and not out.exists()
    else:
        assert sorted(p.name for p in out.iterdir()) == ["mine.txt"]
