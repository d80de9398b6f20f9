"""Running CalculiX (``ccx``, Debian's package ``calculix-ccx``) on a deck, its output streamed."""
from __future__ import annotations

import os
import re
import resource
import shutil
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

from ..errors import UserError

__all__ = ["CCX_MISSING", "CcxRun", "ccx_path", "ccx_version", "run_ccx"]

CCX_MISSING = ("CalculiX (ccx) is not installed: fe-check needs it; on Debian/Ubuntu install the package "
               "calculix-ccx (apt-get install calculix-ccx), or put a ccx executable on PATH or in BEVELOID_CCX")


@dataclass(frozen=True)
class CcxRun:
    """A finished run: the job's folder and name (``<folder>/<job>.frd``, ``.dat``, ``.sta``), wall time (s),
    the version, the log and ccx's CPU time (s)."""

    folder: Path
    job: str
    wall_s: float
    version: str | None
    log: str
    cpu_s: float = float("nan")  #: CPU time of ccx (user + system, all its threads)

    def file(self, ext: str) -> Path:
        return self.folder / f"{self.job}.{ext}"


def ccx_path() -> str | None:
    """The ccx executable: BEVELOID_CCX if set, else ``ccx`` on PATH; None when there is none."""
    env = os.environ.get("BEVELOID_CCX")
    if env:
        return env if os.access(env, os.X_OK) else None
    return shutil.which("ccx")


def ccx_version() -> str | None:
    """CalculiX's version ("2.20"), None when ccx is missing or does not say."""
    exe = ccx_path()
    if exe is None:
        return None
    try:
        text = subprocess.run([exe, "-v"], capture_output=True, text=True, timeout=30).stdout
    except (OSError, subprocess.TimeoutExpired):
        return None
    m = re.search(r"Version\s+([0-9][0-9.]*)", text)
    return m[1] if m else None


def run_ccx(deck_path, progress=None, threads: int = 2) -> CcxRun:
    """Run ccx on ``deck_path`` (``<job>.inp``) in its folder; each line of its output goes to
    ``progress`` (a :class:`beveloid.progress.Progress`: the lines so far, no total, the line; or None).  Raises :class:`UserError` when ccx is missing (``CCX_MISSING``)
    or fails (its last lines)."""
    exe = ccx_path()
    if exe is None:
        raise UserError(CCX_MISSING)
    deck_path = Path(deck_path)
    job = deck_path.stem
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), CCX_NPROC_EQUATION_SOLVER=str(threads),
               GFORTRAN_UNBUFFERED_PRECONNECTED="y")
    t0 = time.perf_counter()
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    lines = []
    with subprocess.Popen([exe, "-i", job], cwd=deck_path.parent, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, env=env) as proc:
        try:
            for line in proc.stdout:
                lines.append(line.rstrip("\n"))
                if progress is not None and line.strip():
                    progress(len(lines), None, line.rstrip("\n"))
            rc = proc.wait()
        except BaseException:  # Ctrl-C (or a failing progress): ccx stops too, before its files are cleaned up
            proc.kill()
            proc.wait()
            raise
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    log = "\n".join(lines)
    failed = rc != 0 or "*ERROR" in log or not (deck_path.parent / f"{job}.frd").exists()
    if failed:
        tail = " | ".join(s.strip() for s in lines if s.strip())[-400:]
        raise UserError(f"CalculiX failed on {deck_path} (exit {rc}): {tail}")
    return CcxRun(deck_path.parent, job, wall, ccx_version(), log, cpu)
