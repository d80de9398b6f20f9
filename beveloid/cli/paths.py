"""The CLI's output targets: the one rule of :mod:`beveloid.outputs` (the API keeps it too)."""
from __future__ import annotations

from ..outputs import OutputError, check_output_dir, check_output_file, created_here, remove_empty_created

__all__ = ["OutputError", "check_output_file", "check_output_dir", "created_here", "remove_empty_created"]
