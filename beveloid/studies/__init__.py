"""Studies: computations that combine the analyses into a result of their own, with figures and a report.

    paper.py     ``beveloid paper``: Table 1 and the studies of the paper's Figs 10-22, report.md
    crowning.py  TE of crowned pairs, and the crowning that gives the paper's aligned TE (in ``paper``)
    loaded.py    the loaded contact of Figs 24-25 (the LTCA, in ``paper``)

Each study takes pairs (:class:`beveloid.pair.Pair`) and writes into a folder; nothing here is
imported by the analyses.
"""

__all__ = ["crowning", "loaded", "micro_geometry", "output", "paper"]

