"""``nonideal friction-law``."""

from __future__ import annotations

from .common import json_option, model_argument, load_spec, check_options, parse_substitutions
from .outputs import Outputs, emit_json


def add_parser(sub, ctx) -> None:
    fl = sub.add_parser("friction-law", help="the friction law of the system mu(lambda) for a contact",
                        description="The friction law of the system (Manglieva & Beknazarov, "
                        "sec. 1.1-1.3): normal force, friction force and the coefficient mu as "
                        "functions of the friction-independent constraint force lambda, for a "
                        "contact sliding in a given direction; Painleve's condition.")
    model_argument(fl)
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
    fl.set_defaults(func=run)


def run(args) -> int:
    from ..analysis.contact.friction_law import friction_law

    check_options(args)
    model = load_spec(args.model, args.set)
    law = friction_law(model, args.contact, args.direction,
                       substitutions=parse_substitutions(args.substitute, model),
                       normal_sign=args.normal_sign)
    outputs = Outputs()
    if args.json:
        emit_json(args, law.to_dict(), outputs)
    elif args.latex:
        print(law.as_latex())
    else:
        print(law.as_text())
    outputs.commit()
    return 0
