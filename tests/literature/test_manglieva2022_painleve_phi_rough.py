"""Seed 000 (Manglieva & Beknazarov), section 1.1, (1.40)-(1.41): Painleve's two points with M
sliding on a rough line, in the coordinates (x, y, phi), phi = pi/2 - theta measured from a
downward Oy (the "elliptic pendulum whose slider has friction").  Derived (and checked here
against the library at random sliding states):

    d/dt[(m + m1) x' + m1 l phi' cos(phi)] = -f N sign(x'),
    N = (m + m1) g + m1 l (phi'' sin(phi) + phi'^2 cos(phi)),                    ((1.41) first)
    l phi'' + x'' cos(phi) + g sin(phi) = 0.                                     ((1.41) second)

**Misprints**: the seed prints the first equation with ``- m1 l phi' cos(phi)`` in the momentum
and ``phi'^2`` where ``phi''`` belongs in the normal force (residual up to ~60 here), and
(1.40) ``R_x = f R_y sign(x')`` puts friction along the velocity for a downward Oy (R_y < 0
there); the second equation is right."""


import numpy as np
import pytest

from nonideal.analysis.crosscheck import compare_forms
from nonideal.analysis.evaluation import evaluate
from nonideal.modeling.modelfile import load_model
from tests.helpers import DATA_DIR

PATH = DATA_DIR / "friction" / "painleve_phi_rough.toml"


@pytest.fixture(scope="module")
def model():
    return load_model(PATH)


def test_derived_1_41_holds_and_the_printed_one_does_not(model):
    p = model.parameter_values
    m, m1, l, g, f = (p[k] for k in ("m", "m1", "l", "g", "f"))
    rng = np.random.default_rng(3)
    printed_worst = 0.0
    for _ in range(12):
        phi, phid = rng.uniform(-1.3, 1.3), rng.uniform(-3, 3)
        xd = float(rng.choice([-1, 1]) * rng.uniform(0.2, 2))
        ev = evaluate(model, at={"x": 0.0, "y": 0.0, "phi": phi, "x'": xd, "y'": 0.0, "phi'": phid})
        assert ev.mode == ("line:slide+" if xd > 0 else "line:slide-")
        xdd, phidd = ev.qdd[0], ev.qdd[2]
        N = (m + m1) * g + m1 * l * (phidd * np.sin(phi) + phid ** 2 * np.cos(phi))
        assert ev.contacts["line"]["normal"] == pytest.approx(N, rel=1e-12)
        dp = (m + m1) * xdd + m1 * l * (phidd * np.cos(phi) - phid ** 2 * np.sin(phi))
        assert dp == pytest.approx(-f * N * np.sign(xd), rel=1e-11, abs=1e-11)
        assert l * phidd + xdd * np.cos(phi) + g * np.sin(phi) == pytest.approx(0.0, abs=1e-11)
        printed = ((m + m1) * xdd - m1 * l * (phidd * np.cos(phi) - phid ** 2 * np.sin(phi))
                   + f * ((m + m1) * g + m1 * l * (np.cos(phi) + np.sin(phi)) * phid ** 2) * np.sign(xd))
        printed_worst = max(printed_worst, abs(printed))
    assert printed_worst > 1.0


def test_forms_agree_while_sliding(model):
    assert compare_forms(model, contact_state="slide", count=10).worst() < 1e-10
