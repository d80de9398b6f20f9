"""The micro-geometry tooth-surface model (derivations/flank_micro_geometry.py): the generated
kernels against the definition of issue 20, written here independently in numpy.

    delta = C_a max(0, (rho - (rho_a(z) - h_a)) / h_a)^e_a + C_e max(0, (|z| - (W/2 - L_e)) / L_e)^e_e
            + f_b z / (W/2),          P = q - delta n   (q, n: the crowned surface)
"""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from beveloid.generated import tca_kernels

FLANKS = ("left", "right")
OFF = dict(tip_relief_um=0.0, tip_relief_height_mm=1.0, tip_relief_shape="parabolic", end_relief_um=0.0,
           end_relief_length_mm=1.0, end_relief_shape="parabolic", lead_slope_um=0.0)
SHAPE = {"linear": 1, "parabolic": 2}


def with_model(geom, model, **opts):
    """The pair with the pinion on ``model`` and its options (the gear unchanged)."""
    return dataclasses.replace(geom, pinion=dataclasses.replace(
        geom.pinion, tooth_surface=model, surface_options=tuple(sorted(opts.items()))))


def removal_mm(geom, q, opts):
    """delta of issue 20 at base points q (..., 3) of the pinion, in mm."""
    m = geom.pinion
    rho = np.hypot(q[..., 0], q[..., 1])
    z = q[..., 2] - m.reference_section_offset_mm
    h, length, w = opts["tip_relief_height_mm"], opts["end_relief_length_mm"], m.face_width_mm
    tip = np.maximum(0.0, (rho - (m.tip_radius(q[..., 2]) - h)) / h) ** SHAPE[opts["tip_relief_shape"]]
    ends = np.maximum(0.0, (np.abs(z) - (w / 2 - length)) / length) ** SHAPE[opts["end_relief_shape"]]
    return 1e-3 * (opts["tip_relief_um"] * tip + opts["end_relief_um"] * ends + opts["lead_slope_um"] * z / (w / 2))


def grid(geom, n=9):
    """(l, u) over the pinion flank, reaching the tip band and both face ends."""
    m = geom.pinion
    lmax = (m.tip_height_mm + m.cutter_addendum_mm) / np.cos(geom.normal_pressure_angle)
    return np.meshgrid(np.linspace(0.2, lmax, n), np.linspace(-0.55, 0.55, n) * m.face_width_mm, indexing="ij")


def kernels(geom, flank, l, u):
    params = geom.surface_params("pinion")
    model = geom.pinion.tooth_surface
    return {"surface": tca_kernels.surface(model, flank, l, u, params),
            "jet": tca_kernels.surface_jet(model, flank, l, u, params),
            "second": tca_kernels.surface_second_derivatives(model, flank, l, u, params),
            "forms": tca_kernels.surface_fundamental_forms(model, flank, l, u, params)}


@pytest.mark.parametrize("crowning", [(0.0, 0.0), (12.0, 7.0)])
def test_all_new_keys_zero_is_the_crowned_or_involute_surface(geom1, crowning):
    prof, lead = crowning
    micro = with_model(geom1, "micro_geometry", profile_crowning_um=prof, lead_crowning_um=lead, **OFF)
    ref = (with_model(geom1, "crowned", profile_crowning_um=prof, lead_crowning_um=lead) if prof or lead
           else geom1)
    assert ref.pinion.tooth_surface == ("crowned" if prof else "involute")
    l, u = grid(geom1)
    for flank in FLANKS:
        a, b = kernels(micro, flank, l, u), kernels(ref, flank, l, u)
        for kind in a:
            for name, x in a[kind]._asdict().items():
                y = getattr(b[kind], name)
                scale = max(1.0, float(np.abs(y).max()))
                assert np.abs(np.asarray(x) - y).max() <= 1e-12 * scale, (flank, kind, name)


def test_crowned_at_zero_crowning_is_involute(geom1):
    crowned = with_model(geom1, "crowned", profile_crowning_um=0.0, lead_crowning_um=0.0)
    l, u = grid(geom1)
    for flank in FLANKS:
        a, b = kernels(crowned, flank, l, u), kernels(geom1, flank, l, u)
        for kind in ("surface", "jet"):
            for name, x in a[kind]._asdict().items():
                assert np.abs(np.asarray(x) - getattr(b[kind], name)).max() <= 1e-12, (flank, kind, name)


CASES = [
    dict(tip_relief_um=25.0, tip_relief_height_mm=1.2, tip_relief_shape="linear", end_relief_um=18.0,
         end_relief_length_mm=4.0, end_relief_shape="parabolic", lead_slope_um=-9.0),
    dict(tip_relief_um=40.0, tip_relief_height_mm=0.8, tip_relief_shape="parabolic", end_relief_um=30.0,
         end_relief_length_mm=6.5, end_relief_shape="linear", lead_slope_um=12.0),
]


@pytest.mark.parametrize("opts", CASES)
def test_displacement_along_the_normal_is_the_removal(geom1, opts):
    crown = dict(profile_crowning_um=8.0, lead_crowning_um=15.0)
    micro = with_model(geom1, "micro_geometry", **crown, **opts)
    base = with_model(geom1, "crowned", **crown)
    l, u = grid(geom1, 15)
    for flank in FLANKS:
        q, n, phi_q = tca_kernels.surface("crowned", flank, l, u, base.surface_params("pinion"))
        p, n_p, phi_p = tca_kernels.surface("micro_geometry", flank, l, u, micro.surface_params("pinion"))
        delta = removal_mm(geom1, q, opts)
        assert np.abs(p - (q - delta[..., None] * n)).max() <= 1e-12
        assert np.abs(phi_p - phi_q).max() <= 1e-14  # the roll angle is the base point's
        # the samples reach every piece of delta
        rho = np.hypot(q[..., 0], q[..., 1])
        in_tip = rho > geom1.pinion.tip_radius(q[..., 2]) - opts["tip_relief_height_mm"]
        z = np.abs(q[..., 2] - geom1.pinion.reference_section_offset_mm)
        assert in_tip.any() and (~in_tip).any()
        assert (z > geom1.pinion.face_width_mm / 2 - opts["end_relief_length_mm"]).any()
        # the normal: unit, perpendicular to the modified surface, on the base normal's side
        jet = tca_kernels.surface_jet("micro_geometry", flank, l, u, micro.surface_params("pinion"))
        assert np.abs(np.linalg.norm(n_p, axis=-1) - 1).max() <= 1e-12
        for k in range(2):
            assert np.abs(np.einsum("...i,...i", jet.point_D_lu[..., k], n_p)).max() <= 1e-12
        assert (np.einsum("...i,...i", n_p, n) > 0.5).all()  # (beyond the tip the ramp keeps rising)


def _complex_step(fn, l, u, h=1e-30):
    """[d/dl, d/du] of fn(l, u) by complex step (fn analytic: away from a ramp's kink)."""
    return np.stack([fn(l + 1j * h, u).imag / h, fn(l, u + 1j * h).imag / h], axis=-1)


@pytest.mark.parametrize("opts", CASES)
def test_jacobians_by_complex_step(geom1, opts):
    """point_D_lu, normal_D_lu and the second derivatives against complex steps of the generated
    point and normal (the kernels take complex l, u: numpy.select compares real parts), at samples
    away from the kinks (each ramp's argument more than 1e-6 from 0)."""
    micro = with_model(geom1, "micro_geometry", profile_crowning_um=8.0, lead_crowning_um=15.0, **opts)
    params = micro.surface_params("pinion")
    l, u = (x.ravel() for x in grid(geom1, 11))
    base = with_model(geom1, "crowned", profile_crowning_um=8.0, lead_crowning_um=15.0)
    q = tca_kernels.surface("crowned", "left", l, u, base.surface_params("pinion")).point
    m = geom1.pinion
    t_tip = (np.hypot(q[:, 0], q[:, 1]) - (m.tip_radius(q[:, 2]) - opts["tip_relief_height_mm"]))
    t_end = np.abs(q[:, 2] - m.reference_section_offset_mm) - (m.face_width_mm / 2 - opts["end_relief_length_mm"])
    keep = (np.abs(t_tip) > 1e-6) & (np.abs(t_end) > 1e-6)
    l, u = l[keep], u[keep]
    for flank in FLANKS:
        def point(ll, uu):
            return tca_kernels.surface("micro_geometry", flank, ll, uu, params.astype(complex)).point

        def normal(ll, uu):
            return tca_kernels.surface("micro_geometry", flank, ll, uu, params.astype(complex)).normal

        def d_point(ll, uu):
            return tca_kernels.surface_jet("micro_geometry", flank, ll, uu, params.astype(complex)).point_D_lu

        jet = tca_kernels.surface_jet("micro_geometry", flank, l, u, params)
        second = tca_kernels.surface_second_derivatives("micro_geometry", flank, l, u, params).point_D2_lu
        assert np.abs(jet.point_D_lu - _complex_step(point, l, u)).max() <= 1e-10
        assert np.abs(jet.normal_D_lu - _complex_step(normal, l, u)).max() <= 1e-10
        d2 = _complex_step(d_point, l, u)  # (..., 3, 2, 2): [d/dl, d/du] of [R_l, R_u]
        assert np.abs(second[..., 0] - d2[..., 0, 0]).max() <= 1e-9
        assert np.abs(second[..., 1] - d2[..., 1, 0]).max() <= 1e-9
        assert np.abs(second[..., 1] - d2[..., 0, 1]).max() <= 1e-9
        assert np.abs(second[..., 2] - d2[..., 1, 1]).max() <= 1e-9


def test_derivatives_at_a_linear_kink_are_one_sided(geom1):
    """At the start of a linear tip relief the point is continuous and its derivative jumps: the
    kernel gives the derivative of the side it is on (central differences over the kink see the
    mean of both, one-sided differences each side)."""
    opts = dict(OFF, tip_relief_um=30.0, tip_relief_height_mm=1.0, tip_relief_shape="linear", profile_crowning_um=0.0,
                lead_crowning_um=0.0)
    micro = with_model(geom1, "micro_geometry", **opts)
    params = micro.surface_params("pinion")
    m = geom1.pinion
    u = 0.0
    # find l where the base point crosses rho = rho_a - h_a (bisection on the involute: no crowning)
    def t(ll):
        q = tca_kernels.surface("involute", "left", ll, u, geom1.surface_params("pinion")).point
        return np.hypot(q[0], q[1]) - (m.tip_radius(q[2]) - 1.0)
    lo, hi = 0.5, (m.tip_height_mm + m.cutter_addendum_mm) / np.cos(geom1.normal_pressure_angle)
    assert t(lo) < 0 < t(hi)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if t(mid) < 0 else (lo, mid)
    h = 1e-6
    below, above = lo - 10 * h, hi + 10 * h
    d_below = tca_kernels.surface_jet("micro_geometry", "left", below, u, params).point_D_lu[:, 0]
    d_above = tca_kernels.surface_jet("micro_geometry", "left", above, u, params).point_D_lu[:, 0]
    pt = lambda ll: tca_kernels.surface("micro_geometry", "left", ll, u, params).point  # noqa: E731
    assert np.abs(d_below - (pt(below + h) - pt(below - h)) / (2 * h)).max() < 1e-6
    assert np.abs(d_above - (pt(above + h) - pt(above - h)) / (2 * h)).max() < 1e-6
    jump = np.linalg.norm(d_above - d_below)
    assert jump > 1e-3  # 30 um over 1 mm of radius: a slope change of order 0.03
    assert np.linalg.norm(pt(hi) - pt(lo)) < 1e-9  # continuous


@pytest.mark.slow
@pytest.mark.long_running
def test_displacement_is_the_removal_in_50_digits():
    """The derivation itself (derivations/flank_micro_geometry.py: the modified point over its stages,
    the stages being the crowned derivation's point and normal and the removal) at 50 digits:
    P - (q - delta n), with delta from the definition in mpmath."""
    import mpmath
    import sympy as sp

    from beveloid.derivations import crowned_flank, flank_micro_geometry as fm
    from beveloid.derivations.flank_boundaries import tip_height
    from beveloid.derivations.symbols import a, alpha_n, b, beta, gamma, l, m_n, r, s, u

    mpmath.mp.dps = 50
    sigma = 1
    point, _, _, substitute, stages = fm.tooth_surface_staged(sigma)
    P = substitute(point)
    q, n, _ = crowned_flank.tooth_surface(sigma)
    jets = {sym: e for sym, e in stages}
    names = [f"_jet_{v}{c}" for v in "qn" for c in "xyz"]
    base = {sp.Symbol(k, real=True): (list(q) + list(n))[i] for i, k in enumerate(names)}
    assert all(sp.Symbol(k, real=True) in jets for k in names)
    R = sp.Rational
    vals = {alpha_n: sp.pi / 9, beta: R(2, 5), gamma: R(7, 200), a: R(15, 2), b: 3 * sp.pi / 2, s: R(3, 10), r: 95,
            m_n: 6, fm.W: 50, crowned_flank.C_alpha: 8, crowned_flank.C_beta: 15, tip_height: 6, fm.b_c: R(3, 2),
            fm.C_a: 25, fm.h_tr: 2, fm.e_a: 1, fm.C_e: 18, fm.L_e: 4, fm.e_e: 2, fm.f_b: -9}
    seen = set()
    for lv, uv in ((R(3), R(-23)), (R(12), R(2)), (R(13), R(24)), (R(6), R(10))):
        at = {k: sp.Float(sp.N(v, 60), 60) for k, v in {**vals, l: lv, u: uv}.items()}
        num = {sym: sp.Float(e.evalf(60, subs=at), 60) for sym, e in base.items()}  # q, n from crowned_flank
        num[sp.Symbol("_jet_delta", real=True)] = jets[sp.Symbol("_jet_delta", real=True)].evalf(60, subs={**at, **num})
        pv = [mpmath.mpf(str(c.evalf(60, subs={**at, **num}))) for c in P]
        qv = [mpmath.mpf(str(num[sp.Symbol(f"_jet_q{c}", real=True)])) for c in "xyz"]
        nv = [mpmath.mpf(str(num[sp.Symbol(f"_jet_n{c}", real=True)])) for c in "xyz"]
        rho = mpmath.sqrt(qv[0] ** 2 + qv[1] ** 2)
        g = mpmath.mpf(7) / 200
        rho_a = 95 + (6 + mpmath.mpf(3) / 10) / mpmath.cos(g) + qv[2] * mpmath.tan(g)
        z = qv[2] - mpmath.mpf(3) / 2
        t_tip = (rho - (rho_a - 2)) / 2
        t_end = (abs(z) - (25 - 4)) / 4
        delta = (25 * max(0, t_tip) + 18 * max(0, t_end) ** 2 - 9 * z / 25) / 1000
        seen |= {("tip", t_tip > 0), ("end", t_end > 0)}
        assert max(abs(pv[i] - (qv[i] - delta * nv[i])) for i in range(3)) < mpmath.mpf(10) ** -40
    assert seen == {("tip", True), ("tip", False), ("end", True), ("end", False)}  # every branch sampled


def test_the_study_map_covers_the_whole_blank_and_peaks_at_the_tip_corners(geom1):
    """The modification map of `beveloid paper` (studies.micro_geometry.delta_map) reaches both face
    ends over the whole flank height (a helical flank's generating lines cross the end planes
    obliquely), and its largest removal is tip + end relief together, at a tip corner."""
    from beveloid.studies import micro_geometry as mg

    both = mg.modified(geom1)
    z, rho, d = mg.delta_map(both)
    w = geom1.pinion.face_width_mm
    inside = np.isfinite(d)
    assert inside.sum() > 0.4 * d.size
    assert z[inside].min() < -0.49 * w and z[inside].max() > 0.49 * w
    for lo, hi in ((0.1, 0.3), (0.7, 0.9)):  # a low and a high band of the flank
        r0, r1 = np.nanmin(rho[inside]), np.nanmax(rho[inside])
        band = inside & (rho > r0 + lo * (r1 - r0)) & (rho < r0 + hi * (r1 - r0))
        assert z[band].min() < -0.47 * w and z[band].max() > 0.47 * w
    opts = dict(both.pinion.surface_options)
    corner = opts["tip_relief_um"] + opts["end_relief_um"]
    assert 0.85 * corner < np.nanmax(d) <= corner * (1 + 1e-9)
    assert np.nanmin(d) > -1e-6
