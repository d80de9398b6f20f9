"""The whole tooth (issue 22): root fillet, undercut, tip thickness, interference, contact ratio.

One module per check; ``body`` is the member cut by the unmodified rack (the FE tooth's); ``fillet`` evaluates the generated root fillet; ``screen`` finds, over many designs
at once, those clear of the undercut and tip checks' statuses.
"""

__all__ = ["body", "contact", "fillet", "plot", "profile", "report", "screen", "sections", "tip", "undercut"]

