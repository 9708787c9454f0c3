"""Limits on what is read from a model file, so that hostile input is refused fast.

A model file is read through :func:`read_text`: at most :data:`MAX_FILE_BYTES` bytes are read
(``/dev/zero`` and ``/dev/urandom`` have no end; a 60 MB file of parameters would take minutes
to parse), a NUL byte means it is not text.  :func:`check_size` bounds the tables whose every
entry costs work (:data:`MAX_PARAMETERS`).  The expressions inside have their own guards
(:mod:`nonideal.modeling.expressions`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..errors import ModelError

__all__ = ["MAX_FILE_BYTES", "MAX_PARAMETERS", "read_text", "check_size"]

MAX_FILE_BYTES = 2 * 2**20
"""Bytes read from a model file at most (a model of a thousand bodies is a hundred KB)."""
MAX_PARAMETERS = 20_000
"""Entries of ``[parameters]`` at most (each is checked and resolved)."""


def read_text(path: Path) -> str:
    """The text of the model file at *path* (UTF-8, at most :data:`MAX_FILE_BYTES` bytes).

    Raises
    ------
    ModelError
        Not found, a directory, too large, not text, not UTF-8, unreadable.
    """
    source = str(path)
    try:
        with open(path, "rb") as handle:  # never more than the cap: /dev/zero has no end
            raw = handle.read(MAX_FILE_BYTES + 1)
        if len(raw) > MAX_FILE_BYTES:
            raise ModelError(f"the model file is larger than {MAX_FILE_BYTES // 2**20} MiB (the limit; "
                             "a model file is a few kilobytes): is this the right file?", source)
        if b"\0" in raw:
            raise ModelError(f"not a text file (it contains a NUL byte at byte {raw.index(0)}); a "
                             "model file is TOML text", source)
        text = raw.decode("utf-8")
    except FileNotFoundError:
        raise ModelError(f"model file not found: {source}; check the path (relative paths are "
                         f"taken from the current directory, {Path.cwd()})") from None
    except IsADirectoryError:
        raise ModelError("is a directory, not a model file; give the path of a .toml file",
                         source) from None
    except UnicodeDecodeError as exc:
        raise ModelError(f"cannot read the model file: not UTF-8 text ({exc.reason} at byte "
                         f"{exc.start}); save it as UTF-8", source) from None
    except OSError as exc:
        raise ModelError(f"cannot read the model file: {exc.strerror or exc}", source) from None
    return text


def check_size(data: dict[str, Any], source: str) -> None:
    """Refuse tables larger than the limits (before any of their entries is processed)."""
    table = data.get("parameters")
    if isinstance(table, dict) and len(table) > MAX_PARAMETERS:
        raise ModelError(f"[parameters]: {len(table)} entries; at most {MAX_PARAMETERS}", source)
