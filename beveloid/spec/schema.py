"""The keys of a spec as text: the README's Markdown table and ``beveloid example --schema``."""
from __future__ import annotations

from .keys import SECTIONS, key_docs_for


def key_docs_markdown() -> str:
    """A Markdown table of every key (for the README), generated from :data:`KEY_DOCS` (built-in models)."""
    lines = [
        "| key | required | default | valid values | description |",
        "|---|---|---|---|---|",
    ]
    for section, docs in key_docs_for().items():
        for key, d in docs.items():
            if d.requirement == "result":
                req, valid = "no (design result)", "must not be given"
            else:
                req = "yes" if d.requirement == "required" else "no"
                valid = d.valid_text
            default = d.default_text
            cells = [f"`{section}.{key}`", req, default, valid, d.description]
            lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return "\n".join(lines)


def key_schema_text(models=()) -> str:
    """Every key of a spec file, one line each: section.key, required or default, valid values, meaning
    (the built-in tooth-surface models' keys and those of the user models named in ``models``)."""
    lines = ["# Keys of a beveloid spec file (TOML). Sections: "
             + "; ".join(f"[{s}] {d}" for s, d in SECTIONS.items())]
    for section, docs in key_docs_for(models).items():
        lines.append("")
        lines.append(f"[{section}]")
        for key, d in docs.items():
            if d.requirement == "result":
                need = "do not give: a result of the direct design"
            elif d.requirement == "required":
                need = f"required, {d.valid_text_in(section)}"
            else:
                default = f"default {d.default_text}" if d.default_text else "no default"
                need = f"optional ({default}), {d.valid_text_in(section)}"
            lines.append(f"{key}: {need}; {d.description}")
    return "\n".join(lines)
