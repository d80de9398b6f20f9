"""The whole tooth (issue 22): root fillet, undercut, tip thickness, interference, contact ratio.

One module per check; ``fillet`` evaluates the generated root fillet; ``screen`` finds, over many designs
at once, those clear of the undercut and tip checks' statuses.
"""

__all__ = ["contact", "fillet", "plot", "profile", "report", "screen", "sections", "tip", "undercut"]

