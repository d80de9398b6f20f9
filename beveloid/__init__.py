"""beveloid: crossed beveloid gears, pitch-cone design and tooth contact analysis.

Implements Zhu, Song, Lim & Peng, "Pitch cone design and influence of misalignments on
tooth contact behaviors of crossed beveloid gears", Mech. Mach. Theory 59 (2013) 48-64.
The runtime uses only the numeric modules in ``beveloid.generated``; sympy is imported
only by ``beveloid.derivations`` and the generator (``beveloid derive``).
"""
__version__ = "0.1.0"
