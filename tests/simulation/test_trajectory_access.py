"""Reading a trajectory by name: ``traj.q["x"]``, ``traj["x"]``, ``traj["x'"]``, the multipliers
and energy terms; ``to_pandas`` holds the same numbers as ``to_csv``; what a notebook shows."""

import csv
import pickle

import numpy as np
import pytest

import nonideal
from nonideal.simulation.trajectory import Columns


@pytest.fixture(scope="module")
def traj(gallery_model):
    return nonideal.simulate(gallery_model("block-on-incline"))


def test_names_read_the_columns(traj):
    k = traj.coordinates.index("x")
    assert np.array_equal(traj.q["x"], traj.q[:, k])
    assert np.array_equal(traj["x"], traj.q[:, k])
    assert np.array_equal(traj["x'"], traj.qd[:, k]) and np.array_equal(traj.qd["x"], traj["x'"])
    assert np.array_equal(traj["x''"], traj.qdd[:, k])
    assert np.array_equal(traj["t"], traj.t)
    assert np.array_equal(traj["kinetic"], traj.energy["kinetic"])
    assert np.array_equal(traj["N_plane"], traj.contacts["plane"]["normal"])
    # the block stops at t1 = v0 / (g (sin a + mu cos a)) at d = v0^2 / (2 g (...)) and sticks
    g, a, mu, v0 = 9.81, 0.4, 0.3, 3.0
    decel = g * (np.sin(a) + mu * np.cos(a))
    assert traj["x"][-1] == pytest.approx(v0 ** 2 / (2 * decel), rel=1e-7)
    assert traj.at("x") == traj["x"][-1]


def test_numpy_indexing_is_unchanged(traj):
    assert isinstance(traj.q, Columns) and traj.q.shape == (len(traj), 2)
    assert type(traj.q[:, 0]) is np.ndarray and type(traj.q[-1]) is np.ndarray
    assert isinstance(traj.q[-1, 0], float)
    back = pickle.loads(pickle.dumps(traj.q))
    assert np.array_equal(back["y"], traj.q["y"])


def test_unknown_names_are_refused_with_the_names(traj):
    with pytest.raises(KeyError, match=r"did you mean 'x'.*the columns are x, y"):
        traj.q["xx"]
    with pytest.raises(KeyError, match="no series 'kinetc'.*did you mean 'kinetic'"):
        traj["kinetc"]
    with pytest.raises(TypeError, match="traj.q"):
        traj[0]


def test_to_pandas_holds_the_csv(traj, tmp_path):
    pd = pytest.importorskip("pandas")
    df = traj.to_pandas()
    path = tmp_path / "t.csv"
    traj.to_csv(path)
    rows = list(csv.reader(path.open()))
    assert rows[0] == ["t"] + list(df.columns)
    assert df.index.name == "t" and np.array_equal(df.index.to_numpy(), traj.t)
    for j, name in enumerate(rows[0][1:], start=1):
        col = [r[j] for r in rows[1:]]
        if df[name].dtype == object or str(df[name].dtype).startswith(("str", "string")):
            assert list(df[name]) == col
        else:
            assert np.array_equal(df[name].to_numpy(), np.array(col, dtype=float))
    assert isinstance(df, pd.DataFrame)


def test_to_pandas_without_pandas_says_how(traj, monkeypatch):
    import builtins

    real = builtins.__import__

    def fake(name, *args, **kwargs):
        if name == "pandas":
            raise ImportError("no pandas")
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", fake)
    with pytest.raises(ImportError, match="pip install pandas"):
        traj.to_pandas()


def test_notebook_display_lists_the_events(traj):
    html = traj._repr_html_()
    assert f"{len(traj.events)} events" in html and traj.events[0]["type"] in html
