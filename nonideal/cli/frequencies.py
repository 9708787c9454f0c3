"""``nonideal frequencies``: the natural frequencies of small oscillations about an equilibrium
or a steady motion, and their modes (elastic members' Galerkin frequencies among them)."""

from __future__ import annotations

from .common import check_options, json_option, load_spec, model_argument
from .outputs import Outputs, emit_json


def add_parser(sub, ctx) -> None:
    p = sub.add_parser(
        "frequencies", help="natural frequencies and modes of small oscillations",
        description="Natural frequencies (rad/s and Hz) and modes of the small oscillations about an "
        "equilibrium (found by Newton from --at) or a steady motion, from the linearization on the "
        "constraint manifold (as `stability`).  Refused with the reason when an eigenvalue is off the "
        "imaginary axis (damping or instability).  For elastic members ([[members]]) they are "
        "Rayleigh-Ritz upper bounds of the exact frequencies.")
    model_argument(p)
    p.add_argument("--about", choices=("equilibrium", "steady"), default="equilibrium",
                   help="the motion to linearize about (default: equilibrium)")
    p.add_argument("--at", help="the state or a guess, e.g. \"x=0\" (default: the model's initial state)")
    p.add_argument("--exact", action="store_true", help="the --at state is exact: no Newton")
    p.add_argument("--modes", action="store_true", help="print each mode's coordinate amplitudes")
    json_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    check_options(args)
    model = load_spec(args.model, args.set)
    from ..analysis.stability.frequencies import natural_frequencies

    result = natural_frequencies(model, at=args.at, about=args.about, exact=args.exact)
    outputs = Outputs()
    if args.json:
        emit_json(args, result.to_dict(), outputs)
    else:
        text = result.as_text()
        if args.modes:
            for k, mode in enumerate(result.modes, 1):
                text += f"\n  mode {k}: " + ", ".join(f"{n} {a:.6g}" for n, a in mode.items())
        print(text)
    outputs.commit()
    return 0
