"""Linearizing the benchmark bicycle: nonideal (from its model file) vs sympy.physics.mechanics.

    python benchmarks/bench_bicycle_linearize.py [--quick] [--repeat 3]

The Whipple bicycle with the parameters of Meijaard et al. (2007), linearized about upright
straight running, on both sides from nothing but the description of the system:

* ours, two routes from ``load_model(benchmark_bicycle.toml)`` (parsing, bodies -> kinetic
  energy, constraint rows):
  - "linearize": the stability analysis, ``linearize(model, about="steady", at=...)`` at each
    speed v = 0..10 (the Jacobians of the implicit motion compiled once per model, the state
    reduced on the constraint manifold, Newton's check of the steady state, eigenvalues and
    the Hurwitz analysis included), the roll/steer block of A;
  - "differences": ``nonideal.gallery.benchmark_bicycle.linear_matrices`` (M from the input
    torques, K(v) and C1 by fourth-order central differences of the library's accelerations
    at consistent states near the steady motion), from which A(v) follows at every speed;
* the peer: the same bicycle built with ``sympy.physics.mechanics`` (frames, points,
  ``v2pt_theory``, rigid bodies; yaw, roll, pitch and steer coordinates with the pitch
  dependent through the front contact's height, six generalized speeds of which the yaw rate,
  the pitch rate and the front wheel rate are dependent through the three components of the
  front contact's velocity), ``KanesMethod.kanes_equations`` and ``KanesMethod.linearize``
  about the upright motion with the speed v kept as a symbol (as sympy's own bicycle test
  does), then the numbers substituted: A(v) symbolic in v.

Both give the 4 x 4 state matrix of (phi, delta, phi', delta'); they are compared at
v = 0..10 m/s (max |A_ours - A_peer|) and with the eigenvalues of Meijaard et al.'s Table 2.
Timings: wall clock, SymPy's cache and our per-model caches cleared before every run, best of
``--repeat`` runs for ours (``--quick``: one), one run for the peer, which takes minutes
(5-20 on the shared 2-core machine).  The ratios ours/peer are printed (< 1: ours faster; the
goal is <= 0.1) and the JSON goes to ``benchmarks/results/bicycle_linearize[-quick].json``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # this checkout's nonideal, not an installed copy

import _common as C  # noqa: E402

SPEEDS = list(range(11))


# ----------------------------------------------------------------------------- ours


def ours_linearize() -> dict:
    from nonideal import gallery
    from nonideal.gallery import benchmark_bicycle as bb

    model = gallery.load(bb.NAME)
    out = {}
    for v in SPEEDS:
        lin = bb.linearization(model, v, controls=())
        i = [lin.variables.index(n) for n in ("phi", "delta", "phi'", "delta'")]
        out[v] = lin.A[np.ix_(i, i)]
    return out


def ours_differences() -> dict:
    from nonideal import gallery
    from nonideal.gallery import benchmark_bicycle as bb

    model = gallery.load(bb.NAME)
    mats = bb.linear_matrices(model)
    return {v: bb.state_matrix(mats, v) for v in SPEEDS}


# ----------------------------------------------------------------------------- the peer


def peer() -> dict:
    """The bicycle with KanesMethod + linearize; A(v) at the speeds of SPEEDS."""
    import sympy as sp
    import sympy.physics.mechanics as me

    yaw, roll, pitch, steer = me.dynamicsymbols("yaw roll pitch steer")
    u_yaw, u_roll, u_pitch, u_steer, u_R, u_F = me.dynamicsymbols("u_yaw u_roll u_pitch u_steer u_R u_F")
    names = ("w c lam g rR mR IRxx IRyy xB zB mB IBxx IByy IBzz IBxz xH zH mH IHxx IHyy IHzz IHxz "
             "rF mF IFxx IFyy").split()
    p = dict(zip(names, sp.symbols(names)))
    v = sp.Symbol("v")

    N = me.ReferenceFrame("N")                                  # x forward, y right, z down
    Y = N.orientnew("Y", "Axis", (yaw, N.z))
    R = Y.orientnew("R", "Axis", (roll, Y.x))
    B = R.orientnew("B", "Axis", (pitch, R.y))                  # rear frame
    S = B.orientnew("S", "Axis", (p["lam"], B.y))               # steer-axis frame
    H1 = S.orientnew("H1", "Axis", (steer, S.z))
    H = H1.orientnew("H", "Axis", (-p["lam"], H1.y))            # front frame, = B at steer 0
    WR = me.ReferenceFrame("WR")                                # wheels: only their rates matter
    WF = me.ReferenceFrame("WF")
    Y.set_ang_vel(N, u_yaw * N.z)
    R.set_ang_vel(Y, u_roll * Y.x)
    B.set_ang_vel(R, u_pitch * R.y)
    H1.set_ang_vel(S, u_steer * S.z)
    WR.set_ang_vel(N, u_yaw * N.z + u_roll * Y.x + u_R * R.y)   # spin in the heading/lean frame
    WF.set_ang_vel(H, u_F * H.y)

    P = me.Point("P")                                           # rear contact: at rest (rolling)
    P.set_vel(N, 0)
    CR = P.locatenew("CR", -p["rR"] * R.z)
    CR.v2pt_theory(P, N, WR)
    Bo = CR.locatenew("Bo", p["xB"] * B.x + (p["zB"] + p["rR"]) * B.z)
    Bo.v2pt_theory(CR, N, B)
    Sg = CR.locatenew("Sg", (p["w"] + p["c"]) * B.x + p["rR"] * B.z)   # steer axis at the ground
    Sg.v2pt_theory(CR, N, B)
    Ho = Sg.locatenew("Ho", (p["xH"] - p["w"] - p["c"]) * H.x + p["zH"] * H.z)
    Ho.v2pt_theory(Sg, N, H)
    CF = Sg.locatenew("CF", -p["c"] * H.x - p["rF"] * H.z)
    CF.v2pt_theory(Sg, N, H)
    down = (N.z - me.dot(N.z, H.y) * H.y).normalize()            # in the wheel plane, downwards
    PF = CF.locatenew("PF", p["rF"] * down)                      # front contact
    PF.v2pt_theory(CF, N, WF)

    bodies = [
        me.RigidBody("WRb", CR, WR, p["mR"], (me.inertia(R, p["IRxx"], p["IRyy"], p["IRxx"]), CR)),
        me.RigidBody("Bb", Bo, B, p["mB"],
                     (me.inertia(B, p["IBxx"], p["IByy"], p["IBzz"], 0, 0, p["IBxz"]), Bo)),
        me.RigidBody("Hb", Ho, H, p["mH"],
                     (me.inertia(H, p["IHxx"], p["IHyy"], p["IHzz"], 0, 0, p["IHxz"]), Ho)),
        me.RigidBody("WFb", CF, WF, p["mF"], (me.inertia(H, p["IFxx"], p["IFyy"], p["IFxx"]), CF)),
    ]
    loads = [(pt, m * p["g"] * N.z) for pt, m in ((CR, p["mR"]), (Bo, p["mB"]), (Ho, p["mH"]),
                                                   (CF, p["mF"]))]
    kd = [yaw.diff() - u_yaw, roll.diff() - u_roll, pitch.diff() - u_pitch, steer.diff() - u_steer]
    vel = PF.vel(N)
    KM = me.KanesMethod(
        N, q_ind=[yaw, roll, steer], q_dependent=[pitch],
        configuration_constraints=[me.dot(PF.pos_from(P), N.z)],
        u_ind=[u_roll, u_R, u_steer], u_dependent=[u_yaw, u_pitch, u_F],
        velocity_constraints=[me.dot(vel, Y.x), me.dot(vel, Y.y), me.dot(vel, N.z)],
        kd_eqs=kd, constraint_solver="CRAMER")
    KM.kanes_equations(bodies, loads)
    op = {yaw: 0, roll: 0, pitch: 0, steer: 0, u_yaw: 0, u_roll: 0, u_pitch: 0, u_steer: 0,
          u_R: -v / p["rR"], u_F: -v / p["rF"]}
    op.update({u.diff(): 0 for u in (u_yaw, u_roll, u_pitch, u_steer, u_R, u_F)})
    A, _, _ = KM.linearize(A_and_B=True, op_point=op, linear_solver="CRAMER")
    values = {p[k]: val for k, val in _benchmark_values().items()}
    A = A.xreplace(values)
    # A acts on the independent states (yaw, roll, steer, u_roll, u_R, u_steer)
    keep = [1, 2, 3, 5]                                          # roll, steer, roll rate, steer rate
    A4 = A.extract(keep, keep)
    f = sp.lambdify(v, A4, "numpy")
    return {s: np.array(f(float(s)), dtype=float) for s in SPEEDS}


def _benchmark_values() -> dict:
    from nonideal.gallery.benchmark_bicycle import PARAMETERS

    out = {k: val for k, val in PARAMETERS.items() if k not in ("v", "Tphi", "Tdelta")}
    out["lam"] = np.pi / 10
    return out


# ----------------------------------------------------------------------------- main


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="one run of each side")
    ap.add_argument("--repeat", type=int, default=3, help="runs of ours (best kept)")
    args = ap.parse_args(argv)
    from nonideal.gallery.benchmark_bicycle import TABLE2

    info = C.machine()
    t_start = time.perf_counter()
    repeat = 1 if args.quick else args.repeat
    t_lin, A_lin = C.best_of(ours_linearize, repeat)
    t_fd, A_fd = C.best_of(ours_differences, repeat)
    t_peer, A_peer = C.best_of(peer, 1)

    def eig_error(A):
        return max(float(np.max(np.abs(np.sort_complex(np.linalg.eigvals(A[v]))
                                       - np.sort_complex(TABLE2[v])) / np.maximum(1.0, np.abs(TABLE2[v]))))
                   for v in SPEEDS)

    def diff(A):
        return max(float(np.max(np.abs(A[v] - A_peer[v]))) for v in SPEEDS)
    rows = [["nonideal: load model file + linearize (about='steady') at v = 0..10", C.fmt_t(t_lin),
             f"{t_lin / t_peer:.4f}", f"{diff(A_lin):.1e}", f"{eig_error(A_lin):.1e}"],
            ["nonideal: load model file + linear_matrices (differences)", C.fmt_t(t_fd),
             f"{t_fd / t_peer:.4f}", f"{diff(A_fd):.1e}", f"{eig_error(A_fd):.1e}"],
            ["sympy: KanesMethod + kanes_equations + linearize + constants", C.fmt_t(t_peer), "1",
             "0", f"{eig_error(A_peer):.1e}"]]
    print(C.table(["benchmark bicycle, linearization", "time", "ratio to sympy",
                   "max |A - A_sympy|, v = 0..10", "eigenvalues vs Table 2 (rel.)"], rows))
    for name, t in (("linearize", t_lin), ("differences", t_fd)):
        ratio = t / t_peer
        print(f"{name}: ours/peer = {ratio:.4f} ({1 / ratio:.0f}x faster; goal >= 10x: "
              f"{'met' if ratio <= 0.1 else 'missed'})")
    info["loadavg_at_end"] = list(__import__("os").getloadavg())
    data = {"machine": info, "elapsed": time.perf_counter() - t_start, "t_linearize": t_lin,
            "t_differences": t_fd, "t_peer": t_peer, "ratio_linearize": t_lin / t_peer,
            "ratio_differences": t_fd / t_peer, "A_difference_linearize": diff(A_lin),
            "A_difference_differences": diff(A_fd), "eigenvalue_error_linearize": eig_error(A_lin),
            "eigenvalue_error_differences": eig_error(A_fd), "eigenvalue_error_peer": eig_error(A_peer)}
    print("written:", C.write_json("bicycle_linearize", data, args.quick))
    return data


if __name__ == "__main__":
    main()
