#!/usr/bin/env bash
# Create (or update) the project's virtual environment in .venv from the pinned lock file
# (with the SLURM executor plugin of envs/cluster.txt, so one environment runs the study
# locally and on a cluster) and install the suspension_fabric package in editable mode, with
# the installer uv (envs/installer.txt, put into .venv by pip).
# Idempotent: a second run only re-checks what is installed.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
    "$PYTHON" -m venv .venv
fi
.venv/bin/python -m pip install --quiet --disable-pip-version-check -r envs/installer.txt
# uv reads its own settings, not pip's: behind a package mirror set UV_DEFAULT_INDEX (or
# UV_INDEX / UV_FIND_LINKS). Byte code is compiled at install, as pip does: with
# PYTHONDONTWRITEBYTECODE set, nothing would compile it later and every process would parse
# the libraries from source.
uv_install() { .venv/bin/uv pip install --quiet --python .venv/bin/python --compile-bytecode "$@"; }
uv_install -r envs/requirements.lock.txt -r envs/cluster.txt
uv_install --no-deps -e .
echo "bootstrap: .venv ready ($(.venv/bin/python --version))"
