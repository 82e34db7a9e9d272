#!/usr/bin/env bash
# Create (or update) the project's virtual environment in .venv from the pinned lock file
# (with the SLURM executor plugin of envs/cluster.txt, so one environment runs the study
# locally and on a cluster) and install the suspension_fabric package in editable mode.
# Idempotent: a second run only re-checks what is installed.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
    "$PYTHON" -m venv .venv
fi
.venv/bin/python -m pip install --quiet --disable-pip-version-check -r envs/requirements.lock.txt -r envs/cluster.txt
.venv/bin/python -m pip install --quiet --disable-pip-version-check --no-deps -e .
echo "bootstrap: .venv ready ($(.venv/bin/python --version))"
