"""Reading a finished run's metadata from its completion marker (suspension_fabric.io.runinfo):
format 2 as the runner writes it, format 1 (startup.lmp and rotate.lmp records) through its upgrade."""

from __future__ import annotations

import json

import pytest

from suspension_fabric.io.protocols import Segment
from suspension_fabric.io.runinfo import RUN_RECORD_FORMAT, RunInfo, read_run_info


def write_marker(path, variables, results, **extra):
    """A completion marker: LAMMPS variables as strings, results as numbers, other entries as given."""
    path.write_text(json.dumps({"label": "x", **extra, "variables": variables, "results": results}, indent=2))
    return path


def test_format_2_marker(tmp_path):
    """A rotary segment after the startup: its segment, index and whole history are read back."""
    startup = Segment(5.0)
    rotary = Segment(2.0, 30.0, 45.0)
    marker = write_marker(
        tmp_path / "run_complete.json",
        {"dt": "1e-04", "rate": "1.0", "eta_f": "223.0"},
        {"first_step": 50000},
        format=RUN_RECORD_FORMAT,
        flow_segment={"index": 1, **rotary.as_dict()},
        flow_history=[startup.as_dict(), rotary.as_dict()],
    )
    info = read_run_info(marker)
    assert info == RunInfo(
        dt=1e-4, rate=1.0, first_step=50000, segment=rotary, index=1, history=(startup, rotary), eta_f=223.0
    )
    assert info.theta_deg == 30.0 and info.turning


def test_format_1_rotation_marker(tmp_path):
    marker = write_marker(
        tmp_path / "run_complete.json",
        {"dt": "2e-05", "rate": "1.0", "theta_deg": "-22.5", "kn": "1250000000.0", "strain_total": "1.5"},
        {"first_step": 250000, "last_step": 325000, "strain": 1.5},
        script="rotate.lmp",
    )
    info = read_run_info(marker)
    assert (info.dt, info.rate, info.first_step, info.theta_deg, info.index) == (2e-5, 1.0, 250000, -22.5, 1)
    assert info.segment == Segment(1.5, -22.5) and info.history == (Segment(1.5, -22.5),)


@pytest.mark.parametrize("theta", [None, "absent"])
def test_format_1_startup_marker_has_angle_zero(tmp_path, theta):
    """Startup records no angle (the runner wrote theta_deg null, older markers leave it out)."""
    variables = {"dt": "2e-07", "rate": "0.5", "strain_total": "5.0"}
    if theta is None:
        variables["theta_deg"] = None
    info = read_run_info(write_marker(tmp_path / "m.json", variables, {"first_step": 0}, script="startup.lmp"))
    assert info == RunInfo(dt=2e-7, rate=0.5, first_step=0, segment=Segment(5.0), index=0, history=(Segment(5.0),))


@pytest.mark.fault("named")
def test_format_1_rotation_without_its_angle_is_refused(tmp_path):
    """A rotation record that lost its angle would read as a startup at 0 degrees."""
    marker = write_marker(tmp_path / "m.json", {"dt": "1e-4", "rate": "1.0"}, {"first_step": 0}, script="rotate.lmp")
    with pytest.raises(ValueError, match=r"missing variables\.theta_deg"):
        read_run_info(marker)


@pytest.mark.fault("named")
def test_unknown_format_is_refused(tmp_path):
    marker = write_marker(tmp_path / "m.json", {"dt": "1e-4", "rate": "1.0"}, {"first_step": 0}, format=3)
    with pytest.raises(ValueError, match="run record format 3"):
        read_run_info(marker)


@pytest.mark.parametrize(
    ("variables", "results", "message"),
    [
        ({"rate": "1.0"}, {"first_step": 0}, r"missing variables\.dt"),
        ({"dt": "1e-5"}, {"first_step": 0}, r"missing variables\.rate"),
        ({"dt": "1e-5", "rate": "1.0"}, {}, r"missing results\.first_step"),
        ({"dt": "fast", "rate": "1.0"}, {"first_step": 0}, r"variables\.dt = 'fast' is not a float"),
    ],
)
@pytest.mark.fault("named")
def test_bad_markers_name_the_file_and_the_key(tmp_path, variables, results, message):
    marker = write_marker(tmp_path / "run_complete.json", variables, results)
    with pytest.raises(ValueError, match=message) as caught:
        read_run_info(marker)
    assert str(marker) in str(caught.value)


@pytest.mark.fault("named")
def test_bad_segment_names_the_key(tmp_path):
    marker = write_marker(
        tmp_path / "m.json",
        {"dt": "1e-4", "rate": "1.0"},
        {"first_step": 0},
        format=RUN_RECORD_FORMAT,
        flow_segment={"index": 0, "strain": -1.0, "flow_angle_deg": 0.0, "turning_deg_per_strain": 0.0},
        flow_history=[{"strain": 1.0, "flow_angle_deg": 0.0, "turning_deg_per_strain": 0.0}],
    )
    with pytest.raises(ValueError, match="flow_segment is not a segment"):
        read_run_info(marker)


@pytest.mark.fault("named")
def test_missing_or_unreadable_marker(tmp_path):
    with pytest.raises(FileNotFoundError, match="run completion marker not found"):
        read_run_info(tmp_path / "run_complete.json")
    truncated = tmp_path / "truncated.json"
    truncated.write_text('{"variables": {"dt": ')
    with pytest.raises(ValueError, match="truncated.json: not valid JSON"):
        read_run_info(truncated)
