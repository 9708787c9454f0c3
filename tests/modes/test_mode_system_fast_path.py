"""The Lagrange I fast path (nonideal.modes.system) gives the general path's numbers.

The index-assembled saddle-point system of a mode (``ModeSystem``) must reproduce, bit for
bit, what ``ModeSolver.assemble`` + ``solve_saddle`` compute, at arbitrary states of every kind
of mode: contacts separated, sticking, sliding with one or two slip components (with and
without a slip reference), bilateral contacts with both signs of the normal force, smooth
(regularized) sliding, unilateral constraints held and released, servo rows, non-potential
forces and explicit time.  The right-hand side of the simulation and the light ``Motion`` the
hybrid loop reads (events, samples) are checked against the general right-hand side and the
full ``Solution``; the gallery's simulations against the numbers the library gave before the
fast path (``tests/data/gallery_reference.json``).
"""

import itertools
import json

import numpy as np
import pytest

import nonideal
from nonideal import gallery
from nonideal.modeling.contacts import Contact, Coulomb
from nonideal.errors import MechanicsError, SingularSystem
from nonideal.modeling.model import Constraint, Model
from nonideal.modes.system import ModeFunction
from nonideal.modes.types import SEPARATED, SLIDE, SMOOTH, STICK, ContactState, Mode
from nonideal.numeric.kernel import SingularMatrix
from nonideal.analysis.contact.realizability import regularized
from nonideal.simulation.hybrid import WORK_ATOL, Simulation
from nonideal.simulation.rhs import general_rhs
from nonideal.modes.switching import effective_compliance
from tests.helpers import DATA_DIR
from tests.systems import rough_rattleback

REFERENCE = json.loads((DATA_DIR / "gallery_reference.json").read_text())


def ball_cart():
    """A ball rolling/sliding on a plane (two slip components), coupled by a spring to a cart
    whose position is a servo program; a wall (unilateral) limits the ball's y; damping and a
    time-dependent force on the cart (non-potential forces, explicit time)."""
    return Model(
        name="ball and servo cart", coordinates=["x", "y", "z", "a", "b", "s"],
        parameters={"m": 1.0, "R": 0.1, "I": 0.004, "M": 2.0, "k": 0.3, "K": 5.0, "g": 9.81, "mu": 0.3,
                    "mus": 0.4, "A": 0.2, "w": 1.3, "F0": 0.7, "c": 0.1, "L": 0.5},
        kinetic="m/2*(x'^2 + y'^2 + z'^2) + I/2*(a'^2 + b'^2) + M/2*s'^2 + k*s'*x'",
        potential="m*g*z + K/2*(s - x)^2",
        forces={"s": "F0*sin(w*t)", "x": "-c*x'"},
        constraints=[Constraint.servo("program", "s - A*sin(w*t)", reaction=["0", "0", "0", "0", "0", "1"]),
                     Constraint.holonomic("wall", "L - y", unilateral=True)],
        contacts=[Contact("plane", "z - R", ("x' - R*b'", "y' + R*a'"), Coulomb(0.3, 0.4))],
        initial={"x": 0.0, "y": 0.0, "z": "R", "a": 0.0, "b": 0.0, "s": 0.0, "x'": 1.0, "s'": "A*w"},
    )


def bead_on_guide():
    """A bead on a rough two-sided guide (bilateral contact: N of either sign)."""
    return Model(
        name="bead on a rough guide", coordinates=["x", "y", "th"],
        parameters={"m": 1.0, "J": 0.2, "g": 9.81, "e": 0.3},
        kinetic="m/2*(x'^2 + y'^2) + J/2*th'^2 + e*x'*th'", potential="m*g*y",
        forces={"th": "-0.5*th'"},
        contacts=[Contact("guide", "y", ("x'",), Coulomb(0.25), bilateral=True)],
        initial={"x": 0.0, "y": 0.0, "th": 0.0, "x'": 1.0, "th'": 2.0},
    )


MODELS = {
    "ball-cart": ball_cart,
    "bead-on-guide": bead_on_guide,
    "painleve-rod": lambda: gallery.load("painleve-rod"),
    "stick-slip-oscillator": lambda: gallery.load("stick-slip-oscillator"),
    "sphere-regularized": lambda: regularized(gallery.load("sphere-sliding-on-plane"), 1e-3, law="smooth"),
    "appell-ladder": lambda: gallery.load("appell-ladder"),
    "knife-chain": lambda: gallery.load("knife-chain"),
}


def contact_states(ck, c, U):
    """Every state contact c can be in; sliding directions from the slip U (and its reverse)."""
    data = ck.data[c]
    sigmas = (1, -1) if data.bilateral else (1,)
    if not data.law.exact:
        return [ContactState(SMOOTH, (), s) for s in sigmas] + ([] if data.bilateral else [ContactState()])
    out = [] if data.bilateral else [ContactState(SEPARATED)]
    for s in sigmas:
        out.append(ContactState(STICK, (), s))
        if len(U) == 1:
            out += [ContactState(SLIDE, (1.0,), s), ContactState(SLIDE, (-1.0,), s)]
        else:
            out.append(ContactState(SLIDE, tuple(U / np.linalg.norm(U)), s))
    return out


def modes_and_states(model, count=3, seed=1):
    """Simulation, and (mode, t, y) for every mode at *count* random states."""
    sim = Simulation(model)
    solver = sim.solver
    rng = np.random.default_rng(seed)
    n = sim.n
    uni = [solver.kernel.rows[i].name for i in solver.unilateral]
    out = []
    for _ in range(count):
        t = float(rng.uniform(0, 2))
        y = np.concatenate((rng.normal(0, 0.5, n), rng.normal(0, 1.5, n), np.zeros(5 if sim.track else 0)))
        cout = solver.ck(solver.input(t, y[:n], y[n:2 * n])) if solver.ck else None
        per_contact = [contact_states(solver.ck, c, solver.ck.slip(cout, c)) for c in range(len(solver.ck.names))]
        for k in range(len(uni) + 1):
            for held in itertools.combinations(uni, k):
                for combo in itertools.product(*per_contact):
                    out.append((Mode(frozenset(held), tuple(zip(solver.ck.names, combo))), t, y))
    return sim, out


@pytest.mark.parametrize("name", list(MODELS))
def test_fast_system_equals_the_general_path_bit_for_bit(name):
    sim, cases = modes_and_states(MODELS[name](), count=4)
    solver, n = sim.solver, sim.n
    checked = 0
    for mode, t, y in cases:
        for reference in ((None, "reverse") if any(cs.state == SLIDE and len(cs.direction) == 2
                                                     for _, cs in mode.contacts) else (None,)):
            solver.reference = {}
            if reference == "reverse":  # a slip reference opposite to the slip: s flips
                solver.reference = {c: -np.array(cs.direction) for c, (_, cs) in enumerate(mode.contacts)
                                    if cs.state == SLIDE and len(cs.direction) == 2}
            try:
                qdd, values, *_ = solver.accelerations(t, y[:n], y[n:2 * n], mode)
            except (MechanicsError, SingularSystem):
                continue  # singular or redundant at this state: the general path explains it
            sol = solver.system(mode).solve(solver, t, y, mode)
            assert np.array_equal(sol[:n], qdd), (mode.label(), t)
            assert np.array_equal(-sol[n:], values), (mode.label(), t)
            checked += 1
    assert checked >= len(cases) // 2  # most random states are regular


@pytest.mark.parametrize("name", list(MODELS))
def test_fast_rhs_equals_the_general_rhs(name):
    sim, cases = modes_and_states(MODELS[name](), count=2, seed=2)
    n = sim.n
    for mode, t, y in cases:
        sim.solver.reference = {}
        try:
            general = general_rhs(sim, mode)(t, y)
        except (MechanicsError, SingularSystem):
            continue
        fast = sim.rhs(mode)(t, y)
        assert np.array_equal(fast[:2 * n], general[:2 * n]), mode.label()
        # the powers of the reactions: the same sums in another order
        scale = 1.0 + float(np.max(np.abs(general)))
        assert np.max(np.abs(fast[2 * n:] - general[2 * n:])) <= 1e-13 * scale, mode.label()


@pytest.mark.parametrize("name", ["ball-cart", "bead-on-guide", "painleve-rod", "sphere-regularized"])
def test_motion_reads_what_the_solution_holds(name):
    sim, cases = modes_and_states(MODELS[name](), count=2, seed=3)
    solver, n = sim.solver, sim.n
    for mode, t, y in cases:
        solver.reference = {}
        try:
            sol = solver.solve(t, y[:n], y[n:2 * n], mode)
        except (MechanicsError, SingularSystem):
            continue
        motion = solver.motion(t, y, mode)

        def close(a, b):
            a, b = np.atleast_1d(np.asarray(a, float)), np.atleast_1d(np.asarray(b, float))
            return np.allclose(a, b, rtol=1e-12, atol=1e-12 * (1 + np.max(np.abs(b), initial=0)))

        assert close(motion.qdd, sol.qdd) and close(motion.values, sol.values)
        for i in sol.rows:
            assert close(motion.multiplier(i), sol.multiplier(i))
        for i in solver.unilateral:
            assert close(motion.constraint_acc(i), sol.G[i] @ sol.qdd + sol.gamma[i])
        assert close(motion.force_scale(), 1 + np.max(np.abs(sol.F)))
        for c, (cname, cs) in enumerate(mode.contacts):
            cf = sol.contacts[cname]
            assert close(motion.normal(c), cf.N) and close(motion.friction(c), cf.F)
            assert close(motion.slip(c), cf.U) and close(motion.slip_acc(c), cf.Udot)
            assert close(motion.gap(c), cf.gap) and close(motion.gap_rate(c), cf.gap_rate)
            assert close(motion.gap_acc(c), cf.gap_acc) and close(motion.mu_s(c), cf.mu_s)
            if cs.state in (SLIDE, SMOOTH, STICK):
                b = effective_compliance(solver, t, y[:n], y[n:2 * n], mode, cname)
                assert np.isclose(motion.compliance(c), b, rtol=1e-9, atol=1e-12), (mode.label(), cname)


def test_step_end_motion_reuses_the_integrators_last_evaluation():
    """DOP853 evaluates the right-hand side at the end of each accepted step; the motion there
    takes it (no solve) and equals a fresh evaluation."""
    from scipy.integrate import DOP853

    model = gallery.load("sphere-sliding-on-plane")
    sim = Simulation(model)
    solver, n = sim.solver, sim.n
    q, qd = sim.initial_state()
    mode = nonideal.modes.switching.select_mode(solver, 0.0, q, qd)
    y0 = np.concatenate((q, qd, np.zeros(5)))
    ode = DOP853(sim.rhs(mode), 0.0, y0, 1.0, rtol=1e-10, atol=1e-12)
    ode.step()
    motion = solver.motion(ode.t, ode.y, mode)
    assert motion._sol is not None  # taken from the integrator's last evaluation
    fresh = solver.solve(ode.t, ode.y[:n], ode.y[n:2 * n], mode)
    assert np.array_equal(motion.qdd, fresh.qdd) and np.array_equal(motion.values, fresh.values)
    assert solver.motion(ode.t, ode.y.copy(), mode)._sol is None  # another state object: solved anew


@pytest.mark.parametrize("name", [n for n in gallery.names() if n in REFERENCE["models"]])
def test_gallery_simulations_are_unchanged(name):
    # the models recorded before the fast path (examples added later have their own tests)
    ref = REFERENCE["models"][name]
    traj = nonideal.simulate(gallery.load(name), every_step=True)  # (the reference's output)
    assert [e["type"] for e in traj.events] == [e[1] for e in ref["events"]]
    for e, (t_ref, _) in zip(traj.events, ref["events"]):
        assert abs(e["t"] - t_ref) <= 1e-9 * max(1.0, abs(t_ref))
    assert traj.t[-1] == pytest.approx(ref["t_end"], rel=1e-12)
    scale = 1.0 + np.max(np.abs(ref["qd_end"]))
    assert np.max(np.abs(traj.q[-1] - ref["q_end"])) <= 1e-6 * (1.0 + np.max(np.abs(ref["q_end"])))
    assert np.max(np.abs(traj.qd[-1] - ref["qd_end"])) <= 1e-6 * scale
    # the work integrals are integrated to WORK_ATOL times the motion's absolute tolerance
    # since the reference was taken: their error, hence the balance's, may be that much larger
    assert traj.diagnostics["energy_balance_relative"] <= 10 * WORK_ATOL * ref["energy_balance_relative"] + 1e-14


@pytest.mark.parametrize("name", ["ball-cart", "bead-on-guide", "painleve-rod", "stick-slip-oscillator",
                                  "sphere-regularized"])
def test_compiled_mode_function_equals_the_index_path(name):
    sim, cases = modes_and_states(MODELS[name](), count=3, seed=4)
    solver, kernel = sim.solver, sim.kernel
    checked = 0
    for mode, t, y in cases:
        system = solver.system(mode)
        if not system.contact_rows:
            continue
        function = ModeFunction.of(kernel, system, mode)
        solver.reference = {c: np.array(cs.direction) for c, (_, cs) in enumerate(mode.contacts)
                            if cs.state == SLIDE and len(cs.direction) == 2}
        try:
            ref = system.solve_with_powers(solver, t, y, mode)
        except SingularMatrix:
            continue
        out = function.solve_with_powers(solver, function.inputs(solver, mode), t, y, mode)
        assert out is not None
        scale = 1.0 + np.max(np.abs(ref[0]))
        assert np.max(np.abs(out[0] - ref[0])) <= 1e-13 * scale, mode.label()
        for a, b in zip(out[1:], ref[1:]):
            if b is not None:
                assert np.max(np.abs(np.asarray(a) - b)) <= 1e-13 * (1.0 + np.max(np.abs(b))) * scale
        assert solver.last[3] is out[0]  # the step-end motion will find it
        checked += 1
    assert checked >= 3


def test_compiled_mode_function_leaves_degenerate_slips_to_the_index_path():
    model = ball_cart()
    sim = Simulation(model)
    solver, n = sim.solver, sim.n
    mode = Mode(frozenset(), (("plane", ContactState(SLIDE, (0.6, 0.8))),))
    function = ModeFunction.of(sim.kernel, solver.system(mode), mode)
    x = function.inputs(solver, mode)
    y = np.zeros(2 * n + 5)
    y[n:2 * n] = [1.0, 0.5, 0.0, 2.0, 0.0, 0.3]  # U = (x' - R b', y' + R a') = (1, 0.7)
    solver.reference = {}
    assert function.solve_with_powers(solver, x, 0.0, y, mode) is None  # no slip reference yet
    solver.reference = {0: np.array([0.0, 0.0])}
    assert function.solve_with_powers(solver, x, 0.0, y, mode) is None  # U . s_ref = 0
    solver.reference = {0: np.array([0.6, 0.8])}
    assert function.solve_with_powers(solver, x, 0.0, y, mode) is not None
    y[n + 3] = 0.0
    y[n:n + 2] = [0.0, 0.0]  # no slip: the index path's friction_shape decides
    assert function.solve_with_powers(solver, x, 0.0, y, mode) is None
    linear = regularized(model, 1e-3)  # the epsilon-linear law is piecewise: not compiled
    sim = Simulation(linear)
    smooth = Mode(frozenset(), (("plane", ContactState(SMOOTH)),))
    assert ModeFunction.of(sim.kernel, sim.solver.system(smooth), smooth) is False


def _compiled_systems(model):
    """The compiled functions of the mode systems derived from *model* (``Model.cached``)."""
    return [system.function for key, system in model.__dict__.get("_derived", {}).items()
            if isinstance(key, tuple) and key[0] == "mode system"]


@pytest.mark.parametrize("name", ["sphere-sliding-on-plane", "painleve-rod", "stick-slip-oscillator",
                                  "car-on-a-turn", "block-on-incline"])
def test_simulation_with_compiled_modes_agrees_with_the_index_path(name, monkeypatch):
    model = gallery.load(name)
    index = nonideal.simulate(model)
    import nonideal.modes.system as mode_system

    model = gallery.load(name)          # a fresh model: no compiled mode systems yet
    monkeypatch.setattr(mode_system, "SPECIALIZE_CALLS", 0)
    compiled = nonideal.simulate(model)
    assert any(_compiled_systems(model))
    assert [e["type"] for e in compiled.events] == [e["type"] for e in index.events]
    for a, b in zip(compiled.events, index.events):
        assert abs(a["t"] - b["t"]) <= 1e-10 * max(1.0, abs(b["t"]))
    assert np.max(np.abs(compiled.qd[-1] - index.qd[-1])) <= 1e-8 * (1 + np.max(np.abs(index.qd[-1])))
    assert compiled.diagnostics["energy_balance_relative"] < 1e-8


def test_specialize_false_keeps_the_index_path_bit_for_bit(monkeypatch):
    """Without specialization a run does not depend on what ran before it in the process."""
    import nonideal.modes.system as mode_system

    model = gallery.load("sphere-sliding-on-plane")
    first = nonideal.simulate(model, specialize=False)
    monkeypatch.setattr(mode_system, "SPECIALIZE_CALLS", 0)
    nonideal.simulate(model)  # the modes it integrates get compiled
    assert any(_compiled_systems(model))
    again = nonideal.simulate(model, specialize=False)
    assert np.array_equal(first.t, again.t) and np.array_equal(first.qd, again.qd)
    assert [e["t"] for e in first.events] == [e["t"] for e in again.events]


def test_a_run_takes_the_same_path_whatever_ran_before_it(tmp_path):
    """A run uses the compiled system of a mode once the run itself has evaluated that mode
    SPECIALIZE_CALLS times, so a run is the same bit for bit whatever ran before it in the
    process.  (The count was the process's: the second run of the rough rattleback was
    compiled from its start, differed at rounding, and its stick-slip sequence shifted.)"""
    model = rough_rattleback(tmp_path, 0.2)
    sim = Simulation(model, native=True)
    first = sim.run(t_end=1.3)
    assert [e["type"] for e in first.events][:4] == ["stick", "slip", "stick", "slip"]
    for again in (sim.run(t_end=1.3), nonideal.simulate(model, native=True, t_end=1.3)):
        assert np.array_equal(first.t, again.t) and np.array_equal(first.qd, again.qd)
        assert [e["t"] for e in first.events] == [e["t"] for e in again.events]
    long = Simulation(gallery.load("stick-slip-oscillator"), native=False)
    long.run()
    assert long.solver.hot  # a long run compiles its hot mode
