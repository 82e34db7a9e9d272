#!/usr/bin/env bash
# The same startup with two builds of the plugin side by side, one per core: the current checkout's and
# that of an older commit (default 1e7c74b, the build the corner's first dataset,
# benchmarks/data/engine_validation/engine_newton_dt8e-6_phi0.55_mu1, was made with), at the map's
# corner point (0.55, 1) with its engine (the Newton contact solve, dt = 8e-6), from seed 1's packing to
# strain 1, twice; prints each run's LAMMPS loop time and whether the two stress tables are byte-identical.
#   bash benchmarks/plugin_pair.sh [commit] [packing.data]
# CURRENT_GUESS, CURRENT_LOCAL and CURRENT_PRECOND (run.initial_guess, run.local_solve_fraction and
# run.preconditioner; default previous, 0 and dilu, the older build's) set the current build's solve, e.g.
# to compare solves on one build:
#   CURRENT_GUESS=quadratic CURRENT_LOCAL=0.02 bash benchmarks/plugin_pair.sh HEAD
# The packing: any seed-1 packing of the corner point, e.g. the one
# benchmarks/configs/engine_newton_dt8e-6_phi0.55_mu1_idle_cost.yaml makes (its rule pack).
set -euo pipefail
cd "$(dirname "$0")/.."
REPO=$(pwd)
COMMIT=${1:-1e7c74b}
PACKING=$(realpath "${2:-results/engine_newton_dt8e-6_phi0.55_mu1_idle_cost/seed1/packing/packing.data}")
WORK=$(mktemp -d)
trap 'git -C "$REPO" worktree remove --force "$WORK/old" > /dev/null 2>&1 || true; rm -rf "$WORK"' EXIT
git worktree add --detach "$WORK/old" "$COMMIT" > /dev/null 2>&1
SUSPENSION_FABRIC_BUILD_DIR="$WORK/old/build/plugin" PYTHONPATH="$WORK/old/src" .venv/bin/python -c \
    "from suspension_fabric.simulation.lammps.plugin import build_plugin; build_plugin()"
.venv/bin/python -c "from suspension_fabric.simulation.lammps.plugin import build_plugin; build_plugin()"
export LD_LIBRARY_PATH="$REPO/.venv/lib:${LD_LIBRARY_PATH:-}"
LMP="$REPO/.venv/lib/python3.11/site-packages/lammps/lmp"
run() {  # label inputs-folder plugin round initial-guess local-solve-fraction preconditioner
    local folder="$WORK/$1_$4"
    mkdir -p "$folder"
    (cd "$folder" && "$LMP" -in "$2/segment.lmp" -log log.lammps -nocite -screen none \
        -var lammps_dir "$2" -var start_from packing -var start_file "$PACKING" -var segment_index 0 \
        -var flow_angle_deg 0.0 -var turning_deg_per_strain 0.0 -var lubrication sf -var eta_f 223.0 \
        -var kn 15625000000.0 -var mu 1.0 -var kt 4464285714.285714 -var delta 0.001 -var h_out 0.05 \
        -var newton_pair on -var integrator implicit -var contact_springs implicit -var contact_solve newton \
        -var preconditioner "$7" -var solver_tol 0.001 -var local_solve_fraction "$6" -var initial_guess "$5" -var verify_solve no \
        -var plugin "$3" -var dt 8e-06 -var rate 1.0 -var dump_strain 0.02 -var table_strain 0.02 \
        -var thermo_strain 0.01 -var restart_strain 0.5 -var skin 0.1 -var strain_total 1.0 \
        -var dump_file trajectory.dump -var table_file stress.txt -var checkpoint_file checkpoint.rst \
        -var restart_file_a restart.a.rst -var restart_file_b restart.b.rst)
}
echo "round,build,loop_s"
for round in 1 2; do
    run "$COMMIT" "$WORK/old/src/suspension_fabric/simulation/lammps/inputs" "$WORK/old/build/plugin/libsuspension_fabric_lammps.so" "$round" previous 0.0 dilu &
    run current "$REPO/src/suspension_fabric/simulation/lammps/inputs" "$REPO/build/plugin/libsuspension_fabric_lammps.so" "$round" "${CURRENT_GUESS:-previous}" "${CURRENT_LOCAL:-0.0}" "${CURRENT_PRECOND:-dilu}" &
    wait
    for build in "$COMMIT" current; do
        echo "$round,$build,$(awk '/^Loop time/ {print $4}' "$WORK/${build}_$round/log.lammps")"
    done
    cmp -s "$WORK/${COMMIT}_$round/stress.txt" "$WORK/current_$round/stress.txt" && echo "# round $round: stress tables byte-identical"
done
