"""Snakemake: compile the LAMMPS plugin (rule build_plugin) and publish it at the rule's output."""
import os
import shutil
from pathlib import Path

from suspension_fabric.lammps.plugin import build_plugin
from suspension_fabric.workflow_io import logged

sm = snakemake  # noqa: F821 (injected by Snakemake)
with logged(sm.log[0]):
    built = build_plugin(force=True)
    target = Path(sm.output[0]).resolve()
    if target != built.resolve():  # workflow run outside the repository (e.g. the tests)
        tmp = target.with_name(f".{target.name}.tmp")
        shutil.copy2(built, tmp)
        os.replace(tmp, target)
    print(f"built {built} -> {target}")
