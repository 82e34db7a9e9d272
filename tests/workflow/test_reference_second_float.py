"""The reference rebuild of test_reference.py under the second floating-point configuration
(tests/workflow_helpers.py, ``second_float_config``): the same test in a module of its own, so that
the suite's two workers, which take whole modules, run the two rebuilds at once."""

import pytest
from test_reference import test_the_reference_study_rebuilds_the_fits_without_simulating as reference_rebuild

pytestmark = pytest.mark.workflow


def test_the_reference_study_rebuilds_the_fits_under_the_second_float_configuration(tmp_path):
    reference_rebuild(tmp_path, "second")
