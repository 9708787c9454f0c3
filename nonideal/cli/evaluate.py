"""``nonideal evaluate``."""

from __future__ import annotations

from ..errors import MechanicsError
from .common import json_option, model_argument, load_spec, check_options, parse_at, parse_independent, explained, form_type
from .outputs import emit_report


def add_parser(sub, ctx) -> None:
    solvers, solver_help = ctx.solvers, ctx.solver_help
    e = sub.add_parser("evaluate", help="accelerations, multipliers and reactions at one state",
                       description="Accelerations, multipliers, reactions (constraint and "
                       "friction parts) and contact forces at one state.")
    model_argument(e)
    e.add_argument("--at", help="state, e.g. \"x=0.1, theta=0.3, x'=1\" (default: the model's initial state)")
    e.add_argument("--t", type=float, default=None, help="time (default t0)")
    e.add_argument("--form", default="lagrange1", type=form_type(solvers), metavar="FORM",
                   help=solver_help)
    e.add_argument("--independent", help="independent coordinates for the reduced forms")
    json_option(e)
    e.set_defaults(func=run)


def run(args) -> int:
    from ..analysis.evaluation import evaluate

    check_options(args)
    model = load_spec(args.model, args.set)
    at = parse_at(model, args.at)
    independent = parse_independent(args.independent, model, args.form)
    try:
        ev = evaluate(model, at=at, t=args.t, form=args.form, independent=independent)
    except MechanicsError as exc:
        raise explained(model, exc) from None
    return emit_report(args, ev)
