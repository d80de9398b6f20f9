"""The verdict's local contact pressure is read beyond the edge break (issue 57): the pressure in a flank
corner next to an edge, which the LTCA's cell-count rule counts as surface on a fine grid and as edge on a
coarse one and which grows there with the grid, belongs to the edge rule on every grid, so S_H does not
move with --grid."""
from __future__ import annotations

import numpy as np

from beveloid import ltca
from beveloid.pair import Pair
from beveloid.rating.analysis import loaded_contact
from beveloid.rating.edge import BAND_MODULES, SURFACE_BAND_MODULES, surface_peaks


def test_the_local_contact_pressure_holds_on_a_finer_grid():
    """Case 1 at 1500 N m: at one position the leaving pair touches in a flank corner.  The LTCA's own surface
    peak jumps on the finer grid (cells near the corner count as surface there), and so does the pressure
    read just beyond the edge rule's band (0.05 m_n: the corner's d^-1/2 tail, 698 against 782 MPa on the
    7x11 and 15x25 grids); read beyond the edge break (0.1 m_n) it holds (698 against 712)."""
    pair = Pair.example("case1")
    m = pair.geometry.normal_module_mm
    b = min(pair.geometry.pinion.face_width_mm, pair.geometry.gear.face_width_mm)
    peaks, raw, near = [], [], []
    for grid in ((7, 11), (15, 25)):
        r = ltca.analyze(pair, ltca.LoadCase(1500.0), ltca.Options(positions=21, grid=grid, tooth_model="plate"))
        peaks.append(loaded_contact(r, pair.geometry, b).surface_pressure_max_mpa)
        raw.append(float(np.nanmax(r.pair_surface_max_pressure_mpa)))
        near.append(float(np.nanmax(surface_peaks(r, pair.geometry, band_mm=BAND_MODULES * m))))
        # every peak read is one of the LTCA's surface cells' pressures, never above its surface peak
        s = surface_peaks(r, pair.geometry)
        ok = np.isfinite(s)
        assert np.all(s[ok] <= r.pair_surface_max_pressure_mpa[ok] + 1e-9)
        np.testing.assert_array_equal(s, surface_peaks(r, pair.geometry, band_mm=SURFACE_BAND_MODULES * m))
    # the case means something: the LTCA's surface peak and the reading at the edge rule's band jump
    assert raw[1] > 1.10 * raw[0]
    assert near[1] > 1.05 * near[0]
    assert abs(peaks[1] / peaks[0] - 1.0) < 0.03, (peaks, near, raw)


def test_a_band_of_zero_is_the_ltcas_surface_peak():
    pair = Pair.example("case1")
    r = ltca.analyze(pair, ltca.LoadCase(300.0), ltca.Options(positions=5, tooth_model="plate"))
    s = surface_peaks(r, pair.geometry, band_mm=0.0)
    np.testing.assert_array_equal(np.isfinite(s), np.isfinite(r.pair_surface_max_pressure_mpa))
    ok = np.isfinite(s)
    np.testing.assert_allclose(s[ok], r.pair_surface_max_pressure_mpa[ok], rtol=1e-12)
    assert BAND_MODULES * pair.geometry.normal_module_mm > 0
