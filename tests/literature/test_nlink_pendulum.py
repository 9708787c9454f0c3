"""Planar n-link pendulum (benchmark system): closed-form small oscillations, energy, forms."""

import numpy as np
import pytest

from nonideal import gallery, simulate
from nonideal.analysis.crosscheck import compare_forms
from nonideal.gallery.nlink_pendulum import build, frequencies_closed_form, linearized_frequencies


@pytest.fixture(scope="module")
def model():
    return gallery.load("nlink-pendulum")


def test_two_link_small_oscillation_frequencies_closed_form():
    # equal masses and lengths: w^2 = (2 -/+ sqrt 2) g / l
    w = linearized_frequencies(build(2, m=1.0, l=1.0, g=9.81))
    assert np.allclose(w ** 2, (2 + np.array([-1, 1]) * np.sqrt(2)) * 9.81, rtol=1e-8)
    # unequal masses and lengths against the general closed form
    two = build(2)
    two = two.replace(parameters={"m1": 2.0, "m2": 0.5, "l1": 0.7, "l2": 1.3, "g": 9.81})
    w = linearized_frequencies(two)
    assert np.allclose(w, frequencies_closed_form(2.0, 0.5, 0.7, 1.3, 9.81), rtol=1e-8)


def test_two_link_small_oscillation_in_the_simulation():
    # a pure slow normal mode at small amplitude oscillates with the slow frequency
    w = frequencies_closed_form(1.0, 1.0, 1.0, 1.0, 9.81)
    eps = 1e-4
    shape = np.array([1.0, np.sqrt(2)])  # slow mode of the equal 2-link pendulum
    model = build(2, q0=0.0).replace(initial={"q1": float(eps * shape[0]), "q2": float(eps * shape[1]),
                                              "q1'": 0.0, "q2'": 0.0})
    period = 2 * np.pi / w[0]
    tr = simulate(model, times=[0.0, period / 2, period])
    q1 = tr.coordinate("q1")
    assert abs(q1[1] + eps) < 1e-9 and abs(q1[2] - eps) < 1e-9


def test_energy_conserved(model):
    tr = simulate(model)
    E = tr.energy["energy"]
    assert np.max(np.abs(E - E[0])) / abs(E[0]) < 1e-8
    assert tr.diagnostics["energy_balance_relative"] < 1e-8


@pytest.mark.parametrize("n", [1, 3, 5])
def test_all_forms_agree(n):
    report = compare_forms(build(n), count=10)
    assert report.worst() < 1e-10, report


def test_mass_matrix_is_the_hanging_mass_matrix():
    # M_jk = mu_jk l_j l_k cos(q_j - q_k), mu_jk = sum_{i >= max(j,k)} m_i
    from nonideal.numeric.kernel import kernel_of, parameter_vector

    model = build(4)
    kernel = kernel_of(model)
    p = parameter_vector(model)
    q = np.array([0.3, -0.2, 0.9, 0.1])
    M = kernel.dynamics(kernel.state_input(0.0, q, np.zeros(4), p))["M"]
    mu = np.array([[4 - max(j, k) for k in range(4)] for j in range(4)], dtype=float)
    assert np.allclose(M, mu * np.cos(q[:, None] - q[None, :]), atol=1e-13)
