#!/usr/bin/env bash
# The README's test command as a new user runs it, timed in its two parts: a clean clone of this
# checkout's HEAD, a fresh virtual environment, empty beveloid and numba caches (XDG_CACHE_HOME) and
# an empty uv cache (UV_CACHE_DIR: uv downloads every dependency), then the install part of the
# README's second Quickstart line, read from the clone's README (`pip install uv && uv pip install ...`),
# and `pytest` (with --durations=0 into the log).  pip's own download cache is kept (it serves uv
# itself).  Not a test: a measurement.
# Each part's wall time, its CPU time (user + system of its processes: what the machine's other work
# does not change) and the load average before and after it: the README states the wall time on an
# idle machine and what the CPU time means beside other work.
#
#     bash benchmarks/fresh_test_command.sh [LOG]      (LOG: the pytest output, default /tmp/fresh_pytest.log)
set -u
log="${1:-/tmp/fresh_pytest.log}"
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
git clone -q "$repo" "$work/clone"
cd "$work/clone"
export XDG_CACHE_HOME="$work/cache" UV_CACHE_DIR="$work/uv-cache"
"${PYTHON:-python3}" -m venv "$work/venv"
# shellcheck disable=SC1091
source "$work/venv/bin/activate"
load() { cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo "?"; }
# the children's user + system CPU from `times`, run in this shell (in a command substitution it
# would report the subshell's children: none)
cpu() { tail -1 "$1" | awk '{ split($1, u, "m"); split($2, s, "m"); print 60 * u[1] + u[2] + 60 * s[1] + s[2] }'; }
load0=$(load)
start=$(date +%s.%N)
# the README's second Quickstart line without its final `&& pytest` (run below, timed on its own)
install="$(sed -n '/^## Quickstart/,/^## /p' README.md | grep -m1 '&& pytest$' | sed 's/ && pytest$//')"
[ -n "$install" ] || { echo "no test command in README.md's Quickstart" >&2; exit 1; }
echo "install: $install" >&2
bash -c "$install" > "$work/install.log" 2>&1 || { cat "$work/install.log" >&2; exit 1; }
mid=$(date +%s.%N)
times > "$work/times_mid"
cpu_mid=$(cpu "$work/times_mid")
load1=$(load)
pytest -p no:cacheprovider --durations=0 -q > "$log" 2>&1
rc=$?
end=$(date +%s.%N)
times > "$work/times_end"
cpu_end=$(cpu "$work/times_end")
load2=$(load)
python - "$start" "$mid" "$end" "$rc" "$cpu_mid" "$cpu_end" "$load0" "$load1" "$load2" <<'PY'
import os, sys
start, mid, end, rc, cpu_mid, cpu_end = map(float, sys.argv[1:7])
load0, load1, load2 = sys.argv[7:10]
print(f"install: {mid - start:.0f} s wall, {cpu_mid:.0f} s CPU (load average {load0} before); "
      f"pytest: {end - mid:.0f} s wall, {cpu_end - cpu_mid:.0f} s CPU (load average {load1} before, {load2} after); "
      f"in all: {end - start:.0f} s wall on {os.cpu_count()} cores (pytest exit {int(rc)})")
PY
exit "$rc"
