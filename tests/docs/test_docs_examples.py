"""Every Python example in the README and the docs runs as written (from the repository's root,
each block in a fresh namespace): an example that no longer runs fails here, not in a reader's hands."""

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DOCUMENTS = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
BLOCKS = [
    pytest.param(code, id=f"{path.relative_to(REPO)}:{n + 1}")
    for path in DOCUMENTS
    for n, code in enumerate(re.findall(r"```python\n(.*?)```", path.read_text(), flags=re.S))
]


@pytest.mark.parametrize("code", BLOCKS)
def test_python_example_runs(code, monkeypatch):
    monkeypatch.chdir(REPO)
    exec(compile(code, "example", "exec"), {"__name__": "example"})


def test_there_are_examples_to_run():
    assert len(BLOCKS) >= 3
