"""CPU of the derivations' checks in one process, as the test suite's sympy group runs them.

    python benchmarks/bench_verification.py [--json OUT]

Prints the CPU seconds (this process) of, in order: ``registry.verify()`` (the models' equations
built and the 50-digit check of Eqs 1-38: the fixture ``verification`` of tests/conftest.py) and
``registry.verify_extra()`` (the checks beyond the print: the fixture ``extra_checks`` of
tests/cli/test_cli_verify.py), each on a fresh stack as the fixtures run them.  With --json, writes
what `beveloid verify --json` prints (the same results) to OUT, to compare two trees' results.
Not a test: a measurement.
"""
from __future__ import annotations

import argparse
import os
import sys
import threading
import time


def _on_a_fresh_stack(fn):
    out = {}
    thread = threading.Thread(target=lambda: out.setdefault("value", fn()))
    thread.start()
    thread.join()
    return out["value"]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", help="write the results as `beveloid verify --json` prints them")
    args = parser.parse_args(argv)
    load = os.getloadavg()[0]
    t0 = time.process_time()
    from beveloid.derivations import registry

    t_import = time.process_time()
    _eqs, results = _on_a_fresh_stack(registry.verify)
    t_verify = time.process_time()
    extra = _on_a_fresh_stack(registry.verify_extra)
    t_extra = time.process_time()
    print(f"load average before {load:.2f}; CPU seconds: import {t_import - t0:.1f}, "
          f"registry.verify() {t_verify - t_import:.1f}, registry.verify_extra() {t_extra - t_verify:.1f}, "
          f"in all {t_extra - t0:.1f}")
    if args.json:
        with open(args.json, "w") as fh:
            fh.write(registry.results_json(list(results) + extra) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
