"""The ``nonideal`` command line.

Exit codes: 0 success; 2 bad input (the message names the file, the key and the fix);
3 the mechanics has no consistent or no unique answer.  Nothing is written to an output path
unless the run succeeded: the options are checked before any work, outputs are produced into
temporary files and committed only when every one of them is ready -- renamed over a regular
file (through symbolic links, onto their final target), written into anything else
(``/dev/null``, a FIFO, ``/dev/stdout``), which is never replaced.
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import json
import math
import os
import stat
import sys
import tempfile
import warnings
from pathlib import Path

from .errors import MechanicsError, ModelError, NonidealError, did_you_mean

__all__ = ["main", "build_parser"]

METHODS = ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")
PLOT_SAMPLES = 601   # samples of a plotted or tabulated (--csv) run when --times is not given


# ------------------------------------------------------------------------------ helpers


def _load(spec: str):
    """A model file path, or the name of a gallery example."""
    from . import gallery
    from .modelfile import load_model

    path = Path(spec)
    if path.exists():
        return load_model(path)
    if spec in gallery.names():
        return gallery.load(spec)
    if spec.endswith(".toml"):
        try:
            nearby = [str(path.parent / f.name) if str(path.parent) != "." else f.name
                      for f in (path.parent if path.parent.is_dir() else Path(".")).iterdir()
                      if f.suffix == ".toml"]
        except OSError:  # pragma: no cover
            nearby = []
        hint = did_you_mean(spec, nearby)
    else:
        hint = did_you_mean(spec, gallery.names())
    raise ModelError(f"model file not found: {spec}{hint}; check the path (relative to "
                     f"{Path.cwd()}), or give a gallery example name (see 'nonideal examples "
                     "list')")


def _destination(path: Path) -> tuple[Path, bool]:
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


def _stat(path: Path) -> os.stat_result | None:
    try:
        return os.stat(path)
    except FileNotFoundError:
        return None


def _write_into(data: bytes, target: Path) -> None:
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


class _Outputs:
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
                    target, descriptor = _destination(path)
                    info = _stat(target)
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
                        _write_into(Path(tmp).read_bytes(), target)
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


#: the smallest relative tolerance: SciPy's integrators raise a smaller one to 100 machine
#: epsilons (2.22e-14) with a warning; rounded up so that the number shown is accepted
RTOL_MIN = 2.3e-14


def _check_options(args) -> None:
    """Check the numbers and the output paths of the command line before any work is done;
    report every problem at once."""
    problems = _number_problems(args) + _output_problems(args, args.model)
    if problems:
        raise ModelError(problems)


def _number_problems(args) -> list[str]:
    """Times must be finite numbers; tolerances in the range the integrators accept."""
    problems = []
    for key, example in (("t", "0.5"), ("t_end", "2")):
        value = getattr(args, key, None)
        if value is not None and not math.isfinite(value):
            flag = "--" + key.replace("_", "-")
            problems.append(f"{flag}: must be a finite number, e.g. {flag} {example} (got {value})")
    rtol = getattr(args, "rtol", None)
    if rtol is not None and not RTOL_MIN <= rtol < 1:
        problems.append(f"--rtol: must be a number in [{RTOL_MIN:g}, 1) (about 100 machine "
                        "epsilons, the finest the integrators honour, up to 1), e.g. 1e-9 "
                        f"(got {rtol!r})")
    atol = getattr(args, "atol", None)
    if atol is not None and not 0 < atol < 1:
        problems.append(f"--atol: must be a number in (0, 1), e.g. 1e-9 (got {atol!r})")
    return problems


def _output_problems(args, model_spec: str) -> list[str]:
    """Output paths that collide with each other or with the model file, paths that cannot
    be files, and plot formats matplotlib cannot write."""
    problems = []
    seen: dict[Path, str] = {}
    model_path = Path(model_spec).resolve() if Path(model_spec).is_file() else None
    for option in ("json", "csv", "plot"):
        value = getattr(args, option, None)
        if not value or value == "-":
            continue
        flag = f"--{option}"
        try:
            path, _ = _destination(Path(value))
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
    plot = getattr(args, "plot", None)
    if plot and Path(plot).suffix:
        from matplotlib.figure import Figure

        formats = Figure().canvas.get_supported_filetypes()
        suffix = Path(plot).suffix.lstrip(".").lower()
        if suffix not in formats:
            problems.append(f"--plot {plot}: matplotlib cannot write '.{suffix}' files; use one "
                            f"of {', '.join('.' + f for f in sorted(formats))}")
    return problems


def _emit_json(args, payload: dict, outputs: _Outputs) -> None:
    text = json.dumps(payload, indent=1, allow_nan=True)
    if args.json == "-":
        print(text)
    else:
        outputs.add("--json", args.json, lambda tmp: Path(tmp).write_text(text + "\n"))


def _times(text: str) -> list[float]:
    """``--times 0,0.5,1``: finite, strictly increasing numbers."""
    parts = [p.strip() for p in text.replace(";", ",").split(",")]
    if not any(parts):
        raise ModelError(f"--times: no times given (got {text!r}); write comma-separated "
                         "numbers, e.g. --times 0,0.5,1")
    empty = [k + 1 for k, p in enumerate(parts) if not p]
    if empty:
        raise ModelError(f"--times: item{'s' if len(empty) > 1 else ''} "
                         f"{', '.join(map(str, empty))} of {len(parts)} "
                         f"{'are' if len(empty) > 1 else 'is'} empty (got {text!r}); write one "
                         "number between each pair of commas, e.g. --times 0,0.5,1")
    values, bad = [], []
    for p in parts:
        try:
            v = float(p)
        except ValueError:
            bad.append(p)
            continue
        if not math.isfinite(v):
            bad.append(p)
            continue
        values.append(v)
    if bad:
        raise ModelError(f"--times: {', '.join(repr(b) for b in bad)} "
                         f"{'is not a finite number' if len(bad) == 1 else 'are not finite numbers'}"
                         f"; write comma-separated numbers, e.g. --times 0,0.5,1 (got {text!r})")
    for a, b in zip(values, values[1:]):
        if not b > a:
            raise ModelError(f"--times: the times must increase strictly, but {b:g} follows "
                             f"{a:g} (got {text!r}); sort them and remove repetitions")
    return values


def _parse_at(model, text: str | None) -> dict[str, float]:
    """``--at "x=0.1, theta=0.3, x'=1"``; values may be expressions in the parameters.

    Every malformed entry is reported at once."""
    if text is None:
        return {}
    import sympy as sp

    from .errors import ExpressionError
    from .expressions import parse_expression

    allowed = list(model.coordinates) + [c + "'" for c in model.coordinates]
    names = {n: sp.Symbol(n) for n in model.parameters}
    values = {sp.Symbol(n): p.value for n, p in model.parameters.items()}
    out: dict[str, float] = {}
    problems: list[str] = []
    parts = [p for p in text.split(",")]
    if not text.strip():
        raise ModelError(f"--at: empty state; write name=value pairs separated by commas, e.g. "
                         f"--at \"{allowed[0]}=0.1, {allowed[-1]}=0\"")
    for part in parts:
        if not part.strip():
            continue
        if "=" not in part:
            problems.append(f"--at: '{part.strip()}' is not of the form name=value (pairs are "
                            f"separated by commas, e.g. \"{allowed[0]}=0.1, {allowed[-1]}=0\")")
            continue
        key, _, val = part.partition("=")
        key = key.strip()
        if key not in allowed:
            problems.append(f"--at: '{key}' is not a coordinate or velocity"
                            f"{did_you_mean(key, allowed)}; allowed: {', '.join(allowed)}")
            continue
        if key in out:
            problems.append(f"--at: '{key}' is given twice")
            continue
        if "=" in val:
            problems.append(f"--at: '{part.strip()}' has more than one '='; separate the pairs "
                            "with commas")
            continue
        try:
            expr = parse_expression(val.strip(), names, f"--at {key}")
        except ExpressionError as exc:
            problems.extend(exc.problems)
            continue
        out[key] = float(expr.subs(values))
    if problems:
        raise ModelError(problems)
    return out


def _independent(text: str | None, model, form: str) -> tuple[str, ...] | None:
    """``--independent x,theta``: distinct coordinates, for a form that has independent ones."""
    from .formalisms import FORMS

    if text is None:
        return None
    reduced = [f for f in FORMS if f != "lagrange1"]
    if form not in reduced:
        raise ModelError(f"--independent: the form {form} keeps every coordinate (its unknowns "
                         "are all the accelerations, with the constraints' multipliers), so it "
                         "has no independent coordinates to choose; drop --independent or use a "
                         f"reduced form: --form {', '.join(reduced)}")
    parts = [s.strip() for s in text.split(",")]
    if not any(parts):
        raise ModelError(f"--independent: no coordinates given (got {text!r}); write "
                         "comma-separated coordinate names, e.g. --independent "
                         f"{model.coordinates[0]}")
    problems = []
    empty = [k + 1 for k, n in enumerate(parts) if not n]
    if empty:
        problems.append(f"--independent: item{'s' if len(empty) > 1 else ''} "
                        f"{', '.join(map(str, empty))} of {len(parts)} "
                        f"{'are' if len(empty) > 1 else 'is'} empty (got {text!r}); write one "
                        "coordinate name between each pair of commas")
    names = tuple(n for n in parts if n)
    for n in dict.fromkeys(names):
        if n not in model.coordinates:
            problems.append(f"--independent: '{n}' is not a coordinate"
                            f"{did_you_mean(n, model.coordinates)}; coordinates: "
                            + ", ".join(model.coordinates))
        elif names.count(n) > 1:
            problems.append(f"--independent: '{n}' is given {names.count(n)} times; name each "
                            "independent coordinate once")
    if problems:
        raise ModelError(problems)
    return names


def _substitutions(text: str | None, model) -> dict:
    """``"x1 = x + l*cos(theta), y1 = l*sin(theta)"`` -> SymPy substitutions for display; names
    that are not in the model (theta) become new symbols."""
    import re

    import sympy as sp

    from .errors import ExpressionError
    from .expressions import parse_expression

    if not text:
        return {}
    out = {}
    names = model.names(order=1)
    problems = []
    for part in re.split(r",(?![^()]*\))", text):
        if not part.strip():
            continue
        if "=" not in part:
            problems.append(f"--substitute: '{part.strip()}' is not of the form name = expression")
            continue
        key, _, expr = part.partition("=")
        key = key.strip()
        if key not in names:
            problems.append(f"--substitute: '{key}' is not a name of the model{did_you_mean(key, names)}")
            continue
        local = dict(names)
        for ident in re.findall(r"[A-Za-z_][A-Za-z_0-9]*", expr):
            if ident not in local and ident not in ("sin", "cos", "tan", "sqrt", "exp", "log", "pi"):
                local[ident] = sp.Symbol(ident)
        try:
            out[names[key]] = parse_expression(expr.strip(), local, f"--substitute {key}")
        except ExpressionError as exc:
            problems.extend(exc.problems)
    if problems:
        raise ModelError(problems)
    return out


def _contact_states(items, model) -> dict[str, str]:
    out = {}
    for item in items or []:
        if "=" not in item:
            raise ModelError(f"--contact: '{item}' is not of the form NAME=STATE (e.g. floor=slide+)")
        name, _, state = item.partition("=")
        out[name.strip()] = state.strip()
    return out


@contextlib.contextmanager
def _numerical_warnings():
    """NumPy's floating-point warnings during a command (overflow on the way to a blow-up)
    carry a source path and a line of code that mean nothing to the user: when the command
    fails they are dropped -- its error explains the failure -- and when it succeeds each is
    shown once, as one line.  Other warnings are shown as usual."""
    caught: list = []
    failed = True
    try:
        with warnings.catch_warnings(record=True) as caught:
            yield
        failed = False
    finally:
        seen = set()
        for w in caught:
            if not issubclass(w.category, RuntimeWarning):
                warnings.showwarning(w.message, w.category, w.filename, w.lineno)
            elif not failed and str(w.message) not in seen:
                seen.add(str(w.message))
                print(f"warning: {w.message}", file=sys.stderr)


def _explained(model, exc: MechanicsError) -> Exception:
    """A singular mass matrix or dependent constraints are bad input, not a paradox: when
    the mode selection reports "no consistent mode" and the initial state is singular, say
    what is singular instead."""
    from .checks import explain_mechanics_error

    try:
        return explain_mechanics_error(model, exc)
    except NonidealError:  # pragma: no cover - the diagnosis must not mask the error
        return exc


# ------------------------------------------------------------------------------ commands


def cmd_check(args) -> int:
    from .checks import check_model

    _check_options(args)
    model = _load(args.model)
    report = check_model(model)
    outputs = _Outputs()
    if args.json:
        _emit_json(args, report.to_dict(), outputs)
    else:
        print(report.as_text())
    outputs.commit()
    return 0


def _well_posed_at_start(model) -> None:
    """The equations are symbolic, but a negative mass or a kinetic energy that is not positive
    definite at the initial state is bad input for them too (checked when the initial state
    is complete; a model without one is derived as it is)."""
    from .checks import diagnose_initial_state

    problem = diagnose_initial_state(model, definite=True)
    if problem is not None:
        raise problem


def cmd_derive(args) -> int:
    from .formalisms import derive

    _check_options(args)
    model = _load(args.model)
    _well_posed_at_start(model)
    independent = _independent(args.independent, model, args.form)
    states = _contact_states(args.contact, model)
    if args.friction == "painleve":
        from .friction_law import painleve_model, touching_contacts

        closed = touching_contacts(model, states) if model.contacts else None
        eom = derive(painleve_model(model, closed)[0], args.form, independent=independent)
    elif model.contacts:
        from .friction_law import derive_in_mode

        eom = derive_in_mode(model, args.form, states, independent)
    else:
        if states:
            raise ModelError("--contact: the model has no [[contacts]]")
        eom = derive(model, args.form, independent=independent)
    outputs = _Outputs()
    if args.json:
        _emit_json(args, eom.to_dict(), outputs)
    elif args.latex:
        print(eom.as_latex(simplify=args.simplify))
    else:
        print(eom.as_text(simplify=args.simplify))
    outputs.commit()
    return 0


def cmd_evaluate(args) -> int:
    from .evaluation import evaluate

    _check_options(args)
    model = _load(args.model)
    at = _parse_at(model, args.at)
    independent = _independent(args.independent, model, args.form)
    try:
        ev = evaluate(model, at=at, t=args.t, form=args.form, independent=independent)
    except MechanicsError as exc:
        raise _explained(model, exc) from None
    outputs = _Outputs()
    if args.json:
        _emit_json(args, ev.to_dict(), outputs)
    else:
        print(ev.as_text())
    outputs.commit()
    return 0


def cmd_simulate(args) -> int:
    from .simulation import simulate

    _check_options(args)
    model = _load(args.model)
    times = _times(args.times) if args.times is not None else None
    if args.t_end is not None and not args.t_end > model.t0:
        raise ModelError(f"--t-end: must be later than t0 = {model.t0:g} (got {args.t_end:g})")
    if times is not None and args.t_end is not None and times[-1] > args.t_end:
        raise ModelError(f"--times: the last time {times[-1]:g} is after --t-end {args.t_end:g}; "
                         "drop --t-end (it defaults to the last time) or extend it")
    if times is not None and times[0] < model.t0:
        raise ModelError(f"--times: {times[0]:g} is before the initial time t0 = {model.t0:g}"
                         " ([simulation] t0)")
    if args.t_end is None and times is None and model.simulation.t_end is None:
        problems = ["no end time: give t_end in [simulation] (e.g. t_end = 10.0), or --t-end T "
                    "or --times on the command line"]
        try:   # report the initial state's problems too, in the same run
            from .consistency import complete_state
            from .numeric import kernel_of, parameter_vector

            complete_state(kernel_of(model), model.numeric_initial(), parameter_vector(model),
                           model.t0)
        except ModelError as exc:
            problems += exc.problems
        raise ModelError(problems, None if model.source == "<api>" else model.source)
    options = {}
    for key in ("rtol", "atol", "method"):
        if getattr(args, key) is not None:
            options[key] = getattr(args, key)
    try:
        traj = simulate(model, t_end=args.t_end, times=times, form=args.form, **options)
    except MechanicsError as exc:
        raise _explained(model, exc) from None
    outputs = _Outputs()
    fine = traj
    if (args.csv or args.plot) and times is None and len(traj.t) < PLOT_SAMPLES:
        # the integrator's steps are far apart for a table or a drawing: the same run sampled
        # on a fine uniform grid (dense output; the events are in the JSON and on the plot)
        import numpy as np

        grid = np.linspace(traj.t[0], traj.t[-1], PLOT_SAMPLES)
        fine = simulate(model, t_end=traj.t[-1], times=grid, form=args.form, **options)
    if args.csv:
        outputs.add("--csv", args.csv, fine.to_csv)
    if args.plot:
        from .plotting import plot_trajectory

        outputs.add("--plot", args.plot, lambda tmp: plot_trajectory(fine, tmp))
    stdout = None
    if args.json == "-":
        stdout = json.dumps(traj.to_dict(), indent=1, allow_nan=True)
    elif args.json:
        _emit_json(args, traj.to_dict(), outputs)
    outputs.commit()
    if stdout is not None:
        print(stdout)
    elif not args.json:
        d = traj.diagnostics
        print(f"{traj.model}: simulated t = {traj.t[0]:g} .. {traj.t[-1]:g} "
              f"({d['samples']} samples, {d['events']} events, form {d['form']}, {d['method']})")
        for k, c in enumerate(traj.coordinates):
            print(f"  {c:>10}(t_end) = {traj.q[-1, k]: .12g}   {c}'(t_end) = {traj.qd[-1, k]: .12g}")
        shown = traj.events if len(traj.events) <= 24 else traj.events[:20]
        for e in shown:
            print(f"  event at t = {e['t']:.12g}: {e['type']} {e.get('constraint', e.get('contact', ''))}"
                  f" -> mode [{e.get('mode', '')}]")
        if len(shown) < len(traj.events):
            last = traj.events[-1]
            print(f"  ... {len(traj.events) - len(shown)} more events, the last at t = {last['t']:.12g} "
                  f"-> mode [{last.get('mode', '')}] (all of them: --json or --csv)")
        print(f"  constraint residual max = {d['constraint_residual_max']:.3e}, "
              f"energy balance (relative) = {d['energy_balance_relative']:.3e}")
    return 0


def cmd_realizability(args) -> int:
    from .realizability import realizability, realizability_along

    _check_options(args)
    if args.t_end is not None and not args.along:
        raise ModelError("--t-end: is the end of the motion followed by --along; add --along, "
                         "or drop --t-end (for one state give --at and --t)")
    model = _load(args.model)
    contacts = [c.strip() for c in args.contact.split(",")] if args.contact else None
    if args.along:
        if args.at or args.t is not None:
            raise ModelError("--along follows the motion from the model's initial state; drop "
                             + ("--at" if args.at else "--t"))
        if contacts is not None:
            raise ModelError("--contact: --along follows the motion with every touching contact "
                             "in the state the motion gives it, and stops at the first slip or "
                             "lift-off of any of them; drop --contact (or drop --along to assess "
                             "chosen contacts at one state)")
        if args.t_end is not None and not args.t_end > model.t0:
            raise ModelError(f"--t-end: must be later than t0 = {model.t0:g} (got {args.t_end:g})")
        report = realizability_along(model, t_end=args.t_end)
    else:
        at = _parse_at(model, args.at)
        report = realizability(model, at=at, t=args.t, contacts=contacts)
    outputs = _Outputs()
    if args.json:
        _emit_json(args, report.to_dict(), outputs)
    else:
        print(report.as_text())
    outputs.commit()
    return 0


def cmd_friction_law(args) -> int:
    from .friction_law import friction_law

    _check_options(args)
    model = _load(args.model)
    law = friction_law(model, args.contact, args.direction,
                       substitutions=_substitutions(args.substitute, model),
                       normal_sign=args.normal_sign)
    outputs = _Outputs()
    if args.json:
        _emit_json(args, law.to_dict(), outputs)
    elif args.latex:
        print(law.as_latex())
    else:
        print(law.as_text())
    outputs.commit()
    return 0


def cmd_examples(args) -> int:
    from . import gallery

    if args.action == "list":
        if args.name is not None:
            name = args.name if args.name in gallery.names() else "NAME"
            raise ModelError(f"examples list takes no name (got '{args.name}'); to see one "
                             f"example: nonideal examples show {name}")
        for name in gallery.names():
            print(f"{name:28} {gallery.module(name).TITLE}")
        return 0
    if not args.name:
        raise ModelError(f"examples {args.action}: give the example's name (see 'nonideal examples list')")
    if args.name not in gallery.names():
        raise ModelError(f"examples: no example '{args.name}'{did_you_mean(args.name, gallery.names())}"
                         "; see 'nonideal examples list'")
    mod = gallery.module(args.name)
    if args.action == "show":
        print(mod.__doc__.strip())
        print()
        print(f"# model file: {gallery.model_path(args.name)}")
        print(gallery.model_path(args.name).read_text())
        return 0
    result = gallery.run(args.name, verbose=True)
    return 0 if result.get("ok", True) else 1


# ------------------------------------------------------------------------------ parser


def _form_type(forms):
    def convert(value: str) -> str:
        if value not in forms:
            raise argparse.ArgumentTypeError(
                f"unknown form '{value}'{did_you_mean(value, forms)}; choose one of "
                + ", ".join(forms))
        return value
    convert.__name__ = "form"
    return convert


def _method_type(value: str) -> str:
    if value not in METHODS:
        raise argparse.ArgumentTypeError(
            f"unknown integrator '{value}'{did_you_mean(value, METHODS)}; choose one of "
            + ", ".join(METHODS))
    return value


def build_parser() -> argparse.ArgumentParser:
    from .formalisms import FORMS

    forms = list(FORMS)
    form_help = f"the form: {', '.join(forms)} (default lagrange1)"
    solvers = forms + ["gauss"]
    solver_help = (f"the form evaluating the accelerations: {', '.join(solvers)} (gauss: the "
                   "generalized Gauss principle with friction, a numerical solver); default lagrange1")
    p = argparse.ArgumentParser(
        prog="nonideal",
        description="Analytical dynamics of systems with ideal and non-ideal constraints.",
        epilog="Exit codes: 0 success, 2 bad input, 3 mechanics without a consistent or unique answer.")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def json_option(sp):
        sp.add_argument("--json", nargs="?", const="-", metavar="OUT",
                        help="machine-readable output (to OUT, or standard output)")

    c = sub.add_parser("check",
                       help="parse and validate a model; degrees of freedom, constraints, determinacy",
                       description="Parse and validate a model; print degrees of freedom, "
                       "constraints, contacts and determinacy, and check the initial state.")
    c.add_argument("model", help="model file (TOML) or gallery example name")
    json_option(c)
    c.set_defaults(func=cmd_check)

    d = sub.add_parser("derive", help="equations of motion in a classical form",
                       description="Equations of motion of a model in a classical form.")
    d.add_argument("model", help="model file (TOML) or gallery example name")
    d.add_argument("--form", default="lagrange1", type=_form_type(forms), metavar="FORM",
                   help=form_help)
    fmt = d.add_mutually_exclusive_group()
    fmt.add_argument("--latex", action="store_true", help="print LaTeX")
    json_option(fmt)
    d.add_argument("--independent", help="independent coordinates for the reduced forms, comma-separated")
    d.add_argument("--simplify", action="store_true", help="trigsimp the printed equations (can be slow)")
    d.add_argument("--contact", action="append", metavar="NAME=STATE",
                   help="state of a contact: separated, stick, slide+, slide- (one slip component) "
                   "or slide (two); repeatable; default: its state at t0")
    d.add_argument("--friction", choices=["physical", "painleve"], default="physical",
                   help="physical: a sliding contact's normal force carries -mu N s (default); "
                   "painleve: the touching contacts (at t0, or not separated by --contact) as ideal "
                   "constraints plus the friction force M V mu of the seed's extended method of "
                   "combining constraints")
    d.set_defaults(func=cmd_derive)

    e = sub.add_parser("evaluate", help="accelerations, multipliers and reactions at one state",
                       description="Accelerations, multipliers, reactions (constraint and "
                       "friction parts) and contact forces at one state.")
    e.add_argument("model", help="model file (TOML) or gallery example name")
    e.add_argument("--at", help="state, e.g. \"x=0.1, theta=0.3, x'=1\" (default: the model's initial state)")
    e.add_argument("--t", type=float, default=None, help="time (default t0)")
    e.add_argument("--form", default="lagrange1", type=_form_type(solvers), metavar="FORM",
                   help=solver_help)
    e.add_argument("--independent", help="independent coordinates for the reduced forms")
    json_option(e)
    e.set_defaults(func=cmd_evaluate)

    s = sub.add_parser("simulate", help="the hybrid simulation",
                       description="The hybrid simulation with exact switching of modes.")
    s.add_argument("model", help="model file (TOML) or gallery example name")
    s.add_argument("--t-end", type=float, default=None, help="end time (default: [simulation] t_end)")
    s.add_argument("--times", help="output exactly at these times, comma-separated, strictly "
                   "increasing (negative times: --times=-1,0,1)")
    s.add_argument("--form", default="lagrange1", type=_form_type(solvers), metavar="FORM",
                   help=solver_help)
    s.add_argument("--rtol", type=float, help="relative tolerance (default: [simulation] rtol)")
    s.add_argument("--atol", type=float, help="absolute tolerance (default: [simulation] atol)")
    s.add_argument("--method", type=_method_type, metavar="METHOD",
                   help=f"integrator: {', '.join(METHODS)} (default: [simulation] method)")
    json_option(s)
    s.add_argument("--csv", metavar="OUT", help="write the trajectory as CSV (at --times, else on 601 uniform samples)")
    s.add_argument("--plot", metavar="PNG", help="plot the trajectory, reactions and energy")
    s.set_defaults(func=cmd_simulate)

    r = sub.add_parser("realizability", help="can Coulomb friction keep the contacts sticking/rolling?",
                       description="Realizability of no-slip constraints by Coulomb friction "
                       "(Kalinin & Novozhilov): the friction force needed to keep each touching "
                       "contact sticking, compared with mu_s N, with the margin; with --along, the "
                       "first time along the rolling motion when it stops being realizable.")
    r.add_argument("model", help="model file (TOML) or gallery example name")
    r.add_argument("--at", help="state (default: the model's initial state)")
    r.add_argument("--t", type=float, default=None, help="time (default t0)")
    r.add_argument("--contact", help="contacts to keep sticking, comma-separated (default: all touching)")
    r.add_argument("--along", action="store_true", help="follow the rolling motion")
    r.add_argument("--t-end", type=float, default=None, help="end of the motion followed by --along")
    json_option(r)
    r.set_defaults(func=cmd_realizability)

    fl = sub.add_parser("friction-law", help="the friction law of the system mu(lambda) for a contact",
                        description="The friction law of the system (Manglieva & Beknazarov, "
                        "sec. 1.1-1.3): normal force, friction force and the coefficient mu as "
                        "functions of the friction-independent constraint force lambda, for a "
                        "contact sliding in a given direction; Painleve's condition.")
    fl.add_argument("model", help="model file (TOML) or gallery example name")
    fl.add_argument("--contact", required=True, help="the contact (one slip component)")
    fl.add_argument("--direction", type=int, choices=[1, -1], default=1, help="sign of the slip")
    fl.add_argument("--normal-sign", type=int, choices=[1, -1], default=1,
                    help="sign of the normal force (-1 only for a bilateral contact, whose "
                    "friction is -f s |N|)")
    fl.add_argument("--substitute", help="display in other variables, e.g. "
                    "\"x1 = x + l*cos(theta), y1 = y + l*sin(theta)\"")
    fmt2 = fl.add_mutually_exclusive_group()
    fmt2.add_argument("--latex", action="store_true", help="print LaTeX")
    json_option(fmt2)
    fl.set_defaults(func=cmd_friction_law)

    x = sub.add_parser("examples", help="the gallery of worked examples",
                       description="The gallery of worked examples: list, show NAME, run NAME.")
    x.add_argument("action", choices=["list", "show", "run"])
    x.add_argument("name", nargs="?")
    x.set_defaults(func=cmd_examples)
    return p


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:   # --help (0) or a usage error (2): return, do not exit
        return int(exc.code or 0)
    try:
        with _numerical_warnings():
            return args.func(args)
    except ModelError as exc:
        model = getattr(args, "model", None)
        if (exc.source is None and isinstance(model, str) and Path(model).is_file()
                and not all(str(pr).startswith("--") for pr in exc.problems)):
            exc = exc.with_source(model)  # an error found past the file's parsing names it too
        print(f"error: {exc}", file=sys.stderr)
        return exc.exit_code
    except MechanicsError as exc:
        print(f"mechanics: {exc}", file=sys.stderr)
        return exc.exit_code
    except NonidealError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return exc.exit_code
    except BrokenPipeError:  # pragma: no cover
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
