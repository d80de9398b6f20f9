"""docs/validation.md 8.2 and 8.3: tip reliefs on case 1 beside the micro-geometry study's.

    python benchmarks/micro_geometry_variants.py

8.3: reliefs smaller and larger than the study's (30 um over 0.4 m_n), loaded as the study loads it
(`studies.micro_geometry.loaded_rows`: plate tooth, right flank, 5 positions, 11 x 21 cells, 200 / 400 /
600 N m); per relief (amount um, height in normal modules, parabolic, both members, no end relief) the
max pressure (MPa) and the loaded TE mean and p-p (urad).  8.2: the TCA (60 positions x 3 pairs) of
case 1 with crowning 20 / 20 um, end relief 15 um over 8 mm and a tip relief of 20 um over 2 mm, linear
and parabolic: the failed points per flank, the positions with a carrying contact and those where
the TE envelope is complete (`mesh.envelope_complete`).
Not a test.
"""
import dataclasses

from beveloid import tca
from beveloid.pair import Pair
from beveloid.status import Status
from beveloid.studies import micro_geometry as study


def relieved(geom, amount_um, height_modules, **more):
    """Both members with a parabolic tip relief of amount_um over height_modules m_n (and ``more``
    surface options)."""
    options = dict(study.modification(geom, tip=True, ends=False), tip_relief_um=amount_um,
                   tip_relief_height_mm=height_modules * geom.normal_module_mm, **more)
    return dataclasses.replace(geom, **{m: dataclasses.replace(getattr(geom, m), tooth_surface="micro_geometry",
                                                               surface_options=tuple(sorted(options.items())))
                                        for m in ("pinion", "gear")})


geom = Pair.example("case1").geometry
for amount_um, height in ((15.0, 0.25), (30.0, 0.4), (50.0, 0.5)):
    for label, torque, peak, te_mean, te_ptp, converged in study.loaded_rows(relieved(geom, amount_um, height),
                                                                             f"{amount_um:g} um over {height:g} m_n"):
        print(f"case1 | {label} | {torque:g} N m | max pressure {peak:.0f} MPa | loaded TE {te_mean:.1f} / "
              f"p-p {te_ptp:.1f} urad | {converged}/{study.POSITIONS} converged")

for shape in ("linear", "parabolic"):
    g = relieved(geom, 20.0, 2.0 / geom.normal_module_mm, tip_relief_shape=shape, profile_crowning_um=20.0,
                 lead_crowning_um=20.0, end_relief_um=15.0, end_relief_length_mm=8.0, end_relief_shape="parabolic")
    res = tca.analyze(g, tca.Options(positions=60))
    for flank, fr in res.flanks.items():
        failed = sum(s == Status.FAILED.label for s in fr.status)
        carried = int(fr.active.reshape(-1, fr.positions).any(axis=0).sum())
        print(f"case1, {shape} tip relief 20 um over 2 mm, crowned, end relief | {flank} | failed {failed} of "
              f"{len(fr.status)} pair-positions | a carrying contact at {carried} of {fr.positions} positions "
              f"(TE envelope complete at {int(fr.te_envelope_complete.sum())})")
