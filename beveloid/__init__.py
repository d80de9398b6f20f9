"""beveloid: crossed beveloid gears, pitch-cone design and tooth contact analysis.

Implements Zhu, Song, Lim & Peng, "Pitch cone design and influence of misalignments on
tooth contact behaviors of crossed beveloid gears", Mech. Mach. Theory 59 (2013) 48-64.
The runtime uses only the numeric modules in ``beveloid.generated``; sympy is imported
only by ``beveloid.derivations`` and the generator (``beveloid derive``).
"""
__version__ = "0.1.0"
#: the public surface is the subpackages (beveloid.pair, beveloid.tca, ...); this module only names the version
__all__ = ["__version__"]

import os as _os

# In a source checkout, ``beveloid.derivations`` and ``beveloid.generated`` are the top-level
# folders derivations/ and generated/ (an install maps them in: pyproject.toml's package-dir).
# Put the checkout on the package path so that ``python -m pytest``, a REPL or a script run in
# the checkout imports the whole package the same way as an installed copy.
_here = _os.path.dirname(_os.path.abspath(__file__))
_checkout = _os.path.dirname(_here)
if not _os.path.isdir(_os.path.join(_here, "generated")) and all(
        _os.path.isfile(_os.path.join(_checkout, d, "__init__.py")) for d in ("generated", "derivations")):
    __path__.append(_checkout)
del _here, _checkout

# Tooth-surface models beyond the built-in ones (docs/models.md): an import hook serves them and
# the glue that dispatches to them into beveloid.generated; nothing is read before the first
# import of a glue module, and nothing is served when there are none.
from .models.finder import install as _install_models  # noqa: E402

_install_models()
del _install_models
