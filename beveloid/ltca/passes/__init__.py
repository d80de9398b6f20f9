"""The passes over the positions of a mesh cycle: the rigid reference and the contact solves of every
position (``cycle``) and the passes from the coarse grid to the result and its convergence indicator
(``analysis``: the one engine of :func:`beveloid.ltca.analyze`)."""

__all__ = ["analysis", "cycle"]
