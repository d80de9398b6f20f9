"""A wrong tooth-surface model for tests/models/test_models_catalog.py: the involute flank sheared
along the member axis in proportion to l, with the involute's normal left unchanged (no longer
the sheared surface's normal): `beveloid derive --model` must refuse it."""
import sympy as sp

from beveloid.derivations import eq04_07_tooth_surface as involute
from beveloid.derivations.interface import Field
from beveloid.derivations.symbols import l

shear = sp.Symbol("shear_mm_per_mm", real=True)

PARAMETERS = (Field("shear_mm_per_mm", shear, "mm/mm", "axial shift of the flank per mm of l"),)
KEYS = {"shear_mm_per_mm": (0.0, 0.0, 0.5)}


def tooth_surface(sigma):
    point, normal, roll = involute.tooth_surface(sigma)
    return point + sp.Matrix([0, 0, shear * l]), normal, roll
