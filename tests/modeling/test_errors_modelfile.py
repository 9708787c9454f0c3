"""Bad model files fail well: exit code 2, the file, the key, what is wrong and the fix --
every problem in one run.  Each case is checked through the Python API (``load_model`` /
``Model``) and through the command line (in-process ``nonideal.cli.main``)."""


import pytest

from nonideal import Constraint, Model
from nonideal.cli import main
from nonideal.errors import ModelError
from nonideal.modeling.modelfile import load_model
from tests.helpers import DATA_DIR

DATA = DATA_DIR


def cli(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def load_error(name) -> ModelError:
    with pytest.raises(ModelError) as info:
        load_model(DATA / name)
    assert type(info.value).exit_code == 2
    return info.value


def lines(err: str) -> list[str]:
    """stderr of the CLI without the leading 'error: '."""
    assert err.startswith("error: ")
    return err[len("error: "):].rstrip("\n").split("\n")


def test_unknown_symbol_did_you_mean(capsys):
    path = DATA / "typo_thetta.toml"
    expected = (f"{path}: constraint 'knife_edge': expr: unknown symbol 'thetta' "
                "(did you mean 'theta'?)")
    assert str(load_error("typo_thetta.toml")) == expected
    code, out, err = cli(capsys, "check", path)
    assert (code, out) == (2, "")
    assert lines(err) == [expected]


def test_missing_parameters_all_listed_in_one_run(capsys):
    path = DATA / "missing_parameters.toml"
    exc = load_error("missing_parameters.toml")
    p = f"{path}: "
    expected = [
        p + "[energy] potential: unknown symbol 'g'",
        p + "[energy] potential: unknown symbol 'k'",
        p + "[forces] x: unknown symbol 'b'",
        p + "[forces] x: unknown symbol 'c'",
        p + "[forces] y: unknown symbol 'b'",
        p + "missing parameters: b, c, g, k -- used in: b (in [forces] x, [forces] y); "
            "c (in [forces] x); g (in [energy] potential); k (in [energy] potential); define "
            "each in [parameters] as name = value (SI units), or correct the spelling; there "
            "are no default values",
    ]
    assert str(exc).split("\n") == expected
    code, _, err = cli(capsys, "check", path)
    assert code == 2 and lines(err) == expected


def test_missing_parameters_python_api():
    with pytest.raises(ModelError) as info:
        Model(name="api", coordinates=["x", "y"], parameters={"m": 1.0},
              kinetic="m/2*(x'^2 + y'^2)", potential="m*g*y + k*x^2",
              constraints=[Constraint.holonomic("line", "y - a*x")])
    problems = info.value.problems
    assert "[energy] potential: unknown symbol 'g'" in problems
    assert "[energy] potential: unknown symbol 'k'" in problems
    assert "constraint 'line': expr: unknown symbol 'a'" in problems
    assert problems[-1].startswith("missing parameters: a, g, k -- used in: a (in constraint "
                                   "'line': expr); g (in [energy] potential)")
    assert str(info.value).count("\n") == 3       # no file name prefix for the API


def test_missing_initial_values_all_listed(capsys):
    path = DATA / "missing_initial.toml"
    model = load_model(path)          # the file itself is well formed
    from nonideal.analysis.checks import check_model
    from nonideal.errors import InconsistentInitialConditions

    with pytest.raises(InconsistentInitialConditions) as info:
        check_model(model)
    p = f"{path}: [initial]: "
    expected = [
        p + "coordinates y, z are not given and not determined by the constraints",
        p + "velocities x', y', z' are not given and not determined by the constraints",
        p + "missing initial values; add them to [initial] (e.g. y = 0.0 and \"x'\" = 0.0; "
            "velocity keys are quoted because of the prime); there are no default values",
    ]
    assert str(info.value).split("\n") == expected
    for command in ("check", "evaluate", "simulate"):
        code, out, err = cli(capsys, command, path)
        assert code == 2, command
        if command == "simulate":    # the model has no t_end either: both are reported
            assert lines(err)[0] == (f"{path}: no end time: give t_end in [simulation] (e.g. "
                                     "t_end = 10.0), or --t-end T or --times on the command line")
            assert lines(err)[1:] == expected
        else:
            assert lines(err) == expected, command
    code, out, err = cli(capsys, "simulate", path, "--t-end", "1")
    assert code == 2 and lines(err) == expected


def test_velocities_partly_determined_by_a_constraint(capsys, tmp_path):
    text = (DATA / "pendulum_xy.toml").read_text().replace("\"x'\" = 0.0\n", "")
    path = tmp_path / "no_velocity.toml"
    path.write_text(text)
    code, _, err = cli(capsys, "check", path)
    assert code == 2
    assert lines(err)[0] == (f"{path}: [initial]: velocities x', y' are not given and the "
                             "constraints determine only 1 of them; give 1 more")


def test_unknown_keys_everywhere_with_suggestions(capsys):
    path = DATA / "unknown_keys.toml"
    p = f"{path}: "
    expected = [
        p + "top level: unknown key 'simulaton' (did you mean 'simulation'?); allowed: bodies, "
            "constraints, contacts, controls, coordinates, energy, forces, forms, frames, gravity, initial, "
            "loads, members, model, outputs, parameters, points, simulation, speeds, units",
        p + "[energy]: unknown key 'potentail' (did you mean 'potential'?); allowed: kinetic, "
            "potential",
        p + "[[constraints]] #1 'floor': unknown key 'expresion' (did you mean 'expr'?); "
            "allowed: cost, description, expr, losses, name, reaction, restitution, root, transform, type, unilateral",
        p + "[[constraints]] #1 'floor': missing expr (a constraint needs name = \"...\" and "
            "expr = \"...\", meaning expr = 0)",
    ]
    assert str(load_error("unknown_keys.toml")).split("\n") == expected
    code, _, err = cli(capsys, "check", path)
    assert code == 2 and lines(err) == expected


def test_unknown_keyword_in_contacts_and_simulation(tmp_path):
    text = (DATA / "pendulum_xy.toml").read_text() + (
        '\n[[contacts]]\nname = "floor"\ngap = "y + 1"\nslip = ["x\'"]\nmu = 0.3\nmus = 0.4\n')
    text = text.replace("t_end = 1.0", "t_end = 1.0\nrtoll = 1e-9")
    path = tmp_path / "keys.toml"
    path.write_text(text)
    message = str(pytest.raises(ModelError, load_model, path).value)
    assert "[simulation]: unknown key 'rtoll' (did you mean 'rtol'?)" in message
    assert "[[contacts]] #1 'floor': unknown key 'mus' (did you mean 'mu'?)" in message


def test_malformed_expressions_key_and_column(capsys):
    path = DATA / "malformed_expression.toml"
    p = f"{path}: "
    expected = [
        p + "[energy] kinetic: malformed expression at column 11: expected a number, a name "
            "or '(' but found '*'",
        "    m/2*x'^2 +* 3",
        "              ^",
        p + "[energy] potential: malformed expression at column 5: '(' is never closed",
        "    m*g*(x + 1",
        "        ^",
    ]
    assert str(load_error("malformed_expression.toml")).split("\n") == expected
    code, _, err = cli(capsys, "check", path)
    assert code == 2 and lines(err) == expected


def test_wrong_toml_syntax(capsys):
    path = DATA / "bad_toml.toml"
    message = str(load_error("bad_toml.toml"))
    first = message.split("\n")[0]
    assert first == (f"{path}: not valid TOML: Expected ']' at the end of a table declaration "
                     "(at line 1, column 7)")
    assert "    line 1: [model\n" in message
    code, out, err = cli(capsys, "simulate", path)
    assert code == 2 and out == "" and lines(err)[0] == first


def test_missing_model_file(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(DATA)
    with pytest.raises(ModelError) as info:
        load_model("pendulum_yx.toml")
    assert str(info.value).startswith("model file not found: pendulum_yx.toml; check the path")
    code, _, err = cli(capsys, "check", "pendulum_yx.toml")
    assert code == 2
    assert lines(err)[0].startswith("model file not found: pendulum_yx.toml (did you mean "
                                    "'pendulum_xy.toml'?); check the path")
    code, _, err = cli(capsys, "simulate", tmp_path / "nowhere.toml")
    assert code == 2 and "model file not found" in err


def test_format_version_mismatch(capsys):
    path = DATA / "format_2.toml"
    expected = (f"{path}: [model] format: this version of nonideal reads model files of format "
                "1, the file declares format = 2; it was written for a newer nonideal: upgrade "
                "nonideal")
    assert str(load_error("format_2.toml")) == expected
    code, _, err = cli(capsys, "check", path)
    assert code == 2 and lines(err) == [expected]


@pytest.mark.parametrize("change, message", [
    (("unilateral = false", 'unilateral = "yes"'),
     "[[constraints]] #1 'rod': unilateral must be true or false (got 'yes')"),
    (('expr = "x^2 + y^2 - l^2"', "expr = true"),
     "[[constraints]] #1 'rod': expr must be an expression in quotes or a number (got a boolean True)"),
    (('q = ["x", "y"]', 'q = "x"'),
     "[coordinates] q: must be a list of names in quotes, e.g. q = [\"x\", \"theta\"] (got a string 'x')"),
    (("t_end = 1.0", "t_end = true"),
     "[simulation]: t_end must be a number, or an expression in the parameters (got True)"),
    (("t_end = 1.0", "t_end = 1.0\nt0 = \"zero\""),
     "[simulation]: t0: unknown symbol 'zero'"),
    (("m = 1.0", "m = true"),
     "[parameters] m: value must be a finite number or an expression in the other parameters, "
     "in quotes (got True)"),
    (("m = 1.0", 'm = {value = 1.0, units = "kg"}'),
     "[parameters] m: unknown key 'units' (did you mean 'unit'?)"),
    (("unilateral = false", 'reaction = "0"'),
     "[[constraints]] #1 'rod': reaction must be a list of expressions"),
    (("unilateral = false", 'reaction = ["0", "1", "2"]'),
     "[[constraints]] #1 'rod': reaction must have 2 entries (got 3)"),
    (("unilateral = false", "restitution = 2"),
     "[[constraints]] #1 'rod': restitution must be a number in [0.0, 1.0], or an expression in "
     "the parameters (got 2)"),
    (('type = "holonomic"', 'type = "holonomc"'),
     "constraint 'rod': type 'holonomc' unknown (did you mean 'holonomic'?); use holonomic, "
     "nonholonomic or servo"),
    (("t_end = 1.0", 't_end = 1.0\nmethod = "rk45"'),
     "[simulation] method: 'rk45' unknown (did you mean 'RK45'?)"),
    (('"x\'" = 0.0', '"xx\'" = 0.0'),
     "[initial] xx': not a coordinate or velocity (did you mean 'x''?)"),
])
def test_wrong_values_are_named(tmp_path, change, message):
    text = (DATA / "pendulum_xy.toml").read_text().replace(
        'expr = "x^2 + y^2 - l^2"', 'expr = "x^2 + y^2 - l^2"\nunilateral = false')
    assert change[0] in text
    path = tmp_path / "model.toml"
    path.write_text(text.replace(change[0], change[1], 1))
    with pytest.raises(ModelError) as info:
        load_model(path)
    assert any(message in p for p in info.value.problems), info.value.problems
    assert str(info.value).startswith(f"{path}: ")


def test_structural_and_expression_problems_reported_together(tmp_path):
    text = (DATA / "typo_thetta.toml").read_text().replace("[energy]", "[energy]\nkinetik = \"0\"")
    path = tmp_path / "both.toml"
    path.write_text(text)
    problems = pytest.raises(ModelError, load_model, path).value.problems
    assert any("unknown key 'kinetik' (did you mean 'kinetic'?)" in p for p in problems)
    assert any("unknown symbol 'thetta' (did you mean 'theta'?)" in p for p in problems)


def test_identically_zero_constraint(capsys):
    path = DATA / "zero_constraint.toml"
    expected = (f"{path}: constraint 'nothing': expr 'x - x' is identically zero, so it "
                "constrains nothing; correct the expression or remove the constraint")
    assert str(load_error("zero_constraint.toml")) == expected
    code, _, err = cli(capsys, "check", path)
    assert code == 2 and lines(err) == [expected]
    with pytest.raises(ModelError) as info:
        Model(name="api", coordinates=["x", "y"], parameters={"m": 1.0},
              kinetic="m/2*(x'^2 + y'^2)",
              constraints=[Constraint.holonomic("trig", "sin(x)^2 + cos(x)^2 - 1")])
    assert "constraint 'trig': expr 'sin(x)^2 + cos(x)^2 - 1' is identically zero" in str(info.value)


def test_malicious_model_file_runs_nothing(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "malicious.toml"
    path.write_text((DATA / "malicious.toml").read_text())
    code, out, err = cli(capsys, "simulate", path, "--json", "out.json")
    assert code == 2 and out == ""
    assert "[energy] kinetic: malformed expression at column 12" in err
    assert "[energy] potential: malformed expression at column 8: ':' is not allowed" in err
    assert "[forces] x: malformed expression" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["malicious.toml"]


def test_any_wrong_type_anywhere_is_a_model_error():
    """Replace every value of a model file (each key, each list entry) by values of the
    wrong type: the loader reports a ModelError, never another exception."""
    import copy
    import tomllib

    from nonideal.modeling.modelfile import model_from_dict

    data = tomllib.loads((DATA / "painleve_rod_paradox.toml").read_text())
    data["constraints"] = [{"name": "c", "expr": "x - 1", "reaction": ["0", "1", "0"]}]
    data["bodies"] = [{"type": "particle", "name": "p", "mass": "m", "position": ["x", "y"]}]

    def paths(node, prefix=()):
        items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
        for key, value in items:
            yield prefix + (key,)
            yield from paths(value, prefix + (key,))

    wrong = [True, -1, 1.5, float("nan"), "", "1/0", "x", [], ["a"], {}, {"a": 1}, [[1]]]
    count = 0
    for path in list(paths(data)):
        for value in wrong:
            mutated = copy.deepcopy(data)
            node = mutated
            for key in path[:-1]:
                node = node[key]
            node[path[-1]] = value
            try:
                model_from_dict(mutated, "fuzz.toml")
            except ModelError as exc:
                assert str(exc).startswith("fuzz.toml: ")
            count += 1
    assert count > 300


def test_kinetic_energy_must_be_smooth_in_the_velocities(tmp_path):
    text = (DATA / "pendulum_xy.toml").read_text().replace('"m/2*(x\'^2 + y\'^2)"',
                                                          '"m/2*(abs(x\')*x\' + y\'^2)"')
    path = tmp_path / "rough.toml"
    path.write_text(text)
    message = str(pytest.raises(ModelError, load_model, path).value)
    assert message == (f"{path}: [energy] kinetic: Abs(x') is not differentiable in the "
                       "velocities; the kinetic energy must be smooth in the velocities (the "
                       "equations of motion use its second derivatives), e.g. m/2*x'^2 instead "
                       "of m/2*abs(x')^2")


def test_one_unknown_name_without_a_near_match_says_how_to_declare_it():
    from nonideal import Model

    with pytest.raises(ModelError) as info:
        Model(name="x", coordinates=["x"], parameters={"k": 1.0}, kinetic="x'^2/2",
              potential="k*x^2/2 + c*x", initial={"x": 0, "x'": 0})
    assert info.value.problems == [
        "[energy] potential: unknown symbol 'c'",
        "'c' is not a parameter, coordinate or known function: define it in [parameters] as "
        "c = value (SI units), or correct the spelling; there are no default values"]


def _pendulum(tmp_path, name, text=None, edit=lambda s: s, encoding="utf-8"):
    path = tmp_path / name
    path.write_text(edit(text or (DATA / "pendulum_xy.toml").read_text()), encoding=encoding)
    return path


def test_parameter_named_like_a_multiplier(tmp_path):
    # the equations print the multiplier of constraint 'rod' as lambda_rod
    path = _pendulum(tmp_path, "clash.toml", edit=lambda s: s.replace("[parameters]\n", "[parameters]\nlambda_rod = 2.0\n"))
    with pytest.raises(ModelError, match=r"\[parameters\] 'lambda_rod' is the name of the multiplier of "
                       "constraint or contact 'rod' in the equations; rename it"):
        load_model(path)


def test_control_characters_are_refused_and_a_byte_order_mark_is_not(tmp_path):
    esc = _pendulum(tmp_path, "esc.toml", edit=lambda s: s.replace("[model]\n", '[model]\ndescription = "a\\nb"\n', 1)
                    .replace('name = "', 'name = "\\u001b[31mred\\u0007 ', 1))
    with pytest.raises(ModelError) as info:
        load_model(esc)
    assert info.value.problems == ["[model] name: contains the control character(s) '\\x07', '\\x1b'; remove them "
                                   "(only plain text is allowed in a model file's strings, and newlines and "
                                   "tabs in a description)"]
    bom = _pendulum(tmp_path, "bom.toml", encoding="utf-8-sig")
    assert bom.read_bytes()[:3] == b"\xef\xbb\xbf"
    assert load_model(bom).coordinates == load_model(DATA / "pendulum_xy.toml").coordinates


def test_description_of_a_constraint_must_be_text(tmp_path):
    path = _pendulum(tmp_path, "desc.toml", edit=lambda s: s.replace('name = "rod"', 'name = "rod"\ndescription = 5'))
    with pytest.raises(ModelError, match=r"\[\[constraints\]\] 'rod': description must be a string"):
        load_model(path)


def test_errors_found_when_deriving_name_the_file(tmp_path):
    from nonideal.analysis.checks import check_model

    path = _pendulum(tmp_path, "transform.toml",
                     edit=lambda s: s.replace('name = "rod"', 'name = "rod"\ntransform = [["0", "0"], ["0", "0"]]'))
    with pytest.raises(ModelError) as info:
        check_model(load_model(path))
    assert str(info.value).startswith(f"{path}: constraint 'rod': transform matrix is singular")
    assert str(info.value).endswith("the transform must be an invertible n x n matrix")


def test_simulation_tolerance_the_integrators_can_resolve(tmp_path):
    path = _pendulum(tmp_path, "rtol.toml", edit=lambda s: s + "\n[simulation]\nrtol = 1e-300\n"
                     if "[simulation]" not in s else s.replace("[simulation]", "[simulation]\nrtol = 1e-300", 1))
    with pytest.raises(ModelError, match=r"\[simulation\] rtol: must be at least 2.3e-14 .* \(got 1e-300\)"):
        load_model(path)
