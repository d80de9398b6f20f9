"""Design input specification for a crossed beveloid gear pair.

A design is described by a TOML file with the sections ``[pair]``, ``[pinion]``, ``[gear]`` and
(optionally) ``[misalignment]`` and ``[material]``; ``beveloid example case1`` prints one.  This
package reads such a file (or an equivalent ``dict``), validates every value, and returns frozen
dataclasses.  Every problem is a :class:`SpecError` whose message is a single line naming the
offending key, its value and what would be valid, e.g.::

    examples/bad.toml: pinion.teeth = 5: must be an integer from 6 to 400

Modules (standard library only, plus the generated tooth-surface model table):

    model.py     the frozen dataclasses (DesignSpec, PairSpec, MemberSpec, ...) and SpecError
    keys.py      KEY_DOCS: THE table of keys, ranges, units, defaults and descriptions
    validate.py  mapping -> DesignSpec (spec_from_dict), the rules between keys (CROSS_CHECKS),
                 spec_to_dict, misalignment_with
    parse.py     TOML files and bytes (load_spec), the packaged examples (load_example)
    schema.py    the keys as text: README table (key_docs_markdown), ``example --schema``
    text.py      values and names as a one-line message shows them

Adding a key
------------
1. Its :class:`KeyDoc` (range, unit, default, description) in ``keys.py``, in the section's table;
   the validation, the error messages, ``beveloid example --schema`` and the README key table
   (regenerate it with ``key_docs_markdown()``; tests/docs/test_docs_readme.py compares) follow from it.
2. The field of the same name and default in the section's dataclass in ``model.py``;
   :mod:`beveloid.spec.validate` refuses to import when the two disagree.
3. Only if its valid range depends on other keys: a function in ``validate.CROSS_CHECKS``.
A tooth-surface model's own keys (micro-geometry) need none of this: they come from the
derivation registry (generated/surface_models.py) into ``MemberSpec.surface_options``.
"""
from __future__ import annotations

from .keys import KEY_DOCS, REQUIRED_SECTIONS, SECTIONS, KeyDoc
from .model import (DEFAULT_SOURCE, DesignSpec, LubricantSpec, MaterialSpec, RatingSpec, MemberSpec, MisalignmentSpec, PairSpec,
                    SpecError)
from .parse import EXAMPLES, MAX_SPEC_BYTES, example_text, load_example, load_spec, spec_from_toml_bytes
from .schema import key_docs_markdown, key_schema_text
from .text import printable
from .validate import misalignment_with, spec_from_dict, spec_to_dict

__all__ = [
    "SpecError",
    "PairSpec",
    "MemberSpec",
    "MisalignmentSpec",
    "MaterialSpec",
    "RatingSpec",
    "LubricantSpec",
    "DesignSpec",
    "DEFAULT_SOURCE",
    "KeyDoc",
    "KEY_DOCS",
    "SECTIONS",
    "REQUIRED_SECTIONS",
    "spec_from_dict",
    "load_spec",
    "spec_to_dict",
    "misalignment_with",
    "key_docs_markdown",
    "key_schema_text",
    "spec_from_toml_bytes",
    "MAX_SPEC_BYTES",
    "EXAMPLES",
    "example_text",
    "load_example",
    "printable",
]
