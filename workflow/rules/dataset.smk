# Studies built on a reference dataset (config key `dataset`): the fabric and stress tables come
# from the dataset's files (their SHA-256 checked) instead of simulations; no LAMMPS job exists.
from suspension_fabric.dataset import check_config_matches, has_run_tables, read_dataset

DATASET_RECORDS = {name: read_dataset(STUDIES[name]["dataset"]) for name in DATASET_STUDIES}
for _name, _record in DATASET_RECORDS.items():
    check_config_matches(STUDIES[_name], _record, STUDIES[_name]["dataset"])
    # datasets exported before the stress parts were recorded carry no stress tables
    if not has_run_tables(_record, "stress.csv"):
        STRESSLESS_STUDIES.append(_name)
        print(f"Note: the dataset {STUDIES[_name]['dataset']} has no per-run stress tables; the stress rules "
              f"are left out of study {_name}.")


rule import_run_table:
    """Fabric or stress table of one run, from the reference dataset (instead of simulating it)."""
    input:
        table=lambda wildcards: f"{STUDIES[wildcards.study]['dataset']}/seed{wildcards.seed}/{wildcards.run}/{wildcards.table}.csv",
        record=lambda wildcards: f"{STUDIES[wildcards.study]['dataset']}/dataset.json",
    output:
        f"{RESULTS}/seed{{seed}}/{{run}}/{{table}}.csv",
    wildcard_constraints:
        study=study_pattern(DATASET_STUDIES),
        run=r"startup|rotation_theta[^/]+",
        table=r"fabric|stress",
    params:
        run=lambda wildcards: f"seed{wildcards.seed}/{wildcards.run}",
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/import_seed{{seed}}_{{run}}_{{table}}.log",
    script:
        "../scripts/import_run_table.py"
