"""LAMMPS engine: the project's plugin styles and helpers to run LAMMPS from Python."""

__all__ = ["build_plugin", "new_lammps", "plugin_path"]


def __getattr__(name: str):
    # Lazy, so `python -m suspension_fabric.lammps.plugin` does not import the module twice.
    if name in {"build_plugin", "new_lammps", "plugin_path"}:
        from . import plugin

        return getattr(plugin, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
