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

__all__ = ["MAX_FILE_BYTES", "MAX_PARAMETERS", "MAX_NESTING", "read_text", "check_nesting",
           "check_size"]

MAX_FILE_BYTES = 2 * 2**20
"""Bytes read from a model file at most (a model of a thousand bodies is a hundred KB)."""
MAX_PARAMETERS = 20_000
"""Entries of ``[parameters]`` at most (each is checked and resolved)."""
MAX_NESTING = 64
"""Levels of nesting of a model file at most (arrays, inline tables, dotted keys and table
headers together; a model needs four).  Deeper TOML overflows the parser's recursion."""


def read_text(path: Path) -> str:
    """The text of the model file at *path* (UTF-8, at most :data:`MAX_FILE_BYTES` bytes).

    Raises
    ------
    ModelError
        Not found, a directory, too large, not text, not UTF-8, unreadable.
    """
    source = str(path)
    try:
        if path.is_fifo() or path.is_socket():  # reading would wait for a writer without end
            raise ModelError("not a regular file (a named pipe or a socket: reading it would wait "
                             "for a writer); give the path of a .toml file", source)
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


def check_nesting(text: str, source: str) -> None:
    """Refuse TOML nested deeper than :data:`MAX_NESTING` levels, scanning the text before it
    is parsed: the brackets of arrays and inline tables open outside strings and comments,
    plus the dots of the keys (``a.b.c = 1``, ``[a.b.c]``).

    Examples
    --------
    >>> check_nesting('x = [[1, 2], {a.b = "[[["}]  # 3 levels', "m.toml")
    >>> check_nesting("x = " + "[" * 100 + "]" * 100, "m.toml")
    Traceback (most recent call last):
    ...
    nonideal.errors.ModelError: m.toml: nested 65 levels deep at line 1 (the limit is 64; a model file needs a few): is this the right file?
    """
    stack: list[tuple[str, int]] = []  # the open brackets, with the key dots before them
    key, dots, line, start, i, n = True, 0, 1, True, 0, len(text)
    while i < n:
        c = text[i]
        if c in "\"'":
            quote = c * 3 if text.startswith(c * 3, i) else c
            i += len(quote)
            while i < n and not text.startswith(quote, i):
                line += text[i] == "\n"
                i += 2 if (c == '"' and text[i] == "\\") else 1
            i += len(quote)
            start = False
            continue
        if c == "#":
            while i < n and text[i] != "\n":
                i += 1
            continue
        if c == "\n":
            line += 1
            if not stack:
                key, dots, start = True, 0, True
        elif c in "[{":
            stack.append((c, dots))
            key = c == "{" or start  # an inline table's keys, a table header
        elif c in "]}":
            if stack:
                dots = stack.pop()[1] if stack[-1][0] == "{" else dots
        elif c == "=":
            key = False
        elif c == "," and stack and stack[-1][0] == "{":
            key, dots = True, stack[-1][1]
        elif c == "." and key:
            dots += 1
        if c not in " \t[\n":
            start = False
        if len(stack) + dots > MAX_NESTING:
            raise ModelError(f"nested {len(stack) + dots} levels deep at line {line} (the limit is "
                             f"{MAX_NESTING}; a model file needs a few): is this the right file?", source)
        i += 1


def check_size(data: dict[str, Any], source: str) -> None:
    """Refuse tables larger than the limits (before any of their entries is processed)."""
    table = data.get("parameters")
    if isinstance(table, dict) and len(table) > MAX_PARAMETERS:
        raise ModelError(f"[parameters]: {len(table)} entries; at most {MAX_PARAMETERS}", source)
