"""The manual's example outputs are what the code gives: `benchmarks/readme_examples.py` computes
each block that README or a page of the manual (`docs/`) quotes, and one of them must quote it,
every number to the digits it gives (one unit of its last digit allowed, for a rounding that other
library versions may tip; whole numbers, counts, exactly) — in every file that quotes it, README
and a page alike; the quickstart, the five commands with their output, in README and in
docs/quickstart.md (`QUOTED_IN`).

Expected values: the code's own output, on purpose. This test checks the documentation against
the code, not the code: the code's numbers are checked against independent values elsewhere.
"""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
NUMBER = r"-?\d+(?:\.\d+)?"
QUOTED_IN = {"quickstart": ("README.md", "docs/quickstart.md")}
"""Blocks that named files must quote, not only some file (the front page's "paper's study in five
commands with their output", issue 44, and the manual's quickstart page, which repeats it): a copy
that drifts no longer matches the block, so without this it would silently go unchecked."""


def examples():
    """benchmarks/readme_examples.py, as a module."""
    path = REPO / "benchmarks" / "readme_examples.py"
    spec = importlib.util.spec_from_file_location("readme_examples", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def pattern(block: str) -> str:
    """A regular expression matching the block with any numbers in its numbers' places and any
    whitespace (a line wrapped elsewhere, a column aligned otherwise) in its whitespace's."""
    parts = re.split(f"({NUMBER})", block)
    return "".join(
        f"({NUMBER})" if odd else r"\s+".join(re.escape(word) for word in re.split(r"\s+", part))
        for odd, part in ((i % 2 == 1, part) for i, part in enumerate(parts))
    )


def off(block: str, readme: str) -> list[tuple[str, str]]:
    """(README's number, the code's) for each number of a block that README quotes beyond one
    unit of the last digit it gives (any difference, for a whole number)."""
    found = re.search(pattern(block), readme)
    assert found, f"README does not quote this block as the code gives it:\n{block}"
    wrong = []
    for text, value in zip(found.groups(), re.findall(NUMBER, block), strict=True):
        digits = len(text.partition(".")[2])
        if abs(float(text) - float(value)) > (10.0**-digits if digits else 0.0) * (1 + 1e-9):
            wrong.append((text, value))
    return wrong


def test_a_quote_may_differ_in_its_last_digit_only():
    readme = "median 0.9358 of 10/10 records, 0.898–0.997"
    assert off("median 0.9359 of 10/10  records,\n0.898–0.996", readme) == []
    assert off("median 0.9378 of 10/10 records, 0.898–0.997", readme) == [("0.9358", "0.9378")]
    assert off("median 0.9358 of 11/10 records, 0.898–0.997", readme) == [("10", "11")]
    with pytest.raises(AssertionError, match="does not quote"):
        off("median 0.9358 of 10/10 record, 0.898–0.997", readme)


@pytest.fixture(scope="module")
def blocks(tmp_path_factory):
    return examples().blocks(tmp_path_factory.mktemp("readme"))


def manual() -> dict[str, str]:
    """The text of README and of every page of the manual, by path."""
    pages = [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]
    return {str(page.relative_to(REPO)): page.read_text(encoding="utf-8") for page in pages}


def quoted(block: str, texts: dict[str, str]) -> dict[str, list[tuple[str, str]]]:
    """For each file that quotes the block, the numbers it quotes off (as `off`); at least one
    file must quote it."""
    found = {
        path: off(block, text) for path, text in texts.items() if re.search(pattern(block), text)
    }
    assert found, (
        f"neither README nor a page of docs/ quotes this block as the code gives it:\n{block}"
    )
    return found


def test_every_file_that_quotes_a_block_is_checked():
    texts = {
        "README.md": "median 0.9358 of 10/10 records",
        "docs/a.md": "median 0.9378 of 10/10 records",
        "docs/b.md": "nothing",
    }
    assert quoted("median 0.9358 of 10/10 records", texts) == {
        "README.md": [], "docs/a.md": [("0.9378", "0.9358")]}  # fmt: skip
    with pytest.raises(AssertionError, match="neither README"):
        quoted("median 0.9358 of 11/10 records", {"docs/b.md": "nothing"})


@pytest.mark.slow
def test_the_manual_quotes_what_the_code_gives(blocks):
    texts = manual()
    assert set(blocks) == {"quickstart", "one analysis", "a study", "fragility study",
                           "fragility table", "gap sweep count", "gap sweep",
                           "select-records"}  # fmt: skip
    for name, block in blocks.items():
        files = quoted(block, texts)
        for path, wrong in files.items():
            assert wrong == [], (name, path)
        for path in QUOTED_IN.get(name, ()):
            assert path in files, f"{path} does not quote {name!r} as the code gives it"
