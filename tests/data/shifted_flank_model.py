"""A tooth-surface model for the plug-in test: the involute flank (Eqs 1-7) moved along the
member's own axis by ``axial_shift_mm``.  Derived from a copy outside the checkout by
tests/models/test_models_installed.py (``beveloid derive --model``); not part of the product."""
import sympy as sp

from beveloid.derivations import eq04_07_tooth_surface as involute
from beveloid.derivations.interface import Field

axial_shift = sp.Symbol("axial_shift_mm", real=True)

PARAMETERS = (Field("axial_shift_mm", axial_shift, "mm", "shift of the whole flank along the member axis"),)
KEYS = {"axial_shift_mm": (0.0, -5.0, 5.0)}
SELECTED_BY = ("axial_shift_mm",)


def tooth_surface(sigma):
    point, normal, roll = involute.tooth_surface(sigma)
    return point + sp.Matrix([0, 0, axial_shift]), normal, roll
