"""The tippe top in body speeds (Leine & Glocker 2003's top): its equations in the
quasi-velocity forms are Euler's equations with the table's reaction, in lines a reader can
read, and its motion is that of the same top in coordinate rates."""

import pytest

from nonideal.gallery import tippe_top_speeds as example


@pytest.mark.parametrize("form", example.FORMS)
def test_the_equations_are_eulers_with_the_reaction(form):
    text = example.equations(form)
    lines = text.splitlines()
    # the centre of mass: m u' = the table's force - m g; the body: Euler's equations
    for eq in ("m*u1' = -mu*s[table,1]*lambda_table", "m*u3' = -g*m + lambda_table",
               "A*w1' + (-A + C)*w2*w3 = lambda_table*(", "A*w2' + (A - C)*w1*w3 = lambda_table*(",
               "C*w3' = mu*lambda_table*("):
        assert any(line.strip().startswith(eq) for line in lines), (form, eq)
    # the pivoting torque acts about the normal only: rho s3 appears in the body's equations
    assert sum("rho*s[table,3]" in line for line in lines) >= 3
    assert max(len(line) for line in lines) < 700          # 3 146 characters in e'' before
    assert "e0**4" not in text and "/e0" not in text        # no unreduced |e|^2, no e0 pivots


def test_the_motion_is_the_one_in_coordinate_rates():
    r = example.check()
    assert r["theta_difference"] < 1e-8 and r["theta"][-1] > r["theta"][0]
