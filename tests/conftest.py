"""Fixtures shared by the tests of every stage."""

import pytest

from nonideal import gallery
from tests.helpers import DATA_DIR


@pytest.fixture(scope="session")
def data_dir():
    """The folder of the model files made for the tests (``tests/data``)."""
    return DATA_DIR


@pytest.fixture(scope="session")
def gallery_model():
    """``gallery_model(name)``: a gallery example's model, read from its model file once per
    session (models are immutable, so tests may share them)."""
    cache = {}

    def load(name: str):
        if name not in cache:
            cache[name] = gallery.load(name)
        return cache[name]

    return load
