"""Fixtures of tests/generated: the sympy specs and the renderings, built once per process (each on a
fresh stack: tests/conftest.py ``on_a_fresh_stack``)."""
from __future__ import annotations

import pytest

from beveloid.derivations import codegen, kernels
from generated_support import PLAIN_MODULES, exec_module, module_specs


@pytest.fixture(scope="session")
def specs(fresh_stack):
    return fresh_stack(module_specs)


@pytest.fixture(scope="session")
def rendered_by():
    """The renderings of the session's spec objects (``codegen.generate(rendered_by=...)``)."""
    return {}


@pytest.fixture(scope="session")
def rendered(specs, rendered_by, fresh_stack):
    """{file name: text} rendered in memory, as ``beveloid derive`` would write it."""
    return fresh_stack(codegen.generate, None, list(specs.values()), extra=kernels.glue_files(),
                       rendered_by=rendered_by)


@pytest.fixture(scope="session")
def nocse_texts(specs, fresh_stack):
    return fresh_stack(lambda: {name: codegen.render_module(specs[name], cse=False) for name in PLAIN_MODULES})


@pytest.fixture(scope="session")
def nocse(nocse_texts):
    """{module name: namespace} of the non-CSE builds, exec'd in memory."""
    return {name: exec_module(text, f"<{name} (no CSE)>") for name, text in nocse_texts.items()}


