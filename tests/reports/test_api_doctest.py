"""The examples in coincli.api's docstrings run, and print what they show; and the api takes
numpy values as the numbers they are, flags as bools only."""

from __future__ import annotations

import doctest

import numpy as np
import pytest

import coincli.api as api
from coincli.errors import InputError


def test_every_example_of_the_api_runs():
    failed, tried = doctest.testmod(api, optionflags=doctest.ELLIPSIS)
    assert tried >= 12 and failed == 0
    for name in api.__all__:  # every command has a function with an example
        assert ">>>" in getattr(api, name).__doc__, name


def test_numpy_numbers_are_the_numbers_they_hold():
    assert api.table(xi=np.float64(0.5)) == api.table(xi=0.5) == api.table(xi="0.5")
    assert api.table(xi=np.array([0.2, 0.577])) == api.table(xi=[0.2, 0.577])
    assert api.stack(quarters=np.int64(8)) == api.stack(quarters=8)


def test_a_flag_takes_a_bool_and_a_value_option_takes_no_bool():
    with pytest.raises(InputError, match="--all is a flag"):
        api.table(xi=0.5, all="yes")
    with pytest.raises(InputError, match="--xi takes a value"):
        api.table(xi=True)
    assert len(api.table(xi=0.5, all=True)) == 5
