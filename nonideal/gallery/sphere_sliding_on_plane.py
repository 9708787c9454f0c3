"""A homogeneous sphere launched sliding on a rough plane: sliding, then pure rolling.

Source: the classical problem of the billiard ball (Coriolis, *Theorie mathematique des effets
du jeu de billard*, 1835; Routh, *Dynamics of a System of Rigid Bodies*, elementary part; any
textbook, e.g. Kleppner & Kolenkow, ch. 7).  It is the benchmark of the friction code (the
library's event time and final velocity agree with the closed form to round-off; see
``benchmarks/``).  The closed form is derived here.

Model.  A homogeneous sphere (mass m, radius R, central moment of inertia I = 2 m R^2 / 5) on
the horizontal plane z = 0, gravity -g e_z.  Coordinates: the centre (x, y, z) and three
"rotation pseudo-coordinates" a, b, c whose derivatives are the components of the angular
velocity in the FIXED axes, omega = (a', b', c'):

    T = m (x'^2 + y'^2 + z'^2) / 2 + I (a'^2 + b'^2 + c'^2) / 2,      V = m g z.

Why a, b, c are legitimate.  In general the components of omega are not the derivatives of
any coordinates (they are quasi-velocities: the rotation is not integrable), and Lagrange's
equations in them would miss the Boltzmann--Hamel terms ``gamma omega . dT/domega``, which for
fixed-axis components are ``omega x dT/domega``.  For a homogeneous sphere the inertia tensor
is ``I E`` (isotropic): T depends on omega only through ``|omega|^2`` whatever the orientation,
so ``dT/domega = I omega`` and ``omega x I omega = 0`` -- the extra terms vanish; nothing
depends on the orientation (T, V, the gap ``z - R``, the slip below, the forces), so
``dT/d(pi) = 0`` for the pseudo-coordinates pi = (a, b, c); and the virtual work of a torque
``M`` on a virtual rotation ``delta pi`` is ``M . delta pi``, so the generalized forces are
the torque components.  The equations in (a, b, c) are therefore exactly Euler's equations
``I omega' = M`` of the sphere, and a, b, c are mere integrals of omega (not angles: the
orientation itself is not tracked, and is not needed).

Contact ``plane``: gap ``z - R`` (height of the lowest point, multiplier N = normal force),
slip = velocity of the contact point ``P = C - R e_z``,

    U = v + omega x (-R e_z) = (x' - R b',  y' + R a'),

isotropic Coulomb friction ``F = -mu N U/|U|`` in the plane (two components).

Closed form.  While sliding, N = m g and with s = U/|U|, F = -mu m g s:

    v' = -mu g s,      I omega' = (-R e_z) x F   =>   omega' = (5 mu g / (2 R)) (-s_y, s_x, 0),
    U' = v' + omega' x (-R e_z) = -mu g s - (5/2) mu g s = -(7/2) mu g s.

So the slip keeps its direction s = U0/|U0| and its magnitude decreases linearly,
``|U|(t) = |U0| - (7/2) mu g t``: pure rolling starts at

    t* = 2 |U0| / (7 mu g),

after which (U = 0 is consistent with F = 0: sticking needs no friction) the sphere rolls
uniformly.  The final velocity is

    v_f = v0 - mu g s t* = v0 - (2/7) U0,       omega_f = omega0 + (5/(7 R)) (-U0_y, U0_x, 0),

(checked: ``v_f - R omega_f,y = v0x - R omega0y - (2/7) U0x - (5/7) U0x = 0`` and likewise for
y).  The spin about the vertical ``c'`` never changes (point contact: no drilling friction).
The centre moves on a parabola while sliding (constant acceleration along -s, not along v0),
then on a straight line.  Independent check: the angular momentum about the contact point,
``L_P = I omega + m R e_z x v``, is conserved (friction and N act at P, gravity's moment about P
vanishes, and P moves parallel to v), which gives the same v_f.  Energy: friction does
``W_f = -mu m g int |U| dt = -mu m g |U0| t*/2 = -m |U0|^2 / 7``, the kinetic energy lost.

One slip component.  Launched along x with spin about y only (U0 along x), the motion stays in
the plane y = 0: the same formulas, with the planar model (x, z, b; one slip ``x' - R b'``) as a
second check of the one-component code path.  With strong backspin (U0 > (7/2) v0) the ball
comes back: v_f = v0 - (2/7) U0 < 0 (the "draw shot").
"""

from __future__ import annotations

import numpy as np

from ..modeling.contacts import Contact, Coulomb
from ..modeling.model import Model

NAME = "sphere-sliding-on-plane"
ORDER = 41
TITLE = ("Sphere launched sliding on a rough plane: rolling from t* = 2|U0|/(7 mu g), v_f = v0 - "
         "(2/7) U0")
FILE = "sphere_sliding_on_plane.toml"

V0 = (2.0, 1.0)
OMEGA0 = (3.0, -5.0, 4.0)


def build(m: float = 1.0, R: float = 0.1, g: float = 9.81, mu: float = 0.2, v0=V0, omega0=OMEGA0,
          t_end: float = 1.0, planar: bool = False) -> Model:
    """The sphere with the Python API (same as the model file for the default values).

    With ``planar=True`` the motion in the plane y = 0 only: coordinates x, z, b, one slip
    component ``x' - R b'`` (``v0 = (v0x,)``, ``omega0 = (omega0y,)``).
    """
    params = {"m": m, "R": R, "g": g, "mu": mu}
    if planar:
        return Model(
            name="Sphere launched sliding on a rough plane (planar, one slip component)",
            coordinates=["x", "z", "b"], parameters=params,
            kinetic="m/2*(x'^2 + z'^2) + (2*m*R^2/5)/2*b'^2", potential="m*g*z",
            contacts=[Contact("plane", "z - R", ("x' - R*b'",), Coulomb("mu"))],
            initial={"x": 0.0, "z": "R", "b": 0.0, "x'": v0[0], "z'": 0.0, "b'": omega0[0]},
            simulation={"t_end": t_end})
    return Model(
        name="Sphere launched sliding on a rough plane",
        coordinates=["x", "y", "z", "a", "b", "c"], parameters=params,
        kinetic="m/2*(x'^2 + y'^2 + z'^2) + (2*m*R^2/5)/2*(a'^2 + b'^2 + c'^2)",
        potential="m*g*z",
        contacts=[Contact("plane", "z - R", ("x' - R*b'", "y' + R*a'"), Coulomb("mu"))],
        initial={"x": 0.0, "y": 0.0, "z": "R", "a": 0.0, "b": 0.0, "c": 0.0,
                 "x'": v0[0], "y'": v0[1], "z'": 0.0, "a'": omega0[0], "b'": omega0[1], "c'": omega0[2]},
        simulation={"t_end": t_end})


def closed_form(p: dict, v0=V0, omega0=OMEGA0) -> dict:
    """Initial slip, rolling time, final velocities, energy loss (see the docstring)."""
    m, R, g, mu = p["m"], p["R"], p["g"], p["mu"]
    v0 = np.array(v0, dtype=float)
    w0 = np.array(omega0, dtype=float)
    U0 = np.array([v0[0] - R * w0[1], v0[1] + R * w0[0]])
    t_star = 2 * np.linalg.norm(U0) / (7 * mu * g)
    v_f = v0 - 2.0 / 7.0 * U0
    w_f = w0 + 5.0 / (7.0 * R) * np.array([-U0[1], U0[0], 0.0])
    return {"U0": U0, "s": U0 / np.linalg.norm(U0), "t_star": t_star, "v_f": v_f, "omega_f": w_f,
            "energy_loss": m * (U0 @ U0) / 7.0}


def motion(t, p: dict, v0=V0, omega0=OMEGA0):
    """Horizontal position, velocity, angular velocity and slip of the closed form at times t
    (arrays of shape (len(t), 2), (len(t), 2), (len(t), 3), (len(t), 2))."""
    cf = closed_form(p, v0, omega0)
    mu, g, R = p["mu"], p["g"], p["R"]
    t = np.asarray(t, dtype=float)[:, None]
    ts = np.minimum(t, cf["t_star"])
    a = -mu * g * cf["s"]
    v0 = np.array(v0, dtype=float)
    pos = v0 * ts + a * ts ** 2 / 2 + cf["v_f"] * (t - ts)
    vel = v0 + a * ts
    dw = 5 * mu * g / (2 * R) * np.array([-cf["s"][1], cf["s"][0], 0.0])
    omega = np.array(omega0, dtype=float) + dw * ts
    U = cf["U0"] * (1 - ts / cf["t_star"])
    return pos, vel, omega, U


def check(model: Model, v0=V0, omega0=OMEGA0, t_end: float | None = None) -> dict:
    """Simulate the 3-D *model* and compare with the closed form."""
    from ..simulation.hybrid import simulate

    p = model.parameter_values
    cf = closed_form(p, v0, omega0)
    t_end = t_end or model.simulation.t_end
    times = np.union1d(np.linspace(0.0, t_end, 41), [cf["t_star"] / 2])
    tr = simulate(model, times=times)
    full = simulate(model, t_end=t_end)
    pos, vel, omega, U = motion(times, p, v0, omega0)
    I = 0.4 * p["m"] * p["R"] ** 2
    w = tr.qd[:, 3:6]
    L = I * w + p["m"] * p["R"] * np.column_stack((-tr.qd[:, 1], tr.qd[:, 0], np.zeros(len(times))))
    slip = np.array(tr.contacts["plane"]["slip"])
    sliding = np.array([s == "slide" for s in tr.contacts["plane"]["mode"]])
    cross = slip[:, 0] * cf["s"][1] - slip[:, 1] * cf["s"][0]
    ev = full.events
    dKE = full.energy["kinetic"][-1] - full.energy["kinetic"][0]
    return {
        "U0": cf["U0"].tolist(), "t_star": cf["t_star"],
        "t_star_simulated": ev[0]["t"] if ev else None,
        "t_star_relative_error": abs(ev[0]["t"] / cf["t_star"] - 1) if ev else np.inf,
        "events": [(e["t"], e["type"], e["mode"]) for e in ev],
        "timeline": [full.modes[0]] + [e["mode"] for e in ev],
        "v_f": cf["v_f"].tolist(), "v_f_simulated": full.qd[-1, :2].tolist(),
        "v_f_relative_error": float(np.linalg.norm(full.qd[-1, :2] - cf["v_f"]) / np.linalg.norm(cf["v_f"])),
        "omega_f_relative_error": float(np.linalg.norm(full.qd[-1, 3:6] - cf["omega_f"])
                                        / np.linalg.norm(cf["omega_f"])),
        "max_error_position": float(np.max(np.abs(tr.q[:, :2] - pos))),
        "max_error_velocity": float(np.max(np.abs(tr.qd[:, :2] - vel))),
        "max_error_omega": float(np.max(np.abs(w - omega))),
        "max_error_slip": float(np.max(np.abs(slip - U))),
        "slip_direction_drift": float(np.max(np.abs(cross[sliding]))) if sliding.any() else 0.0,
        "angular_momentum_about_P_drift": float(np.max(np.abs(L - L[0]))),
        "spin_drift": float(np.max(np.abs(tr.velocity("c") - omega0[2]))),
        "kinetic_energy_lost": float(-dKE), "energy_loss_closed_form": cf["energy_loss"],
        "friction_work": float(full.energy["friction_work"][-1]),
        "friction_power_max": float(np.max(np.diff(full.energy["friction_work"]))),
        "max_error_normal": float(np.max(np.abs(np.array(tr.contacts["plane"]["normal"]) - p["m"] * p["g"]))),
        "energy_balance_relative": full.diagnostics["energy_balance_relative"],
        "constraint_residual_max": full.diagnostics["constraint_residual_max"],
    }


def _ok(r: dict) -> bool:
    return (r["t_star_relative_error"] < 1e-9 and r["v_f_relative_error"] < 1e-9
            and r["omega_f_relative_error"] < 1e-9 and len(r["events"]) == 1
            and r["timeline"] == ["plane:slide", "plane:stick"]
            and max(r["max_error_position"], r["max_error_velocity"], r["max_error_slip"],
                    r["slip_direction_drift"], r["angular_momentum_about_P_drift"],
                    r["spin_drift"], r["max_error_normal"]) < 1e-9 and r["max_error_omega"] < 1e-8
            and abs(r["friction_work"] + r["energy_loss_closed_form"]) < 1e-9
            and abs(r["kinetic_energy_lost"] - r["energy_loss_closed_form"]) < 1e-9
            and r["friction_power_max"] <= 1e-12 and r["energy_balance_relative"] < 1e-8)


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.crosscheck import compare_forms
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    r3 = check(model)
    # launched along x with backspin: U0 along x (one component active); it comes back
    r1 = check(build(v0=(2.0, 0.0), omega0=(0.0, -60.0, 0.0), t_end=2.0), v0=(2.0, 0.0),
               omega0=(0.0, -60.0, 0.0))
    planar = simulate(build(v0=(2.0,), omega0=(-60.0,), planar=True, t_end=2.0))
    p = model.parameter_values
    cf1 = closed_form(p, (2.0, 0.0), (0.0, -60.0, 0.0))
    err_planar_t = abs(planar.events[0]["t"] / cf1["t_star"] - 1)
    err_planar_v = abs(planar.qd[-1, 0] / cf1["v_f"][0] - 1)
    cross = {state: compare_forms(model, contact_state=state).worst() for state in ("slide", "stick")}
    ok = (_ok(r3) and _ok(r1) and err_planar_t < 1e-9 and err_planar_v < 1e-9
          and [e["mode"] for e in planar.events] == ["plane:stick"] and max(cross.values()) < 1e-10)
    out = {"ok": bool(ok), "arbitrary_directions": r3, "along_x": r1,
           "planar": {"t_star_relative_error": err_planar_t, "v_f_relative_error": err_planar_v},
           "forms_disagreement": cross}
    if verbose:
        print(TITLE)
        for label, r in (("v0 = (2, 1), omega0 = (3, -5, 4)", r3), ("along x, backspin omega0 = (0, -60, 0)", r1)):
            print(f"{label}: U0 = {np.round(r['U0'], 12).tolist()}")
            print(f"  t* = 2|U0|/(7 mu g) = {r['t_star']:.12f}, simulated {r['t_star_simulated']:.12f} "
                  f"(rel. error {r['t_star_relative_error']:.1e}); modes {' -> '.join(r['timeline'])}")
            print(f"  v_f = v0 - (2/7) U0 = {np.round(r['v_f'], 12).tolist()}, simulated "
                  f"{np.round(r['v_f_simulated'], 12).tolist()} (rel. error {r['v_f_relative_error']:.1e})")
            print(f"  kinetic energy lost {r['kinetic_energy_lost']:.12f} = m|U0|^2/7 = "
                  f"{r['energy_loss_closed_form']:.12f} = -(friction work {r['friction_work']:.12f})")
            print(f"  slip direction drift {r['slip_direction_drift']:.1e}, L_P drift "
                  f"{r['angular_momentum_about_P_drift']:.1e}, energy balance {r['energy_balance_relative']:.1e}")
        print(f"planar model (one slip component): t* rel. error {err_planar_t:.1e}, v_f rel. error {err_planar_v:.1e}")
        print(f"all forms vs Lagrange I (sliding, sticking): {cross['slide']:.1e}, {cross['stick']:.1e}")
        print("ok" if ok else "FAILED")
    return out
