"""Issue 38 (hardening, fourth round): caught flips against stated chances with no coin, wide
study columns that never collide, one path for a checkpoint and a calibration, and the note of
a study where no toss settles."""

from __future__ import annotations

import json

import pytest

from coincli import api
from coincli.reports.bounce_table import _distinct_texts


@pytest.mark.parametrize("extra", [["--fair"], ["--expect", "0.2,0.2,0.6"]])
def test_caught_flips_against_stated_chances_need_no_coin(coin, extra):
    for fmt in ("table", "csv", "json"):
        code, out, err = coin("check", "--same", "10", "--different", "5", *extra, "-f", fmt)
        assert code == 0 and err == "", (fmt, err)
    assert "spread of psi is not fitted: it needs the coin" in coin(
        "check", "--same", "10", "--different", "5", *extra)[1].replace("\n", " ")


def test_wide_names_are_distinct_where_six_digits_are_not():
    assert _distinct_texts([0.3, 0.5]) == {0.3: "0.3", 0.5: "0.5"}
    texts = _distinct_texts([0.3, 0.3000001])
    assert len(set(texts.values())) == 2 and texts[0.3000001] == "0.3000001"


def test_a_wide_study_keeps_every_cell(coin):
    args = ["table", "--landing", "bounce", "--xi", "0.5", "--friction", "0.3,0.3000001",
            "--restitution", "0.5", "-n", "4", "--seed", "1", "--layout", "wide", "-f", "json",
            "--jobs", "1"]
    code, out, _ = coin(*args)
    assert code == 0
    row = json.loads(out)[0]
    # xi, diameter_mm and surface, the 11 cells of each of the 2 tables, the seed: 26 keys
    # (15 when the two frictions shared their names)
    assert len(row) == 3 + 2 * 11 + 1
    assert "e0.5_mu0.3_p_sides" in row and "e0.5_mu0.3000001_p_sides" in row
