"""``nonideal realizability``."""

from __future__ import annotations

from ..errors import ModelError
from .common import json_option, model_argument, load_spec, check_options, parse_at
from .outputs import emit_report


def add_parser(sub, ctx) -> None:
    r = sub.add_parser("realizability", help="can Coulomb friction keep the contacts sticking/rolling?",
                       description="Realizability of no-slip constraints by Coulomb friction "
                       "(Kalinin & Novozhilov): the friction force needed to keep each touching "
                       "contact sticking, compared with mu_s N, with the margin; with --along, the "
                       "first time along the rolling motion when it stops being realizable.")
    model_argument(r)
    r.add_argument("--at", help="state (default: the model's initial state)")
    r.add_argument("--t", type=float, default=None, help="time (default t0)")
    r.add_argument("--contact", help="contacts to keep sticking, comma-separated (default: all touching)")
    r.add_argument("--along", action="store_true", help="follow the rolling motion")
    r.add_argument("--t-end", type=float, default=None, help="end of the motion followed by --along")
    json_option(r)
    r.set_defaults(func=run)


def run(args) -> int:
    from ..analysis.contact.realizability import realizability, realizability_along

    check_options(args)
    if args.t_end is not None and not args.along:
        raise ModelError("--t-end: is the end of the motion followed by --along; add --along, "
                         "or drop --t-end (for one state give --at and --t)")
    model = load_spec(args.model, args.set)
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
        at = parse_at(model, args.at)
        report = realizability(model, at=at, t=args.t, contacts=contacts)
    return emit_report(args, report)
