"""The loaded contact with the FE tooth: the JSON keys of issue 31, root stress, FE against plate."""
from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from beveloid import ltca
from beveloid.fe import cache

pytestmark = pytest.mark.xdist_group(name="fe_case1")


@pytest.fixture(scope="module")
def results(case1, coarse_teeth):
    mp = pytest.MonkeyPatch()
    # the session's coarse FE data stands for the cached data of the default mesh
    mp.setattr(cache, "cached_tooth_data", lambda pair, member, *a, **k: (coarse_teeth[member], "hit"))
    try:
        out = {m: ltca.analyze(case1, ltca.LoadCase(300.0), ltca.Options(positions=4, tooth_model=m))
               for m in ("fe", "plate")}
    finally:
        mp.undo()
    return out


def test_the_box_leaves_out_the_root_stress_along_the_face_and_the_compressive_one_and_nothing_else(
        case1, coarse_teeth, monkeypatch):
    """``analyze_many(..., along_face=False, compression=False)`` (the tolerance box's and optimize's call,
    ``ltca.studies.box_results``): every result's ``root_stress_along_face`` and
    ``pair_root_compressive_stress_mpa`` empty (the other fillet's extreme not sought), every other field
    bit-identical to the full analysis's, which has them."""
    import collections.abc
    import dataclasses

    from beveloid.fe import contact

    def same(x, y, name):
        if isinstance(x, collections.abc.Mapping):  # the members' FrozenMaps
            assert set(x) == set(y), name
            for k in x:
                np.testing.assert_equal(x[k], y[k], err_msg=f"{name}[{k}]")
        else:
            np.testing.assert_equal(x, y, err_msg=name)

    monkeypatch.setattr(cache, "cached_tooth_data", lambda pair, member, *a, **k: (coarse_teeth[member], "hit"))
    options = ltca.Options(positions=4, tooth_model="fe")
    load = ltca.LoadCase([150.0, 300.0])
    full = ltca.analyze_many(case1, load, options, convergence=False).results[0]
    lean = ltca.analyze_many(case1, load, options, convergence=False, along_face=False).results[0]
    signs = []
    real = contact.principal.functions

    class Spy:
        def __getattr__(self, name):
            return getattr(real(), name)

        @staticmethod
        def extreme(fillet, g, sign, node, value):
            signs.append(sign)
            return real().extreme(fillet, g, sign, node, value)

    monkeypatch.setattr(contact.principal, "functions", Spy)
    boxed = ltca.studies.box_results(case1, load, options)[0]
    assert signs and set(signs) == {1.0}  # the tension alone sought
    for a, b, c in zip(full, lean, boxed):
        assert set(a.root_stress_along_face) == {"pinion", "gear"} == set(a.pair_root_compressive_stress_mpa)
        assert b.root_stress_along_face == {} and c.root_stress_along_face == {}
        assert set(b.pair_root_compressive_stress_mpa) == {"pinion", "gear"} and c.pair_root_compressive_stress_mpa == {}
        for f in dataclasses.fields(a):
            if f.name not in ("pair", "root_stress_along_face"):
                same(getattr(b, f.name), getattr(a, f.name), f.name)
            if f.name not in ("pair", "root_stress_along_face", "pair_root_compressive_stress_mpa"):
                same(getattr(c, f.name), getattr(a, f.name), f.name)


def test_a_pairs_flank_departure_is_measured_once_per_pair(case1, coarse_teeth, monkeypatch):
    """The FE tooth's departure note (the flank against its body) is measured once per (pair, member, FE
    data): optimize's candidate calls the loaded engine three times on one pair; another pair object is
    measured again; the notes are those of the first call."""
    from beveloid.ltca.model import teeth
    from beveloid.pair import Pair
    from beveloid.tooth import departure

    monkeypatch.setattr(cache, "cached_tooth_data", lambda pair, member, *a, **k: (coarse_teeth[member], "hit"))
    calls = []
    real = departure.flank_departure
    monkeypatch.setattr(departure, "flank_departure", lambda *a, **k: calls.append(a[1]) or real(*a, **k))
    getattr(teeth, "_DEPARTURES", {}).clear()  # (a module of the older code has none: it measures every call)
    options = ltca.Options(positions=4, tooth_model="fe")
    first = ltca.analyze_many(case1, ltca.LoadCase([150.0]), options, convergence=False).results[0][0]
    again = ltca.analyze_many(case1, ltca.LoadCase([300.0]), options, convergence=False).results[0][0]
    assert calls == ["pinion", "gear"] and first.notes[:1] == again.notes[:1]
    ltca.analyze_many(Pair.example("case1"), ltca.LoadCase([150.0]), options, convergence=False)
    assert calls == ["pinion", "gear"] * 2


def test_a_departure_note_keeps_neither_its_pair_nor_its_fe_data_alive(monkeypatch):
    """The departure notes outlive their call (the reuse above) but refer to their pair and FE data weakly:
    three designs' pairs and data, dropped by their caller and by the FE caches, are freed whatever the notes
    keep (they held them, 2 x 4 entries of up to ~180 MB of FE data each, beyond the FE caches' own bound)."""
    import gc
    import types
    import weakref

    from beveloid.ltca.model import teeth
    from beveloid.tooth import departure

    class Data:  # a stand-in for an FE tooth's data, new at each call (a new design's)
        points_mm = normals = None

    class Source:
        pass

    monkeypatch.setattr(teeth, "fe_tooth", lambda source, member, moduli, options: types.SimpleNamespace(data=Data()))
    monkeypatch.setattr(departure, "flank_departure", lambda *a: types.SimpleNamespace(note=lambda m: f"{m} departs"))
    material = types.SimpleNamespace(pinion_e_mpa=2.1e5, pinion_nu=0.3, gear_e_mpa=2.1e5, gear_nu=0.3)
    refs = []
    for _ in range(3):
        source = Source()
        out, notes = teeth.member_teeth(source, None, types.SimpleNamespace(tooth_model="fe"), material)
        assert notes == ("pinion departs", "gear departs")
        refs += [weakref.ref(source)] + [weakref.ref(t.data) for t in out]
        del source, out
    gc.collect()
    assert len(refs) == 9 and not any(r() is not None for r in refs)


def test_json_has_the_fe_keys_and_is_strict(results, case1):
    d = results["fe"].to_json()
    json.dumps(d, allow_nan=False)
    assert d["tooth_model"] == "fe" and d["fe_refinement"] == 1
    for m in ("pinion", "gear"):
        rows = d["pair_root_stress_mpa"][m]
        assert len(rows) == 4 and all(len(r) == 3 for r in rows)
        assert d["root_stress_max_mpa"][m] == pytest.approx(max(v for r in rows for v in r if v is not None))
        loc = d["root_stress_location"][m]
        assert set(loc) == {"position", "pair", "z_mm", "height_mm", "flank"} and loc["flank"] == "right"
        assert rows[loc["position"]][list(d["tooth_pairs"]).index(loc["pair"])] == d["root_stress_max_mpa"][m]
        lo, hi = sorted(case1.geometry.member(m).face_limits)
        assert lo - 1e-6 <= loc["z_mm"] <= hi + 1e-6 and loc["height_mm"] >= -1e-6
    assert all(v > 0 for v in d["mesh_stiffness_n_per_um"])
    plate = results["plate"].to_json()
    json.dumps(plate, allow_nan=False)
    assert plate["tooth_model"] == "plate" and plate["pair_root_stress_mpa"] is None


def test_root_stress_is_tension_where_loaded_and_zero_where_not(results):
    r = results["fe"]
    for m in ("pinion", "gear"):
        s = r.pair_root_stress_mpa[m]
        c = r.pair_root_compressive_stress_mpa[m]
        loaded = r.pair_load_n > 0
        assert np.all(s[loaded] > 0) and np.all(c[loaded] < 0)
        assert np.all(s[~loaded] == 0)


def test_the_order_of_the_root_stress_is_that_of_a_cantilever(results, case1):
    # the bending stress at the root of a cantilever of the tooth's height and root thickness under the
    # largest pair load spread over the face: 6 F h / (b s^2); the FE peak (concentration, a point of
    # the face) lies between 0.5 and 4 times that
    r = results["fe"]
    g = case1.geometry
    m = g.member("pinion")
    h = m.tip_height_mm + m.cutter_addendum_mm
    s = 2.2 * g.normal_module_mm  # root chord thickness of a 20 deg rack tooth, about
    nominal = 6 * np.nanmax(r.pair_load_n) * np.cos(g.normal_pressure_angle) * h / (m.face_width_mm * s ** 2)
    assert 0.5 * nominal < np.nanmax(r.pair_root_stress_mpa["pinion"]) < 4 * nominal


def test_fe_and_plate_agree_on_the_loads_and_te_to_within_their_model_difference(results):
    fe, plate = results["fe"], results["plate"]
    assert fe.converged.all() and plate.converged.all()
    te_fe = fe.loaded_te - fe.unloaded_te
    te_plate = plate.loaded_te - plate.unloaded_te
    assert np.allclose(te_fe, te_plate, rtol=0.3)
    share = lambda r: r.pair_load_n / r.pair_load_n.sum(axis=1, keepdims=True)  # noqa: E731
    assert np.max(np.abs(share(fe) - share(plate))) < 0.15


def test_plot_has_the_root_stress_panel(results, case1, tmp_path):
    from beveloid.ltca.results.plots import ltca_summary

    r = results["fe"]
    for m in ("pinion", "gear"):
        z, s = r.root_stress_along_face[m]
        lo, hi = sorted(case1.geometry.member(m).face_limits)
        assert np.all((z > lo) & (z < hi)) and np.nanmax(s) == pytest.approx(r.root_stress_max_mpa()[m])
    out = tmp_path / "ltca.png"
    ltca_summary(r, case1.geometry, out)
    assert out.read_bytes().startswith(b"\x89PNG")


def test_ltca_plot_prints_no_warning(case1, coarse_teeth, tmp_path, monkeypatch):
    """`ltca --plot` with the FE tooth (the default, root stress panel included) prints no matplotlib
    warning (issue 29, item 11); the session's coarse FE data stands for the cached default mesh."""
    from pathlib import Path

    from beveloid import cli

    used = []

    def cached(pair, member, *a, **k):
        used.append(member)
        return coarse_teeth[member], "hit"

    monkeypatch.setattr(cache, "cached_tooth_data", cached)
    case1_toml = Path(__file__).resolve().parents[2] / "examples" / "case1.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert cli.main(["ltca", str(case1_toml), "--torque-nm", "200", "--positions", "3",
                         "--plot", str(tmp_path / "l.png")]) == 0
    assert sorted(set(used)) == ["gear", "pinion"]
    assert (tmp_path / "l.png").read_bytes().startswith(b"\x89PNG")


@pytest.mark.parametrize("flags, names", [(["--fe-refinement", "9"], "--fe-refinement = 9: must be an integer from 1 to 4"),
                                          (["--tooth-model", "beam"], "--tooth-model")])
def test_bad_tooth_flags_are_one_line_and_exit_2(capsys, flags, names):
    from pathlib import Path

    from beveloid import cli

    case1 = Path(__file__).resolve().parents[2] / "examples" / "case1.toml"
    try:
        rc = cli.main(["ltca", str(case1), "--torque-nm", "10", *flags])
    except SystemExit as exc:  # argparse's own refusal
        rc = exc.code
    out, err = capsys.readouterr()
    assert rc == 2 and not out and names in err and "Traceback" not in err
    assert len([line for line in err.splitlines() if line.strip()]) <= 2  # argparse adds its usage line


def test_the_node_loads_of_the_loaded_points_alone_are_those_of_every_point(coarse_teeth):
    """FeTooth.loads reads the corners of the points that carry a force only (a contact grid's loaded
    cells); the node loads equal, bit for bit, the bilinear spread of every point of the sets (zero
    forces and points off the surface included), and W^T f to round-off."""
    from beveloid.fe.contact import FeTooth

    t = FeTooth(coarse_teeth["pinion"], "right")
    grid = np.asarray(coarse_teeth["pinion"].points_mm[1]).reshape(-1, 3)
    rng = np.random.default_rng(11)
    pts = grid[rng.integers(0, len(grid), (4, 30))] + rng.normal(0.0, 0.2, (4, 30, 3))
    pts[1, 3] = np.nan  # a cell off the flanks: no point, no force
    forces = np.where(rng.random((4, 30)) < 0.3, rng.uniform(1.0, 300.0, (4, 30)), 0.0)
    forces[1, 3] = np.nan
    forces[2] = 0.0  # a set without load
    g = t.loads(pts, forces)
    G = t.radius_mm.size
    nodes, w = t.corners(pts.reshape(-1, 3))  # every point, as the loads were spread before
    at = (nodes.reshape(4, -1, 4) + G * np.arange(4)[:, None, None]).ravel()
    every = np.bincount(at, weights=(w.reshape(4, -1, 4) * np.nan_to_num(forces)[..., None]).ravel(),
                        minlength=4 * G).reshape(4, G)
    np.testing.assert_array_equal(g, every)
    assert not g[2].any() and g[0].sum() > 0
    for q in range(4):
        np.testing.assert_allclose(g[q], t.weights(pts[q]).T @ np.nan_to_num(forces[q]), rtol=1e-12, atol=1e-9)


def _numpy_corners(t, points):
    """FeTooth.corners as numpy arrays compute it (the form before fe.lines.corners)."""
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    ns, nz = t.radius_mm.shape
    ok = np.all(np.isfinite(p), axis=1)
    p = np.where(ok[:, None], p, t.data.points_mm[t.index][0, 0])
    z = np.clip(p[:, 2], t.z_mm[0], t.z_mm[-1])
    fz = np.interp(z, t.z_mm, np.arange(nz))
    jz = np.minimum(fz.astype(int), nz - 2)
    tz = fz - jz
    r = np.hypot(p[:, 0], p[:, 1])
    col = (1 - tz)[:, None] * t.radius_mm[:, jz].T + tz[:, None] * t.radius_mm[:, jz + 1].T
    js = np.clip(np.sum(col <= r[:, None], axis=1) - 1, 0, ns - 2)
    rows = np.arange(p.shape[0])
    lo, hi = col[rows, js], col[rows, js + 1]
    ts = np.clip((r - lo) / (hi - lo), 0.0, 1.0)
    nodes = np.stack([(js + da) * nz + jz + dz for da in (0, 1) for dz in (0, 1)], axis=1)
    w = np.stack([wa * wz for wa in (1 - ts, ts) for wz in (1 - tz, tz)], axis=1)
    return nodes, np.where(ok[:, None], w, 0.0)


@pytest.mark.parametrize("member", ["pinion", "gear"])
def test_the_compiled_corners_and_line_compliances_are_those_of_numpy(coarse_teeth, member):
    """fe.lines (compiled): each point's four load-grid nodes and weights bit for bit those of the numpy
    form (points between and on the grid's nodes and z levels, beyond its ends, off the surfaces), on both
    backends; the line compliances W C W^T those of the dense product to round-off, symmetric."""
    from beveloid.fe import lines
    from beveloid.fe.contact import FeTooth

    t = FeTooth(coarse_teeth[member], "right")
    grid = np.asarray(coarse_teeth[member].points_mm[1]).reshape(-1, 3)
    rng = np.random.default_rng(5)
    pts = grid[rng.integers(0, len(grid), 6000)] * (1.0 + rng.normal(0.0, 0.05, (6000, 3)))
    pts[::50] = grid[rng.integers(0, len(grid), 120)]  # on the nodes
    pts[1::50, 2] = t.z_mm[rng.integers(0, t.z_mm.size, 120)]  # on the z levels
    pts[2::97] = np.nan
    pts[3::89, 0] = np.inf
    ref_nodes, ref_w = _numpy_corners(t, pts)
    nodes, w = t.corners(pts)
    np.testing.assert_array_equal(nodes, ref_nodes)
    np.testing.assert_array_equal(w.view(np.int64), ref_w.view(np.int64))  # to the bit, signed zeros too
    few = slice(0, 300)
    n2, w2 = np.empty((300, 4), dtype=np.int64), np.empty((300, 4))
    lines.corners(pts[few], t._radius, t._z, t._spare, n2, w2)  # the interpreted form
    np.testing.assert_array_equal(n2, ref_nodes[few])
    np.testing.assert_array_equal(w2, ref_w[few])
    line = pts[:440].reshape(40, 11, 3)
    W = t.weights(line.reshape(-1, 3)).reshape(40, 11, -1)
    dense = (W @ t.compliance_mm_per_n) @ np.swapaxes(W, 1, 2)
    got = t.line_compliances(line)
    np.testing.assert_allclose(got, dense, rtol=1e-13, atol=1e-15 * np.abs(dense).max())
    np.testing.assert_allclose(got, np.swapaxes(got, 1, 2), rtol=1e-13, atol=1e-15 * np.abs(dense).max())
    interpreted = np.empty((2, 11, 11))
    lines.line_compliances(t.compliance_mm_per_n, *(a.reshape(-1, 11, 4)[:2] for a in t.corners(line[:2])), interpreted)
    np.testing.assert_array_equal(interpreted, got[:2])


def test_root_stresses_of_many_sets_are_those_of_every_node(coarse_teeth):
    """The batched root stress (bounds from each column's eigenvalues, pruned by blocks of nodes and by
    node; closed-form eigenvalues) against numpy's eigenvalues at every counted fillet node (beyond the
    reading depth of every loaded grid node and of its row neighbours), for several load sets at once: the
    value and the node it is at."""
    from beveloid.fe.contact import FeTooth

    t = FeTooth(coarse_teeth["pinion"], "right")
    ns, nz = np.asarray(coarse_teeth["pinion"].points_mm[1]).shape[:2]
    grid = np.asarray(coarse_teeth["pinion"].points_mm[1]).reshape(-1, 3)
    rng = np.random.default_rng(3)
    pts = np.stack([grid[rng.choice(len(grid), 6, replace=False)] for _ in range(5)])
    forces = rng.uniform(10.0, 400.0, (5, 6))
    r = t.root_stresses(pts, forces)
    # the reading depth widened by the read-out's window (fe.contact.tooth_arrays)
    reach = np.max(coarse_teeth["pinion"].depth_mm[1]) + np.hypot(*coarse_teeth["pinion"].smoothing_mm)
    for q in range(5):
        g = t.weights(pts[q]).T @ forces[q]
        for side, sign, got in ((1, 1.0, r.tension_mpa[q]), (0, -1.0, r.compression_mpa[q])):
            s = t.stress[side] @ g  # (nf, 6): xx, yy, zz, xy, yz, zx
            m = np.stack([s[:, [0, 3, 5]], s[:, [3, 1, 4]], s[:, [5, 4, 2]]], axis=1)
            # counted: the fillet nodes farther than the reading depth from every grid node this set loads
            # and from those nodes' neighbours up and down the profile
            fp = coarse_teeth["pinion"].fillet_points_mm[side]
            loaded = (g != 0).reshape(ns, nz)
            spread = loaded.copy()
            spread[1:] |= loaded[:-1]
            spread[:-1] |= loaded[1:]
            far = np.linalg.norm(fp[:, None] - grid[spread.ravel()][None], axis=-1).min(axis=1) > reach
            assert far.any()
            ev = np.linalg.eigvalsh(m)[far]
            want = ev[:, 2].max() if sign > 0 else ev[:, 0].min()
            assert got == pytest.approx(want, rel=1e-9)
            if sign > 0:
                assert r.z_mm[q] == fp[far][np.argmax(ev[:, 2]), 2]
    assert all(np.array_equal(a, b) for a, b in zip(r, t.root_stresses(pts, forces)))  # deterministic
    one = t.root_stress(pts[2], forces[2])
    assert one.tension_mpa == pytest.approx(r.tension_mpa[2], rel=1e-12) and one.z_mm == r.z_mm[2]


def test_the_root_stress_along_the_face_is_the_largest_of_each_slice(coarse_teeth):
    """FeTooth.along_face (pruned by the same bounds as the root stress) against numpy's eigenvalues at
    every counted node of the loaded fillet, slice by slice; its largest slice is the root stress."""
    from beveloid.fe.contact import FeTooth

    data = coarse_teeth["pinion"]
    t = FeTooth(data, "right")
    grid = np.asarray(data.points_mm[1]).reshape(-1, 3)
    rng = np.random.default_rng(5)
    for _ in range(3):
        pts = grid[rng.choice(len(grid), 8, replace=False)]
        forces = rng.uniform(10.0, 400.0, 8)
        centres, got = t.along_face(pts, forces)
        g = t.weights(pts).T @ forces
        s = t.stress[1] @ g
        ev = np.linalg.eigvalsh(np.stack([s[:, [0, 3, 5]], s[:, [3, 1, 4]], s[:, [5, 4, 2]]], axis=1))[:, 2]
        counted = t.counted(g)[0]
        edges = np.linspace(t.z_mm[0], t.z_mm[-1], len(centres) + 1)
        slot = np.clip(np.searchsorted(edges, data.fillet_points_mm[1][:, 2]) - 1, 0, len(centres) - 1)
        want = np.array([ev[counted & (slot == b)].max() if (counted & (slot == b)).any() else np.nan
                         for b in range(len(centres))])
        assert np.isfinite(want).sum() >= len(centres) // 2
        np.testing.assert_allclose(got, want, rtol=1e-9)  # NaN where a slice holds no counted node, on both
        assert np.nanmax(got) == pytest.approx(t.root_stress(pts, forces).tension_mpa, rel=1e-12)


def test_compile_now_leaves_the_fe_tooth_nothing_to_compile(coarse_teeth):
    """principal.compile_now (what `beveloid paper` runs on a worker before the FE teeth exist) passes the
    argument types the FE tooth passes: after it, an FE tooth's root stresses and stress along the face
    add no compiled signature.  Without numba (or with NUMBA_DISABLE_JIT) they are plain functions."""
    import types

    from beveloid.fe import principal
    from beveloid.fe.contact import FeTooth

    names = ("largest_eigenvalue", "_loaded_columns", "slice_extremes", "bounds", "block_bounds", "_exact", "extreme")
    fn = principal.functions()
    principal.compile_now()
    if all(isinstance(getattr(fn, n), types.FunctionType) for n in names):
        return  # interpreted: nothing is compiled
    before = {n: list(getattr(fn, n).signatures) for n in names}
    # the functions called from Python once each; their callees compiled inside them (or none, when
    # numba's disk cache held the callers)
    assert all(len(before[n]) == 1 for n in ("slice_extremes", "bounds", "block_bounds", "extreme")), before
    assert all(len(s) <= 1 for s in before.values()), before
    data = coarse_teeth["gear"]
    t = FeTooth(data, "left")
    grid = np.asarray(data.points_mm[0]).reshape(-1, 3)
    t.root_stresses(grid[None, :5], np.full((1, 5), 100.0))
    t.along_face(grid[:5], np.full(5, 100.0))
    assert {n: list(getattr(fn, n).signatures) for n in names} == before


def test_a_fillet_node_is_left_out_only_near_the_grid_nodes_a_set_loads(coarse_teeth):
    """The reading depth leaves out the fillet nodes near a loaded grid node, not near any grid node:
    under a load on the top row the upper fillet (within the reading depth of the flank's lowest row)
    counts, under a load on the lowest row it does not; a set whose loads are near every fillet node has
    no root stress (NaN, no place), not 0.  (A gear's 0.5 mm fillet under its lowest row read 0 MPa.)"""
    from beveloid.fe.contact import FeTooth

    data = coarse_teeth["pinion"]
    t = FeTooth(data, "right")
    grid = np.asarray(data.points_mm[1])  # (ns, nz, 3): row 0 the flank's lowest
    fp = np.asarray(data.fillet_points_mm[1])
    reach = np.max(data.depth_mm[1])
    near_lowest = np.linalg.norm(fp[:, None] - grid[0][None], axis=-1).min(axis=1) <= reach
    assert near_lowest.any()
    mid = grid.shape[1] // 2
    top = t.loads(grid[-1:, mid][None], np.array([[1000.0]]))[0]
    low = t.loads(grid[:1, mid][None], np.array([[1000.0]]))[0]
    assert t.counted(top)[0][near_lowest].all()
    near_low_node = np.linalg.norm(fp - grid[0, mid], axis=-1) <= reach
    assert near_low_node.any() and not t.counted(low)[0][near_low_node].any()
    monkeypatched = FeTooth(data, "right")
    monkeypatched.near = np.ones_like(t.near)
    monkeypatched.fillets = tuple(f._replace(near=np.ones_like(f.near)) for f in t.fillets)
    r = monkeypatched.root_stresses(grid[-1:, mid][None], np.array([[1000.0]]))
    assert np.isnan(r.tension_mpa[0]) and np.isnan(r.z_mm[0]) and np.isnan(r.height_mm[0])
    assert np.isfinite(t.root_stresses(grid[-1:, mid][None], np.array([[1000.0]])).tension_mpa[0])


def test_locate_reads_inside_and_measures_how_far_outside():
    from types import SimpleNamespace

    from beveloid.fe import solve

    corners = np.array([[0.0, 0, 0], [2, 0, 0], [0, 2, 0], [0, 0, 2]])
    mids = np.array([(corners[a] + corners[b]) / 2 for a, b in solve.EDGES])
    one = np.vstack([corners, mids])
    # a second tet far away: the nearest tet is chosen among the candidates
    mesh = SimpleNamespace(nodes=np.vstack([one, one + [10.0, 0, 0]]), tets=np.arange(20).reshape(2, 10))
    inside, below = [0.3, 0.3, 0.3], [0.3, 0.3, -0.25]
    loc = solve.locate(mesh, [inside, below])
    assert np.allclose(loc.bary.sum(axis=1), 1.0) and np.all(loc.bary >= 0) and np.all(loc.tet == 0)
    read = loc.bary[1] @ corners  # read on the face below the point (inside the solid)
    assert read[2] == pytest.approx(0.0, abs=1e-15) and loc.outside_mm[0] == 0.0
    assert loc.outside_mm[1] == pytest.approx(np.linalg.norm(read - below), rel=1e-12)
    assert 0.25 <= loc.outside_mm[1] < 0.26  # at least the distance to the solid (0.25 mm)
    solve.locate(mesh, [inside, below], max_outside_mm=0.3)
    with pytest.raises(ValueError, match=r"lies 0\.25\d* mm outside the mesh: must be inside the solid or within 0\.1"):
        solve.locate(mesh, [inside, below], max_outside_mm=0.1)


def _one_tet(corners):
    """The 10 nodes of a straight tet."""
    from beveloid.fe import solve

    corners = np.asarray(corners, dtype=float)
    return np.vstack([corners, [(corners[a] + corners[b]) / 2 for a, b in solve.EDGES]])


def test_locate_reads_a_point_of_a_curved_face_where_it_is():
    from types import SimpleNamespace

    from beveloid.fe import solve

    nodes = _one_tet([[0.0, 0, 0], [2, 0, 0], [0, 2, 0], [0, 0, 2]])
    nodes[4] = [1.0, -0.2, 0.0]  # the mid-node of edge 01 moved out: the face y = 0 bulges
    mesh = SimpleNamespace(nodes=nodes, tets=np.arange(10)[None, :])
    point = np.array([1.0, -0.1, 0.1])  # outside the straight tet (y < 0), inside the curved one
    assert solve._barycentric(nodes[:4], point).min() < 0
    loc = solve.locate(mesh, point, max_outside_mm=0.0)
    assert loc.outside_mm[0] == 0.0 and loc.bary.min() > 0
    # the isoparametric map of the coordinates found is the point
    assert solve.shape_values(loc.bary[0]) @ nodes == pytest.approx(point, abs=1e-12)


def test_locate_finds_a_large_tet_whose_centre_is_further_than_many_small_ones():
    from types import SimpleNamespace

    from beveloid.fe import solve

    big = _one_tet([[0.0, 0, 0], [100, 0, 0], [0, 100, 0], [0, 0, 100]])  # centre (25, 25, 25)
    small = _one_tet([[0.0, 0, -1], [1, 0, -1], [0, 1, -1], [0, 0, -2]])  # below the big one
    shifts = [[x, y, 0.0] for x in range(6) for y in range(6)]  # 36 small tets nearer the point than 40 mm
    nodes = np.vstack([big] + [small + s for s in shifts])
    mesh = SimpleNamespace(nodes=nodes, tets=np.arange(len(nodes)).reshape(-1, 10))
    point = [3.0, 3.0, 1.0]
    # more small tets than the search's nearest centres lie nearer the point than the big tet's centre
    nearer = np.linalg.norm(small[:4].mean(axis=0) + np.array(shifts) - point, axis=1) < np.linalg.norm(big[:4].mean(axis=0) - point)
    assert nearer.sum() > solve._CANDIDATES
    loc = solve.locate(mesh, point, max_outside_mm=0.0)
    assert loc.tet[0] == 0 and loc.outside_mm[0] == 0.0
    assert loc.bary[0] @ big[:4] == pytest.approx(point, abs=1e-12)


def test_a_flank_point_outside_the_tooth_is_an_error_named_by_member_and_kind():
    import re
    from types import SimpleNamespace

    from itertools import permutations

    from beveloid.fe.tooth import flank_compliance

    # a 14 x 6 x 10 mm block as six straight tets about its diagonal (Kuhn's split)
    size = np.array([14.0, 6.0, 10.0])
    tets = []
    for axes in permutations(range(3)):
        corners = [np.zeros(3)]
        for k in axes:
            corners.append(corners[-1] + np.eye(3)[k])
        tets.append(_one_tet(np.array(corners) * size))
    nodes = np.vstack(tets)
    mesh = SimpleNamespace(nodes=nodes, tets=np.arange(len(nodes)).reshape(-1, 10))
    n = len(mesh.nodes)  # the points are located before anything is solved: no factorisation needed
    elastic = SimpleNamespace(mesh=mesh, node_dofs=3 * np.arange(n)[:, None] + np.arange(3), ndofs=3 * n,
                              e_mpa=2.06e5, nu=0.3, geometry=None)  # (the tets' geometry computed where needed)
    normal = np.array([[0.0, 1.0, 0.0]])
    label = "FE tooth pinion, right flank"
    # on the flank y = 6, read 2 mm beneath: inside
    flank_compliance(elastic, np.array([[7.0, 6.0, 6.0]]), normal, np.array([2.0]), solutions=np.zeros((3 * n, 1)),
                     max_outside_mm=0.05, label=label)
    cases = {"load": ([7.0, 7.0, 6.0], 2.0),  # 1 mm off the flank, its reading point 1 mm inside
             "reading": ([7.0, 6.0, 6.0], 7.0)}  # read 7 mm deep through the 6 mm thick block
    for kind, (point, d) in cases.items():
        with pytest.raises(ValueError) as err:
            flank_compliance(elastic, np.array([point]), normal, np.array([d]), max_outside_mm=0.05, label=label)
        text = str(err.value)
        where = point if kind == "load" else [7.0, 6.0 - d, 6.0]
        assert text.startswith(f"{label} {kind} point {where} mm lies ") and "\n" not in text
        assert text.endswith("mm outside the mesh: must be inside the solid or within 0.05 mm of it")
        # at least its distance to the block (1 mm): it is read at its clipped barycentric coordinates
        assert 1.0 <= float(re.search(r"lies (\S+) mm", text).group(1)) < 2.0
