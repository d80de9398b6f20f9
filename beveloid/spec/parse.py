"""Reading a TOML spec: a bounded regular file, UTF-8, TOML syntax, then :func:`spec_from_dict`.

Also the packaged examples (``beveloid/data/<name>.toml``, ``beveloid example``).
"""
from __future__ import annotations

import os
import stat
import tomllib

from .model import DEFAULT_SOURCE, DesignSpec, SpecError
from .text import fmt_value, printable
from .validate import NESTED_TOO_DEEP, spec_from_dict

#: A spec file larger than this (bytes) is refused: real specs are about 2 kB.
MAX_SPEC_BYTES = 1_000_000

#: Example specs shipped in the package (beveloid/data/<name>.toml): the paper's Table 1 cases.
EXAMPLES: dict[str, str] = {
    "case1": "Case 1 of the paper's Table 1",
    "case2": "Case 2 of the paper's Table 1",
}


def _read_spec_bytes(path: str | os.PathLike, source: str) -> bytes:
    """The file's bytes: only a regular file of at most :data:`MAX_SPEC_BYTES` (no device, FIFO, folder)."""
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise SpecError("cannot read spec file: no such file", source=source) from None
    except (OSError, ValueError) as err:  # ValueError: embedded NUL in the path
        reason = getattr(err, "strerror", None) or str(err)
        raise SpecError(f"cannot read spec file: {reason}", source=source) from None
    if not stat.S_ISREG(st.st_mode):
        kind = ("a folder" if stat.S_ISDIR(st.st_mode) else "a FIFO" if stat.S_ISFIFO(st.st_mode)
                else "a device" if (stat.S_ISCHR(st.st_mode) or stat.S_ISBLK(st.st_mode))
                else "a socket" if stat.S_ISSOCK(st.st_mode) else "not a regular file")
        raise SpecError(f"cannot read spec file: it is {kind}; give a regular TOML file"
                        " (`beveloid example case1` prints one)", source=source)
    if st.st_size > MAX_SPEC_BYTES:
        raise SpecError(f"cannot read spec file: {st.st_size} bytes, more than the {MAX_SPEC_BYTES} bytes a"
                        " spec may have", source=source)
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_SPEC_BYTES + 1)  # bounded, in case the file grows meanwhile
    except OSError as err:
        raise SpecError(f"cannot read spec file: {err.strerror or err}", source=source) from None
    if len(data) > MAX_SPEC_BYTES:
        raise SpecError(f"cannot read spec file: more than the {MAX_SPEC_BYTES} bytes a spec may have",
                        source=source)
    return data


def spec_from_toml_bytes(data: bytes, source: str = DEFAULT_SOURCE) -> DesignSpec:
    """Parse and validate the bytes of a TOML spec; a leading UTF-8 byte-order mark is accepted."""
    if data.startswith(b"\xef\xbb\xbf"):  # written by some Windows editors; TOML itself has no BOM
        data = data[3:]
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise SpecError(f"cannot read spec file: not valid UTF-8 ({err.reason} at byte {err.start})",
                        source=source) from None
    try:
        parsed = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise SpecError(f"TOML syntax error: {printable(str(err))}", source=source) from None
    except RecursionError:  # tomllib parses nested arrays and inline tables recursively
        raise SpecError(NESTED_TOO_DEEP, source=source) from None
    return spec_from_dict(parsed, source=source)


def load_spec(path: str | os.PathLike) -> DesignSpec:
    """Read and validate a TOML design file.

    A missing/unreadable file, anything that is not a regular file (folder, device, FIFO), a file
    over :data:`MAX_SPEC_BYTES` or a TOML syntax error raises :class:`SpecError` whose one-line
    message starts with the path.
    """
    source = printable(os.fsdecode(path))
    return spec_from_toml_bytes(_read_spec_bytes(path, source), source=source)


def example_text(name: str) -> str:
    """The TOML text of a packaged example (a key of :data:`EXAMPLES`), as shipped in beveloid/data/."""
    from importlib import resources

    if name not in EXAMPLES:
        raise SpecError(f"example = {fmt_value(name)}: must be one of {', '.join(EXAMPLES)}")
    return (resources.files("beveloid") / "data" / f"{name}.toml").read_text(encoding="utf-8")


def load_example(name: str) -> DesignSpec:
    """A packaged example spec (``"case1"`` or ``"case2"``); works from any working directory."""
    return spec_from_toml_bytes(example_text(name).encode("utf-8"), source=f"{name}.toml")
