"""Models that parse but whose mechanics is ill-posed fail well: an inconsistent initial
state (which constraint, the residual), dependent constraints (named), a singular mass
matrix (which coordinate), and an integration failure (time and reason).  Exit code 2."""

import re

import pytest

from nonideal.analysis.checks import check_model
from nonideal.cli import main
from nonideal.errors import (
    InconsistentInitialConditions,
    IntegrationFailed,
    MechanicsError,
    ModelError,
    SingularSystem,
)
from nonideal.analysis.evaluation import evaluate
from nonideal.modeling.modelfile import load_model
from nonideal.simulation.hybrid import simulate
from tests.helpers import DATA_DIR

DATA = DATA_DIR


def cli(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_inconsistent_initial_coordinates(capsys):
    path = DATA / "inconsistent_initial.toml"
    expected = (f"{path}: [initial]: constraint 'rod' is violated by the initial coordinates: "
                "residual 9.000e-02; give consistent values (expressions in the parameters are "
                "allowed) or leave a dependent coordinate out to have it completed")
    model = load_model(path)
    for run in (check_model, evaluate, lambda m: simulate(m, t_end=1.0)):
        with pytest.raises(InconsistentInitialConditions) as info:
            run(model)
        assert str(info.value) == expected
    for command in ("check", "evaluate", "simulate"):
        code, out, err = cli(capsys, command, path, *(["--t-end", "1"] if command == "simulate" else []))
        assert (code, out, err) == (2, "", f"error: {expected}\n"), command


def test_inconsistent_initial_velocities(capsys, tmp_path):
    text = (DATA / "pendulum_xy.toml").read_text().replace("\"x'\" = 0.0", "\"x'\" = 1.0\n\"y'\" = 1.0")
    path = tmp_path / "velocities.toml"
    path.write_text(text)
    code, _, err = cli(capsys, "evaluate", path)
    assert code == 2
    assert err == (f"error: {path}: [initial]: constraint 'rod' is violated by the initial "
                   "velocities: residual -4.000e-01; give consistent velocities or leave a "
                   "dependent velocity out\n")


def test_initial_coordinates_that_cannot_be_completed(capsys, tmp_path):
    text = (DATA / "pendulum_xy.toml").read_text().replace("x = 0.6\ny = -0.8\n", "x = 1.6\n")
    path = tmp_path / "far.toml"
    path.write_text(text)
    code, _, err = cli(capsys, "check", path)
    assert code == 2
    assert err.startswith(f"error: {path}: [initial]: the coordinates y cannot be completed: no "
                          "values satisfy the constraints 'rod' (residual")
    assert "check the given values, or give these coordinates too" in err


def test_same_constraint_twice_is_named(capsys):
    path = DATA / "duplicate_constraint.toml"
    expected = (f"{path}: dependent (redundant) constraints: 'rod_again' repeats constraint "
                "'rod' at t = 0 (x = 0.6, y = -0.8); the multipliers of dependent constraints "
                "are not unique: remove 'rod_again' or make the constraints independent")
    with pytest.raises(SingularSystem) as info:
        check_model(load_model(path))
    assert str(info.value) == expected
    for command in ("check", "evaluate", "simulate"):
        code, out, err = cli(capsys, command, path)
        assert (code, out, err) == (2, "", f"error: {expected}\n"), command


def test_proportional_constraints_are_named_with_the_factor(capsys):
    path = DATA / "dependent_constraints.toml"
    expected = (f"{path}: dependent (redundant) constraints: 'floor_twice' repeats constraint "
                "'floor' (its gradient is 2 times that of 'floor') at t = 0 (x = 0, y = 0); the "
                "multipliers of dependent constraints are not unique: remove 'floor_twice' or "
                "make the constraints independent")
    with pytest.raises(SingularSystem) as info:
        check_model(load_model(path))
    assert str(info.value) == expected
    for command in ("check", "simulate"):
        code, _, err = cli(capsys, command, path)
        assert (code, err) == (2, f"error: {expected}\n"), command


def test_constraint_with_zero_gradient(capsys, tmp_path):
    text = (DATA / "dependent_constraints.toml").read_text().replace('expr = "2*y"', 'expr = "x^2"')
    text = text.replace("x = 0.0", "x = 0.0\n").replace('"x\'" = 1.0', '"x\'" = 0.0')
    path = tmp_path / "zero_gradient.toml"
    path.write_text(text)
    code, _, err = cli(capsys, "check", path)
    assert code == 2
    assert "constraint 'floor_twice' has a zero gradient at t = 0 (x = 0, y = 0)" in err
    assert "write it with a nonzero gradient (y = 0 instead of y^2 = 0)" in err


def test_singular_mass_matrix_names_the_coordinate(capsys):
    path = DATA / "singular_mass.toml"
    expected = (f"{path}: singular mass matrix at t = 0 (x = 0, y = 0): the kinetic energy does "
                "not depend on y', so coordinate 'y' has no inertia and its acceleration is "
                "undetermined; give it inertia (a mass or moment of inertia in [energy] kinetic "
                "or [[bodies]]), constrain it with a [[constraints]] block, or remove the "
                "coordinate")
    with pytest.raises(SingularSystem) as info:
        check_model(load_model(path))
    assert str(info.value) == expected
    for command in ("check", "evaluate", "simulate"):
        code, out, err = cli(capsys, command, path)
        assert (code, out, err) == (2, "", f"error: {expected}\n"), command


def test_singular_combination_of_velocities(capsys, tmp_path):
    text = (DATA / "singular_mass.toml").read_text().replace('"m/2*x\'^2"', '"m/2*(x\' + y\')^2"')
    path = tmp_path / "combination.toml"
    path.write_text(text)
    code, _, err = cli(capsys, "check", path)
    assert code == 2
    assert "the kinetic energy does not depend on the velocity combination x' - y'" in err


def test_mass_matrix_singular_only_along_a_constrained_motion_is_fine(capsys, tmp_path):
    text = (DATA / "singular_mass.toml").read_text().replace(
        "[initial]", '[[constraints]]\nname = "rail"\nexpr = "y"\n\n[initial]')
    path = tmp_path / "constrained.toml"
    path.write_text(text)
    code, out, _ = cli(capsys, "check", path)
    assert code == 0 and out.rstrip().endswith("ok")


def test_indefinite_kinetic_energy(capsys, tmp_path):
    text = (DATA / "singular_mass.toml").read_text().replace('"m/2*x\'^2"', '"m/2*x\'^2 - m/2*y\'^2"')
    path = tmp_path / "negative.toml"
    path.write_text(text)
    code, _, err = cli(capsys, "check", path)
    assert code == 2
    assert "the kinetic energy is not positive definite at t = 0 (x = 0, y = 0): along the " \
           "velocity combination y' it is negative" in err


@pytest.mark.parametrize("name", ["singular_mass.toml", "duplicate_constraint.toml"])
def test_python_api_simulate_names_the_singularity(name):
    with pytest.raises(SingularSystem):
        simulate(load_model(DATA / name))


def test_integration_failure_time_and_reason(capsys, tmp_path):
    path = DATA / "blowup.toml"
    model = load_model(path)
    with pytest.raises(IntegrationFailed) as info:
        simulate(model)
    exc = info.value
    assert exc.exit_code == 2
    # x'' = x^2 from x0 = 100 at rest: blow-up at 2.9744774 / sqrt(100)
    assert exc.t == pytest.approx(0.29744774, rel=1e-6)
    assert exc.mode == "free"
    assert "step size" in exc.reason
    message = str(exc)
    assert message.startswith(f"{path}: integration failed at t = 0.29744774")
    assert "the solution probably blows up (grows without bound) near this time" in message
    assert "--t-end below 0.297448" in message
    assert ".." not in message
    code, out, err = cli(capsys, "simulate", path)
    assert code == 2 and out == ""
    assert err == f"error: {message}\n"


def test_painleve_and_friends_keep_exit_code_3():
    assert MechanicsError("x").exit_code == 3
    assert issubclass(SingularSystem, ModelError) and SingularSystem("x").exit_code == 2


def test_painleve_paradox_exit_code_3_with_explanation(capsys, tmp_path):
    import math

    from nonideal.errors import PainleveParadox

    path = DATA / "painleve_rod_paradox.toml"
    with pytest.raises(PainleveParadox) as info:
        evaluate(load_model(path))
    exc = info.value
    assert exc.exit_code == 3 and exc.t == 0.0
    critical = (1 + 3 * math.cos(0.8)**2) / (3 * math.sin(0.8) * math.cos(0.8))
    assert float(exc.details["floor: critical friction coefficient"]) == pytest.approx(critical, rel=1e-5)
    for command in ("evaluate", "simulate"):
        code, out, err = cli(capsys, command, path, "--json", tmp_path / "out.json")
        assert code == 3 and out == "", command
        assert err.startswith("mechanics: Painleve paradox (inconsistency) at contact(s) floor")
        assert "  at t = 0\n" in err and "floor: critical friction coefficient: 1.63817" in err
        assert not (tmp_path / "out.json").exists()


def test_constraint_outside_its_domain_at_the_initial_state(capsys, tmp_path):
    text = (DATA / "pendulum_xy.toml").read_text().replace('"x^2 + y^2 - l^2"', '"sqrt(-x) - 1"')
    text = text.replace("y = -0.8\n", "y = -0.8\n\"y'\" = 0.0\n")
    path = tmp_path / "domain.toml"
    path.write_text(text)
    expected = (f"error: {path}: [initial]: constraint 'rod' cannot be evaluated at the initial "
                "state (t = 0, x = 0.6, y = -0.8): its value or gradient is not a finite number (a "
                "square root or logarithm of a negative number, a division by zero, or asin/acos "
                "beyond [-1, 1]); give initial values inside its domain or rewrite it\n")
    for command in ("check", "evaluate", "simulate"):
        code, out, err = cli(capsys, command, path)
        assert (code, out, err) == (2, "", expected), command


@pytest.mark.parametrize("reason, advice", [
    ("Required step size is less than spacing between numbers.",
     "use method = \"Radau\" in [simulation] if the problem is stiff"),
    ("more than 10000 mode switches (chattering or Zeno behaviour)",
     "impacts that repeat without end (Zeno) stop with restitution = 0"),
    ("the step size collapsed below 1e-9 of the time span for 2000 steps: the right-hand side "
     "is not smooth here", "make the right-hand side smooth there"),
])
def test_integration_failed_advice_fits_the_reason(reason, advice):
    exc = IntegrationFailed(1.25, "floor:slide+", reason, "model.toml")
    message = str(exc)
    assert message.startswith("model.toml: integration failed at t = 1.25 in mode [floor:slide+]: ")
    assert "Fix: simulate to an earlier end time (--t-end below 1.25 or [simulation] t_end)" in message
    assert advice in message and ".." not in message
    assert (exc.t, exc.mode, exc.reason) == (1.25, "floor:slide+", reason)


def test_singular_configuration_away_from_the_initial_state(capsys):
    path = DATA / "polar_coordinates.toml"
    assert cli(capsys, "check", path)[0] == 0
    code, out, err = cli(capsys, "evaluate", path, "--at", "r=0, phi=0, r'=1, phi'=0")
    assert code == 2 and out == ""
    assert err == (f"error: {path}: singular mass matrix at t = 0 (r = 0, phi = 0): the kinetic "
                   "energy does not depend on phi', so coordinate 'phi' has no inertia and its "
                   "acceleration is undetermined; give it inertia (a mass or moment of inertia in "
                   "[energy] kinetic or [[bodies]]), constrain it with a [[constraints]] block, or "
                   "remove the coordinate; the equations are regular at the initial state, so "
                   "this is a singular configuration of the coordinates or constraints (like r = 0 "
                   "in polar coordinates): choose another state or other coordinates\n")


NEGATIVE_MASS_ON_A_ROUGH_FLOOR = """
[model]
name = "block with a negative mass"
format = 1
[parameters]
m = -1.0
g = 9.81
[coordinates]
q = ["x", "y"]
[energy]
kinetic = "m/2*(x'^2 + y'^2)"
potential = "m*g*y"
[[contacts]]
name = "floor"
gap = "y"
slip = ["x'"]
mu = 0.3
[initial]
x = 0.0
y = 0.0
"x'" = 1.0
"y'" = 0.0
[simulation]
t_end = 1.0
"""


@pytest.mark.parametrize("with_contact", [True, False])
def test_negative_mass_is_bad_input_in_every_command(capsys, tmp_path, with_contact):
    # was: simulate ran and the body fell upward (no contact), or a "Painleve paradox" (exit 3)
    text = NEGATIVE_MASS_ON_A_ROUGH_FLOOR
    if not with_contact:
        text = text.split("[[contacts]]")[0] + "[initial]" + text.split("[initial]")[1]
    path = tmp_path / "negative_mass.toml"
    path.write_text(text)
    model = load_model(path)
    for run in (check_model, evaluate, lambda m: simulate(m, t_end=1.0)):
        with pytest.raises(SingularSystem, match="kinetic energy is not positive definite.*along the velocity "
                           "combination x' it is negative"):
            run(model)
    for command in ("check", "evaluate", "simulate", "derive"):
        code, out, err = cli(capsys, command, path, "--json", tmp_path / "out.json")
        assert code == 2 and err.rstrip().endswith("masses and moments of inertia of [[bodies]]"), command
        assert not (tmp_path / "out.json").exists()


@pytest.mark.parametrize("potential, what", [("m*g*y + asin(x + 1.5)", "[energy] potential"),
                                             ("m*g*y + log(x)", "[energy] potential"),
                                             ("m*g*y + exp(1000*(x + 1))", "[energy] potential")])
def test_terms_not_finite_at_the_initial_state_are_named(capsys, tmp_path, potential, what):
    # was: exit 3, "no consistent set of held constraints ... among []"
    text = NEGATIVE_MASS_ON_A_ROUGH_FLOOR.replace("m = -1.0", "m = 1.0").replace('"m*g*y"', f'"{potential}"')
    path = tmp_path / "nan.toml"
    path.write_text(text)
    model = load_model(path)
    for run in (check_model, evaluate, lambda m: simulate(m, t_end=1.0)):
        with pytest.raises(ModelError, match=rf"{re.escape(what)} is not finite at t = 0 \(x = 0, y = 0\)"):
            run(model)
    code, _, err = cli(capsys, "evaluate", path)
    assert code == 2 and "change the initial state or the expression" in err


def test_servo_constraint_that_its_reaction_cannot_realize_is_named(tmp_path):
    # the control acts along y, the program x = t needs a force along x: exit 3, named.  The
    # free motion keeps x = t by itself (x' = 1 at t0), so the program does not determine the
    # control: Beghin's indeterminate case, found when the program is differentiated
    text = (NEGATIVE_MASS_ON_A_ROUGH_FLOOR.replace("m = -1.0", "m = 1.0").split("[[contacts]]")[0]
            + '[[constraints]]\nname = "prog"\ntype = "servo"\nexpr = "x - t"\nreaction = ["0", "1"]\n'
            + "[initial]" + NEGATIVE_MASS_ON_A_ROUGH_FLOOR.split("[initial]")[1])
    path = tmp_path / "servo.toml"
    path.write_text(text)
    with pytest.raises(MechanicsError, match="'prog': its control direction does not act on the program") as info:
        evaluate(load_model(path))
    assert info.value.exit_code == 3 and "indeterminate" in str(info.value)


def test_check_validates_the_friction_data(tmp_path):
    # check used to say "ok" where evaluate and simulate refused the contact
    text = NEGATIVE_MASS_ON_A_ROUGH_FLOOR.replace("m = -1.0", "m = 1.0").replace("mu = 0.3", "mu = 0.3\nmu_static = 0.1")
    path = tmp_path / "mu.toml"
    path.write_text(text)
    with pytest.raises(ModelError, match="mu_static = 0.1 is smaller than the kinetic mu = 0.3"):
        check_model(load_model(path))


def test_two_programs_one_control_direction_is_impossible(tmp_path):
    # Béghin 1922 (Appell's treatise): r = 2 servo-constraints realized by j = 1 control direction (the same actuator
    # declared for both): impossible in general -- exit 3 with Beghin's count, the programs named
    text = (NEGATIVE_MASS_ON_A_ROUGH_FLOOR.replace("m = -1.0", "m = 1.0").split("[[contacts]]")[0]
            + '[[constraints]]\nname = "px"\ntype = "servo"\nexpr = "x - t"\nreaction = ["1", "1"]\n'
            + '[[constraints]]\nname = "py"\ntype = "servo"\nexpr = "y - t^2"\nreaction = ["1", "1"]\n'
            + "[initial]" + NEGATIVE_MASS_ON_A_ROUGH_FLOOR.split("[initial]")[1])
    path = tmp_path / "r_gt_j.toml"
    path.write_text(text)
    for run in (check_model, evaluate, lambda m: simulate(m, t_end=1.0)):
        with pytest.raises(MechanicsError, match=r"2 servo/quasi-ideal constraints \('px', 'py'\) but their "
                           r"control directions span only j = 1.*impossible \(Béghin's count"):
            run(load_model(path))
