"""An independent check of the loaded contact by full-contact finite elements (CalculiX).

``deck`` writes a CalculiX input deck of elastic solids in frictionless contact; ``run`` starts
``ccx`` (Debian's package ``calculix-ccx``) with its output streamed; ``results`` reads its .frd /
.dat and writes a VTU; ``sphere_block`` is the closed-form check of that pipeline (Hertz);
``pair_model`` builds the pair's contact model from the FE tooth's sector meshes, refined over the
LTCA's loaded patches (``strips``: ``beveloid.fe.sizes``' contact strips), and ``check`` runs it
beside the LTCA (``beveloid fe-check``):

    from beveloid import fecheck, ltca
    result = fecheck.analyze(pair, ltca.LoadCase(200.0), fecheck.Options(ltca=ltca.Options(flank="left")))
    result.to_json()
"""
from __future__ import annotations

from .check import Options, analyze
from .deck import Body, ContactDeck, RigidLoad, write_deck
from .result import CheckResult
from .run import CCX_MISSING, ccx_path, ccx_version, run_ccx

__all__ = ["Body", "CCX_MISSING", "CheckResult", "ContactDeck", "Options", "RigidLoad", "analyze", "ccx_path",
           "ccx_version", "run_ccx", "write_deck"]
