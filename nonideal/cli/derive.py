"""``nonideal derive``."""

from __future__ import annotations

from ..errors import ModelError
from .common import json_option, model_argument, load_spec, check_options, parse_independent, parse_contact_states, well_posed_at_start, form_type
from .outputs import Outputs, emit_json


def add_parser(sub, ctx) -> None:
    forms, form_help = ctx.forms, ctx.form_help
    d = sub.add_parser("derive", help="equations of motion in a classical form",
                       description="Equations of motion of a model in a classical form.")
    model_argument(d)
    d.add_argument("--form", default="lagrange1", type=form_type(forms), metavar="FORM",
                   help=form_help)
    fmt = d.add_mutually_exclusive_group()
    fmt.add_argument("--latex", action="store_true", help="print LaTeX")
    json_option(fmt)
    fmt.add_argument("--code", choices=["c", "python", "julia", "matlab"],
                     help="write the right-hand side dy/dt = (q', q'') of the mode derived (the "
                     "saddle-point system solved at each call; the state and parameter order in "
                     "the file's header) as a self-contained source file; to standard output "
                     "or --output")
    d.add_argument("--output", metavar="FILE", help="--code: the file written (a MATLAB "
                   "function takes the file's name)")
    d.add_argument("--independent", help="independent coordinates for the reduced forms, comma-separated")
    d.add_argument("--simplify", action="store_true", help="SymPy's trigsimp of the raw equations instead of the readable default (slow: grows fast with the number of angles)")
    d.add_argument("--contact", action="append", metavar="NAME=STATE",
                   help="state of a contact: separated, stick, slide+, slide- (one slip component) "
                   "or slide (two); repeatable; default: its state at t0")
    d.add_argument("--friction", choices=["physical", "painleve"], default="physical",
                   help="physical: a sliding contact's normal force carries -mu N s (default); "
                   "painleve: the touching contacts (at t0, or not separated by --contact) as ideal "
                   "constraints plus the friction force M V mu of Manglieva & Beknazarov's extended method of "
                   "combining constraints")
    d.set_defaults(func=run)


def run(args) -> int:
    from ..analysis.derivation import derive

    check_options(args)
    model = load_spec(args.model, args.set)
    well_posed_at_start(model)
    independent = parse_independent(args.independent, model, args.form)
    states = parse_contact_states(args.contact, model)
    if states and not model.contacts:
        raise ModelError("--contact: the model has no [[contacts]]")
    if args.output and not args.code:
        raise ModelError("--output: the file of --code; give --code c|python|julia|matlab")
    if args.code and args.simplify:
        raise ModelError("--simplify: changes the printed equations only; drop it with --code")
    eom = derive(model, args.form, independent=independent, contacts=states, friction=args.friction)
    outputs = Outputs()
    if args.code:
        from pathlib import Path

        from ..equations.codegen import generate

        name = None
        if args.output and args.code == "matlab":
            name = Path(args.output).stem
        mode = ", ".join(f"{k} {v}" for k, v in states.items()) if states else ""
        source = generate(eom, args.code, name=name, mode=mode)
        if args.output:
            outputs.add("--output", args.output, lambda tmp: Path(tmp).write_text(source))
        else:
            print(source, end="")
    elif args.json:
        emit_json(args, eom.to_dict(), outputs)
    elif args.latex:
        print(eom.as_latex(simplify=args.simplify))
    else:
        print(eom.as_text(simplify=args.simplify))
    outputs.commit()
    return 0
