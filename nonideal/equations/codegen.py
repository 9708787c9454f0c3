"""Equations that leave the library: the right-hand side of a model's equations of motion as
a self-contained source file in C, Python, Julia or MATLAB/Octave.

The file evaluates, at a state ``y = (q, q')`` and time ``t`` with the parameters ``p``, the
equations of an :class:`~nonideal.equations.eom.EquationsOfMotion` (one mode: the constraints
and the contacts' states it was derived with)::

    A a + c = Q_f + B mu        (k dynamic rows)
    G a + gamma = 0             (m constraint rows)
    q'' = R a + r

by solving the saddle-point system ``[[A, -B], [G, 0]] [a; mu] = [Q_f - c; -gamma]`` and
returns ``dy/dt = (q', q'')`` and the multipliers ``mu``.  The expressions are printed by
SymPy's code printers (``ccode``, ``pycode``, ``julia_code``, ``octave_code``) after common
subexpressions are eliminated once over all of them (``sympy.cse``).  The C file solves the
system by its own dense LU factorization with partial pivoting (no library beyond
``<math.h>``); the Python file uses NumPy's ``solve``, Julia and MATLAB their ``\\``.  Like
PyDy's generated ODE functions (Gede et al. 2013), the file's header documents the order of
the state and of the parameters, with the model's values as defaults.

What is not generated: the events.  A contact is in the state the equations were derived
with for the whole call -- touching and sticking, sliding (its friction ``-mu N s`` in ``B``
with the direction ``s`` of that mode) or separated (no row) -- and a unilateral constraint
is held; the file says which.  Integrate it only while that mode lasts (its multipliers say
when a normal force turns negative; the library's ``simulate`` switches modes).
"""

from __future__ import annotations

import re

import sympy as sp

from ..errors import ModelError

__all__ = ["LANGUAGES", "generate"]

#: language -> file suffix
LANGUAGES = {"c": ".c", "python": ".py", "julia": ".jl", "matlab": ".m"}


def generate(eom, language: str, name: str | None = None, mode: str = "") -> str:
    """The source of the right-hand side of *eom* in *language*.

    Parameters
    ----------
    eom : EquationsOfMotion
        Any form without auxiliary linear systems (Lagrange I, Lagrange II, Maggi, Appell;
        Shulgin's large systems define auxiliaries and are refused).
    language : {"c", "python", "julia", "matlab"}
    name : str, optional
        The function's name (a C, Julia or MATLAB identifier); default: ``rhs_<model>``.  A
        MATLAB function must be saved as ``<name>.m``.
    mode : str, optional
        A line describing the mode (the contacts' states), written in the header.

    Returns
    -------
    str

    Examples
    --------
    >>> import nonideal
    >>> pend = nonideal.Model("pendulum", ["phi"], parameters={"g": 9.81, "l": 1.0},
    ...     kinetic="l**2*phi'**2/2", potential="-g*l*cos(phi)")
    >>> src = generate(nonideal.derive(pend), "c")
    >>> [line for line in src.splitlines() if line.startswith(" *   y[")]
    [' *   y[0] = phi', " *   y[1] = phi'"]
    """
    if language not in LANGUAGES:
        raise ModelError(f"--code {language!r}: unknown; use one of {', '.join(LANGUAGES)}")
    if eom.auxiliaries:
        raise ModelError(f"--code: the form {eom.form} defines auxiliary symbols solved as linear "
                         "systems at each evaluation; generate code from --form lagrange1")
    model = eom.model
    name = name or "rhs_" + _identifier(model.name)
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        raise ModelError(f"--code: {name!r} is not a function name (letters, digits and _, "
                         "not starting with a digit)")
    if language == "matlab" and not name[0].isalpha():
        raise ModelError(f"--code matlab: {name!r} must start with a letter")
    system = _System(eom)
    return {"c": _c, "python": _python, "julia": _julia, "matlab": _matlab}[language](system, name, mode)


class _System:
    """The expressions of the saddle-point system, with the symbols renamed for printing."""

    def __init__(self, eom):
        self.eom = eom
        model = eom.model
        self.coordinates = tuple(model.coordinates)
        self.parameters = dict(model.parameter_values)
        self.units = {k: p.unit for k, p in model.parameters.items()}
        self.n, self.k, self.m = len(self.coordinates), eom.k, len(eom.multipliers)
        A, Qf, c = eom.mass_matrix, eom.generalized_forces, eom.inertial_terms
        B, G, gamma = eom.reaction_matrix, eom.constraint_jacobian, eom.constraint_bias
        R, r = eom.acceleration_map
        self.blocks = {"A": A, "b": Qf - c, "B": B, "G": G, "gamma": gamma, "R": R, "r": r}
        known = {"t"} | set(self.coordinates) | {c + "'" for c in self.coordinates} | set(self.parameters)
        free = set()
        for block in self.blocks.values():
            free |= {s.name for s in block.free_symbols}
        unknown = sorted(free - known)
        if unknown:
            raise ModelError(f"--code: the equations of {model.name} contain {', '.join(unknown)}, "
                             "which is neither a coordinate, a velocity, a parameter nor t; "
                             "generate code from --form lagrange1")

    def printed(self, base: int, call: str = "[]"):
        """``(temporaries, blocks)``: the common subexpressions and every entry, with the
        coordinates as ``q[i]``, the velocities ``u[i]`` and the parameters ``p[i]`` (``base``:
        the first index, ``call``: the brackets)."""
        o, c = call
        rename = {sp.Symbol(x): sp.Symbol(f"q{o}{i + base}{c}") for i, x in enumerate(self.coordinates)}
        rename.update({sp.Symbol(x + "'"): sp.Symbol(f"u{o}{i + base}{c}")
                       for i, x in enumerate(self.coordinates)})
        rename.update({sp.Symbol(x): sp.Symbol(f"p{o}{i + base}{c}") for i, x in enumerate(self.parameters)})
        entries, where = [], []
        for key, block in self.blocks.items():
            for i in range(block.shape[0]):
                for j in range(block.shape[1]):
                    e = block[i, j]
                    if e != 0:
                        entries.append(e.xreplace(rename))
                        where.append((key, i, j))
        temps, reduced = sp.cse(entries, symbols=sp.numbered_symbols("w"), order="none")
        filled = {key: {} for key in self.blocks}
        for (key, i, j), e in zip(where, reduced):
            filled[key][(i, j)] = e
        return temps, filled

    def header(self, comment: str, mode: str, language: str, usage: list[str]) -> str:
        eom, model = self.eom, self.eom.model
        width = max([len(x) for x in self.parameters] + [1])
        lines = [
            f"{model.name}: the right-hand side of its equations of motion",
            f"generated by nonideal {_version()} (derive --code {language}); form {eom.form} "
            f"({eom.title}, {eom.citation})",
            "",
            "Equations (one mode, solved as a saddle-point system at each call):",
            "    A a + c = Q_f + B mu,   G a + gamma = 0,   q'' = R a + r",
            f"  unknowns a ({self.k}): {', '.join(eom.unknowns)}",
            f"  multipliers mu ({self.m}): {', '.join(eom.multipliers) or '(none)'}"
            + (f"  -- rows {', '.join(eom.constraint_names)}" if self.m else ""),
        ]
        if mode:
            lines.append(f"  mode: {mode}")
        for note in eom.notes:
            lines.append(f"  note: {note}")
        lines += [
            "  No events: contacts stay in this mode and unilateral constraints are held; the",
            "  multipliers say when a normal force turns negative (then the mode has ended).",
            "",
            f"State y ({2 * self.n}), in this order:",
        ]
        lines += [f"  y[{i}] = {x}" for i, x in enumerate(self.coordinates)]
        lines += [f"  y[{self.n + i}] = {x}'" for i, x in enumerate(self.coordinates)]
        lines += ["dy/dt = (q', q'')  (same order)", "",
                  f"Parameters p ({len(self.parameters)}), in this order, with the model's values:"]
        for i, (k, v) in enumerate(self.parameters.items()):
            unit = f" [{self.units[k]}]" if self.units.get(k) else ""
            lines.append(f"  p[{i}] = {k:<{width}} = {v!r}{unit}")
        lines += ["(indices from 0 here; Julia and MATLAB count from 1)", ""] + usage
        return "\n".join(f"{comment} {line}".rstrip() for line in lines) + "\n"


def _times(factor: str, value: str) -> str:
    return value if factor in ("1", "1.0") else f"({factor})*{value}"


def _version() -> str:
    from .. import __version__

    return __version__


def _identifier(text: str) -> str:
    out = re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_").lower()
    return out if out and not out[0].isdigit() else "model_" + out


# --------------------------------------------------------------------------- C

_LU_C = """
/* Solve K x = b (K dense, N x N, row-major) by LU with partial pivoting; K and b are
   overwritten, x is returned in b.  Returns 0, or 1 when a pivot is below 1e-14 of the
   largest entry of K (the mode's system is singular). */
static int nonideal_solve(int N, double *K, double *b)
{
    double scale = 0.0;
    for (int i = 0; i < N * N; ++i) if (fabs(K[i]) > scale) scale = fabs(K[i]);
    for (int c = 0; c < N; ++c) {
        int piv = c;
        for (int i = c + 1; i < N; ++i) if (fabs(K[i * N + c]) > fabs(K[piv * N + c])) piv = i;
        if (!(fabs(K[piv * N + c]) > 1e-14 * scale)) return 1;
        if (piv != c) {
            for (int j = 0; j < N; ++j) { double s = K[c * N + j]; K[c * N + j] = K[piv * N + j]; K[piv * N + j] = s; }
            double s = b[c]; b[c] = b[piv]; b[piv] = s;
        }
        for (int i = c + 1; i < N; ++i) {
            double f = K[i * N + c] / K[c * N + c];
            if (f == 0.0) continue;
            for (int j = c + 1; j < N; ++j) K[i * N + j] -= f * K[c * N + j];
            b[i] -= f * b[c];
        }
    }
    for (int i = N - 1; i >= 0; --i) {
        double s = b[i];
        for (int j = i + 1; j < N; ++j) s -= K[i * N + j] * b[j];
        b[i] = s / K[i * N + i];
    }
    return 0;
}
"""


def _c(system: _System, name: str, mode: str) -> str:
    n, k, m = system.n, system.k, system.m
    N = k + m
    temps, e = system.printed(0)

    def code(x):
        return sp.ccode(x, standard="C99")

    body = [f"    const double *q = y, *u = y + {n};", "    (void)t; (void)q; (void)u; (void)p; (void)mu;"]
    body += [f"    const double {code(s)} = {code(x)};" for s, x in temps]
    body += [f"    double K[{N * N}] = {{0}}, b[{N}] = {{0}};"]
    body += [f"    K[{i * N + j}] = {code(x)};" for (i, j), x in e["A"].items()]
    body += [f"    K[{i * N + k + j}] = -({code(x)});" for (i, j), x in e["B"].items()]
    body += [f"    K[{(k + i) * N + j}] = {code(x)};" for (i, j), x in e["G"].items()]
    body += [f"    b[{i}] = {code(x)};" for (i, _), x in e["b"].items()]
    body += [f"    b[{k + i}] = -({code(x)});" for (i, _), x in e["gamma"].items()]
    body += [f"    if (nonideal_solve({N}, K, b)) return 1;"]
    body += [f"    dydt[{i}] = u[{i}];" for i in range(n)]
    for i in range(n):
        terms = [_times(code(x), f"b[{j}]") for (r, j), x in e["R"].items() if r == i]
        terms += [f"({code(x)})" for (r, _), x in e["r"].items() if r == i]
        body.append(f"    dydt[{n + i}] = {' + '.join(terms) or '0.0'};")
    if m:
        body += [f"    if (mu) for (int j = 0; j < {m}; ++j) mu[j] = b[{k} + j];"]
    body += ["    return 0;"]
    defaults = ", ".join(repr(float(v)) for v in system.parameters.values()) or "0.0"
    usage = [
        "Usage (C99, only <math.h>; cc -O2 -c file.c):",
        f"  int {name}(double t, const double y[{2 * n}], const double p[{max(len(system.parameters), 1)}],",
        f"             double dydt[{2 * n}], double mu[{max(m, 1)}]);  (mu may be NULL)",
        "  returns 0, or 1 when the mode's saddle-point system is singular at this state.",
        f"  {name}_parameters[] holds the model's parameter values (the order above).",
    ]
    return ("/*\n" + system.header(" *", mode, "c", usage).replace("*/", "* /") + " */\n#include <math.h>\n\n"
            f"const double {name}_parameters[{max(len(system.parameters), 1)}] = {{{defaults}}};\n"
            + _LU_C + f"\nint {name}(double t, const double *y, const double *p, double *dydt, double *mu)\n{{\n"
            + "\n".join(body) + "\n}\n")


# --------------------------------------------------------------------------- Python

def _python(system: _System, name: str, mode: str) -> str:
    n, k, m = system.n, system.k, system.m
    N = k + m
    temps, e = system.printed(0)

    def code(x):
        return sp.pycode(x, fully_qualified_modules=True)

    body = [f"    q, u = y[:{n}], y[{n}:{2 * n}]"]
    body += [f"    {code(s)} = {code(x)}" for s, x in temps]
    body += [f"    K = numpy.zeros(({N}, {N}))", f"    b = numpy.zeros({N})"]
    body += [f"    K[{i}, {j}] = {code(x)}" for (i, j), x in e["A"].items()]
    body += [f"    K[{i}, {k + j}] = -({code(x)})" for (i, j), x in e["B"].items()]
    body += [f"    K[{k + i}, {j}] = {code(x)}" for (i, j), x in e["G"].items()]
    body += [f"    b[{i}] = {code(x)}" for (i, _), x in e["b"].items()]
    body += [f"    b[{k + i}] = -({code(x)})" for (i, _), x in e["gamma"].items()]
    body += ["    x = numpy.linalg.solve(K, b)", f"    qdd = numpy.zeros({n})"]
    for i in range(n):
        terms = [_times(code(x), f"x[{j}]") for (r, j), x in e["R"].items() if r == i]
        terms += [f"({code(x)})" for (r, _), x in e["r"].items() if r == i]
        if terms:
            body.append(f"    qdd[{i}] = {' + '.join(terms)}")
    body += [f"    return qdd, x[{k}:]"]
    usage = [
        "Usage (needs NumPy):",
        f"  {name}(t, y, p=PARAMETERS) -> dy/dt, ndarray ({2 * n},), e.g. for",
        f"  scipy.integrate.solve_ivp({name}, (t0, t1), y0, args=(p,))",
        f"  {name}_solve(t, y, p) -> (q'', mu); numpy.linalg.LinAlgError when the mode's",
        "  saddle-point system is singular at this state.",
    ]
    params = ", ".join(repr(float(v)) for v in system.parameters.values())
    return ('"""\n' + system.header("", mode, "python", usage).replace('"""', "'''") + '"""\n\n'
            "import math\n\nimport numpy\n\n"
            f"COORDINATES = {system.coordinates!r}\n"
            f"PARAMETER_NAMES = {tuple(system.parameters)!r}\n"
            f"PARAMETERS = numpy.array([{params}], dtype=float)\n"
            f"MULTIPLIERS = {tuple(system.eom.multipliers)!r}\n\n\n"
            f"def {name}_solve(t, y, p=PARAMETERS):\n"
            '    """The accelerations q\'\' and the multipliers mu at (t, y)."""\n'
            "    y = numpy.asarray(y, dtype=float)\n"
            + "\n".join(body) + "\n\n\n"
            f"def {name}(t, y, p=PARAMETERS):\n"
            '    """dy/dt = (q\', q\'\') at (t, y)."""\n'
            f"    qdd, _ = {name}_solve(t, y, p)\n"
            f"    return numpy.concatenate((numpy.asarray(y, dtype=float)[{n}:{2 * n}], qdd))\n")


# --------------------------------------------------------------------------- Julia, MATLAB

def _julia(system: _System, name: str, mode: str) -> str:
    n, k, m = system.n, system.k, system.m
    N = k + m
    temps, e = system.printed(1)

    def code(x):
        return sp.julia_code(x)

    body = [f"    q = @view y[1:{n}]", f"    u = @view y[{n + 1}:{2 * n}]"]
    body += [f"    {code(s)} = {code(x)}" for s, x in temps]
    body += [f"    K = zeros({N}, {N})", f"    b = zeros({N})"]
    body += [f"    K[{i + 1}, {j + 1}] = {code(x)}" for (i, j), x in e["A"].items()]
    body += [f"    K[{i + 1}, {k + j + 1}] = -({code(x)})" for (i, j), x in e["B"].items()]
    body += [f"    K[{k + i + 1}, {j + 1}] = {code(x)}" for (i, j), x in e["G"].items()]
    body += [f"    b[{i + 1}] = {code(x)}" for (i, _), x in e["b"].items()]
    body += [f"    b[{k + i + 1}] = -({code(x)})" for (i, _), x in e["gamma"].items()]
    body += ["    x = K \\ b"]
    body += [f"    dydt[{i + 1}] = u[{i + 1}]" for i in range(n)]
    for i in range(n):
        terms = [_times(code(x), f"x[{j + 1}]") for (r, j), x in e["R"].items() if r == i]
        terms += [f"({code(x)})" for (r, _), x in e["r"].items() if r == i]
        body.append(f"    dydt[{n + i + 1}] = {' + '.join(terms) or '0.0'}")
    body += [f"    return x[{k + 1}:end]"]
    usage = [
        "Usage (Julia, no packages):",
        f"  {name}!(dydt, y, p, t) fills dy/dt and returns the multipliers mu (the in-place",
        "  signature of DifferentialEquations.jl's ODEProblem).",
    ]
    params = ", ".join(repr(float(v)) for v in system.parameters.values())
    return ("#=\n" + system.header("", mode, "julia", usage).replace("=#", "= #") + "=#\n\n"
            f"const {name.upper()}_PARAMETERS = Float64[{params}]\n\n"
            f"function {name}!(dydt, y, p, t)\n" + "\n".join(body) + "\nend\n")


def _matlab(system: _System, name: str, mode: str) -> str:
    n, k, m = system.n, system.k, system.m
    N = k + m
    temps, e = system.printed(1, "()")

    def code(x):
        return sp.octave_code(x)

    body = [f"  q = y(1:{n});", f"  u = y({n + 1}:{2 * n});"]
    body += [f"  {code(s)} = {code(x)};" for s, x in temps]
    body += [f"  K = zeros({N}, {N});", f"  b = zeros({N}, 1);"]
    body += [f"  K({i + 1}, {j + 1}) = {code(x)};" for (i, j), x in e["A"].items()]
    body += [f"  K({i + 1}, {k + j + 1}) = -({code(x)});" for (i, j), x in e["B"].items()]
    body += [f"  K({k + i + 1}, {j + 1}) = {code(x)};" for (i, j), x in e["G"].items()]
    body += [f"  b({i + 1}) = {code(x)};" for (i, _), x in e["b"].items()]
    body += [f"  b({k + i + 1}) = -({code(x)});" for (i, _), x in e["gamma"].items()]
    body += ["  x = K \\ b;", f"  dydt = zeros({2 * n}, 1);"]
    body += [f"  dydt({i + 1}) = u({i + 1});" for i in range(n)]
    for i in range(n):
        terms = [_times(code(x), f"x({j + 1})") for (r, j), x in e["R"].items() if r == i]
        terms += [f"({code(x)})" for (r, _), x in e["r"].items() if r == i]
        body.append(f"  dydt({n + i + 1}) = {' + '.join(terms) or '0'};")
    body += [f"  mu = x({k + 1}:end);"]
    params = "; ".join(repr(float(v)) for v in system.parameters.values())
    usage = [
        f"Usage (MATLAB or GNU Octave; save as {name}.m):",
        f"  [dydt, mu] = {name}(t, y, p)   -- p defaults to the model's values;",
        f"  ode45(@(t, y) {name}(t, y), [t0 t1], y0)",
    ]
    return (f"function [dydt, mu] = {name}(t, y, p)\n" + system.header("%", mode, "matlab", usage)
            + f"  if nargin < 3\n    p = [{params}];\n  end\n" + "\n".join(body) + "\nend\n")
