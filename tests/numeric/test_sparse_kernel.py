"""The sparse kernel (only nonzero entries compiled) and the block solves give the numbers of
the dense path; a system of many bodies compiles O(n_q) entries, not n_q^2."""

import numpy as np
import pytest
import symengine as se

from nonideal import Model, Particle
from nonideal.analysis.checks import check_model
from nonideal.equations.dynamics import dynamics_of
from nonideal.modes.solver import ModeSolver
from nonideal.modes.system import system_of
from nonideal.modes.types import Mode
from nonideal.numeric.blocks import BlockSolver, blocks_of, definite_above
from nonideal.numeric.kernel import Compiled, kernel_of, parameter_vector


def dense_outputs(kernel):
    """The kernel's dynamics compiled the old way: every entry of the dense M, G, B."""
    dyn, rows, n = kernel.dyn, kernel.rows, kernel.n
    outputs = {"M": dyn.M, "F": list(dyn.F)}
    if rows:
        outputs.update(G=[[r.G[j] for j in range(n)] for r in rows], gamma=[r.gamma for r in rows],
                       B=[[r.B[j] for r in rows] for j in range(n)])
    return Compiled(kernel.symbols, outputs, sparse=False)


@pytest.mark.parametrize("name", ["nlink-pendulum", "rolling-disk", "painleve-rod", "sleeping-top"])
def test_sparse_kernel_equals_dense_on_gallery_models(gallery_model, name):
    model = gallery_model(name)
    kernel = kernel_of(model)
    dense = dense_outputs(kernel)
    assert dense.compiled == dense.size
    zeros = sum(1 for e in list(kernel.dyn.M) if e == 0)
    assert kernel.dynamics.compiled <= kernel.dynamics.size - zeros  # M's zeros are not compiled
    rng = np.random.default_rng(3)
    params = parameter_vector(model)
    solver = ModeSolver(kernel, params)
    for _ in range(3):
        q, qd = rng.uniform(-1, 1, kernel.n), rng.uniform(-1, 1, kernel.n)
        x = kernel.state_input(0.3, q, qd, params)
        a, b = kernel.dynamics(x), dense(x)
        for key in b:
            assert np.allclose(a[key], b[key], rtol=1e-14, atol=1e-14), key
        # accelerations of the free motion (no rows held): the solver's path vs a dense solve
        if not kernel.rows:
            qdd = solver.solve(0.3, q, qd, Mode()).qdd
            assert np.allclose(qdd, np.linalg.solve(b["M"], b["F"]), rtol=1e-12, atol=1e-12)


def test_raw_zeroes_a_foreign_buffer_once():
    x, y = se.symbols("x y")
    c = Compiled([x, y], {"M": [[x, 0], [0, y * y]], "s": 0})
    assert (c.compiled, c.size) == (2, 5)
    assert c.entries("M").tolist() == [0, 3] and c.entries("s").tolist() == []
    out = np.full(c.size, np.nan)
    c.raw(np.array([2.0, 3.0]), out)
    assert out.tolist() == [2.0, 0.0, 0.0, 9.0, 0.0]
    batch = c.batch(np.array([[1.0, 2.0], [3.0, 4.0]]))
    assert batch.tolist() == [[1.0, 0.0, 0.0, 4.0, 0.0], [3.0, 0.0, 0.0, 16.0, 0.0]]


def mixed(n_particles: int, springs: bool = True) -> Model:
    """Particles on springs (1 x 1 blocks of M), a double pendulum (one 2 x 2 block) and a
    particle in a plane (two 1 x 1 blocks)."""
    coords = [f"{a}{k}" for k in range(n_particles) for a in "xyz"] + ["th1", "th2", "X", "Y"]
    bodies = [Particle(f"p{k}", "m", [f"x{k}", f"y{k}", f"z{k}"]) for k in range(n_particles)]
    bodies += [Particle("a", "m", ["sin(th1)", "-cos(th1)", "0"]),
               Particle("b", "m", ["sin(th1) + sin(th2)", "-cos(th1) - cos(th2)", "0"]),
               Particle("c", "2*m", ["X", "Y", "X*Y"])]
    V = "k/2*(" + " + ".join(f"(x{i + 1} - x{i} - 1)^2 + z{i}*z{i + 1}" for i in range(n_particles - 1)) + ")"
    init = {c: 0.1 * i for i, c in enumerate(coords)}
    init.update({c + "'": 0.05 * (-1) ** i for i, c in enumerate(coords)})
    return Model(name="mixed", coordinates=coords, parameters={"m": 1.3, "g": 9.81, "k": 5.0},
                 bodies=bodies, gravity=["0", "-g", "0"], potential=V if springs else "0", initial=init)


def test_block_solve_and_gradients_of_many_bodies():
    model = mixed(22)                                 # 70 coordinates: above BLOCKS_MIN_N
    dyn = dynamics_of(model)
    # the potential's gradient term by term is se.diff's, expression for expression
    assert all(se.expand(se.diff(dyn.V, q) - d) == 0 for q, d in zip(dyn.q, dyn.dV))
    kernel = kernel_of(model)
    n = kernel.n
    assert len(dyn.mass_entries) == n + 4              # the diagonal and two couplings
    params = parameter_vector(model)
    solver = ModeSolver(kernel, params)
    system = system_of(kernel, Mode())
    assert system.blocks is not None and len(system.blocks.blocks) == n - 2
    q = np.array([model.numeric_initial()[c] for c in model.coordinates])
    qd = np.array([model.numeric_initial()[c + "'"] for c in model.coordinates])
    out = kernel.dynamics(kernel.state_input(0.0, q, qd, params))
    qdd = solver.solve(0.0, q, qd, Mode()).qdd
    assert np.allclose(qdd, np.linalg.solve(out["M"], out["F"]), rtol=1e-12, atol=1e-12)


def test_blocks_helpers():
    rng = np.random.default_rng(0)
    A = np.zeros((7, 7))
    for idx in ([0, 3], [1], [2, 4, 6], [5]):
        R = rng.random((len(idx), len(idx)))
        A[np.ix_(idx, idx)] = R @ R.T + len(idx) * np.eye(len(idx))
    rows, cols = np.nonzero(A)
    blocks = blocks_of(7, zip(rows, cols))
    assert [b.tolist() for b in blocks] == [[0, 3], [1], [2, 4, 6], [5]]
    b = rng.random(7)
    assert np.allclose(BlockSolver(7, blocks).solve(A, b), np.linalg.solve(A, b), rtol=1e-13)
    A[5, 5] = -1.0                                     # not positive definite: the caller goes dense
    assert BlockSolver(7, blocks).solve(A, b) is None
    assert not definite_above(A, 0.0)
    A[5, 5] = 1.0
    w = np.linalg.eigvalsh(A)
    assert definite_above(A, 0.99 * w.min()) and not definite_above(A, 1.01 * w.min())
    big = np.diag(np.linspace(1.0, 2.0, 100))         # by blocks (100 >= BLOCKS_MIN_N)
    assert definite_above(big, 0.99) and not definite_above(big, 1.01)


def test_check_of_300_particles_compiles_O_n_entries():
    n = 300
    coords = [f"{a}{k}" for k in range(n) for a in "xyz"]
    init = {c: 0.0 for c in coords}
    init.update({c + "'": 0.1 for c in coords})
    model = Model(name="free particles", coordinates=coords, parameters={"m": 1.0, "g": 9.81},
                  bodies=[Particle(f"p{k}", "m", [f"x{k}", f"y{k}", f"z{k}"]) for k in range(n)],
                  gravity=["0", "0", "-g"], initial=init)
    report = check_model(model)
    assert report.counts["n_q"] == 3 * n and report.initial_mode == "free"
    kernel = kernel_of(model)
    n_q = 3 * n
    # M's diagonal and the n gravity forces are compiled, not the n_q^2 entries of M, and the
    # layout holds M's entries only (a compact kernel: 900 >= SPARSE_MIN_N)
    assert kernel.compact
    assert kernel.dynamics.compiled == n_q + n
    assert kernel.dynamics.size == n_q + n_q
    assert len(system_of(kernel, Mode()).blocks.blocks) == n_q
    qdd = ModeSolver(kernel, parameter_vector(model)).solve(0.0, np.zeros(n_q), np.full(n_q, 0.1), Mode()).qdd
    assert np.allclose(qdd[2::3], -9.81) and np.allclose(qdd[0::3], 0) and np.allclose(qdd[1::3], 0)
