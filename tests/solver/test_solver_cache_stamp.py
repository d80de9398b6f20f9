"""numba's cache checks only a function's own file; the compiled core calls (and inlines) the
generated kernels of other files, so each cache entry is named after a digest of all of them."""
from __future__ import annotations

import types

from beveloid.solver import backends


def _module(path, text):
    path.write_text(text)
    mod = types.ModuleType(path.stem)
    mod.__file__ = str(path)
    return mod


def test_the_stamp_follows_every_module_compiled_together(tmp_path):
    core = _module(tmp_path / "core.py", "def f(x):\n    return g(x)\n")
    kernel = _module(tmp_path / "kernel.py", "def g(x):\n    return x\n")
    before = backends.sources_stamp([core, kernel])
    assert before == backends.sources_stamp([core, kernel])  # deterministic: unchanged sources load the cache
    (tmp_path / "kernel.py").write_text("def g(x):\n    return 2 * x\n")  # beveloid derive changed a kernel
    assert backends.sources_stamp([core, kernel]) != before


def test_compiled_functions_are_named_after_the_stamp_of_the_core():
    stamp = backends.core_stamp()
    assert len(stamp) == 12 and all(c in "0123456789abcdef" for c in stamp)
