"""``nonideal check``."""

from __future__ import annotations

from .common import json_option, model_argument, load_spec, check_options
from .outputs import emit_report


def add_parser(sub, ctx) -> None:
    c = sub.add_parser("check",
                       help="parse and validate a model; degrees of freedom, constraints, determinacy",
                       description="Parse and validate a model; print degrees of freedom, "
                       "constraints, contacts and determinacy, and check the initial state.")
    model_argument(c)
    json_option(c)
    c.set_defaults(func=run)


def run(args) -> int:
    from ..analysis.checks import check_model

    check_options(args)
    model = load_spec(args.model, args.set)
    report = check_model(model)
    return emit_report(args, report)
