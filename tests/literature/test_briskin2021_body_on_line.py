"""Briskin et al. 2021, sec. 3.3: stability of phi = 0 for the planar body with a quasi-ideal
constraint -- the corrected (3.25) k = c F l/(J + M c l^2), c = 1 - alpha beta; the printed
condition (3.26) is incomplete beyond c = -J/(M l^2); the constraint is unrealizable there."""

import numpy as np
import pytest

from nonideal import gallery
from nonideal.analysis.stability.linearize import linearize
from nonideal.errors import LinearizationUndefined

MOD = gallery.module("briskin-body-on-line")
M, J, L = 2.0, 0.5, 0.4
JC = J / (M * L * L)          # 1.5625


@pytest.mark.parametrize("F, c", [(3.0, 0.75), (-3.0, -0.5 * JC), (3.0, -2.0 * JC), (-3.0, -2.0 * JC)])
def test_corrected_variational_equation(F, c):
    lin = linearize(MOD.build(F=F, alpha=1.0, beta=1.0 - c), about="steady", at={"phi": 0.0})
    k = c * F * L / (J + M * c * L * L)
    assert lin.variables == ("phi", "phi'") and lin.dependent == ("yc", "yc'")
    assert set(lin.ignorable) == {"xc", "xc'"}          # the body slides along the line, accelerated
    assert np.allclose(lin.A, [[0, 1], [-k, 0]], atol=1e-10 * max(1, abs(k)))
    assert lin.verdict == ("critical" if k > 0 else "unstable")
    printed_stable = c * F > 0                           # (3.25)-(3.26) as printed
    assert printed_stable == (k > 0) or c < -JC          # they disagree exactly beyond -J/(M l^2)


def test_unrealizable_at_the_boundary():
    with pytest.raises(LinearizationUndefined):
        linearize(MOD.build(alpha=1.0, beta=1.0 + JC), about="steady", at={"phi": 0.0})


def test_y_equation_sign_3_22():
    """(3.22) prints M y_C'' = F sin(phi) - lambda/(1 - alpha beta); with R_y = lambda/c (3.21)
    it is + lambda/c, and lambda is (3.24)'s c J (M l phi'^2 - F) sin(phi)/(J + M c l^2 cos^2)."""
    import math

    from nonideal.analysis.evaluation import evaluate

    phi, w, F, alpha, beta = 0.3, 0.5, 3.0, 0.5, 0.5
    c = 1 - alpha * beta
    at = {"phi": phi, "yc": -L * math.sin(phi), "phi'": w, "xc'": 1.0, "yc'": -L * math.cos(phi) * w}
    d = evaluate(MOD.build(F=F, alpha=alpha, beta=beta), at=at).to_dict()
    lam, ydd = d["reactions"]["line"]["lambda"], d["qddot"]["yc"]
    assert d["multipliers"]["line"] * c == pytest.approx(lam, rel=1e-12)   # lambda = det(A) mu
    assert lam == pytest.approx(c * J * (M * L * w ** 2 - F) * math.sin(phi)
                                / (J + M * c * L ** 2 * math.cos(phi) ** 2), rel=1e-10)
    assert M * ydd - F * math.sin(phi) == pytest.approx(lam / c, rel=1e-10)
    assert abs(M * ydd - F * math.sin(phi) + lam / c) > 0.5      # not the printed sign
