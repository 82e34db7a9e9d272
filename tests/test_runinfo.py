"""Reading a finished run's metadata from its completion marker (suspension_fabric.io.runinfo)."""

from __future__ import annotations

import json

import pytest

from suspension_fabric.io.runinfo import RunInfo, read_run_info


def write_marker(path, variables, results):
    """A completion marker as the runner writes it: LAMMPS variables as strings, results as numbers."""
    path.write_text(json.dumps({"label": "x", "variables": variables, "results": results}, indent=2))
    return path


def test_rotation_marker(tmp_path):
    marker = write_marker(
        tmp_path / "run_complete.json",
        {"dt": "2e-05", "rate": "1.0", "theta_deg": "-22.5", "kn": "1250000000.0"},
        {"first_step": 250000, "last_step": 325000, "strain": 1.5},
    )
    assert read_run_info(marker) == RunInfo(dt=2e-5, rate=1.0, first_step=250000, theta_deg=-22.5)


@pytest.mark.parametrize("theta", [None, "absent"])
def test_startup_marker_has_angle_zero(tmp_path, theta):
    """Startup records no angle (the runner writes theta_deg null, older markers leave it out)."""
    variables = {"dt": "2e-07", "rate": "0.5"}
    if theta is None:
        variables["theta_deg"] = None
    info = read_run_info(write_marker(tmp_path / "m.json", variables, {"first_step": 0}))
    assert info == RunInfo(dt=2e-7, rate=0.5, first_step=0, theta_deg=0.0)


@pytest.mark.parametrize(
    ("variables", "results", "message"),
    [
        ({"rate": "1.0"}, {"first_step": 0}, r"missing variables\.dt"),
        ({"dt": "1e-5"}, {"first_step": 0}, r"missing variables\.rate"),
        ({"dt": "1e-5", "rate": "1.0"}, {}, r"missing results\.first_step"),
        ({"dt": "fast", "rate": "1.0"}, {"first_step": 0}, r"variables\.dt = 'fast' is not a float"),
    ],
)
def test_bad_markers_name_the_file_and_the_key(tmp_path, variables, results, message):
    marker = write_marker(tmp_path / "run_complete.json", variables, results)
    with pytest.raises(ValueError, match=message) as caught:
        read_run_info(marker)
    assert str(marker) in str(caught.value)


def test_missing_or_unreadable_marker(tmp_path):
    with pytest.raises(FileNotFoundError, match="run completion marker not found"):
        read_run_info(tmp_path / "run_complete.json")
    truncated = tmp_path / "truncated.json"
    truncated.write_text('{"variables": {"dt": ')
    with pytest.raises(ValueError, match="truncated.json: not valid JSON"):
        read_run_info(truncated)
