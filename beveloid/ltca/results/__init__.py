"""What a loaded analysis returns: the result and its JSON (``result``), many of them (``batch``:
torques x error sets, the per-run summary), the pattern over the cycle (``pattern``) and the figures
(``plots``)."""

__all__ = ["batch", "pattern", "plots", "result"]
