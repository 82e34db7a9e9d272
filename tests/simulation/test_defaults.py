"""One source for every default: config/schema.yaml. The package's dataclasses read it; the
LAMMPS scripts' own -var defaults (for runs by hand) must equal it, checked here."""

from __future__ import annotations

import re

import pytest

from suspension_fabric.io.resources import LAMMPS_SCRIPTS_DIR
from suspension_fabric.io.schema import schema_default
from suspension_fabric.simulation.lammps import ForceModel, ShearSettings, run_rotation, run_startup


def script_defaults(name: str) -> dict[str, str]:
    """The ``variable NAME index VALUE`` lines of a LAMMPS script."""
    text = (LAMMPS_SCRIPTS_DIR / name).read_text()
    return dict(re.findall(r"^variable\s+(\w+)\s+index\s+(\S+)", text, flags=re.M))


SHARED = script_defaults("shear_defaults.lmp")


@pytest.mark.parametrize(
    "section, key",
    [
        ("forces", "eta_f"),
        ("forces", "kn"),
        ("forces", "mu"),
        ("forces", "delta"),
        ("forces", "h_out"),
        ("run", "solver_tol"),
        ("run", "dt"),
        ("run", "dump_strain"),
        ("run", "table_strain"),
        ("run", "thermo_strain"),
        ("run", "restart_strain"),
    ],
)
def test_shear_script_defaults_equal_the_schema(section, key):
    assert float(SHARED[key]) == schema_default(section, key)


def test_shear_script_text_defaults_and_python_defaults():
    """Non-numeric script defaults, kt = 2/7 kn (schema null), and the dataclass defaults."""
    assert SHARED["integrator"] == schema_default("run", "integrator") == ForceModel().integrator
    for key in ("contact_springs", "contact_solve", "preconditioner"):
        assert SHARED[key] == schema_default("run", key) == getattr(ForceModel(), key), key
    assert schema_default("forces", "kt") is None and SHARED["kt"] == "$(2.0/7.0*v_kn)"
    model, settings = ForceModel(), ShearSettings()
    assert (SHARED["newton_pair"], SHARED["lubrication"]) == (model.newton_pair, model.lubrication)
    for key in ("eta_f", "kn", "mu", "delta", "h_out"):
        assert getattr(model, key) == schema_default("forces", key), key
    for key in (
        "dt",
        "dump_strain",
        "table_strain",
        "thermo_strain",
        "restart_strain",
        "max_overlap",
        "max_stress_jitter",
    ):
        assert getattr(settings, key) == schema_default("run", key), key
    assert float(SHARED["rate"]) == settings.rate and float(SHARED["skin"]) == settings.skin


def test_strain_and_packing_defaults():
    """segment.lmp's strain_total (a segment from a packing: the startup) equals the schema's startup
    strain; the Python runners' strains equal the schema's run strains; pack.lmp's particle defaults
    equal the schema's particles section."""
    import inspect

    segment_defaults = script_defaults("segment.lmp")
    assert float(segment_defaults["strain_total"]) == schema_default("run", "startup_strain")
    assert (segment_defaults["start_from"], float(segment_defaults["flow_angle_deg"])) == ("packing", 0.0)
    for function, key in ((run_startup, "startup_strain"), (run_rotation, "rotation_strain")):
        assert inspect.signature(function).parameters["strain_total"].default == schema_default("run", key)
    pack_defaults = script_defaults("pack.lmp")
    assert int(pack_defaults["n_particles"]) == schema_default("particles", "n")
    for key in ("phi", "d_small", "d_large", "fraction_large"):
        assert float(pack_defaults[key]) == schema_default("particles", key), key
    assert pack_defaults["split"] == schema_default("particles", "split")


def test_the_shear_script_takes_the_shared_defaults():
    """segment.lmp defines no shared variable itself: it includes shear_defaults.lmp."""
    own = script_defaults("segment.lmp")
    assert not set(own) & set(SHARED)
    assert "include         ${lammps_dir}/shear_defaults.lmp" in (LAMMPS_SCRIPTS_DIR / "segment.lmp").read_text()


def test_the_scripts_default_plugin_path_is_the_workflows():
    """Run by hand from the repository root, the scripts load the library the workflow builds."""
    from suspension_fabric.io.resources import PLUGIN_LIBRARY_NAME

    assert SHARED["plugin"] == f"build/plugin/{PLUGIN_LIBRARY_NAME}"
    assert script_defaults("restart_probe.lmp")["plugin"] == SHARED["plugin"]
