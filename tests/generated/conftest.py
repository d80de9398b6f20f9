"""Fixtures of tests/generated: the sympy specs and the renderings, built once per process (each on a
fresh stack: tests/conftest.py ``on_a_fresh_stack``)."""
from __future__ import annotations

import pytest

from beveloid.derivations import codegen, kernels
from generated_support import GENERATED, PLAIN_MODULES, RENDERED_IN_THE_SLOW_TIER, exec_module, module_specs


@pytest.fixture(scope="session")
def specs(fresh_stack):
    return fresh_stack(module_specs)


@pytest.fixture(scope="session")
def rendered_by():
    """The renderings of the session's spec objects (``codegen.generate(rendered_by=...)``)."""
    return {}


@pytest.fixture(scope="session")
def rendered(specs, rendered_by, fresh_stack):
    """{file name: text} rendered in memory, as ``beveloid derive`` would write it; the files of the surface
    models of RENDERED_IN_THE_SLOW_TIER are the committed ones (given to the generator as rendered before:
    ``rendered_by``), rendered by the slow tier's test_slow_tier_surfaces_render_as_committed."""
    for module in RENDERED_IN_THE_SLOW_TIER:
        names = (f"{module}.py", f"{module}_scalar.py")
        rendered_by[(id(specs[module]), True)] = (specs[module], {n: (GENERATED / n).read_text() for n in names})
    return fresh_stack(codegen.generate, None, list(specs.values()), extra=kernels.glue_files(),
                       rendered_by=rendered_by)


@pytest.fixture(scope="session")
def nocse_texts(specs, fresh_stack):
    return fresh_stack(lambda: {name: codegen.render_module(specs[name], cse=False) for name in PLAIN_MODULES})


@pytest.fixture(scope="session")
def nocse(nocse_texts):
    """{module name: namespace} of the non-CSE builds, exec'd in memory."""
    return {name: exec_module(text, f"<{name} (no CSE)>") for name, text in nocse_texts.items()}


