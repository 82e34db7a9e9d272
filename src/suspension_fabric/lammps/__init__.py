"""LAMMPS engine: the project's plugin styles and helpers to run LAMMPS from Python."""

__all__ = ["build_plugin", "new_lammps", "plugin_path"]


def __getattr__(name: str):
    # Lazy, so `python -m suspension_fabric.lammps.plugin` does not import the module twice.
    if name in {"build_plugin", "new_lammps", "plugin_path"}:
        from . import plugin

        return getattr(plugin, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

# Running the workflow/lammps scripts (pack, startup shear, shear rotation).
from .runner import (  # noqa: E402
    COMPLETION_MARKER, ForceModel, LammpsRunError, PackResult, ShearRunResult,
    is_complete, iter_dump_frames, max_overlap_in_dump, pack, read_stress_table,
    run_rotation, run_startup,
)

__all__ += [
    "COMPLETION_MARKER", "ForceModel", "LammpsRunError", "PackResult", "ShearRunResult",
    "is_complete", "iter_dump_frames", "max_overlap_in_dump", "pack", "read_stress_table",
    "run_rotation", "run_startup",
]
