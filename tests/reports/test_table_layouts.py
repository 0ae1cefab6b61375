"""``coin table --layout wide`` and ``coin table --landing bounce`` (a parameter study of tables):
the wide table is the long one rearranged, value for value; a bouncing cell is the same tosses
``coin simulate --landing bounce`` makes with the same seed (common random numbers: every cell
tosses the same launches); the command line's json is ``coincli.api.table``; bad input is one
line."""

from __future__ import annotations

import csv
import io
import json

import pytest

from coincli import api
from coincli.errors import InputError

pytestmark = pytest.mark.xdist_group("bounce-study")  # one worker: its module fixture once


def _csv(coin, *argv, stdin=None):
    rc, out, err = coin("table", *argv, "--format", "csv", stdin=stdin)
    assert rc == 0, err
    return list(csv.DictReader(io.StringIO(out)))


def _error(coin, *argv) -> str:
    rc, out, err = coin("table", *argv)
    assert rc == 2 and out == "" and err.startswith("coin: error: ") and err.count("\n") == 1, \
        (rc, out, err)
    return err


# --------------------------------------------------------------------------- --layout wide


@pytest.mark.parametrize("argv, stdin", [
    (["--xi", "0.5,0.6", "--psi", "60", "--psi-dist", "normal:90:18"], None),
    (["--xi", "0.01:1:0.01", "--all"], None),  # 100 coins: the streamed path
    (["--xi", "-"], "\n".join(str(0.005 * k) for k in range(1, 400))),  # stdin, streamed
    (["--quarters", "1:4:1"], None),  # stacked: coin and count lead
    (["--xi", "0.5", "--method", "mc", "--tol", "0.02", "--seed", "4", "--psi-dist", "normal"],
     None),
])
def test_wide_is_the_long_table_rearranged(coin, argv, stdin):
    long = _csv(coin, *argv, stdin=stdin)
    wide = _csv(coin, *argv, "--layout", "wide", stdin=stdin)
    models = list(dict.fromkeys(r["model"] for r in long))
    assert len(wide) * len(models) == len(long)
    lead = [k for k in long[0] if k in ("coin", "count", "xi")]
    values = [k for k in long[0] if k not in lead and k != "model"]
    want = [f"{m}_{v}" for m in models for v in values]
    assert list(wide[0]) == lead + want
    for j, row in enumerate(wide):
        block = long[j * len(models):(j + 1) * len(models)]
        for k in lead:
            assert {r[k] for r in block} == {row[k]}
        for r in block:
            for v in values:
                assert row[f"{r['model']}_{v}"] == r[v]


def test_wide_table_and_json_name_the_same_columns(coin):
    rc, out, err = coin("table", "--xi", "0.5", "--psi-dist", "normal", "--layout", "wide")
    assert rc == 0 and "normal (paper) P(sides)" in out
    rows = json.loads(coin("table", "--xi", "0.5", "--psi-dist", "normal", "--layout", "wide",
                           "-f", "json")[1])
    assert rows == api.table(xi=0.5, psi_dist="normal", layout="wide")
    long = {r["model"]: r for r in api.table(xi=0.5, psi_dist="normal")}
    assert rows[0]["normal_p_sides"] == long["normal"]["p_sides"]
    assert rows[0]["geometric_p_heads"] == long["geometric"]["p_heads"]


@pytest.mark.parametrize("argv, words", [
    (["--xi", "0.5", "--layout", "tall"], ["--layout must be long", "or wide", "'tall'"]),
    (["--xi", "0.5", "--layout", "wide", "-q"], ["--layout wide", "-q prints one P(sides)"]),
])
def test_layout_errors_are_one_line(coin, argv, words):
    err = _error(coin, *argv)
    for w in words:
        assert w in err


# --------------------------------------------------------------------------- --landing bounce

STUDY = ["--landing", "bounce", "--xi", "0.45,0.6", "--surface", "wood", "--friction",
         "0.2,0.4", "-n", "24", "--seed", "11"]


@pytest.fixture(scope="module")
def study_json():
    return api.table(landing="bounce", xi="0.45,0.6", surface="wood", friction="0.2,0.4",
                     tosses=24, seed=11, jobs=1)


def test_bounce_study_rows_in_order_with_intervals(study_json):
    rows = study_json
    assert [(r["xi"], r["friction"]) for r in rows] == [(0.45, 0.2), (0.45, 0.4), (0.6, 0.2),
                                                        (0.6, 0.4)]
    for r in rows:
        assert r["restitution"] == 0.5 and r["seed"] == 11 and r["diameter_mm"] == 24.26
        assert r["settled"] + r["unsettled"] == 24
        total = 0
        for o in ("heads", "sides", "tails"):
            assert r[f"p_{o}_low"] <= r[f"p_{o}"] <= r[f"p_{o}_high"]
            total += r[f"p_{o}"] * r["settled"]
        assert total == pytest.approx(r["settled"], abs=1e-9)


def test_bounce_cell_is_coin_simulate_with_the_same_seed(coin, study_json):
    """Common random numbers: every cell tosses the launches ``coin simulate`` draws from the
    same seed, so a cell's counts are simulate's at that coin and table."""
    rc, out, err = coin("simulate", "--landing", "bounce", "--xi", "0.6", "--surface", "wood",
                        "--friction", "0.4", "-n", "24", "--seed", "11", "--jobs", "1", "-f",
                        "json")
    assert rc == 0, err
    sim = {r["outcome"]: r for r in json.loads(out)}
    cell = study_json[3]
    for o in ("heads", "sides", "tails"):
        assert cell[f"p_{o}"] == sim[o]["frequency"]
        assert (cell[f"p_{o}_low"], cell[f"p_{o}_high"]) == (sim[o]["ci_low"], sim[o]["ci_high"])
    assert cell["unsettled"] == sim["unsettled"]["count"]


def test_bounce_study_same_bytes_any_jobs_and_json_is_api(coin, study_json):
    one = coin("table", *STUDY, "--jobs", "1", "-f", "csv")
    two = coin("table", *STUDY, "--jobs", "2", "-f", "csv")
    assert one[0] == two[0] == 0 and one[1] == two[1]
    rc, out, err = coin("table", *STUDY, "--jobs", "2", "-f", "json")
    assert json.loads(out) == study_json


def test_bounce_study_wide_is_the_long_rearranged(coin, study_json):
    wide = api.table(landing="bounce", xi="0.45,0.6", surface="wood", friction="0.2,0.4",
                     tosses=24, seed=11, jobs=1, layout="wide")
    assert len(wide) == 2
    for row, block in zip(wide, (study_json[:2], study_json[2:]), strict=True):
        assert row["xi"] == block[0]["xi"] and row["seed"] == 11
        for cell in block:
            key = f"e{cell['restitution']:g}_mu{cell['friction']:g}_"
            for name in ("p_heads", "p_sides_low", "p_tails_high", "settled", "unsettled"):
                assert row[key + name] == cell[name]


def test_bounce_cells_none_where_nothing_settled():
    """A cell whose tosses all stay moving has empty chances (None), never nan."""
    from types import SimpleNamespace

    from coincli.reports.bounce_table import study_row

    nan = float("nan")
    sim = SimpleNamespace(settled=0, counts=(0, 0, 0, 5), seed=2,
                          frequencies=[SimpleNamespace(p=nan, lo=0.0, hi=1.0)] * 3)
    surf = SimpleNamespace(name="wood", restitution=0.5, friction=0.3)
    coins = SimpleNamespace(unit=None, counts=None)
    row = study_row(coins, 0, 0.5, 0.02426, surf, sim, False)
    assert row[5:14] == [None] * 9 and row[14:] == [0, 5, 2]


@pytest.mark.parametrize("argv, words", [
    (["--landing", "bounce", "--xi", "0.5", "--vs", "psi"], ["--vs goes with --landing catch"]),
    (["--landing", "bounce", "--xi", "0.5", "--tol", "1e-3"], ["--tol goes with --landing catch"]),
    (["--xi", "0.5", "--u", "2"], ["--u goes with --landing bounce"]),
    (["--xi", "0.5", "--surface", "wood"], ["--surface goes with --landing bounce"]),
    (["--xi", "0.5", "-n", "8"], ["-n is a number of tosses", "--count N"]),
    (["--landing", "bounce", "--xi", "0.5", "--psi", "60,90"], ["--psi with --landing bounce",
                                                                "'60,90'"]),
    (["--landing", "bounce", "--xi", "0.1:0.9:0.01", "--surface", "wood", "--friction",
      "0.1:1.5:0.1"], ["at most 1000 cells", "make 1215"]),
    (["--landing", "bounce", "--xi", "0.5", "--surface", "wood", "--restitution", "0.3,1.2"],
     ["--restitution must be a number from 0.06 to 0.95", "'1.2'"]),
    (["--landing", "bounce", "--xi", "0.1:0.5:0.1", "--surface", "wood", "--friction",
      "0.1,0.2,0.3", "-n", "100000"], ["15 cells is 1500000 tosses", "at most 1000000"]),
])
def test_bounce_study_errors_are_one_line(coin, argv, words):
    err = _error(coin, *argv)
    for w in words:
        assert w in err, err


def test_bounce_study_error_is_the_api_error(coin):
    err = _error(coin, "--landing", "bounce", "--xi", "0.5", "--vs", "psi")
    with pytest.raises(InputError) as exc:
        api.table(landing="bounce", xi=0.5, vs="psi")
    assert f"coin: error: {exc.value}\n" == err
