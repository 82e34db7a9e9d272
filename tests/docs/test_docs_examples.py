"""Every Python example in the README and the docs runs as written (from the repository's root,
each block in a fresh namespace): an example that no longer runs fails here, not in a reader's hands."""

import re
from pathlib import Path

import pytest
import yaml

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


def test_the_several_ranks_example_of_the_workflow_page_validates_and_its_warning_holds():
    """docs/workflow.md's YAML for one simulation on several ranks, over the default study, passes the
    config validation with the values it names; written as 5e-4 (no point) the tol is refused, naming
    run.solver_tol, as its comment warns."""
    from suspension_fabric.study.config import ConfigError, read_config_file, validate_config

    page = (REPO / "docs" / "workflow.md").read_text()
    (example,) = [block for block in re.findall(r"```yaml\n(.*?)```", page, flags=re.S) if "mpi_ranks" in block]
    run = yaml.safe_load(example)["run"]
    config = read_config_file(REPO / "config" / "config.yaml")
    config["run"] = {**config.get("run", {}), **run}
    validated = validate_config(config)
    assert (validated["run"]["mpi_ranks"], validated["run"]["preconditioner"]) == (2, "jacobi")
    assert validated["run"]["solver_tol"] == 5.0e-4

    config = read_config_file(REPO / "config" / "config.yaml")
    config["run"] = {**config.get("run", {}), **yaml.safe_load(example.replace("5.0e-4", "5e-4"))["run"]}
    with pytest.raises(ConfigError, match=r"run\.solver_tol"):
        validate_config(config)
