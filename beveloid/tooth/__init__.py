"""The whole tooth (issue 22): root fillet, undercut, tip thickness, interference, contact ratio.

One module per check; ``fillet`` evaluates the generated root fillet.
"""

__all__ = ["contact", "fillet", "plot", "profile", "report", "sections", "tip", "undercut"]

