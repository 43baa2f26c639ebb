"""The docstrings' examples run."""

import doctest

import pytest

import delone
import delone.tetgen
import delone.triangle


@pytest.mark.parametrize("module", [delone, delone.triangle, delone.tetgen])
def test_docstring_examples(module):
    r = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert r.attempted > 0
    assert r.failed == 0
