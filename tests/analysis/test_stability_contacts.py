"""``stability`` of models with contacts: each touching contact linearized as the constraint it
is in its mode -- rolling (gap holonomic, slip rows nonholonomic), sliding (the friction force
with the current slip direction in the gap's reaction).

* the rolling disk written with a contact (``mu = inf``; gap and slip by hand, or from the
  disk's shape) against the gallery's disk with two hand-written rolling constraints: the
  same ``A`` and eigenvalues, and the classical
  threshold of upright rolling ``W^2 > g/(3 r)`` (Neimark & Fufaev) reproduced from the contact;
* a block held by springs on a moving belt (sliding at rest): the friction is a damping
  ``mu m g/v_b`` across the belt, so ``s^2 + (mu g/v_b) s + k/m = 0`` across and ``s^2 + k/m``
  along it -- closed form.
"""

import numpy as np
import pytest

from nonideal.analysis.stability.contacts import as_constraints, contact_modes
from nonideal.analysis.stability.linearize import linearize
from nonideal.errors import ModelError
from nonideal.gallery import rolling_disk
from nonideal.modeling.contacts import LinearizedCoulomb
from nonideal.modeling.modelfile import load_model
from tests.helpers import DATA_DIR

DISK = DATA_DIR / "contacts" / "rolling_disk_contact.toml"
BELT = DATA_DIR / "contacts" / "block_on_belt_springs.toml"


def _sorted(z):
    z = np.asarray(z, complex)
    return z[np.lexsort((np.round(z.imag, 9), np.round(z.real, 9)))]


@pytest.fixture(scope="module")
def disk():
    return load_model(DISK)


@pytest.fixture(scope="module")
def disk_constraints():
    return rolling_disk.build()


@pytest.mark.parametrize("W", [5.0, 2.5, 1.0])
def test_contact_disk_is_the_constrained_disk(disk, disk_constraints, W):
    a = linearize(disk, about="steady", at={"phi'": W})
    b = linearize(disk_constraints, about="steady", at={"phi'": W})
    assert a.contacts["floor"][0] == "stick" and not b.contacts
    assert a.variables == b.variables
    assert np.max(np.abs(a.A - b.A)) < 1e-9
    assert np.max(np.abs(_sorted(a.eigenvalues) - _sorted(b.eigenvalues))) < 1e-9
    assert a.verdict == b.verdict


@pytest.mark.parametrize("W", [5.0, 2.5])
def test_shape_disk_is_the_constrained_disk(disk_constraints, W):
    """The same disk from its shape (the rim of a disk on the plane z = 0): gap and slip derived
    by the library, then linearized as the rolling constraints they are."""
    shaped = load_model(DATA_DIR / "contacts" / "rolling_disk_shape.toml")
    a = linearize(shaped, about="steady", at={"phi'": W})
    b = linearize(disk_constraints, about="steady", at={"phi'": W})
    assert a.contacts["floor"][0] == "stick" and a.variables == b.variables
    assert np.max(np.abs(a.A - b.A)) < 1e-9
    assert np.max(np.abs(_sorted(a.eigenvalues) - _sorted(b.eigenvalues))) < 1e-9


def test_upright_rolling_threshold_from_the_contact(disk):
    p = disk.parameter_values
    Wc = np.sqrt(p["g"] / (3 * p["r"]))
    above = linearize(disk, about="steady", at={"phi'": Wc * 1.001})
    below = linearize(disk, about="steady", at={"phi'": Wc * 0.999})
    assert above.verdict == "critical" and np.max(np.abs(above.eigenvalues.real)) < 1e-9
    assert below.verdict == "unstable" and np.max(below.eigenvalues.real) > 1e-3
    # the closed form of the thin uniform disk (I_d = m r^2/4 about a diameter, I_a = m r^2/2
    # about the axis): (I_d + m r^2) theta'' = m g r theta + (I_a + m r^2) W psi',
    # I_d psi'' = -I_a W theta'  ->  s^2 = -(4/(5 r)) (3 r W^2 - g), besides s = 0
    W = 4.0
    lin = linearize(disk, about="steady", at={"phi'": W})
    r, g = p["r"], p["g"]
    omega2 = 4 / (5 * r) * (3 * r * W ** 2 - g)
    nonzero = [z for z in lin.eigenvalues if abs(z) > 1e-6]
    assert len(nonzero) == 2
    assert all(abs(z ** 2 + omega2) < 1e-9 * omega2 for z in nonzero)


def test_sliding_block_on_belt_closed_form():
    model = load_model(BELT)
    p = model.parameter_values
    m, k, g, mu, v = p["m"], p["k"], p["g"], p["mu"], p["v_b"]
    lin = linearize(model, about="equilibrium")
    assert lin.contacts["belt"][0] == "slide"
    assert lin.q["x"] == pytest.approx(mu * m * g / k, rel=1e-12)
    expected = np.concatenate((np.roots([1, 0, k / m]), np.roots([1, mu * g / v, k / m])))
    assert np.max(np.abs(_sorted(lin.eigenvalues) - _sorted(expected))) < 1e-9


def test_separated_contact_is_ignored():
    """The belt's block held above the belt: the contact is separated and the model, with the
    height free, falls -- no equilibrium; with the height held by a spring it has one."""
    model = load_model(BELT)
    mode = contact_modes(model, {"z": 0.1, "x'": 0, "y'": 0, "z'": 0, "x": 0, "y": 0}, 0.0)
    reduced, labels = as_constraints(model, mode)
    assert labels == {"belt": "separated"}
    assert reduced.constraints == () and reduced.contacts == ()


def test_epsilon_linear_law_is_refused():
    model = load_model(BELT)
    c = model.contacts[0]
    from dataclasses import replace
    smooth = model.replace(contacts=(replace(c, friction=LinearizedCoulomb(c.friction.mu, 0.01)),))
    with pytest.raises(ModelError, match="epsilon-linear law"):
        linearize(smooth, about="equilibrium")


def test_pivoting_torque_in_the_linearization():
    """A disk on a turntable held by a torsion spring pivots at rest: the torque l m g balances
    the spring at psi = l m g/k, and is constant about it: s^2 + k/I = 0."""
    model = load_model(DATA_DIR / "torques" / "disk_torsion_turntable.toml")
    p = model.parameter_values
    I = p["m"] * p["R"] ** 2 / 2
    lin = linearize(model, about="equilibrium")
    assert lin.contacts["table"][0] == "stick" and lin.contacts["table_spin"][0] == "slide-"
    assert lin.q["psi"] == pytest.approx(p["l"] * p["m"] * p["g"] / p["k"], rel=1e-12)
    assert lin.variables == ("psi", "psi'")
    assert np.max(np.abs(_sorted(lin.eigenvalues) - _sorted(np.roots([1, 0, p["k"] / I])))) < 1e-9
