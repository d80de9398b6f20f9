"""Issue 57: a pair that runs onto several flank edges is told to relieve each of them.  The edge rule
judged only the most loaded edge, so the condition named one (and which one flipped with the grid where
two edges carried about the same share), though relieving it alone would not make the pair pass."""
from __future__ import annotations

from beveloid import ltca, rating
from beveloid.pair import Pair
from beveloid.rating.edge import edge_loads
from beveloid.rating.verdict import EDGE_SHARE
from beveloid.spec import spec_from_dict

#: design H of benchmarks/rating_invariance.py: m_n 4, 20/37 teeth, a narrow face (4.5 m_n) without any
#: modification, 0.03 deg vertical and 0.05 mm axial error; both tips carry 17-20 % of the mesh's load
SPEC = {
    "pair": {"normal_module_mm": 4.0, "normal_pressure_angle_deg": 20.0, "shaft_angle_deg": 18.0, "offset_mm": 117.0},
    "pinion": {"teeth": 20, "cone_angle_deg": 2.5, "helix_angle_deg": 22.0, "profile_shift": 0.2, "face_width_mm": 18.0},
    "gear": {"teeth": 37, "cone_angle_deg": 1.0, "face_width_mm": 20.0},
    "misalignment": {"vertical_deg": 0.03, "dz_mm": 0.05},
}


def test_the_condition_names_every_edge_over_the_limit():
    pair = Pair.from_spec(spec_from_dict(SPEC))
    opts = ltca.Options(positions=11, tooth_model="plate")
    lt = ltca.analyze(pair, ltca.LoadCase(80.0), opts)
    every = edge_loads(lt, pair.geometry, by_edge=True)
    assert len({(e.member, e.edge) for e in every}) == len(every)
    assert [e.share for e in every] == sorted((e.share for e in every), reverse=True)
    assert every[0] == edge_loads(lt, pair.geometry)  # the rule's edge is still the most loaded
    over = [e for e in every if e.share > EDGE_SHARE]
    assert {(e.member, e.edge) for e in over} >= {("pinion", "tip"), ("gear", "tip")}

    v = rating.verdict(rating.analyze(pair, ltca.LoadCase(80.0), rating.Options(opts), ltca_result=lt))
    assert v["status"] == "conditional"
    also = v["edge_contact"]["also"]
    assert [(a["member"], a["edge"]) for a in also] == [(e.member, e.edge) for e in over[1:]]
    for e in over:
        where = f"the {e.edge} of the {e.member}"
        assert f"{where} is relieved (tip relief)" in v["condition"] if e.edge == "tip" else where in v["condition"]
        assert where in v["line"]
