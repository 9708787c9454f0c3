"""docs/MODEL_FORMAT.md is the complete reference of the model file: every table and key the
reader accepts is documented there (a ``##`` section per table, each key in backquotes), and
its complete example is a valid model file."""

import re
import tomllib
from pathlib import Path

import pytest

from nonideal.modeling import modelfile
from nonideal.modeling.members import MEMBER_KEYS
from nonideal.modeling.modelfile import model_from_dict

DOC = Path(__file__).resolve().parents[2] / "docs" / "MODEL_FORMAT.md"


@pytest.fixture(scope="module")
def doc() -> str:
    return DOC.read_text(encoding="utf-8")


def _section(doc: str, heading: str) -> str:
    m = re.search(rf"^## {re.escape(heading)}\s*$(.*?)(?=^## |\Z)", doc, re.M | re.S)
    assert m, f"docs/MODEL_FORMAT.md has no section '## {heading}'"
    return m.group(1)


def test_every_table_has_its_section(doc):
    for key in modelfile.TOP_KEYS:
        arrays = {"bodies", "loads", "constraints", "contacts", "controls", "frames", "points", "members"}
        _section(doc, f"[[{key}]]" if key in arrays else f"[{key}]")


def test_every_key_is_documented_in_its_section(doc):
    tables = {f"[{k}]": keys for k, keys in modelfile.SECTION_KEYS.items()}
    tables["[[constraints]]"] = modelfile.CONSTRAINT_KEYS
    tables["[[contacts]]"] = modelfile.CONTACT_KEYS
    tables["[[controls]]"] = modelfile.CONTROL_KEYS
    tables["[[bodies]]"] = set().union(*modelfile.BODY_KEYS.values())
    tables["[[loads]]"] = set().union(*modelfile.LOAD_KEYS.values())
    tables["[[frames]]"] = modelfile.FRAME_KEYS
    tables["[[points]]"] = modelfile.POINT_KEYS
    tables["[[members]]"] = MEMBER_KEYS
    # in its table's section, or in a section of its own that names it in backquotes (the
    # sections that document a group of features together, e.g. `[[constraints]] losses`)
    missing = [f"{table} {key}" for table, keys in tables.items() for key in keys
               if f"`{key}`" not in _section(doc, table) and f"{table} {key}`" not in doc
               and f"`{key}`" not in doc]
    assert not missing, missing


def test_the_examples_are_valid_toml_and_the_complete_one_a_model(doc):
    blocks = re.findall(r"```toml\n(.*?)```", doc, re.S)
    assert len(blocks) >= 12
    for block in blocks:
        tomllib.loads(block)
    model = model_from_dict(tomllib.loads(blocks[0]), "MODEL_FORMAT.md")
    assert model.coordinates == ("x", "y", "theta") and model.contacts[0].name == "A"
