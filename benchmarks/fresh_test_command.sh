#!/usr/bin/env bash
# The README's test command as a new user runs it, timed in its two parts: a clean clone of this
# checkout's HEAD, a fresh virtual environment, empty beveloid and numba caches (XDG_CACHE_HOME),
# then `pip install ".[test]"` and `pytest` (with --durations=0 into the log).  pip's own download
# cache is kept (a machine that has installed the dependencies once).  Not a test: a measurement.
#
#     bash benchmarks/fresh_test_command.sh [LOG]      (LOG: the pytest output, default /tmp/fresh_pytest.log)
set -u
log="${1:-/tmp/fresh_pytest.log}"
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
git clone -q "$repo" "$work/clone"
cd "$work/clone"
export XDG_CACHE_HOME="$work/cache"
"${PYTHON:-python3}" -m venv "$work/venv"
# shellcheck disable=SC1091
source "$work/venv/bin/activate"
start=$(date +%s.%N)
pip install -q ".[test]" || exit 1
mid=$(date +%s.%N)
pytest -p no:cacheprovider --durations=0 -q > "$log" 2>&1
rc=$?
end=$(date +%s.%N)
python - "$start" "$mid" "$end" "$rc" <<'PY'
import os, sys
start, mid, end, rc = map(float, sys.argv[1:])
print(f"pip install: {mid - start:.0f} s, pytest: {end - mid:.0f} s, in all: {end - start:.0f} s "
      f"(pytest exit {int(rc)}; load average {' '.join(open('/proc/loadavg').read().split()[:3]) if os.path.exists('/proc/loadavg') else '?'})")
PY
exit "$rc"
