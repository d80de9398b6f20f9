"""The pair under load: the unloaded gap over each contact grid (``gaps``), the grids sized from the
contact (``grid``), the compliance of a tooth pair (``compliance``) and the teeth that bend (``teeth``:
the plate or the FE tooth)."""

__all__ = ["compliance", "gaps", "grid", "teeth"]
