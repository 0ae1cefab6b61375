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


def test_one_path_for_checkpoint_and_save_is_refused_before_any_toss(coin, tmp_path):
    tosses = tmp_path / "t.csv"
    tosses.write_text("xi,heads,sides,tails\n0.5,40,30,30\n")
    path = tmp_path / "both.json"
    code, out, err = coin("fit", tosses, "--landing", "bounce", "--fit", "friction",
                          "--design-tosses", "32", "--seed", "1", "--checkpoint", path,
                          "--save", tmp_path / "." / "both.json")
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "--save and --checkpoint name one file" in err
    assert not path.exists()


@pytest.mark.parametrize("option", ["--save", "--checkpoint"])
def test_an_unwritable_directory_is_refused_before_any_toss(coin, tmp_path, monkeypatch,
                                                            option):
    """Root may write anywhere, so the directory's refusal is simulated: os.access says no
    for it, as it does for a user without write permission."""
    import os

    tosses = tmp_path / "t.csv"
    tosses.write_text("xi,heads,sides,tails\n0.5,40,30,30\n")
    locked = tmp_path / "locked"
    locked.mkdir()
    real_access = os.access
    monkeypatch.setattr(os, "access", lambda p, mode, **kw: False if os.fspath(p) == str(
        locked) else real_access(p, mode, **kw))
    started = []
    from coincli.core.bounce import calibrate as core_calibrate

    monkeypatch.setattr(core_calibrate, "run_design", lambda *a, **k: started.append(1))
    code, out, err = coin("fit", tosses, "--landing", "bounce", "--fit", "friction",
                          "--design-tosses", "32", "--seed", "1", option, locked / "x.json")
    assert code == 1 and out == "" and err.count("\n") == 1
    assert "is not writable" in err and started == []


def test_a_study_where_no_toss_settles_says_so_after_the_table(coin):
    args = ["table", "--landing", "bounce", "--xi", "0.5", "-n", "3", "--seed", "1",
            "--t-max", "0.1", "--u", "0.1", "--jobs", "1"]
    for layout in ("long", "wide"):
        code, out, err = coin(*args, "--layout", layout, "-f", "csv")
        assert code == 0 and out.count("\n") == 2
        assert err.startswith("coin: note: 3 of 3 tosses did not settle") and \
            err.count("\n") == 1
    rows = api.table(xi=0.5, landing="bounce", tosses=3, seed=1, t_max=0.1, u=0.1, jobs=1)
    assert rows[0]["p_sides"] is None and rows[0]["unsettled"] == 3
    assert [n.kind for n in rows.notes] == ["note"] and "did not settle" in rows.notes[0].text
