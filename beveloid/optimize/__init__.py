"""Flank-modification optimisation (``beveloid optimize``, docs/optimize.md): the micro-geometry that
keeps the loaded contact quiet and strong over a duty cycle (torques and weights) and a tolerance box
(error sets drawn once, the same for every candidate).

request.py   what a run asks: the varied micro-geometry keys and their ranges, the torques and
             weights, the error sets, the objectives, the loaded analysis' settings (Request)
evaluate.py  one candidate: its spec, the loaded quantities per torque and error set
             (:func:`evaluate.loaded_quantities`, the one loop over ``ltca.analyze``), the
             objectives and the rating's local safeties at the highest torque
search.py    NSGA-II (pymoo) asking for candidates, evaluated on any executor (beveloid.parallel),
             each kept on disk as it finishes; a resumed run replays the seeded search
report.py    candidates.csv, pareto.csv, summary.json, pareto_<n>.toml, the figures and the JSON
The command itself is beveloid/cli/optimize.py.
"""

__all__ = ["evaluate", "report", "request", "search"]
