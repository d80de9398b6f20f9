"""Studies: computations that combine the analyses into a result of their own, with figures and a report.

    paper.py     ``beveloid paper``: PAPER_CONTENTS (below), report.md
    crowning.py  TE of crowned pairs, and the crowning that gives the paper's aligned TE (in ``paper``)
    loaded.py    the loaded contact of Figs 24-25 (the LTCA, in ``paper``)
    micro_geometry.py  tip and end relief on the paper's cases (in ``paper``)

Each study takes pairs (:class:`beveloid.pair.Pair`) and writes into a folder; nothing here is
imported by the analyses.
"""

__all__ = ["PAPER_CONTENTS", "crowning", "loaded", "micro_geometry", "output", "paper"]

#: what ``beveloid paper`` reproduces and adds: its report's title and its help text say it
PAPER_CONTENTS = ("Table 1, Figs 10-22 (unloaded TCA), Figs 24-25 (loaded contact), a crowning and a "
                  "micro-geometry study")

