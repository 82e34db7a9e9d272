# A study built on a reference dataset (config key `dataset`): the fabric and stress tables come
# from the dataset's files (their SHA-256 checked) instead of simulations; no LAMMPS job exists.
from suspension_fabric.dataset import check_config_matches, has_run_tables, read_dataset

DATASET = config["dataset"]
DATASET_RECORD = read_dataset(DATASET)
check_config_matches(config, DATASET_RECORD, DATASET)
# datasets exported before the stress parts were recorded carry no stress tables
STRESS_TABLES = has_run_tables(DATASET_RECORD, "stress.csv")
if not STRESS_TABLES:
    print(f"Note: the dataset {DATASET} has no per-run stress tables; the stress rules are left out.")


rule import_run_table:
    """Fabric or stress table of one run, from the reference dataset (instead of simulating it)."""
    input:
        table=f"{DATASET}/seed{{seed}}/{{run}}/{{table}}.csv",
        record=f"{DATASET}/dataset.json",
    output:
        f"{RESULTS}/seed{{seed}}/{{run}}/{{table}}.csv",
    wildcard_constraints:
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
