"""A Ctrl-C swallowed by a ctypes callback still stops the run (beveloid/interrupts.py).

numba's compiles call back into Python through ctypes; a KeyboardInterrupt raised there is printed as
"Exception ignored" and lost.  Here the callback is libc's qsort comparison, which sends SIGINT to its
own process: the same loss, without waiting for a compile to be under way.
"""
import subprocess
import sys
import textwrap

import pytest

SWALLOW = textwrap.dedent("""
    import ctypes, ctypes.util, os, signal
    libc = ctypes.CDLL(ctypes.util.find_library("c"))
    CMP = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.c_int))

    def compare(a, b):
        os.kill(os.getpid(), signal.SIGINT)  # handled on the next bytecode: inside the callback
        for _ in range(1000):
            pass
        return a[0] - b[0]

    def swallowed():
        arr = (ctypes.c_int * 3)(3, 1, 2)
        libc.qsort(arr, 3, ctypes.sizeof(ctypes.c_int), CMP(compare))
        return "carried on"  # the comparison that raised counts as 0: the order is not checked
""")


def _run(body):
    proc = subprocess.run([sys.executable, "-c", SWALLOW + textwrap.dedent(body)], capture_output=True,
                          text=True, timeout=60)
    return proc.returncode, proc.stdout, proc.stderr


def test_the_interrupt_is_lost_inside_a_callback_without_install():
    """The premise: Python alone reports the interrupt as ignored and carries on."""
    rc, out, err = _run("""
        print(swallowed())
    """)
    assert rc == 0 and out.strip() == "carried on", (rc, out, err)
    assert "KeyboardInterrupt" in err


def test_check_raises_the_swallowed_interrupt_and_nothing_is_printed():
    rc, out, err = _run("""
        from beveloid import interrupts
        interrupts.install()
        print(swallowed(), interrupts.seen())
        try:
            interrupts.check()
        except KeyboardInterrupt:
            print("stopped")
    """)
    assert rc == 0, err
    assert out.splitlines() == ["carried on True", "stopped"], out
    assert "Exception ignored" not in err and "Traceback" not in err, err


def test_a_serial_run_stops_after_the_piece_that_swallowed_it():
    rc, out, err = _run("""
        from beveloid import interrupts, parallel
        interrupts.install()
        done = []
        try:
            for i, r in parallel.executor(1).__enter__().map_unordered(lambda x: swallowed(), range(5)):
                done.append(i)
        except KeyboardInterrupt:
            print("stopped after", len(done))
    """)
    assert rc == 0, err
    assert out.strip() == "stopped after 0", (out, err)


def test_without_install_check_does_nothing():
    from beveloid import interrupts
    assert not interrupts.seen()
    interrupts.check()


def test_an_error_after_the_interrupt_counts_as_the_interrupt():
    """numba fails later on the state a swallowed interrupt left half-made ("no compiled object yet")."""
    rc, out, err = _run("""
        from beveloid import interrupts
        interrupts.install()
        try:
            with interrupts.guard():
                swallowed()
                raise RuntimeError("no compiled object yet")
        except KeyboardInterrupt:
            print("stopped")
    """)
    assert rc == 0, err
    assert out.splitlines() == ["stopped"], out


def test_errors_are_errors_when_no_interrupt_came():
    from beveloid import interrupts
    with pytest.raises(ValueError):
        with interrupts.guard():
            raise ValueError("a bug")


def test_a_finalizer_failing_after_the_interrupt_prints_nothing_and_before_it_is_reported():
    """After a Ctrl-C, objects of the abandoned work fail in __del__ (llvmlite's at the exit): no
    report; before any Ctrl-C a failing finalizer is reported as usual."""
    rc, out, err = _run("""
        import gc
        from beveloid import interrupts
        interrupts.install()

        class Broken:
            def __del__(self):
                raise RuntimeError("finalizer failed")

        Broken(); gc.collect()
        print("before", flush=True)
        swallowed()
        keep = Broken()  # finalized at the interpreter's exit
        Broken(); gc.collect()
        print("after", flush=True)
    """)
    assert rc == 0 and out.split() == ["before", "after"], (out, err)
    assert err.count("finalizer failed") == 1 and err.count("Exception ignored") == 1, err
