"""A car on a turn whose wheels skid sideways when friction is not enough.

Source: M. P. Yushkov, *Equations of motion of nonholonomic systems and variational
principles of mechanics* (1999), appendix B, "motion of a car on a turn as a problem with
unilateral nonholonomic constraints" (types of motion of the car; rational choice of
quasi-velocities; the classic treatment is in Levin & Fufaev, *Theory of rolling of a
deformable wheel*).  Only the table of contents of the appendix is in the paper, so the model
below is built from mechanics, and every formula is derived here and checked against the
simulation, against every form of the equations and against the energy balance.

Model (single-track "bicycle" model with longitudinal load transfer).  A rigid body: mass m,
central inertia diag(Ixx, Iyy, Izz) in body axes (e1 forward, e2 left, e3 up), centre of
mass G = (x, y, z), yaw psi and pitch theta, rotation R = Rz(psi) Ry(theta) (no roll
coordinate: the roll moment is taken by an ideal, workless constraint).  Two wheel contacts,
rear at the body point (-b, 0, -h), front at (a, 0, -h), L = a + b:

* gap = world height of the contact point (>= 0), so its multiplier N is the axle load;
* one slip component: the velocity of the contact point across the wheel plane.  The rear
  wheel lies along e1; the front wheel is steered by the prescribed angle
  ``delta(t) = delta0 (1 - exp(-(t/tau)^2))`` (a rheonomic contact; delta is constant to
  double precision for t > 6.1 tau).  With e_r = Rz(psi) e2, e_f = Rz(psi + delta) e2:

      U_r = -x' sin psi + y' cos psi - psi' (b cos theta + h sin theta),
      U_f = -x' sin(psi+delta) + y' cos(psi+delta) + psi' cos(delta) (a cos theta - h sin theta)
            + theta' sin(delta) (a sin theta + h cos theta);

* Coulomb friction mu, mu_s across the wheel; along the wheel the wheels roll freely (no
  friction); the drive force F0 acts along the rear wheel at the rear contact point.

While both slips stick the two lateral no-slip conditions are nonholonomic constraints and
the car is the *kinematic car* (one degree of freedom); they are unilateral in the sense of
the appendix: they hold only while |F| <= mu_s N.  With speed the needed lateral friction
grows until one axle skids ("slip" event): the rear (oversteer: the car spins) or the front
(understeer: it ploughs on a wider curve); a sliding axle may re-grip ("stick").

Rational quasi-velocity (appendix B's phrase): the speed V of the rear contact point along
the car.  No coordinate velocity serves everywhere as the independent one (x' fails where
a cos(psi) cos(delta) + b cos(psi + delta) = 0, a heading near Oy; y' where
a sin(psi) cos(delta) + b sin(psi + delta) = 0, near Ox; psi' whenever delta = 0, as at the
start), while V is regular on the whole sticking motion; after a skid the slip velocities U_r, U_f join it as quasi-velocities, and
the no-slip constraints are simply U = 0.  Sticking, with the curvature k = tan(delta)/L of
the rear-axle path:

    psi' = k V,     v_G = V e1 + b k V e2,     z = h, theta = 0.

Newton-Euler in body axes (F_r, F_f: friction across the rear / front wheel, positive along
e_r, e_f; a_x, a_y: acceleration of G along e1, e2):

    m a_x = m (V' - b k^2 V^2)            = F0 - F_f sin(delta)
    m a_y = m (b k' V + b k V' + k V^2)   = F_r + F_f cos(delta)
    Izz psi'' = Izz (k' V + k V')          = a F_f cos(delta) - b F_r
    N_r + N_f = m g
    b N_r - a N_f - h (F0 - F_f sin(delta)) = 0          (pitch: Euler's equation about e2 with
                                                          omega = psi' e3 gives zero moment)

Eliminating the forces, with J = Izz + m b^2 and M_e = m + k^2 J (the effective mass: the
kinetic energy is M_e V^2 / 2):

    M_e V' + k k' J V = F0,   i.e.   d/dt (sqrt(M_e) V) = F0 / sqrt(M_e),
    V(t) = [sqrt(M_e(0)) V0 + F0 int_0^t ds / sqrt(M_e(s))] / sqrt(M_e(t)),

    F_r = (a m a_y - Izz psi'') / L,        F_f = (b m a_y + Izz psi'') / (L cos delta),
    N_r = m (g a + h a_x) / L,              N_f = m (g b - h a_x) / L

(longitudinal load transfer m h a_x / L through the pitch equilibrium).  For constant delta
(k' = 0): V' = A = F0/M_e is constant, V = V1 + A (t - t1), and

    F_r = k [(m a b - Izz) A + m a V^2] / L,   F_f = k [(Izz + m b^2) A + m b V^2] / (L cos delta),
    a_x = A - b k^2 V^2.

The rear axle runs on the circle of radius L/tan(delta) (G on the radius sqrt(R^2 + b^2)).

Skid onset.  The first time |F_r| = mu_s N_r or |F_f| = mu_s N_f; for constant delta (and
F > 0) it is a quadratic in V,

    rear:   V^2 = [mu_s m (g a + h A) - k (m a b - Izz) A] / [k m (a + mu_s h b k)],
    front:  V^2 = [mu_s m (g b - h A) - k J A / cos(delta)] / [k m b (1/cos(delta) - mu_s h k)],

and t = t1 + (V - V1)/A.  Default car (m = 1500 kg, a = 1.2, b = 1.4, h = 0.55 m,
Izz = 2500 kg m^2, mu = mu_s = 0.9, delta0 = 0.15, V0 = 10 m/s, F0 = 500 N): the rear skids
at t = 6.909262516907 s (``run`` prints the digits; the simulation's "slip" event agrees to
~1e-14 relative, and so does ``realizability_along``).

Which axle skids first (same friction at both axles).  Per unit load,

    F_r/N_r = k [V^2 + (b - Izz/(m a)) A] / [g + (h/a) a_x],
    F_f/N_f = k [V^2 + (b + Izz/(m b)) A] / [cos(delta) (g - (h/b) a_x)],

so the static weight distribution cancels and the longitudinal acceleration of G decides:

* G runs on a bigger circle than the rear axle, so its centripetal acceleration has the
  component -b k^2 V^2 along the car; this transfers m h b k^2 V^2 / L from the rear to the
  front axle and the rear reaches its limit first -- *oversteer* -- when the drive is gentle
  (as A -> 0: iff tan(delta/2) < mu_s h / a, exactly -- independent of b and Izz);
* a drive acceleration A transfers m h A / L to the rear, and the front must supply more of
  the force that turns and yaw-accelerates the accelerating car (share b + Izz/(m b) against
  b - Izz/(m a)): hard driving makes the front skid first -- *power understeer*.

For the default car the two axles reach the limit together at F0* = 736.93 N (``run``):
F0 = 500 N oversteers, F0 = 1500 N understeers (front skids at t = 2.160780173792 s).  A
higher centre of mass (h) or a centre of mass farther ahead of the rear axle (larger b)
raises F0* (more oversteer): h = 0.7 gives 800 N, (a, b) = (1.0, 1.6) gives 873 N.

After the skid (default car): the rear slides at 6.909 s, the car yaws faster, the front
slides too at 7.097 s (the spin), the front re-grips at 11.895 s and the rear at 12.350 s:
the kinematic car again, at V = 5.95 m/s instead of 12.21 m/s before the skid.  While both
axles slide outwards (U_r, U_f < 0, so F_r = mu N_r, F_f = mu N_f along fixed body
directions) the loads and the yaw acceleration are constant:

    a_x = (F0/m - mu g b sin(delta)/L) / (1 - mu h sin(delta)/L),
    N_r = m (g a + h a_x)/L,   N_f = m (g b - h a_x)/L,   psi'' = mu (a N_f cos(delta) - b N_r)/Izz
    (default car: N_r = 6668.375418 N, N_f = 8046.624582 N, psi'' = 0.076247283 rad/s^2).

Limits of the model (stated, not hidden): massless wheels; no roll, so the left/right load
transfer is not represented (with one mu per axle it does not change the axle's friction
limit mu N as long as no wheel lifts off, h a_y < g x half track); the drive force is
prescribed and does not use the rear friction budget (no friction circle); rigid Coulomb
tyres (no slip-angle characteristic).  With mu < mu_s the motion after the first skid is
not unique in rigid Coulomb theory when the other axle needs more than mu N (but less than
mu_s N): it may keep sticking or start sliding too, both consistent; the mode selection then
stops with an indeterminacy (exit code 3).  The example uses mu = mu_s.

No misprints to report: the appendix text is not in the paper.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from scipy.integrate import quad
from scipy.optimize import brentq

from ..modeling.bodies import Force, RigidBody
from ..modeling.contacts import Contact, Coulomb
from ..modeling.model import Model

NAME = "car-on-a-turn"
ORDER = 12
TITLE = ("Car on a turn: kinematic car, load transfer, skid onset, oversteer/understeer "
         "(Yushkov 1999, app. B)")
FILE = "car_on_a_turn.toml"

DEFAULTS = {"m": 1500.0, "Ixx": 550.0, "Iyy": 2300.0, "Izz": 2500.0, "a": 1.2, "b": 1.4,
            "h": 0.55, "g": 9.81, "mu": 0.9, "mu_s": 0.9, "delta0": 0.15, "tau": 0.3,
            "F0": 500.0}
V0 = 10.0
RAMP = 6.5   # delta is constant to double precision for t > RAMP * tau (exp(-42) ~ 6e-19)


def build(V0: float = V0, t_end: float = 14.0, **parameters) -> Model:
    """The car with the Python API; the slip velocities are derived here symbolically
    (lateral unit vector . velocity of the contact point), independently of the model file."""
    p = dict(DEFAULTS)
    unknown = set(parameters) - set(p)
    if unknown:
        raise TypeError(f"build: unknown parameter(s) {sorted(unknown)}; known: {sorted(p)}")
    p.update(parameters)
    x, y, z, psi, th, t = sp.symbols("x y z psi theta t")
    q = [x, y, z, psi, th]
    qd = [sp.Symbol(s.name + "'") for s in q]
    a, b, h, d0, tau, F0 = sp.symbols("a b h delta0 tau F0")
    delta = d0 * (1 - sp.exp(-(t / tau) ** 2))
    Rz = sp.Matrix([[sp.cos(psi), -sp.sin(psi), 0], [sp.sin(psi), sp.cos(psi), 0], [0, 0, 1]])
    Ry = sp.Matrix([[sp.cos(th), 0, sp.sin(th)], [0, 1, 0], [-sp.sin(th), 0, sp.cos(th)]])
    R = Rz * Ry
    G = sp.Matrix([x, y, z])
    rear = G + R * sp.Matrix([-b, 0, -h])
    front = G + R * sp.Matrix([a, 0, -h])

    def velocity(r):
        return sp.Matrix([sum(sp.diff(c, qk) * vk for qk, vk in zip(q, qd)) + sp.diff(c, t) for c in r])

    def lateral(angle):
        return sp.Matrix([-sp.sin(angle), sp.cos(angle), 0])

    U_r = sp.simplify(lateral(psi).dot(velocity(rear)))
    U_f = sp.simplify(lateral(psi + delta).dot(velocity(front)))
    friction = Coulomb("mu", "mu_s")
    return Model(
        name="Car on a turn (single-track model with load transfer)",
        coordinates=["x", "y", "z", "psi", "theta"],
        parameters=p,
        bodies=[RigidBody("car", "m", [["Ixx", 0, 0], [0, "Iyy", 0], [0, 0, "Izz"]], [x, y, z],
                          R.tolist())],
        gravity=["0", "0", "-g"],
        loads=[Force("drive", list(rear), [F0 * sp.cos(psi), F0 * sp.sin(psi), 0])],
        contacts=[Contact("rear", rear[2], [U_r], friction),
                  Contact("front", front[2], [U_f], friction)],
        initial={"x": 0.0, "y": 0.0, "z": p["h"], "psi": 0.0, "theta": 0.0, "x'": V0,
                 "y'": 0.0, "z'": 0.0, "psi'": 0.0, "theta'": 0.0},
        simulation={"t_end": t_end, "rtol": 1e-11, "atol": 1e-11},
    )


# ----------------------------------------------------------------------------- closed forms


def steering(t, p):
    """``delta(t), delta'(t)``."""
    e = np.exp(-(t / p["tau"]) ** 2)
    return p["delta0"] * (1 - e), p["delta0"] * 2 * t / p["tau"] ** 2 * e


def sticking_motion(t: float, p: dict, V0: float = V0) -> dict:
    """The kinematic car at time *t* (both axles sticking from t = 0, straight start at V0):
    rear speed V, V', yaw rate, curvature k, longitudinal acceleration a_x of G, lateral
    friction F_r, F_f and axle loads N_r, N_f (module docstring)."""
    m, Izz, a, b, h, g, F = (p[k] for k in ("m", "Izz", "a", "b", "h", "g", "F0"))
    L = a + b
    J = Izz + m * b * b

    def curvature(s):
        d, dd = steering(s, p)
        return np.tan(d) / L, dd / (L * np.cos(d) ** 2)

    def Me(s):
        return m + curvature(s)[0] ** 2 * J
    t_r = min(t, RAMP * p["tau"])
    integral = quad(lambda s: 1 / np.sqrt(Me(s)), 0.0, t_r, epsabs=1e-15, epsrel=1e-14,
                    limit=200)[0] + (t - t_r) / np.sqrt(Me(t))
    V = (np.sqrt(Me(0.0)) * V0 + F * integral) / np.sqrt(Me(t))
    k, kd = curvature(t)
    d = steering(t, p)[0]
    Vd = (F - k * kd * J * V) / Me(t)
    ax = Vd - b * k * k * V * V
    ay = b * kd * V + b * k * Vd + k * V * V
    psidd = kd * V + k * Vd
    return {"V": V, "Vd": Vd, "psid": k * V, "k": k, "ax": ax, "ay": ay,
            "Fr": (a * m * ay - Izz * psidd) / L, "Ff": (b * m * ay + Izz * psidd) / (L * np.cos(d)),
            "Nr": m * (g * a + h * ax) / L, "Nf": m * (g * b - h * ax) / L}


def constant_steering_forces(V: float, p: dict) -> dict:
    """Lateral forces and loads of the kinematic car at rear speed V, constant delta0."""
    m, Izz, a, b, h, g, F = (p[k] for k in ("m", "Izz", "a", "b", "h", "g", "F0"))
    L = a + b
    d = p["delta0"]
    k = np.tan(d) / L
    A = F / (m + k * k * (Izz + m * b * b))
    ax = A - b * k * k * V * V
    return {"A": A, "ax": ax, "Fr": k * ((m * a * b - Izz) * A + m * a * V * V) / L,
            "Ff": k * ((Izz + m * b * b) * A + m * b * V * V) / (L * np.cos(d)),
            "Nr": m * (g * a + h * ax) / L, "Nf": m * (g * b - h * ax) / L}


def onset_speed(p: dict) -> dict:
    """Rear speed at which each axle reaches mu_s N (constant delta0, F0 > 0): the quadratics."""
    m, Izz, a, b, h, g, mu = (p[k] for k in ("m", "Izz", "a", "b", "h", "g", "mu_s"))
    L = a + b
    d = p["delta0"]
    k = np.tan(d) / L
    J = Izz + m * b * b
    A = p["F0"] / (m + k * k * J)
    rear = (mu * m * (g * a + h * A) - k * (m * a * b - Izz) * A) / (k * m * (a + mu * h * b * k))
    front = (mu * m * (g * b - h * A) - k * J * A / np.cos(d)) / (k * m * b * (1 / np.cos(d) - mu * h * k))
    return {"rear": float(np.sqrt(rear)), "front": float(np.sqrt(front))}


def skid_onset(p: dict, V0: float = V0, t_max: float = 60.0) -> dict:
    """First time each axle reaches ``|F| = mu_s N`` along the sticking motion, two ways:
    ``"root"`` (root of the margin of :func:`sticking_motion`, valid for any steering) and
    ``"quadratic"`` (:func:`onset_speed`, when the onset falls after the steering ramp)."""
    out = {}
    for axle, (F, N) in {"rear": ("Fr", "Nr"), "front": ("Ff", "Nf")}.items():
        def margin(t):
            s = sticking_motion(t, p, V0)
            return p["mu_s"] * s[N] - abs(s[F])
        grid = np.linspace(0.0, t_max, 241)
        vals = [margin(s) for s in grid]
        k = next((i for i in range(len(grid) - 1) if vals[i] > 0 >= vals[i + 1]), None)
        root = None if k is None else brentq(margin, grid[k], grid[k + 1], xtol=1e-14, rtol=8.9e-16)
        quadratic = None
        t1 = RAMP * p["tau"]
        if root is not None and root > t1:
            V1 = sticking_motion(t1, p, V0)["V"]
            A = constant_steering_forces(V1, p)["A"]
            quadratic = t1 + (onset_speed(p)[axle] - V1) / A
        out[axle] = {"root": root, "quadratic": quadratic}
    return out


def first_to_skid(p: dict, V0: float = V0) -> tuple[str, float]:
    on = skid_onset(p, V0)
    times = {k: v["root"] for k, v in on.items() if v["root"] is not None}
    axle = min(times, key=times.get)
    return axle, times[axle]


def drive_crossover(p: dict, V0: float = V0, bracket=(300.0, 1500.0)) -> float:
    """Drive force F0* at which both axles reach their limit at the same time."""
    def diff(F):
        on = skid_onset(dict(p, F0=F), V0)
        return on["rear"]["root"] - on["front"]["root"]
    return brentq(diff, *bracket, xtol=1e-9)


def both_sliding(p: dict, sign_r: float = -1.0, sign_f: float = -1.0) -> dict:
    """Both axles sliding with slip signs ``sign_r, sign_f`` (constant delta0): the friction
    forces are ``-mu N sign(U)`` along fixed body directions, so a_x, the loads and the yaw
    acceleration are constant."""
    m, Izz, a, b, h, g, mu, F = (p[k] for k in ("m", "Izz", "a", "b", "h", "g", "mu", "F0"))
    L = a + b
    d = p["delta0"]
    cf = -mu * sign_f          # F_f = cf N_f
    cr = -mu * sign_r          # F_r = cr N_r
    # m a_x = F - cf N_f sin(d),  N_f = m (g b - h a_x) / L
    ax = (F / m - cf * g * b * np.sin(d) / L) / (1 - cf * h * np.sin(d) / L)
    Nr, Nf = m * (g * a + h * ax) / L, m * (g * b - h * ax) / L
    return {"ax": ax, "Nr": Nr, "Nf": Nf, "Fr": cr * Nr, "Ff": cf * Nf,
            "ay": (cr * Nr + cf * Nf * np.cos(d)) / m,
            "psidd": (a * cf * Nf * np.cos(d) - b * cr * Nr) / Izz}


def rear_axle(traj, p: dict) -> np.ndarray:
    """Rear contact point (x, y) along a trajectory."""
    psi, th = traj.coordinate("psi"), traj.coordinate("theta")
    r = p["b"] * np.cos(th) + p["h"] * np.sin(th)
    return np.column_stack((traj.coordinate("x") - r * np.cos(psi), traj.coordinate("y") - r * np.sin(psi)))


def rear_speed(traj) -> np.ndarray:
    """V = velocity of the rear contact point along the car (= that of G along e1)."""
    psi = traj.coordinate("psi")
    return traj.velocity("x") * np.cos(psi) + traj.velocity("y") * np.sin(psi)


def circumradius(P: np.ndarray) -> float:
    """Radius of the circle through three points."""
    A, B, C = P
    ab, bc, ca = np.linalg.norm(A - B), np.linalg.norm(B - C), np.linalg.norm(C - A)
    cross = (B - A)[0] * (C - A)[1] - (B - A)[1] * (C - A)[0]
    return float(ab * bc * ca / (2 * abs(cross)))


# ----------------------------------------------------------------------------- run


def run(verbose: bool = True) -> dict:
    from .. import gallery
    from ..analysis.contact.realizability import realizability_along
    from ..simulation.hybrid import simulate

    model = gallery.load(NAME)
    p = model.parameter_values
    L = p["a"] + p["b"]
    traj = simulate(model)
    ev = traj.events
    slips = [e for e in ev if e["type"] == "slip"]

    # (1) kinematic path: rear axle on the circle L / tan(delta0) once the ramp is over
    on = skid_onset(p)
    t_skid = on["rear"]["root"]
    ts = np.linspace(RAMP * p["tau"], t_skid - 0.05, 9)
    tr = simulate(model, times=ts)
    P = rear_axle(tr, p)
    R = L / np.tan(p["delta0"])
    radii = [circumradius(P[[0, k, -1]]) for k in range(1, len(ts) - 1)]
    err_R = max(abs(r - R) / R for r in radii)
    err_curv = float(np.max(np.abs(tr.velocity("psi") / rear_speed(tr) - 1 / R) * R))

    # (2) forces along the sticking motion vs the Newton-Euler formulas
    tf = np.array([0.2, 0.5, 1.0, 2.0, 4.0, 6.5])
    trf = simulate(model, times=tf)
    err_f = 0.0
    for i, s in enumerate(tf):
        f = sticking_motion(s, p)
        for c, F, N in (("rear", "Fr", "Nr"), ("front", "Ff", "Nf")):
            err_f = max(err_f, abs(trf.contacts[c]["friction"][i][0] - f[F]) / (p["m"] * p["g"]),
                        abs(trf.contacts[c]["normal"][i] - f[N]) / (p["m"] * p["g"]))
    t_quad = on["rear"]["quadratic"]
    err_onset = abs(slips[0]["t"] - t_skid) / t_skid
    along = realizability_along(model, t_end=10.0).along
    err_along = abs(along["lost_at"] - t_skid) / t_skid

    # (3) after the skid: energy, friction work, both-sliding phase, re-grip
    fw = traj.energy["friction_work"]
    slide = both_sliding(p)
    both = [i for i, md in enumerate(traj.modes) if md == "rear:slide-, front:slide-"]
    err_slide = max(max(abs(traj.contacts["rear"]["normal"][i] - slide["Nr"]),
                        abs(traj.contacts["front"]["normal"][i] - slide["Nf"])) for i in both) / (p["m"] * p["g"])
    err_psidd = max(abs(traj.qdd[i, 3] - slide["psidd"]) for i in both)

    # (4) understeer variant and the crossover drive force
    under = dict(p, F0=1500.0)
    axle_u, t_u = first_to_skid(under)
    tr_u = simulate(model, parameters={"F0": 1500.0}, t_end=4.0, stop_on={"slip"})
    F_star = drive_crossover(p)

    result = {
        "path_radius": R, "path_radius_error": err_R, "curvature_error": err_curv,
        "force_error": err_f, "skid_onset_formula": t_skid, "skid_onset_quadratic": t_quad,
        "skid_onset_simulation": slips[0]["t"], "skid_onset_error": err_onset,
        "realizability_along_error": err_along, "first_skid": slips[0]["contact"],
        "events": [(e["type"], e["contact"], e["t"]) for e in ev],
        "energy_balance_relative": traj.diagnostics["energy_balance_relative"],
        "constraint_residual_max": traj.diagnostics["constraint_residual_max"],
        "friction_work_end": float(fw[-1]),
        "both_sliding_load_error": err_slide, "both_sliding_psidd_error": err_psidd,
        "understeer_first": axle_u, "understeer_onset_formula": t_u,
        "understeer_onset_simulation": tr_u.events[0]["t"], "drive_crossover_F0": F_star,
    }
    result["ok"] = bool(
        err_R < 1e-8 and err_curv < 1e-8 and err_f < 1e-8 and err_onset < 1e-8
        and abs(t_quad - t_skid) / t_skid < 1e-12 and err_along < 1e-8
        and slips[0]["contact"] == "rear" and result["energy_balance_relative"] < 1e-8
        and result["constraint_residual_max"] < 1e-8 and np.all(np.diff(fw) <= 1e-9 * abs(fw[-1]))
        and err_slide < 1e-8 and err_psidd < 1e-8 and axle_u == "front"
        and tr_u.events[0]["contact"] == "front" and abs(tr_u.events[0]["t"] - t_u) / t_u < 1e-8)
    if verbose:
        print(TITLE)
        print(f"kinematic path: rear axle radius L/tan(delta0) = {R:.10f} m, "
              f"max relative error of the 3-point radius {err_R:.2e}, of psi'/V {err_curv:.2e}")
        print(f"lateral forces and axle loads along the sticking motion (6 times): "
              f"max |sim - formula| / (m g) = {err_f:.2e}")
        print(f"skid onset (rear): formula {t_skid:.12f} s, quadratic {t_quad:.12f} s, "
              f"simulation {slips[0]['t']:.12f} s, realizability_along {along['lost_at']:.12f} s")
        print("mode timeline: " + "; ".join(f"{e['type']} {e['contact']} at {e['t']:.6f}" for e in ev))
        print(f"both axles sliding: N_r = {slide['Nr']:.6f}, N_f = {slide['Nf']:.6f} N, "
              f"psi'' = {slide['psidd']:.9f} rad/s^2 (errors {err_slide:.1e} relative, {err_psidd:.1e})")
        print(f"energy balance (relative) {result['energy_balance_relative']:.2e}, constraint residual "
              f"{result['constraint_residual_max']:.2e}, friction work {fw[-1]:.6g} J")
        print(f"F0 = 1500 N: the {axle_u} axle skids first at {t_u:.12f} s (simulation "
              f"{tr_u.events[0]['t']:.12f} s); both axles together at F0* = {F_star:.6f} N")
        print("ok" if result["ok"] else "FAILED")
    return result
