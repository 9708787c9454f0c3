"""``nonideal stability``: the first approximation about an equilibrium, a steady motion or a
programmed motion; characteristic polynomial, Hurwitz minors, verdict; controllability; LQR."""

from __future__ import annotations

from ..errors import ModelError
from .common import check_options, json_option, load_spec, model_argument
from .outputs import Outputs, emit_json


def add_parser(sub, ctx) -> None:
    p = sub.add_parser(
        "stability", help="linearization, characteristic polynomial, Hurwitz conditions, eigenvalues",
        description="Stability by the first approximation (Lyapunov).  The perturbations are kept on "
        "the constraint manifold: dependent coordinates and velocities are eliminated, ignorable "
        "coordinates dropped and named, the held velocities of a family of steady motions named.  "
        "--about equilibrium: found by Newton from --at; steady: cyclic velocities held, the rest at "
        "rest; program: A(t), B(t) along the programmed motion from the initial state.")
    model_argument(p)
    p.add_argument("--about", choices=("equilibrium", "steady", "program"), default="equilibrium",
                   help="the motion to linearize about (default: equilibrium)")
    p.add_argument("--at", help="the state or a guess, e.g. \"theta=0.1, psi'=20\" (values may be "
                   "expressions in the parameters; default: the model's initial state)")
    p.add_argument("--exact", action="store_true", help="the --at state is exact: no Newton")
    p.add_argument("--symbolic", metavar="P1,P2", help="parameters kept as symbols: A, the "
                   "polynomial and the stability conditions in them")
    p.add_argument("--controls", metavar="U1,U2", help="parameters that act as inputs (they enter "
                   "[forces]); gives B and the controllability")
    p.add_argument("--keep", metavar="Q1,Q2", help="coordinates kept in the state even when "
                   "ignorable (e.g. a cart's position)")
    p.add_argument("--lqr", metavar="Q,R", help="optimal stabilization: weights Q,R (numbers or "
                   "';'-separated diagonals), gain, Riccati matrix (Lyapunov function) and the "
                   "closed-loop eigenvalues; needs --controls")
    p.add_argument("--t-end", type=float, default=None,
                   help="--about program: the end of the programmed motion followed")
    json_option(p)
    p.add_argument("--plot", metavar="PNG", help="eigenvalues in the complex plane (for --about "
                   "program: the real parts against t)")
    p.set_defaults(func=run)


def _names(text):
    return tuple(x.strip() for x in text.split(",") if x.strip()) if text else ()


def run(args) -> int:
    check_options(args)
    model = load_spec(args.model, args.set)
    outputs = Outputs()
    if args.about == "program":
        from ..analysis.program import linearize_program

        if args.lqr:
            raise ModelError("--lqr: optimal stabilization of a programmed motion needs the "
                             "differential Riccati equation; use --about equilibrium|steady or drop --lqr")
        result = linearize_program(model, controls=_names(args.controls), t_end=args.t_end,
                                   keep=_names(args.keep))
        payload = result.to_dict()
        text = result.as_text()
    else:
        if args.t_end is not None:
            raise ModelError("--t-end: only for --about program (the programmed motion followed)")
        from ..analysis.linearize import linearize

        lin = linearize(model, about=args.about, at=args.at, symbolic=_names(args.symbolic),
                        controls=_names(args.controls), keep=_names(args.keep), exact=args.exact)
        payload = lin.to_dict()
        text = lin.as_text()
        if args.lqr:
            from ..analysis.control import lqr, weights

            if not lin.controls:
                raise ModelError("--lqr: needs --controls (the parameters that act as inputs)")
            Q, R = weights(args.lqr, len(lin.variables), len(lin.controls))
            reg = lqr(lin, Q, R)
            payload["lqr"] = reg.to_dict()
            text += "\n" + reg.as_text()
        result = lin
    if args.plot:
        from ..plotting import plot_stability

        outputs.add("--plot", args.plot, lambda tmp: plot_stability(result, tmp))
    if args.json:
        emit_json(args, payload, outputs)
    else:
        print(text)
    outputs.commit()
    return 0
