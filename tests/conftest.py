"""Shared fixtures.

``verification`` runs ``registry.verify()`` (the 50-digit check of all 38 equations,
~15-20 s) once per test session; every test that needs results uses it.
"""
from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def verification():
    """``(equations, results)`` from one ``registry.verify()`` call per session."""
    from beveloid.derivations import registry

    return registry.verify()
