"""The compact kernel (M, G, B as vectors of their nonzero entries) and the sparse
saddle-point solves give the numbers of the dense path: the same models built twice, once
with the threshold :data:`~nonideal.numeric.compact.SPARSE_MIN_N` lowered so that even their
few coordinates take the sparse path."""

import numpy as np
import pytest
from scipy.sparse import issparse

from nonideal import gallery, simulate
from nonideal.errors import ModelError
from nonideal.modes.solver import ModeSolver
from nonideal.modes.switching import select_mode
from nonideal.modes.system import system_of
from nonideal.numeric import compact as compact_module
from nonideal.numeric.blocks import SparseSaddle, definite_above, definite_above_sparse, dependent_rows
from nonideal.numeric.consistency import complete_state
from nonideal.numeric.kernel import kernel_of, parameter_vector

MODELS = ["chaplygin-sleigh", "painleve-two-points", "nlink-pendulum", "knife-chain", "block-on-incline",
          "sphere-sliding-on-plane"]


def pair(name, monkeypatch):
    """(dense model, compact model) of the gallery example *name* (two loads: the kernel is
    cached per model)."""
    dense = gallery.load(name)
    kernel_of(dense)
    with monkeypatch.context() as mp:
        mp.setattr(compact_module, "SPARSE_MIN_N", 1)
        compact = gallery.load(name)
        kernel_of(compact)
    assert not kernel_of(dense).compact and kernel_of(compact).compact
    return dense, compact


@pytest.mark.parametrize("name", MODELS)
def test_compact_solves_equal_dense_at_admissible_states(name, monkeypatch):
    dense, compact = pair(name, monkeypatch)
    kd, kc = kernel_of(dense), kernel_of(compact)
    params = parameter_vector(dense)
    q0, qd0, _ = complete_state(kd, dense.numeric_initial(), params, dense.t0)
    sd, sc = ModeSolver(kd, params), ModeSolver(kc, params)
    mode = select_mode(sd, dense.t0, q0, qd0)
    assert select_mode(sc, dense.t0, q0, qd0).label() == mode.label()
    rng = np.random.default_rng(7)
    for k in range(4):
        q = q0 + (0.0 if k == 0 else 1e-3) * rng.standard_normal(kd.n)
        qd = qd0 + (0.0 if k == 0 else 1e-3) * rng.standard_normal(kd.n)
        a, b = sd.solve(0.1, q, qd, mode), sc.solve(0.1, q, qd, mode)
        assert np.allclose(b.qdd, a.qdd, rtol=1e-12, atol=1e-12)
        assert np.allclose(b.values, a.values, rtol=1e-12, atol=1e-12)
        assert np.allclose(b.multipliers, a.multipliers, rtol=1e-12, atol=1e-12)
        for name, cf in a.contacts.items():
            assert np.allclose(b.contacts[name].F, cf.F, rtol=1e-12, atol=1e-12)
        assert issparse(b.M) and np.allclose(b.M.toarray(), a.M, rtol=1e-14, atol=1e-14)
        # the right-hand side of the simulation: ModeSystem by index, dense LU vs SuperLU
        y = np.concatenate((q, qd))
        ya, yb = system_of(kd, mode).solve(sd, 0.1, y, mode), system_of(kc, mode).solve(sc, 0.1, y, mode)
        assert np.allclose(yb, ya, rtol=1e-12, atol=1e-12)
    if system_of(kc, mode).sparse is not None:
        assert system_of(kc, mode).sparse.s == kd.n + system_of(kd, mode).m


@pytest.mark.parametrize("name", ["chaplygin-sleigh", "painleve-two-points", "block-on-incline"])
def test_compact_simulation_follows_the_dense_one(name, monkeypatch):
    dense, compact = pair(name, monkeypatch)
    t_end = min(1.0, dense.simulation.t_end)
    a, b = simulate(dense, t_end=t_end), simulate(compact, t_end=t_end)
    assert [e["mode"] for e in a.events] == [e["mode"] for e in b.events]
    assert np.allclose([e["t"] for e in b.events], [e["t"] for e in a.events], rtol=1e-9, atol=1e-12)
    assert np.allclose(b.q[-1], a.q[-1], rtol=1e-9, atol=1e-9)
    assert np.allclose(b.qd[-1], a.qd[-1], rtol=1e-9, atol=1e-9)


def test_compact_diagnosis_names_a_singular_mass_matrix(monkeypatch):
    from nonideal import Model
    monkeypatch.setattr(compact_module, "SPARSE_MIN_N", 1)
    model = Model(name="no inertia", coordinates=["x", "y"], parameters={"m": 1.0},
                  kinetic="m/2*x'^2", initial={"x": 0.0, "y": 0.0, "x'": 1.0, "y'": 0.0})
    from nonideal.analysis.checks import check_model
    with pytest.raises(ModelError, match="singular mass matrix.*y"):
        check_model(model)


def test_sparse_helpers():
    A = np.diag([2.0, 1.0, 3.0, 4.0])
    A[0, 2] = A[2, 0] = 0.5
    from scipy.sparse import csr_matrix
    for tol in (0.5, 0.9, 1.0, 1.5):
        assert definite_above_sparse(csr_matrix(A), tol) == definite_above(A, tol)
    G = csr_matrix(np.array([[1.0, 0, 0, 0], [0, 1.0, 1.0, 0], [2.0, 0, 0, 0], [0, 0, 0, 1.0], [0, 2.0, 2.0, 1.0]]))
    assert dependent_rows(G, 1e-10) == [2, 4]
    K = np.array([[2.0, 0, 1.0], [0, 3.0, 1.0], [1.0, 1.0, 0]])
    rows, cols = np.nonzero(K)
    saddle = SparseSaddle(3, rows, cols, np.arange(len(rows)))
    x, _ = SparseSaddle.factor(saddle.matrix(saddle.data(K[rows, cols])), np.array([1.0, 2.0, 3.0]))
    assert np.allclose(x, np.linalg.solve(K, [1.0, 2.0, 3.0]), rtol=1e-14)


def elastic_chain(n):
    """n links, each its own (x, y, th) and a knife edge, springs between the centres."""
    from nonideal import Model
    from nonideal.modeling.bodies import PlanarBody
    from nonideal.modeling.model import Constraint
    import math
    init = {}
    for i in range(n):
        th = 0.3 * (-1) ** i
        init.update({f"x{i}": float(i), f"y{i}": 0.0, f"th{i}": th,
                     f"x{i}'": math.cos(th), f"y{i}'": math.sin(th), f"th{i}'": 0.0})
    springs = "+".join(f"(x{i + 1}-x{i}-l)^2+(y{i + 1}-y{i})^2" for i in range(n - 1))
    return Model(name="elastic chain", coordinates=[f"{a}{i}" for i in range(n) for a in ("x", "y", "th")],
                 parameters={"m": 1.0, "l": 1.0, "k": 100.0},
                 bodies=[PlanarBody(f"link{i}", "m", "m*l^2/12", [f"x{i}", f"y{i}"], f"th{i}") for i in range(n)],
                 constraints=[Constraint.nonholonomic(f"knife{i}", f"-x{i}'*sin(th{i}) + y{i}'*cos(th{i})")
                              for i in range(n)],
                 potential=f"k/2*({springs})", initial=init,
                 simulation={"t_end": 0.2, "rtol": 1e-10, "atol": 1e-12})


@pytest.mark.slow
def test_chain_of_200_knife_edges_is_solved_sparse_and_keeps_its_invariants():
    model = elastic_chain(200)   # 600 coordinates: a compact kernel
    kernel = kernel_of(model)
    assert kernel.compact
    # M diagonal, G two entries per row: no n^2 layout
    assert kernel.dynamics.size == 600 + 600 + 2 * 200 + 200 + 2 * 200
    traj = simulate(model)
    system = system_of(kernel, select_mode(ModeSolver(kernel, parameter_vector(model)), 0.0,
                                           traj.q[0], traj.qd[0]))
    assert system.sparse is not None and system.sparse.s == 800
    E = np.asarray(traj.energy["energy"])
    assert np.max(np.abs(E - E[0])) < 1e-9 * abs(E[0])   # springs conservative, knife edges ideal
    assert traj.diagnostics["constraint_residual_max"] < 1e-12
    th, xd, yd = traj.q[-1][2::3], traj.qd[-1][0::3], traj.qd[-1][1::3]
    assert np.max(np.abs(-xd * np.sin(th) + yd * np.cos(th))) < 1e-12


@pytest.mark.slow
def test_check_of_3000_particles_keeps_m_sparse():
    from nonideal import Model, Particle
    from nonideal.analysis.checks import check_model
    n = 3000
    coords = [f"{a}{k}" for k in range(n) for a in "xyz"]
    init = {c: 0.0 for c in coords}
    init.update({c + "'": 0.1 for c in coords})
    model = Model(name="free particles", coordinates=coords, parameters={"m": 2.0, "g": 9.81},
                  bodies=[Particle(f"p{k}", "m", [f"x{k}", f"y{k}", f"z{k}"]) for k in range(n)],
                  gravity=["0", "0", "-g"], initial=init)
    assert check_model(model).initial_mode == "free"
    kernel = kernel_of(model)
    assert kernel.compact and kernel.dynamics.size == 2 * 3 * n   # M's diagonal and F
    sol = ModeSolver(kernel, parameter_vector(model)).solve(0.0, np.zeros(3 * n), np.full(3 * n, 0.1),
                                                            select_mode(ModeSolver(kernel, parameter_vector(model)),
                                                                        0.0, np.zeros(3 * n), np.full(3 * n, 0.1)))
    assert np.allclose(sol.qdd[2::3], -9.81, rtol=1e-15) and not np.any(sol.qdd[0::3]) and issparse(sol.M)


@pytest.mark.parametrize("name", ["block-on-incline", "painleve-two-points", "chaplygin-sleigh"])
def test_compact_evaluate_reports_the_dense_numbers(name, monkeypatch):
    from nonideal.analysis.evaluation import evaluate
    dense, compact = pair(name, monkeypatch)
    a, b = evaluate(dense).to_dict(), evaluate(compact).to_dict()
    assert a.keys() == b.keys()
    for key in ("qddot", "multipliers", "reactions", "contacts", "mode"):
        assert repr(b[key]) == repr(a[key]) or np.allclose(np.asarray(b[key], dtype=float) if isinstance(b[key], list) else 0,
                                                             np.asarray(a[key], dtype=float) if isinstance(a[key], list) else 0,
                                                             rtol=1e-12, atol=1e-12), key
