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
                   "closed-loop eigenvalues (--about program: the differential Riccati equation); "
                   "needs --controls")
    p.add_argument("--t-end", type=float, default=None,
                   help="--about program: the end of the programmed motion followed")
    p.add_argument("--vary", action="append", default=[], metavar="NAME=START:STOP:N",
                   help="a parameter study: the eigenvalues against NAME (root locus; once) or the "
                   "stable region over two parameters (twice); in the JSON as 'locus' and on --plot")
    json_option(p)
    p.add_argument("--plot", metavar="PNG", help="eigenvalues in the complex plane (for --about "
                   "program: the real parts against t; with --vary: the root locus or the stability "
                   "region)")
    p.set_defaults(func=run)


def _names(text):
    return tuple(x.strip() for x in text.split(",") if x.strip()) if text else ()


def run(args) -> int:
    check_options(args)
    _ranges(args.vary)                  # a malformed --vary is reported before any work
    model = load_spec(args.model, args.set)
    outputs = Outputs()
    if args.about == "program":
        from ..analysis.stability.program import linearize_program

        result = linearize_program(model, controls=_names(args.controls), t_end=args.t_end,
                                   keep=_names(args.keep))
        payload = result.to_dict()
        text = result.as_text()
        if args.lqr:
            from ..analysis.stability.control import program_lqr, weights

            if not result.controls:
                raise ModelError("--lqr: needs --controls (the parameters that act as inputs)")
            Q, R = weights(args.lqr, len(result.variables), len(result.controls))
            reg = program_lqr(result, Q, R)
            payload["lqr"] = {"t": reg.t.tolist(), "K": reg.K.tolist(), "P": reg.P.tolist(),
                              "exponent_open": reg.exponent_open, "exponent_closed": reg.exponent_closed}
            text += ("\noptimal stabilization (differential Riccati equation, P(T) = 0):"
                     f"\n  K(t0) = {reg.K[0].tolist()}\n  characteristic exponents: open loop "
                     f"{reg.exponent_open:.6g}, closed loop {reg.exponent_closed:.6g}")
    else:
        if args.t_end is not None:
            raise ModelError("--t-end: only for --about program (the programmed motion followed)")
        from ..analysis.stability.linearize import linearize

        lin = linearize(model, about=args.about, at=args.at, symbolic=_names(args.symbolic),
                        controls=_names(args.controls), keep=_names(args.keep), exact=args.exact)
        payload = lin.to_dict()
        text = lin.as_text()
        if args.lqr:
            from ..analysis.stability.control import lqr, weights

            if not lin.controls:
                raise ModelError("--lqr: needs --controls (the parameters that act as inputs)")
            Q, R = weights(args.lqr, len(lin.variables), len(lin.controls))
            reg = lqr(lin, Q, R)
            payload["lqr"] = reg.to_dict()
            text += "\n" + reg.as_text()
        result = lin
    locus = _locus(args) if args.vary else None
    if locus is not None:
        payload["locus"] = locus
        text += "\n" + _locus_text(locus)
    if args.plot:
        from ..plotting import plot_locus, plot_stability

        if locus is not None:
            outputs.add("--plot", args.plot, lambda tmp: plot_locus(locus, payload["model"], tmp))
        else:
            outputs.add("--plot", args.plot, lambda tmp: plot_stability(result, tmp))
    if args.json:
        emit_json(args, payload, outputs)
    else:
        print(text)
    outputs.commit()
    return 0


def _ranges(items) -> list[tuple[str, list[float]]]:
    import numpy as np

    out, problems = [], []
    for item in items:
        name, _, spec = item.partition("=")
        parts = spec.split(":")
        try:
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
            if len(parts) != 3 or count < 2:
                raise ValueError
        except (ValueError, IndexError):
            problems.append(f"--vary {item}: expected NAME=START:STOP:N with N >= 2, e.g. --vary J=0.3:0.6:20")
            continue
        out.append((name.strip(), [float(x) for x in np.linspace(start, stop, count)]))
    if len(out) > 2:
        problems.append("--vary: at most two parameters (a root locus, or a stability region)")
    if problems:
        raise ModelError(problems)
    return out


def _locus(args) -> dict:
    """Linearize at every point of the --vary grid (the same options); each point's verdict and
    eigenvalues, or its error message."""
    import itertools

    from ..analysis.stability.linearize import linearize
    from ..analysis.stability.program import linearize_program
    from ..errors import NonidealError

    ranges = _ranges(args.vary)
    names = [n for n, _ in ranges]
    rows = []
    for values in itertools.product(*[v for _, v in ranges]):
        sets = list(args.set) + [f"{n}={v!r}" for n, v in zip(names, values)]
        model = load_spec(args.model, sets)
        try:
            if args.about == "program":
                res = linearize_program(model, t_end=args.t_end, keep=_names(args.keep))
                eig = [complex(*z) for z in res.frozen["eigenvalues"]]
            else:
                res = linearize(model, about=args.about, at=args.at, keep=_names(args.keep), exact=args.exact)
                eig = list(res.eigenvalues)
            rows.append({"parameters": dict(zip(names, values)), "verdict": res.verdict,
                         "eigenvalues": [[z.real, z.imag] for z in eig]})
        except NonidealError as exc:
            rows.append({"parameters": dict(zip(names, values)), "verdict": None, "error": str(exc),
                         "eigenvalues": []})
    return {"vary": {n: v for n, v in ranges}, "rows": rows}


def _locus_text(locus: dict) -> str:
    lines = ["parameter study (--vary):"]
    for row in locus["rows"]:
        at = ", ".join(f"{k} = {v:.6g}" for k, v in row["parameters"].items())
        worst = max((re for re, _ in row["eigenvalues"]), default=float("nan"))
        lines.append(f"  {at}: {row['verdict'] or 'error: ' + row.get('error', '')} (largest Re = {worst:.6g})")
    return "\n".join(lines)
