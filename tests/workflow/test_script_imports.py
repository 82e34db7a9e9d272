"""Start-up of the workflow's per-run and per-study scripts: a study runs them hundreds of times
(121 jobs for the map's rebuild), so each heavy library is imported inside the function that
uses it, not when the script starts. The check imports a script's top-level imports in a fresh
interpreter and lists the heavy modules loaded."""

import ast
import subprocess
import sys

import pytest

from workflow_helpers import REPO

#: Libraries that cost 0.2-0.4 s each to import and that these scripts need only in some calls.
HEAVY = ("MDAnalysis", "matplotlib", "scipy.integrate", "scipy.optimize", "scipy.stats")
#: The scripts of the rules that run once per run or per study point.
FREQUENT_SCRIPTS = (
    "aggregate",
    "claims",
    "fabric_table",
    "fit_models",
    "import_run_tables",
    "predict",
    "stress_table",
    "verdicts",
)


def heavy_modules_at_start(script: str) -> list[str]:
    """The modules of HEAVY that the script's top-level imports load."""
    tree = ast.parse((REPO / "workflow" / "scripts" / f"{script}.py").read_text())
    imports = [ast.unparse(node) for node in tree.body if isinstance(node, (ast.Import, ast.ImportFrom))]
    probe = "\n".join([*imports, "import sys", f"print(' '.join(m for m in {HEAVY!r} if m in sys.modules))"])
    result = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, cwd=REPO)
    assert result.returncode == 0, result.stderr[-2000:]
    return result.stdout.split()


@pytest.mark.parametrize("script", FREQUENT_SCRIPTS)
def test_a_frequent_script_starts_without_the_heavy_libraries(script):
    assert heavy_modules_at_start(script) == []


def test_the_probe_sees_a_heavy_import():
    """The figure scripts import matplotlib at start: the probe must report it."""
    assert "matplotlib" in heavy_modules_at_start("figure_startup")
