"""Output files of the command line: nothing is written to an output path unless the run
succeeded.  Outputs are produced into temporary files and committed only when every one of them
is ready -- renamed over a regular file (through symbolic links, onto their final target),
written into anything else (``/dev/null``, a FIFO, ``/dev/stdout``), which is never replaced.
"""

from __future__ import annotations

import errno
import json
import os
import stat
import sys
import tempfile
from pathlib import Path

from ..errors import ModelError

__all__ = ["Outputs", "destination", "emit_json", "output_problems", "emit_report"]


def destination(path: Path) -> tuple[Path, bool]:
    """Where a write to *path* lands: the final target of its symbolic links (in any of its
    components), and whether that is one of this process's file descriptors (``/dev/stdout``,
    ``/dev/fd/N``, ``/proc/self/fd/N``: a file to write into, never to replace).

    Raises OSError (ELOOP) for a loop of symbolic links."""
    current = path if path.is_absolute() else Path.cwd() / path
    for _ in range(40):
        parent = Path(os.path.realpath(current.parent))
        current = parent / current.name
        if parent.parts[:2] == ("/", "proc"):
            return current, True
        if not current.is_symlink():
            return current, False
        current = parent / os.readlink(current)
    raise OSError(errno.ELOOP, os.strerror(errno.ELOOP), str(path))


def stat_or_none(path: Path) -> os.stat_result | None:
    try:
        return os.stat(path)
    except FileNotFoundError:
        return None


def write_into(data: bytes, target: Path) -> None:
    """Write *data* into an existing file that is not replaced: a device (``/dev/null``), a
    FIFO, a terminal, or a file descriptor of this process (written through the descriptor
    itself, so that ``--json /dev/stdout`` works whatever standard output is)."""
    parts = target.parts
    own = (len(parts) == 5 and parts[:2] == ("/", "proc") and parts[2] == str(os.getpid())
           and parts[3] == "fd" and parts[4].isdigit())
    if own:
        sys.stdout.flush()
        sys.stderr.flush()
        fd, close = int(parts[4]), False
    else:
        fd, close = os.open(target, os.O_WRONLY), True   # no O_CREAT: never make a new node
    try:
        if close and stat.S_ISREG(os.fstat(fd).st_mode):
            os.ftruncate(fd, 0)
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view):]
    finally:
        if close:
            os.close(fd)


class Outputs:
    """Collects output files and writes them only when everything succeeded.

    Each output is produced into a temporary file first.  A regular file (or a new one) is
    then replaced atomically -- the final target of a symbolic link, never the link itself,
    in the target's directory; an existing file that is not a regular file (``/dev/null``, a
    FIFO, a terminal, ``/dev/stdout``) is written into, never replaced."""

    def __init__(self):
        self.pending: list[tuple[str, Path, object]] = []

    def add(self, option: str, path: str, producer) -> None:
        self.pending.append((option, Path(path), producer))

    def commit(self) -> None:
        staged = []     # (option, path, temporary file, target, write into the target?)
        try:
            for option, path, producer in self.pending:
                try:
                    target, descriptor = destination(path)
                    info = stat_or_none(target)
                    if info is not None and stat.S_ISDIR(info.st_mode):
                        raise ModelError(f"{option} {path}: is a directory; give a file name")
                    into = descriptor or (info is not None and not stat.S_ISREG(info.st_mode))
                    if not into:
                        target.parent.mkdir(parents=True, exist_ok=True)
                    fd, tmp = tempfile.mkstemp(prefix=".nonideal-", suffix=path.suffix,
                                               dir=None if into else target.parent)
                    os.close(fd)
                    staged.append((option, path, tmp, target, into))
                    producer(tmp)
                except OSError as exc:
                    raise ModelError(f"{option} {path}: cannot write: "
                                     f"{exc.strerror or exc}") from None
                except ValueError as exc:   # e.g. an image format matplotlib does not know
                    raise ModelError(f"{option} {path}: cannot write: {exc}") from None
            # the files written into first: that cannot be undone, and when it fails (a full
            # device, a socket) the regular outputs are left as they were
            for option, path, tmp, target, into in staged:
                if into:
                    try:
                        write_into(Path(tmp).read_bytes(), target)
                    except OSError as exc:
                        raise ModelError(f"{option} {path}: cannot write: "
                                         f"{exc.strerror or exc}") from None
            mask = os.umask(0)      # mkstemp creates 0600: give the files the usual mode
            os.umask(mask)
            for option, path, tmp, target, into in staged:
                if not into:
                    os.chmod(tmp, 0o666 & ~mask)
                    os.replace(tmp, target)
        finally:
            for _, _, tmp, _, _ in staged:
                if os.path.exists(tmp):
                    os.unlink(tmp)


def output_problems(args, model_spec: str) -> list[str]:
    """Output paths that collide with each other or with the model file, paths that cannot
    be files, and plot formats matplotlib cannot write."""
    problems = []
    seen: dict[Path, str] = {}
    model_path = Path(model_spec).resolve() if Path(model_spec).is_file() else None
    for option in ("json", "csv", "plot", "animate"):
        value = getattr(args, option, None)
        if not value or value == "-":
            continue
        flag = f"--{option}"
        try:
            path, _ = destination(Path(value))
        except OSError as exc:
            problems.append(f"{flag} {value}: cannot write: {exc.strerror}; fix the symbolic "
                            "links or choose another path")
            continue
        blocker = next((a for a in Path(value).parents if a.exists()), None)
        if model_path is not None and path == model_path:
            problems.append(f"{flag} {value}: this is the model file itself; choose another "
                            "output path")
        elif path in seen:
            problems.append(f"{flag} {value}: the same path as {seen[path]}; give each output "
                            "its own file")
        elif path.is_dir():
            problems.append(f"{flag} {value}: is a directory; give a file name")
        elif blocker is not None and not blocker.is_dir():
            problems.append(f"{flag} {value}: cannot write: {blocker} is not a directory; "
                            "choose another path")
        seen[path] = flag
    anim = getattr(args, "animate", None)
    if anim:
        suffix = Path(anim).suffix.lower()
        if suffix not in (".gif", ".mp4", ".png"):
            problems.append(f"--animate {anim}: write a .gif (or an .mp4, with ffmpeg installed; "
                            "a .png holds the last frame)")
        elif suffix == ".mp4":
            from matplotlib import animation

            if not animation.FFMpegWriter.isAvailable():
                problems.append(f"--animate {anim}: .mp4 needs ffmpeg, which is not installed; "
                                "write a .gif")
    plot = getattr(args, "plot", None)
    if plot and Path(plot).suffix:
        from matplotlib.figure import Figure

        formats = Figure().canvas.get_supported_filetypes()
        suffix = Path(plot).suffix.lstrip(".").lower()
        if suffix not in formats:
            problems.append(f"--plot {plot}: matplotlib cannot write '.{suffix}' files; use one "
                            f"of {', '.join('.' + f for f in sorted(formats))}")
    return problems


def emit_json(args, payload: dict, outputs: Outputs) -> None:
    text = json.dumps(payload, indent=1, allow_nan=True)
    if args.json == "-":
        print(text)
    else:
        outputs.add("--json", args.json, lambda tmp: Path(tmp).write_text(text + "\n"))


def emit_report(args, result) -> int:
    """Print *result* (an object with ``to_dict()`` and ``as_text()``) as text, or as JSON
    with ``--json [OUT]``; the command's usual ending (exit code 0)."""
    outputs = Outputs()
    if args.json:
        emit_json(args, result.to_dict(), outputs)
    else:
        print(result.as_text())
    outputs.commit()
    return 0
