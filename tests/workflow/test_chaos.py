"""A study survives random kills (tests/chaos_helpers.py): the test study run from scratch while Snakemake,
a LAMMPS run or an analysis job is SIGKILLed at random moments, each time restarted as the docs say
(`snakemake --unlock`, then the same command), ends with every table, figure, report and data file
byte-identical to the session's uninterrupted run of the same study (the run records too, but for
when and through which launches each run was made; LAMMPS's own logs hold timings), and no
unfinished or failed run folder left.

Byte-identical holds wherever no simulation was resumed part-way: a killed run that wrote no
restart file yet starts again from strain 0 and repeats its trajectory bit for bit. A run resumed
from one of its restart files is identical only up to its restart step (docs/workflow.md,
"Interrupted runs"; tests/simulation/test_resume.py), so when a kill lands after one, the files of
the other seeds are compared and the tables over all seeds only for their presence. The full-size trial, more
kills with the seeds recorded, is benchmarks/chaos.py (BENCHMARKS.md, "Random kills")."""

import json

import pytest

from chaos_helpers import chaos_run, comparable_digests, leftovers, resumed_runs
from workflow_helpers import TEST_CONFIG, copy_workflow, snakemake

pytestmark = pytest.mark.workflow

#: The CI size: kills landed and the seed of their schedule (kinds and delays).
KILLS, SEED, MAX_DELAY = 6, 20261207, 6.0


@pytest.mark.fault("survived")
def test_a_study_killed_at_random_moments_ends_as_an_uninterrupted_one(study, tmp_path):
    workdir = copy_workflow(tmp_path / "chaos")
    rounds, final = chaos_run(workdir, TEST_CONFIG, KILLS, SEED, MAX_DELAY)
    schedule = json.dumps([vars(r) for r in rounds], indent=1)
    assert final == 0, schedule
    landed = [r for r in rounds if r.victim != "nothing"]
    assert len(landed) >= 3, f"too few kills landed before the study finished: {schedule}"
    assert not leftovers(workdir), (leftovers(workdir), schedule)
    plan = snakemake(workdir, *TEST_CONFIG, "-n")
    assert plan.returncode == 0 and "Nothing to be done" in plan.stdout + plan.stderr, schedule
    made, reference = comparable_digests(workdir), comparable_digests(study)
    extra = sorted(made.keys() ^ reference.keys())
    assert not extra, "files in one tree only:\n" + "\n".join(extra[:30]) + "\n" + schedule
    # a run resumed part-way is identical only up to its restart step (tests/simulation/test_resume.py),
    # so what follows it in its seed, and every table over the seeds, may differ within the statistics
    resumed = resumed_runs(workdir)
    changed_seeds = {run.split("/")[1] for run in resumed}
    compared = [
        name
        for name in made
        if not resumed or (name.split("/")[1].startswith("seed") and name.split("/")[1] not in changed_seeds)
    ]
    differing = sorted(name for name in compared if made[name] != reference[name])
    assert not differing, f"files that differ (resumed part-way: {resumed}):\n" + "\n".join(differing[:30]) + schedule
