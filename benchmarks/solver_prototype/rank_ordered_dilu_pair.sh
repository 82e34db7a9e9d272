#!/usr/bin/env bash
# The dilu preconditioner across MPI ranks (rank_ordered_dilu.patch: a red-black order of the
# subdomains, black ranks first in the elimination, one exchange each way per sweep) against the
# engine's block Jacobi across ranks: the 2-rank continuation of `mpi_scaling.py prepare --n 16000`'s
# state for 0.02 strain with each build, alternating (AB BA ...), six pairs. Prints per run the
# loop time and the mean CG iterations per step (CSV). Both builds are made from the commit the patch
# was written for (default 3c86fdd), so later changes of the engine leave the comparison as it was.
# Run on an otherwise idle machine:
#   bash benchmarks/solver_prototype/rank_ordered_dilu_pair.sh [commit] | tee benchmarks/data/mpi_scaling/n16000/rank_ordered_dilu_pair.csv
set -euo pipefail
cd "$(dirname "$0")/../.."
REPO=$(pwd)
BASE=${1:-3c86fdd}
WORK=$(mktemp -d)
trap 'for tree in base patched; do git -C "$REPO" worktree remove --force "$WORK/$tree" > /dev/null 2>&1 || true; done; rm -rf "$WORK"' EXIT
git worktree add --detach "$WORK/base" "$BASE" > /dev/null 2>&1
git worktree add --detach "$WORK/patched" "$BASE" > /dev/null 2>&1
git -C "$WORK/patched" apply "$REPO/benchmarks/solver_prototype/rank_ordered_dilu.patch"
build() {  # source tree
    SUSPENSION_FABRIC_BUILD_DIR="$1/build/plugin" PYTHONPATH="$1/src" .venv/bin/python -c \
        "from suspension_fabric.simulation.lammps.plugin import build_plugin; build_plugin()" > /dev/null
}
run() {  # pair label source-tree
    SUSPENSION_FABRIC_BUILD_DIR="$3/build/plugin" PYTHONPATH="$3/src:$3/benchmarks" .venv/bin/python -c "
import mpi_scaling as m
f = m.continuation(16000, 2, 0.02, 'preconditioner_pair_$2')
print('$1,$2,' + format(f['loop_s'], '.2f') + ',' + format(f['iterations'], '.2f'), flush=True)"
}
build "$WORK/base"
build "$WORK/patched"
echo "pair,preconditioner,loop_s,iterations"
for pair in 1 2 3 4 5 6; do
    if [ $((pair % 2)) = 1 ]; then
        run "$pair" block_jacobi "$WORK/base"
        run "$pair" rank_ordered_dilu "$WORK/patched"
    else
        run "$pair" rank_ordered_dilu "$WORK/patched"
        run "$pair" block_jacobi "$WORK/base"
    fi
done
