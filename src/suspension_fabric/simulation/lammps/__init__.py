"""LAMMPS engine: the project's plugin styles and helpers to run LAMMPS from Python.

Modules, lowest first: ``plugin`` (build and load the plugin), ``process`` (launch and
watch lmp), ``checks`` (overlap and stress-jitter checks of finished runs), ``rundir``
(partial run directories, resume, publishing), ``runner`` (the public runs: pack,
any segment of a flow history).
"""

__all__ = ["build_plugin", "new_lammps", "plugin_path"]


def __getattr__(name: str):
    # Lazy, so `python -m suspension_fabric.simulation.lammps.plugin` does not import the module twice.
    if name in {"build_plugin", "new_lammps", "plugin_path"}:
        from . import plugin

        return getattr(plugin, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


from suspension_fabric.io.dumpio import iter_dump_frames  # noqa: E402
from suspension_fabric.io.stressio import read_stress_table  # noqa: E402

from .checks import max_overlap_in_dump, stress_jitter  # noqa: E402
from .runner import (  # noqa: E402
    COMPLETION_MARKER,
    PACK_FILES,
    RUN_FILES,
    ForceModel,
    LammpsRunError,
    PackResult,
    ShearRunResult,
    ShearSettings,
    is_complete,
    pack,
    run_rotation,
    run_segment,
    run_startup,
)

__all__ += [
    "COMPLETION_MARKER",
    "PACK_FILES",
    "RUN_FILES",
    "ForceModel",
    "LammpsRunError",
    "PackResult",
    "ShearRunResult",
    "ShearSettings",
    "is_complete",
    "iter_dump_frames",
    "max_overlap_in_dump",
    "pack",
    "read_stress_table",
    "run_rotation",
    "run_segment",
    "run_startup",
    "stress_jitter",
]
