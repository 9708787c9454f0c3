"""A servo-constraint that stops being realizable during the motion (Beghin): a point in
gravity is made to follow the parabola y = b x^2 by a thrust of fixed direction (1, 1).  With
z = 1 - 2 b x, the first integral x'^2 = (x0'^2 + g/(2b)) z0^2/z^2 - g/(2b) takes it to
x = 1/(2b) in the finite time T = int_0^{1/(2b)} dx / x'(x), where the thrust is tangent to the
path and the control force grows without bound: the run stops there with exit code 3 naming
the constraint (it was reported as an integration failure, exit code 2)."""


import numpy as np
import pytest
from scipy.integrate import quad

from nonideal.cli import main
from nonideal.errors import MechanicsError
from nonideal.modeling.modelfile import load_model
from nonideal.simulation.hybrid import simulate
from tests.helpers import DATA_DIR

PATH = DATA_DIR / "servo_parabola.toml"


def blow_up_time(b, g, v0):
    c = g / (2 * b)
    return quad(lambda x: 1.0 / np.sqrt((v0 ** 2 + c) / (1 - 2 * b * x) ** 2 - c), 0.0, 1 / (2 * b),
                epsabs=1e-14, epsrel=1e-13)[0]


def test_stops_where_the_thrust_turns_tangent(capsys, tmp_path):
    model = load_model(PATH)
    p = model.parameter_values
    T = blow_up_time(p["b"], p["g"], 1.0)
    with pytest.raises(MechanicsError, match="'program' stop being realizable") as info:
        simulate(model, t_end=0.4)
    assert info.value.exit_code == 3
    assert info.value.t == pytest.approx(T, rel=1e-8)
    code = main(["simulate", str(PATH), "--json", str(tmp_path / "out.json")])
    err = capsys.readouterr().err
    assert code == 3 and err.startswith("mechanics: the servo/quasi-ideal constraint(s) 'program'")
    assert not (tmp_path / "out.json").exists()
    tr = simulate(model, t_end=0.3)                       # before it: the program is followed
    x, y = tr.q[:, 0], tr.q[:, 1]
    assert np.max(np.abs(y - p["b"] * x ** 2)) < 1e-9


def test_regulator_loses_its_program_when_the_wheel_reaches_the_axis(capsys, tmp_path):
    # Manglieva & Beknazarov 2022, (3.5): with a braking torque on shaft 2 (M2 < 0, so k1 < 0)
    # k rho' = k1/rho + k2 drives the wheel to the axis rho = 0 in the finite time (3.10) with
    # rho = 0; there the control (which reaches phi2' only through rho', order 3) loses its lever
    # and the force needed grows without bound: exit 3 naming the program and the order, not an
    # integration failure (exit 2)
    from nonideal.gallery import friction_speed_regulator as reg
    p = dict(reg.DEFAULTS, M2=-0.5)
    t_star = float(reg.quadrature_time(0.0, p))
    with pytest.raises(MechanicsError, match="servo-constraint 'speed': the program is lost") as info:
        simulate(reg.build(**p), t_end=1.0)
    err = info.value
    assert err.exit_code == 3 and err.details["program"] == "speed" and err.details["order_tried"] == 3
    assert err.t == pytest.approx(t_star, rel=1e-6)
    assert abs(err.state["rho"]) < 1e-6 and err.state["rho'"] < -1e3   # rho' = (k1/rho + k2)/k
    code = main(["simulate", "friction-speed-regulator", "--set", "M2=-0.5", "--t-end", "1",
                 "--json", str(tmp_path / "out.json")])
    msg = capsys.readouterr().err
    assert code == 3 and "program is lost" in msg and "order 3" in msg and "rho = " in msg
    assert not (tmp_path / "out.json").exists()
