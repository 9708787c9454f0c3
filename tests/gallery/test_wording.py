"""The product speaks for itself: what users read (messages, docstrings, gallery titles and
model files, the docs) cites the literature by author and year, never the project's internal
names of its sources ("seed 000"), its specification ("SPEC") or its issue numbers."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
INTERNAL = re.compile(r"(?i:\bseeds?\b)(?!\s*[=:)\],])|\bSPEC\b|(?i:\bissue \d+)")


def _texts():
    for pattern in ("nonideal/**/*.py", "nonideal/**/*.toml", "docs/*.md"):
        for path in sorted(ROOT.glob(pattern)):
            yield path, path.read_text(encoding="utf-8")


def test_no_internal_names_in_what_users_read():
    found = []
    for path, text in _texts():
        for number, line in enumerate(text.splitlines(), 1):
            for m in INTERNAL.finditer(line):
                if re.search(r"(random|rng|Random|default_rng)\W*\(?\s*seed|seed: int|seed=", line):
                    continue                      # a random-number seed is not a source
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()[:90]}")
    assert not found, "\n".join(found)
