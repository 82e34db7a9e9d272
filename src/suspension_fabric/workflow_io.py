"""Helpers for the thin Snakemake scripts in workflow/scripts: logging to the rule's log, and the
config of the job's study."""

from __future__ import annotations

import contextlib
import os
import sys
import traceback
from pathlib import Path

__all__ = ["logged", "job_study_config"]


@contextlib.contextmanager
def logged(log_path: str | os.PathLike):
    """Send stdout and stderr of the block to ``log_path``; log and re-raise any error."""
    log_path = Path(log_path)
    log_path.parent.mkdir(parents=True, exist_ok=True)
    with open(log_path, "w", buffering=1) as log, contextlib.redirect_stdout(log), contextlib.redirect_stderr(log):
        try:
            yield
        except BaseException:
            traceback.print_exc(file=log)
            sys.__stderr__.write(f"error: see {log_path}\n")
            raise


def job_study_config(snakemake_object) -> dict:
    """The validated config of the study a job belongs to (its ``study`` wildcard): the workflow's
    config itself, or one point of its campaign (suspension_fabric.study.campaign)."""
    from suspension_fabric.study.campaign import study_configs

    return study_configs(snakemake_object.config)[snakemake_object.wildcards.study]
