"""Chain of n knife-edge links (nonholonomic benchmark): energy, constraints, forms, sizes."""

import numpy as np
import pytest

from nonideal import derive, gallery, simulate
from nonideal.analysis.crosscheck import compare_forms
from nonideal.equations.formalisms import FORMS
from nonideal.gallery.knife_chain import build


@pytest.fixture(scope="module")
def model():
    return gallery.load("knife-chain")


def test_energy_conserved_and_constraints_held(model):
    tr = simulate(model)
    E = tr.energy["energy"]
    assert np.max(np.abs(E - E[0])) / E[0] < 1e-8
    assert tr.diagnostics["constraint_residual_max"] < 1e-8
    assert np.max(np.abs(tr.energy["reaction_work"])) < 1e-8


def test_knife_edges_hold_along_the_motion(model):
    # velocity of every link centre across its link, recomputed from the samples
    tr = simulate(model, times=np.linspace(0, 5, 11))
    x_d, y_d = tr.velocity("x"), tr.velocity("y")
    th = [tr.coordinate(f"theta{k}") for k in (1, 2, 3)]
    thd = [tr.velocity(f"theta{k}") for k in (1, 2, 3)]
    for k in range(3):
        vx = x_d - sum(thd[j] * np.sin(th[j]) for j in range(k)) - 0.5 * thd[k] * np.sin(th[k])
        vy = y_d + sum(thd[j] * np.cos(th[j]) for j in range(k)) + 0.5 * thd[k] * np.cos(th[k])
        across = -vx * np.sin(th[k]) + vy * np.cos(th[k])
        assert np.max(np.abs(across)) < 1e-9


def test_two_degrees_of_freedom_whatever_n():
    for n in (1, 4):
        eom = derive(build(n), "maggi")
        assert len(eom.unknowns) == 2
        assert eom.multipliers == ()


@pytest.mark.parametrize("n", [1, 3, 6])
def test_all_forms_agree(n):
    report = compare_forms(build(n), count=10)
    assert report.worst() < 1e-10, report
    # a chain of two or more is no Chaplygin system (T depends on the eliminated angles): skipped,
    # saying why; one knife edge (the sleigh) is one
    assert ("Chaplygin system" in report.skipped["chaplygin"]) if n > 1 else "chaplygin" in report.accelerations
    assert set(report.skipped) <= {"chaplygin", "boltzmann_hamel", "poincare_chetaev"}, report.skipped
    assert "kane" in report.accelerations and "voronets" in report.accelerations


def test_reduced_forms_stay_polynomial_in_size():
    # the explicit inverse of the dependent block doubles per link; the reduced forms must
    # switch to auxiliary symbols before that: compiled size grows at most ~ n^3
    from nonideal.equations.dynamics import count_ops
    from nonideal.errors import FormNotApplicable

    sizes = {}
    for n in (4, 8):
        model = build(n)
        for f in FORMS:
            try:
                eom = derive(model, f)
            except FormNotApplicable:  # e.g. a form for holonomic systems only
                continue
            exprs = list(eom.A_) + list(eom.Qf_ - eom.c_) + list(eom.R_) + list(eom.r_)
            for aux in eom.auxiliaries:
                exprs += list(aux.K) + list(aux.Y)
            sizes[f, n] = count_ops(exprs)
    for f in FORMS:
        if (f, 8) in sizes:
            assert sizes[f, 8] < 2 ** 3 * 2 * sizes[f, 4], (f, sizes[f, 4], sizes[f, 8])
