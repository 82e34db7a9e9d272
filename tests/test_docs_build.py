"""The documentation site builds with warnings as errors (mkdocs --strict: broken links, missing
pages, API reference from the docstrings, BENCHMARKS.md included), so docs that rot fail CI."""

import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def test_docs_build_strict(tmp_path):
    mkdocs = Path(sys.executable).with_name("mkdocs")
    result = subprocess.run(
        [str(mkdocs), "build", "--strict", "--quiet", "-d", str(tmp_path / "site")],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=300,
        env={"NO_MKDOCS_2_WARNING": "1", "PATH": "/usr/bin:/bin"},
    )
    assert result.returncode == 0, result.stderr[-3000:]
    api = (tmp_path / "site" / "api" / "index.html").read_text()
    assert "suspension_fabric.models.stress_relations" in api and "with_lubrication_stress" in api
    assert "Pair stresslets against force dipoles" in (tmp_path / "site" / "benchmarks" / "index.html").read_text()
    assert "&lt;nn&gt;" in (tmp_path / "site" / "results" / "index.html").read_text()
