import doctest
import importlib

import pytest

MODULES = ["odnn_sep.mismatch", "odnn_sep.mismatch.model", "odnn_sep.mismatch.calibrate",
           "odnn_sep.mismatch.locate", "odnn_sep.mismatch.explain"]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_run(name):
    res = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS)
    assert res.failed == 0
