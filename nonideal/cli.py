"""The ``nonideal`` command line.

Exit codes: 0 success; 2 bad input (the message names the file, the key and the fix);
3 the mechanics has no consistent or no unique answer.  Nothing is written to an output path
unless the run succeeded (outputs are written to a temporary file and renamed at the end).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

from .errors import MechanicsError, ModelError, NonidealError

__all__ = ["main"]


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
    raise ModelError(f"model file not found: {spec} (nor is it a gallery example; "
                     "see 'nonideal examples list')")


class _Outputs:
    """Collects output files and writes them only when everything succeeded."""

    def __init__(self):
        self.pending: list[tuple[Path, object]] = []

    def add(self, path: str, producer) -> None:
        self.pending.append((Path(path), producer))

    def commit(self) -> None:
        staged = []
        try:
            for path, producer in self.pending:
                path.parent.mkdir(parents=True, exist_ok=True)
                fd, tmp = tempfile.mkstemp(prefix=".nonideal-", suffix=path.suffix, dir=path.parent)
                os.close(fd)
                producer(tmp)
                staged.append((tmp, path))
            for tmp, path in staged:
                os.replace(tmp, path)
        finally:
            for tmp, _ in staged:
                if os.path.exists(tmp):
                    os.unlink(tmp)


def _emit_json(args, payload: dict, outputs: _Outputs) -> None:
    text = json.dumps(payload, indent=1, allow_nan=True)
    if args.json == "-":
        print(text)
    else:
        outputs.add(args.json, lambda tmp: Path(tmp).write_text(text + "\n"))


def _floats(text: str, option: str) -> list[float]:
    try:
        return [float(x) for x in text.replace(";", ",").split(",") if x.strip()]
    except ValueError:
        raise ModelError(f"{option}: expected comma-separated numbers (got {text!r})") from None


# ------------------------------------------------------------------------------ commands


def cmd_check(args) -> int:
    from .checks import check_model

    model = _load(args.model)
    report = check_model(model)
    outputs = _Outputs()
    if args.json:
        _emit_json(args, report.to_dict(), outputs)
    else:
        print(report.as_text())
    outputs.commit()
    return 0


def cmd_derive(args) -> int:
    from .formalisms import derive

    model = _load(args.model)
    independent = tuple(s.strip() for s in args.independent.split(",")) if args.independent else None
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
    from .evaluation import evaluate, parse_state

    model = _load(args.model)
    at = parse_state(model, args.at)
    independent = tuple(s.strip() for s in args.independent.split(",")) if args.independent else None
    ev = evaluate(model, at=at, t=args.t, form=args.form, independent=independent)
    outputs = _Outputs()
    if args.json:
        _emit_json(args, ev.to_dict(), outputs)
    else:
        print(ev.as_text())
    outputs.commit()
    return 0


def cmd_simulate(args) -> int:
    from .simulation import simulate

    model = _load(args.model)
    times = _floats(args.times, "--times") if args.times else None
    options = {}
    for key in ("rtol", "atol", "method"):
        if getattr(args, key) is not None:
            options[key] = getattr(args, key)
    traj = simulate(model, t_end=args.t_end, times=times, form=args.form, **options)
    outputs = _Outputs()
    if args.csv:
        outputs.add(args.csv, traj.to_csv)
    if args.plot:
        from .plotting import plot_trajectory

        outputs.add(args.plot, lambda tmp: plot_trajectory(traj, tmp))
    if args.json:
        _emit_json(args, traj.to_dict(), outputs)
    else:
        d = traj.diagnostics
        print(f"{traj.model}: simulated t = {traj.t[0]:g} .. {traj.t[-1]:g} "
              f"({d['samples']} samples, {d['events']} events, form {d['form']}, {d['method']})")
        for k, c in enumerate(traj.coordinates):
            print(f"  {c:>10}(t_end) = {traj.q[-1, k]: .12g}   {c}'(t_end) = {traj.qd[-1, k]: .12g}")
        for e in traj.events:
            print(f"  event at t = {e['t']:.12g}: {e['type']} {e.get('constraint', e.get('contact', ''))}"
                  f" -> mode [{e.get('mode', '')}]")
        print(f"  constraint residual max = {d['constraint_residual_max']:.3e}, "
              f"energy balance (relative) = {d['energy_balance_relative']:.3e}")
    outputs.commit()
    return 0


def cmd_examples(args) -> int:
    from . import gallery

    if args.action == "list":
        for name in gallery.names():
            print(f"{name:28} {gallery.module(name).TITLE}")
        return 0
    if not args.name:
        raise ModelError(f"examples {args.action}: give the example's name (see 'nonideal examples list')")
    if args.name not in gallery.names():
        from .errors import did_you_mean
        raise ModelError(f"examples: no example '{args.name}'{did_you_mean(args.name, gallery.names())}")
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


def build_parser() -> argparse.ArgumentParser:
    from .formalisms import FORMS

    p = argparse.ArgumentParser(
        prog="nonideal",
        description="Analytical dynamics of systems with ideal and non-ideal constraints.",
        epilog="Exit codes: 0 success, 2 bad input, 3 mechanics without a consistent or unique answer.")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def json_option(sp):
        sp.add_argument("--json", nargs="?", const="-", metavar="OUT",
                        help="machine-readable output (to OUT, or standard output)")

    c = sub.add_parser("check", help="parse and validate a model; degrees of freedom, constraints, determinacy")
    c.add_argument("model", help="model file (TOML) or gallery example name")
    json_option(c)
    c.set_defaults(func=cmd_check)

    d = sub.add_parser("derive", help="equations of motion in a classical form")
    d.add_argument("model")
    d.add_argument("--form", default="lagrange1", choices=list(FORMS), help="the form (default lagrange1)")
    fmt = d.add_mutually_exclusive_group()
    fmt.add_argument("--latex", action="store_true", help="print LaTeX")
    json_option(fmt)
    d.add_argument("--independent", help="independent coordinates for the reduced forms, comma-separated")
    d.add_argument("--simplify", action="store_true", help="trigsimp the printed equations (can be slow)")
    d.set_defaults(func=cmd_derive)

    e = sub.add_parser("evaluate", help="accelerations, multipliers and reactions at one state")
    e.add_argument("model")
    e.add_argument("--at", help="state, e.g. \"x=0.1, theta=0.3, x'=1\" (default: the model's initial state)")
    e.add_argument("--t", type=float, default=None, help="time (default t0)")
    e.add_argument("--form", default="lagrange1", choices=list(FORMS))
    e.add_argument("--independent", help="independent coordinates for the reduced forms")
    json_option(e)
    e.set_defaults(func=cmd_evaluate)

    s = sub.add_parser("simulate", help="the hybrid simulation")
    s.add_argument("model")
    s.add_argument("--t-end", type=float, default=None, help="end time (default: [simulation] t_end)")
    s.add_argument("--times", help="output exactly at these times, comma-separated")
    s.add_argument("--form", default="lagrange1", choices=list(FORMS))
    s.add_argument("--rtol", type=float)
    s.add_argument("--atol", type=float)
    s.add_argument("--method", choices=["DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA"])
    json_option(s)
    s.add_argument("--csv", metavar="OUT", help="write the trajectory as CSV")
    s.add_argument("--plot", metavar="PNG", help="plot the trajectory, reactions and energy")
    s.set_defaults(func=cmd_simulate)

    x = sub.add_parser("examples", help="the gallery of worked examples")
    x.add_argument("action", choices=["list", "show", "run"])
    x.add_argument("name", nargs="?")
    x.set_defaults(func=cmd_examples)
    return p


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except ModelError as exc:
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
