"""Elastic members ([[members]]): shape functions, exact matrices, the model-file keys and
their errors, and the member coupled into every form."""

import tomllib

import numpy as np
import pytest
import sympy as sp

from nonideal import gallery
from nonideal.analysis.crosscheck import compare_forms
from nonideal.errors import ModelError
from nonideal.modeling.members import XI, Member, member_matrices, shape_functions
from nonideal.modeling.modelfile import model_from_dict

BASE = """
[parameters]
L = 1.0
rho_A = 1.0
EI = 1.0
[coordinates]
q = []
"""


@pytest.mark.parametrize("ends", [("clamped", "free"), ("clamped", "pinned"), ("pinned", "free"), ("free", "clamped")])
def test_polynomial_shapes_satisfy_the_geometric_end_conditions(ends):
    for phi in shape_functions("beam", ends, 5, "polynomial"):
        for end, at in zip(ends, (0, 1)):
            if end in ("clamped", "pinned"):
                assert phi.subs(XI, at) == 0
            if end == "clamped":
                assert sp.diff(phi, XI).subs(XI, at) == 0


def test_matrices_are_the_exact_integrals():
    phis = shape_functions("beam", ("clamped", "free"), 3, "polynomial")
    mats = member_matrices("beam", phis)
    for i in range(3):
        for j in range(3):
            assert mats["m"][i, j] == sp.integrate(phis[i] * phis[j], (XI, 0, 1))
            assert mats["k"][i, j] == sp.integrate(sp.diff(phis[i], XI, 2) * sp.diff(phis[j], XI, 2), (XI, 0, 1))
            assert mats["g1"][i, j] == sp.integrate((1 - XI ** 2) / 2 * sp.diff(phis[i], XI) * sp.diff(phis[j], XI), (XI, 0, 1))
    sines = member_matrices("rod", shape_functions("rod", ("fixed", "free"), 2, "modes"))
    assert sp.simplify(sines["m"] - sp.eye(2) / 2) == sp.zeros(2)
    assert sp.simplify(sines["d"][0] - 4 / sp.pi ** 2) == 0     # int xi sin(pi xi/2) = 4/pi^2


def member_file(extra: str) -> dict:
    return tomllib.loads(BASE + "[[members]]\n" + extra)


def test_a_model_file_member_adds_its_coordinates_and_initial_state():
    m = model_from_dict(member_file('name = "beam"\nkind = "beam"\nlength = "L"\nmass_per_length = "rho_A"\n'
                                    'bending_stiffness = "EI"\nends = ["clamped", "free"]\nmodes = 3\n'))
    assert m.coordinates == ("beam_1", "beam_2", "beam_3")
    assert m.numeric_initial()["beam_2'"] == 0.0
    assert [e.name for e in m.elastic_members] == ["beam"] and m.members == ()
    again = m.replace(parameters={"L": 2.0, "rho_A": 1.0, "EI": 1.0})   # not expanded twice
    assert again.coordinates == m.coordinates
    assert sp.simplify(again.kinetic - m.kinetic) == 0


@pytest.mark.parametrize("extra, words", [
    ('name = "b"\nkind = "bean"\nlength = "L"\nends = ["clamped", "free"]\nmodes = 2\n', ["did you mean 'beam'"]),
    ('name = "b"\nkind = "beam"\nlength = "L"\nmass_per_length = "rho_A"\nbending_stiffness = "EI"\n'
     'ends = ["clamped", "fre"]\nmodes = 2\n', ["end condition 'fre'", "did you mean 'free'"]),
    ('name = "b"\nkind = "beam"\nlength = "L"\nmass_per_length = "rho_A"\naxial_stiffness = "EI"\n'
     'ends = ["clamped", "free"]\nmodes = 2\n', ["missing bending_stiffness", "axial_stiffness is not a beam's"]),
    ('name = "b"\nkind = "beam"\nlength = "L"\nmass_per_length = "rho_A"\nbending_stiffness = "EI"\n'
     'ends = ["clamped", "free"]\nmodes = 40\n', ["modes must be a whole number from 1 to 16"]),
    ('name = "b"\nkind = "beam"\nlength = "L"\nmass_per_length = "rho_A"\nbending_stiffness = "EI"\n'
     'ends = ["clamped", "free"]\nmodes = 2\nshape = "modes"\n', ["not trigonometric", "polynomial"]),
    ('name = "b"\nkind = "beam"\nlength = "L"\nmass_per_length = "rho_A"\nbending_stiffness = "E*I"\n'
     'ends = ["clamped", "free"]\nmodes = 2\n', ["'E'", "'I'"]),
    ('name = "b"\nkind = "beam"\nlength = "L"\nmass_per_length = "rho_A"\nbending_stiffness = "EI"\n'
     'ends = ["clamped", "free"]\nmodes = 2\npoints = { tip = "2*L" }\n', ["outside the member"]),
    ('name = "b"\nkind = "beam"\nlength = "L"\nmass_per_length = "rho_A"\nbending_stiffness = "EI"\n'
     'ends = ["clamped", "free"]\nmodes = 2\nlenght = 1\n', ["lenght", "did you mean 'length'"]),
    ('name = "b"\nkind = "beam"\nlength = "L"\nmass_per_length = "rho_A"\nbending_stiffness = "EI"\n'
     'ends = ["clamped", "free"]\nmodes = 2\nframe = "Q"\n', ["frame 'Q' is not declared", "[[frames]]"]),
])
def test_bad_members_are_refused_by_name(extra, words):
    with pytest.raises(ModelError) as err:
        model_from_dict(member_file(extra), "m.toml")
    text = str(err.value)
    for w in words:
        assert w in text, text


def joined_tip():
    """A beam on a spinning hub whose tip is joined to a particle by a constraint."""
    from nonideal.modeling.frames import Frame
    from nonideal.modeling.model import Constraint, Model

    return Model("joined", ["y", "th"], {"L": 1.0, "rho_A": 1.0, "EI": 1.0, "m": 0.3, "J": 0.2},
                 kinetic="m/2*y'^2 + J/2*th'^2",
                 frames=[Frame("B", axis=["0", "0", "1"], angle="th")],
                 constraints=[Constraint.holonomic("joint", "y - dot(pos(tip), B.z)")],
                 members=[Member("beam", "beam", "L", "EI", ("clamped", "free"), 3, mass_per_length="rho_A",
                                 frame="B", deflection="z", points={"tip": "L"})],
                 initial={"y": 0.0, "th": 0.0, "th'": 2.0})


@pytest.mark.parametrize("build", [lambda: gallery.load("elastic-arm-on-cart"), joined_tip],
                         ids=["arm-on-cart", "joined-tip-on-hub"])
def test_every_form_and_the_gauss_principle_give_the_same_accelerations(build):
    """The Galerkin equations from Lagrange's equations of the member's energies are those the
    generalized Gauss principle gives on the family of admissible motions (Yushkov 1999,
    appendix E): every form, and the numerical minimization of the Gauss function, agree."""
    check = compare_forms(build(), count=5)
    assert {"lagrange2", "kane", "appell", "maggi", "gauss"} <= set(check.accelerations), check
    assert check.worst() < 1e-8, check


@pytest.mark.slow
def test_sixteen_shape_functions_stay_well_conditioned():
    """The Legendre-based basis keeps the mass matrix usable at 16 functions (monomials give a
    Hilbert matrix): the cantilever's first three frequencies to 1e-9."""
    from nonideal.analysis.stability.frequencies import natural_frequencies
    from nonideal.modeling.model import Model

    m = Model("cantilever", [], {"L": 1.0, "rho_A": 1.0, "EI": 1.0},
              members=[Member("beam", "beam", "L", "EI", ("clamped", "free"), 16, mass_per_length="rho_A")])
    mass = np.array(member_matrices("beam", shape_functions("beam", ("clamped", "free"), 16, "polynomial"))["m"],
                    dtype=float)
    assert np.linalg.cond(mass) < 1e8
    w = natural_frequencies(m, at={}).omega[:3]
    assert np.allclose(np.sqrt(w), [1.8751040687, 4.6940911330, 7.8547574382], rtol=1e-9)
