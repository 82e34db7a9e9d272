"""The study schema as the package reads it (suspension_fabric.io.schema): libyaml's safe loader
when PyYAML has it, parsed once per version of the file, each caller given its own copy."""

import yaml

from suspension_fabric.io.resources import SCHEMA_PATH
from suspension_fabric.io.schema import load_schema, read_schema


def test_the_schema_reads_as_pyyaml_s_pure_python_safe_loader_reads_it():
    assert read_schema() == yaml.safe_load(SCHEMA_PATH.read_text()) == load_schema()


def test_a_copy_changed_by_its_caller_leaves_the_next_read_alone():
    first = read_schema()
    first["properties"]["run"]["properties"]["dt"]["default"] = -1.0
    assert read_schema()["properties"]["run"]["properties"]["dt"]["default"] > 0


def test_an_edited_schema_file_is_read_again(tmp_path):
    path = tmp_path / "schema.yaml"
    path.write_text("type: object\nproperties: {a: {default: 1}}\n")
    assert read_schema(path)["properties"]["a"]["default"] == 1
    path.write_text("type: object\nproperties: {a: {default: 22}}\n")
    assert read_schema(path)["properties"]["a"]["default"] == 22
