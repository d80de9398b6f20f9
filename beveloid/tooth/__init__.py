"""The whole tooth (issue 22): root fillet, undercut, tip thickness, interference, contact ratio,
and the tooth's solid below the analyses that build on it.

One module per check; ``fillet`` evaluates the generated root fillet; ``screen`` finds, over many
designs at once, those clear of the undercut and tip checks' statuses; ``sampling`` samples the
tooth's faces (the export, the FE tooth and fe-check build their solids from it); ``body`` is the
member cut by the unmodified rack (the FE tooth's).  The analysis: ``tooth.analyze(pair, options=None, *,
solver=None) -> ToothResult`` (``report``).
"""
from .report import Options, ToothResult, analyze

__all__ = ["analyze", "Options", "ToothResult", "body", "contact", "fillet", "plot", "profile", "report", "sampling", "screen", "sections", "tip", "undercut"]

