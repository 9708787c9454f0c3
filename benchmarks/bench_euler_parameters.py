"""Simulation in Euler parameters vs Euler angles: the heavy symmetric top, side by side.

    python benchmarks/bench_euler_parameters.py [--repeat 5]

The same motion of the top of the gallery (``heavy-symmetric-top``, Z-X-Z Euler angles, and
``heavy-top-euler-parameters``, the quaternion frame, |e| kept by the library with no
constraint), started away from the gimbal lock at theta = 0.6 rad with nutation, simulated for 3 s at
rtol 1e-10, atol 1e-12 (DOP853) in one process.  Reported: the wall time of each (warm: the
kernels compiled; and cold: from a fresh model, derivation and compilation included) and the
ratio parameters / angles (goal: no slower, ratio <= 1), with the final symmetry axes compared.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # this checkout's nonideal

import _common as C  # noqa: E402

from nonideal import gallery  # noqa: E402
from nonideal.gallery.heavy_top_euler_parameters import rotation  # noqa: E402
from nonideal.simulation import simulate  # noqa: E402

T_END = 3.0
START = {"psi": 0.3, "theta": 0.6, "phi": 0.0, "psi'": 1.0, "theta'": 0.5, "phi'": 60.0}


def quaternion_start(s: dict) -> dict:
    """Euler parameters of the Z-X-Z angles and their rates (q = qz(psi) qx(theta) qz(phi))."""
    def qz(a):
        return np.array([np.cos(a / 2), 0, 0, np.sin(a / 2)])

    def qx(a):
        return np.array([np.cos(a / 2), np.sin(a / 2), 0, 0])

    def mul(p, q):
        return np.concatenate([[p[0] * q[0] - p[1:] @ q[1:]], p[0] * q[1:] + q[0] * p[1:] + np.cross(p[1:], q[1:])])
    ps, th, ph = s["psi"], s["theta"], s["phi"]
    e = mul(mul(qz(ps), qx(th)), qz(ph))
    w = np.array([s["psi'"] * np.sin(th) * np.sin(ph) + s["theta'"] * np.cos(ph),
                  s["psi'"] * np.sin(th) * np.cos(ph) - s["theta'"] * np.sin(ph),
                  s["psi'"] * np.cos(th) + s["phi'"]])
    ed = 0.5 * mul(e, np.concatenate([[0.0], w]))        # e' = e (0, w_body) / 2
    out = {f"e{i}": float(e[i]) for i in range(4)}
    out.update({f"e{i}'": float(ed[i]) for i in range(4)})
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    angles = gallery.load("heavy-symmetric-top").replace(initial=START)
    params = gallery.load("heavy-top-euler-parameters")
    params = params.replace(initial=quaternion_start(START))
    rows, finals = {}, {}
    for label, model in (("Euler angles", angles), ("Euler parameters", params)):
        cold, _ = C.best_of(lambda m=model: simulate(m.replace(), t_end=T_END), repeat=1)
        simulate(model, t_end=T_END)
        warm, traj = C.best_of(lambda m=model: simulate(m, t_end=T_END), repeat=args.repeat, clear=False)
        rows[label] = (warm, cold, len(traj.t))
        if label == "Euler angles":
            ps, th = traj.at("psi"), traj.at("theta")
            finals[label] = np.array([np.sin(th) * np.sin(ps), -np.sin(th) * np.cos(ps), np.cos(th)])
        else:
            finals[label] = rotation([traj.at(f"e{i}") for i in range(4)])[:, 2]
    print(f"heavy symmetric top, {T_END} s, rtol 1e-10 (DOP853)")
    print("| coordinates | simulate (warm) s | simulate (cold) s | samples |")
    print("|---|---|---|---|")
    for label, (warm, cold, n) in rows.items():
        print(f"| {label} | {warm:.3f} | {cold:.3f} | {n} |")
    ratio = rows["Euler parameters"][0] / rows["Euler angles"][0]
    print(f"ratio parameters/angles (warm): {ratio:.2f}; cold: "
          f"{rows['Euler parameters'][1] / rows['Euler angles'][1]:.2f}")
    print(f"final symmetry axes differ by {np.max(np.abs(finals['Euler angles'] - finals['Euler parameters'])):.1e}")
    C.write_json("euler_parameters", {"rows": {k: list(v) for k, v in rows.items()}, "ratio_warm": ratio}, quick=False)


if __name__ == "__main__":
    main()
