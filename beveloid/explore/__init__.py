"""Design exploration (``beveloid explore``, docs/explore.md): map the pitch-cone design space.

grid.py     the designs: --vary grids and Latin hypercube samples (Plan)
(the designs themselves: beveloid.design.design_arrays, the one design of one or many specs)
contact.py  the aligned contact at P and tca.sensitivity's derivatives for arrays of designs
aligned.py  its loop over the designs through the solver core (compiled: the module's compiled twin)
rows.py     one row per design: status, working data, FPD angles, sensitivities, Monte Carlo
pareto.py   the Pareto front
run.py      fixed chunks on any executor (beveloid.parallel), kept on disk, resume
report.py   explore.csv, pareto.csv, summary.json, figures
The command itself is beveloid/cli/explore.py.
"""

__all__ = ["aligned", "contact", "grid", "pareto", "report", "rows", "run", "tooth"]

