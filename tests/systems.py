"""Small systems built with the Python API that the tests of several stages share."""

from pathlib import Path

from nonideal import Constraint, Model, Particle, PlanarBody, gallery
from nonideal.modeling.modelfile import load_model


def sleigh():
    """Chaplygin sleigh (the gallery's "chaplygin-sleigh", Yushkov 1999, app. A)."""
    return Model(
        name="Chaplygin sleigh", coordinates=["x", "y", "theta"],
        parameters={"m": 2.0, "I": 0.3, "a": 0.4},
        bodies=[PlanarBody("sleigh", "m", "I", ["x + a*cos(theta)", "y + a*sin(theta)"], "theta")],
        constraints=[Constraint.nonholonomic("knife", "-x'*sin(theta) + y'*cos(theta)")],
        initial={"x": 0.0, "y": 0.0, "theta": 0.0, "x'": 1.0, "theta'": 1.5},
    )


def painleve(midpoint=False, th0=0.3, thd0=0.8, v0=0.5, independent=None):
    """M (mass m) on the line y = 0 and M1 (m1) joined by a rod l; gravity along +y
    (Manglieva & Beknazarov 2022, sec. 1.1); with *midpoint*, the velocity of the rod's midpoint
    along the rod (sec. 1.3, problem 1)."""
    cons = [Constraint.holonomic("line", "y"),
            Constraint.holonomic("rod", "(x1 - x)^2 + (y1 - y)^2 - l^2")]
    if midpoint:
        cons.append(Constraint.nonholonomic("midpoint", "(x1 - x)*(y1' + y') - (y1 - y)*(x1' + x')"))
        v0 = f"l*{thd0}/(2*sin({th0}))"
    return Model(
        name="Painleve two points" + (" with the midpoint constraint" if midpoint else ""),
        coordinates=["x", "y", "x1", "y1"],
        parameters={"m": 1.0, "m1": 2.0, "l": 0.5, "g": 9.81},
        bodies=[Particle("M", "m", ["x", "y"]), Particle("M1", "m1", ["x1", "y1"])],
        gravity=["0", "g"], constraints=cons,
        initial={"x": 0.0, "y": 0.0, "x1": f"l*cos({th0})", "y1": f"l*sin({th0})",
                 "x'": v0, "y'": 0.0, "x1'": f"{v0} - l*sin({th0})*{thd0}",
                 "y1'": f"l*cos({th0})*{thd0}"},
        independent=independent,
    )


def rotating_line(w=0.7):
    """A bead on the line y cos(wt) = x sin(wt) turning about the origin, under gravity."""
    return Model(
        name="bead on a rotating line", coordinates=["x", "y"],
        parameters={"m": 1.3, "w": w, "g": 9.81},
        bodies=[Particle("P", "m", ["x", "y"])], gravity=["0", "-g"],
        constraints=[Constraint.holonomic("line", "y*cos(w*t) - x*sin(w*t)")],
        initial={"x": 0.8, "y": 0.0, "x'": 0.3, "y'": "0.8*w"},
    )


def sphere_on_plane(pull=0.0, spin=(0.0, 0.0), mu=0.1):
    """A sphere (m = 1, R = 0.1) at rest on a rough plane (Coulomb, two slip components), pulled
    along x by *pull* m g; *spin* = (b', a') gives it the slip (-R b', R a') of those rates."""
    from nonideal.modeling.modelfile import model_from_dict

    return model_from_dict({
        "model": {"name": "sphere on a plane", "format": 1},
        "parameters": {"m": 1.0, "R": 0.1, "g": 9.81, "mu": mu},
        "coordinates": {"q": ["x", "y", "z", "a", "b", "c"]},
        "energy": {"kinetic": "m/2*(x'^2 + y'^2 + z'^2) + (2*m*R^2/5)/2*(a'^2 + b'^2 + c'^2)",
                   "potential": f"m*g*z - {pull}*m*g*x"},
        "contacts": [{"name": "plane", "gap": "z - R", "slip": ["x' - R*b'", "y' + R*a'"], "mu": "mu"}],
        "initial": {"x": 0, "y": 0, "z": "R", "a": 0, "b": 0, "c": 0, "x'": 0, "y'": 0, "z'": 0,
                    "a'": spin[1], "b'": spin[0], "c'": 0},
        "simulation": {"t_end": 0.1}}, "sphere.toml")


def rough_rattleback(tmp_path, pitch, spin=-2.0):
    """The gallery's rattleback with Coulomb friction mu = 0.1, pitched by *pitch* rad and spun
    at *spin* rad/s (a model file in *tmp_path*): it sticks and slips 30-40 times in 5 s."""
    text = Path(gallery.__file__).with_name("rattleback.toml").read_text(encoding="utf-8")
    for old, new in (('mu = "inf"', 'mu = "0.1"'), ("b = 0.01", f"b = {pitch}"),
                     ('value = -2.0, unit = "rad/s"', f'value = {spin}, unit = "rad/s"')):
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / "rough_rattleback.toml"
    path.write_text(text, encoding="utf-8")
    return load_model(path)
