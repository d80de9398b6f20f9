"""The folder of a long run that keeps its pieces on disk (``beveloid explore``'s chunks, ``beveloid
optimize``'s candidates): its request (``request.json``) beside a subfolder of pieces, so that a run
stopped early goes on with ``--resume`` and a second run cannot mix its pieces into another's.

:class:`RunStore` is the one implementation of the rules both commands keep: a fresh run into a folder
that holds another request is refused, one line; ``--resume`` of a folder without a request, or of one
whose pieces another version of the code computed, is refused, one line saying how to go on (that last
one with :attr:`beveloid.errors.ErrorCode.STALE_RESULTS`); the request is written before any piece.
:class:`RunResult` is what both runs return: how the run ended, a :class:`beveloid.result.Result`.
"""
from __future__ import annotations

import json
import os
from dataclasses import dataclass

from .errors import ErrorCode, StopReason, UserError
from .result import Result, thaw

__all__ = ["REQUEST", "RunResult", "RunStore", "version_text"]

#: the request's file in the run's folder
REQUEST = "request.json"


@dataclass(frozen=True, eq=False)
class RunResult(Result):
    """How a run that keeps its pieces in ``out_dir`` ended: ``stop`` None when it finished, else why it
    stopped (a StopReason) and ``why``, a line saying so.  ``options``: the run's request (its ``to_json()``
    is in the JSON); ``pair`` None (a run computes many designs)."""

    out_dir: str
    stop: StopReason | None
    why: str

    @property
    def complete(self) -> bool:
        return self.stop is None

    def to_json(self) -> dict:
        return {"out_dir": self.out_dir, "complete": self.complete,
                "stop": None if self.stop is None else str(self.stop), "why": self.why or None,
                "request": thaw(self.options.to_json())}


def version_text(code: dict | None) -> str:
    """The code version a request records (``code_version()``), in words."""
    code = code or {}
    return (f"beveloid {code.get('package_version', '(unknown)')}, generated kernels"
            f" {code.get('generated_kernels_sha1', '(unknown)')}")


class RunStore:
    """The folder ``out_dir`` of one run: its request and its ``pieces`` subfolder (named after what they
    are, ``what``: "chunks", "candidates"), for the command ``run`` ("exploration", "optimisation")."""

    def __init__(self, out_dir: str, pieces: str, what: str, run: str):
        self.out_dir, self.pieces, self.what, self.run = out_dir, pieces, what, run

    @property
    def request_path(self) -> str:
        return os.path.join(self.out_dir, REQUEST)

    def held(self) -> dict | None:
        """The request the folder holds (its JSON), None when it holds none."""
        if not os.path.exists(self.request_path):
            return None
        with open(self.request_path) as f:
            return json.load(f)

    def resumed(self, code: dict) -> dict:
        """The held request to go on with, computed by this ``code`` (``code_version()``); else one line."""
        held = self.held()
        if held is None:
            raise UserError(f"--resume {self.out_dir}: no {REQUEST} there; start a run with --out {self.out_dir}")
        if held.get("code") != code:
            raise UserError(f"--resume {self.out_dir}: its {self.what} were computed by {version_text(held.get('code'))},"
                            f" this is {version_text(code)}; {self.what} of two versions would mix: run the same"
                            f" request again with --out {self.out_dir} (it computes them again) or with the version"
                            " that started it", code=ErrorCode.STALE_RESULTS)
        return held

    def check_fresh(self, mine: dict, ignore: tuple = ()) -> dict | None:
        """For a fresh run of the request ``mine`` (its JSON): the request held there (None: none), refused
        in one line when it differs from ``mine`` in more than the keys ``ignore``."""
        held = self.held()
        mine = json.loads(json.dumps(mine))
        if held is not None and {k: v for k, v in held.items() if k not in ignore} != \
                {k: v for k, v in mine.items() if k not in ignore}:
            raise UserError(f"--out {self.out_dir}: holds another {self.run} ({REQUEST}); continue it with --resume"
                            f" {self.out_dir} or choose another --out")
        return held

    def write(self, request: dict) -> None:
        """The folder and its pieces' subfolder made, the request written (before any piece)."""
        os.makedirs(os.path.join(self.out_dir, self.pieces), exist_ok=True)
        with open(self.request_path, "w") as f:
            json.dump(request, f, indent=1)
