"""Briskin et al. 2021, sec. 3.2: a point on a circle with a quasi-ideal constraint -- the
Riccati equation (3.13) with the coefficients of Table 1 (the printed (3.11)/(3.14) signs do
not give them: derived here), the regimes of Table 1, omega(t), the reactions (3.12)/(3.18) and
their work against the simulation."""

import math

import pytest
import sympy as sp

from nonideal import gallery
from nonideal.gallery.briskin_point_on_circle import TABLE_1, check, regime, riccati_coefficients
from nonideal.modeling.modelfile import load_model

PATH = gallery.model_path("briskin-point-on-circle")


def _B(tangential_sign):
    """B of omega' = A omega^2 + B derived from the equations of motion on r = r0 with the
    tangential generalized force sign * F r cos(gamma) and the radial -F sin(gamma)."""
    m, F, r0, gam, beta, w = sp.symbols("m F r0 gamma beta omega")
    R_r = F * sp.sin(gam) - m * r0 * w ** 2          # radial equation on the circle
    R_phi = -beta * R_r                                # (3.12)
    wdot = sp.expand((tangential_sign * F * r0 * sp.cos(gam) + R_phi) / (m * r0 ** 2))
    A = wdot.coeff(w, 2)
    B = sp.simplify(wdot - A * w ** 2)
    return A, B, (m, F, r0, gam, beta)


def test_table_1_coefficients_need_the_forward_force():
    A, B, (m, F, r0, gam, beta) = _B(+1)
    values = {m: 1, F: 2, r0: 2, gam: sp.pi / 4}
    for b, (A_t, B_t, _, _) in TABLE_1.items():
        assert float(A.subs(values).subs(beta, b)) == pytest.approx(A_t)
        assert float(B.subs(values).subs(beta, b)) == pytest.approx(B_t, abs=1e-15)
    # (3.11) as printed (-F r cos(gamma)) gives -(1 + A)/sqrt(2): not Table 1
    _, B_printed, _ = _B(-1)
    assert float(B_printed.subs(values).subs(beta, 1)) == pytest.approx(-1.5 / math.sqrt(2))
    # and (3.14) as printed, F sin(g) beta/(m r0^2) + F cos(g)/(m r0), is (1 + A)/sqrt(2)
    assert float((F * sp.sin(gam) * beta / (m * r0 ** 2) + F * sp.cos(gam) / (m * r0))
                 .subs(values).subs(beta, 1)) == pytest.approx(1.5 / math.sqrt(2))


@pytest.mark.parametrize("beta", sorted(TABLE_1))
def test_regimes_of_table_1_and_the_motion(beta):
    model = load_model(PATH, parameters={"beta": beta})
    A_t, B_t, ratio_printed, case = TABLE_1[beta]
    A, B = riccati_coefficients(model.parameter_values)
    assert (A, B) == pytest.approx((A_t, B_t), abs=1e-12)
    reg = regime(model)
    assert reg.case == case
    if ratio_printed not in (None, 0.0):
        # printed B/A rounded (0.707 as 0.7), except beta = -1: -2.12, printed -2.18
        assert B / A == pytest.approx(ratio_printed, abs=0.01 if beta != -1 else 0.07)
    r = check(model)
    assert max(r["omega_error"], r["R_r_error"], r["R_phi_error"], r["work_error"]) < 1e-8


def test_blow_up_time_and_limits():
    blow = regime(load_model(PATH, parameters={"beta": 1.0}))
    A, B = 0.5, 0.5 / math.sqrt(2)
    assert blow.blowup_time == pytest.approx(math.pi / 2 / math.sqrt(A * B), rel=1e-14)
    up = regime(load_model(PATH, parameters={"beta": -1.0}))
    assert up.limit == pytest.approx(math.sqrt(1.5 / math.sqrt(2) / 0.5), rel=1e-12)  # +sqrt(-B/A)
    down = regime(load_model(PATH, parameters={"beta": 3.0}))
    assert down.limit == pytest.approx(-math.sqrt(0.5 / math.sqrt(2) / 1.5), rel=1e-12)  # -sqrt(-B/A)
