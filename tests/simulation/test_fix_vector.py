"""The global vector of fix hydro/implicit/sf is indexed in one place, the HydroVector list of
simulation/lammps/plugin_source/fix_hydro_implicit_sf.h; every f_integrate[i] that forces_sf.lmp reads is checked
against it here (a LAMMPS input cannot include a C++ header, so the .lmp repeats the numbers)."""

import re

import pytest

from suspension_fabric.io.resources import LAMMPS_SCRIPTS_DIR, PLUGIN_SOURCE_DIR

HEADER = PLUGIN_SOURCE_DIR / "fix_hydro_implicit_sf.h"
FORCES = LAMMPS_SCRIPTS_DIR / "forces_sf.lmp"
AXES = {"x": 0, "y": 1, "z": 2}


def vector_entries() -> dict[str, int]:
    """NAME -> index of the HydroVector enum."""
    block = re.search(r"namespace HydroVector \{(.*?)\}", HEADER.read_text(), flags=re.S).group(1)
    return {name: int(value) for name, value in re.findall(r"\b([A-Z_]+) = (\d+)", block)}


def expected_index(variable: str, entries: dict[str, int]) -> int:
    """The entry an input-script variable of forces_sf.lmp stands for."""
    counts = {
        "solver_iterations": "LAST_ITERATIONS",
        "contact_count": "CONTACTS",
        "frictional_count": "FRICTIONAL_CONTACTS",
        "critical_load_now": "CRITICAL_LOAD",
    }
    if variable in counts:
        return entries[counts[variable]]
    part, _, component = variable.rpartition("_")
    if part == "contact_torque":
        return entries["CONTACT_TORQUE"] + AXES[component]
    start = {"contact": "CONTACT_VIRIAL", "lubrication": "LUBRICATION_VIRIAL", "stresslet": "STRESSLET_VIRIAL"}
    name, number = variable.split("_p")
    return entries[start[name]] + int(number) - 1


def test_the_enum_is_contiguous_and_sized():
    """Entries in order, each block as wide as its components, SIZE the last index."""
    entries = vector_entries()
    widths = {"CONTACT_VIRIAL": 6, "CONTACT_TORQUE": 3, "LUBRICATION_VIRIAL": 6, "STRESSLET_VIRIAL": 6}
    names = [name for name in entries if name != "SIZE"]
    assert entries[names[0]] == 1
    for this, following in zip(names, names[1:]):
        assert entries[following] == entries[this] + widths.get(this, 1), (this, following)
    assert entries["SIZE"] == entries[names[-1]] + widths.get(names[-1], 1) - 1


def test_the_fix_reports_the_enum_size():
    assert "size_vector = HydroVector::SIZE;" in (PLUGIN_SOURCE_DIR / "fix_hydro_implicit_sf.cpp").read_text()


@pytest.mark.parametrize(
    "variable",
    [
        "solver_iterations",
        "contact_count",
        "frictional_count",
        "critical_load_now",
        *(f"{part}_p{k}" for part in ("contact", "lubrication", "stresslet") for k in range(1, 7)),
        *(f"contact_torque_{axis}" for axis in AXES),
    ],
)
def test_every_index_the_input_reads(variable):
    entries = vector_entries()
    found = re.findall(rf'"variable {variable} equal f_integrate\[(\d+)\]', FORCES.read_text())
    assert found, f"{FORCES.name} does not read {variable} from f_integrate"
    assert {int(i) for i in found} == {expected_index(variable, entries)}


def test_no_other_index_is_read():
    """Every f_integrate[i] of the input is one of the checked variables."""
    read = re.findall(r'"variable (\w+) equal f_integrate\[\d+\]', FORCES.read_text())
    assert len(read) == 4 + 3 * 6 + 3
