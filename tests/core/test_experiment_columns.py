"""The experiments file read into columns (issue 27: flat memory) gives back, row by row, the
rows the list parser reads, and the fit of the columns is the fit of the list."""

from pathlib import Path

import numpy as np

from coincli.core.stats import fit as stats_fit
from coincli.core.stats.counts import Caught, Counts
from coincli.io import experiments

DATA = Path(__file__).resolve().parents[1] / "data"

MIXED = """label,coin,xi,diameter,thickness,heads,sides,tails,n,same,different,start
a,quarter,,,,,,,,5080,4920,
b,,0.5,,,30,20,50,,,,
c,,0.75,,,,33,,100,,,
d,,,24.26,1.75,,,,100,51,,
e,,0.09,,,40,,60,,,,tails
"""


def test_columns_give_back_the_rows():
    text = MIXED
    rows = experiments.parse_experiments(text)
    cols = experiments.parse_experiment_columns(text)
    assert len(cols) == len(rows) == 5
    assert list(cols) == rows
    assert isinstance(cols[0].counts, Caught) and isinstance(cols[1].counts, Counts)
    assert cols[-1] == rows[-1] and cols[1:3] == rows[1:3]
    assert cols[2].diameter is None and cols[0].diameter == rows[0].diameter


def test_fit_of_columns_is_fit_of_rows():
    for name in ("tosses.csv", "caught.csv"):
        text = (DATA / name).read_text()
        a = stats_fit.fit(experiments.parse_experiments(text))
        b = stats_fit.fit(experiments.parse_experiment_columns(text))
        assert a.models == b.models
        assert a.rows[0] == b.rows[0] and a.rows[len(a.rows) - 1] == b.rows[len(b.rows) - 1]
        for ta, tb in zip(a.rows.tests, b.rows.tests, strict=True):
            np.testing.assert_array_equal(ta.p_value, tb.p_value)
            assert ta.method == tb.method and ta.verdict == tb.verdict
