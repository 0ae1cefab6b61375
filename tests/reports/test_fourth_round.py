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


def test_a_design_the_tosses_cannot_determine_exits_1(coin):
    """A valid bouncing design whose tosses never land on a side (no spin, no speed): no curve
    of P(sides) can be fitted, an answer that cannot be computed (exit 1), not a usage error."""
    code, out, err = coin("design", "-p", "1/3", "--landing", "bounce", "--u", "0", "--omega",
                          "0", "--psi", "0", "--seed", "1", "--max-tosses", "180", "--jobs",
                          "1", "--no-table")
    assert code == 1 and out == "" and err.count("\n") == 1
    assert "do not determine a curve of P(sides)" in err


def test_one_tossers_failed_table_design_keeps_the_others(monkeypatch):
    """coin fit --design --calibration: a tosser whose design on the table finds no answer gets
    empty table_design cells and a note; the other tossers keep theirs."""
    from types import SimpleNamespace

    import numpy as np

    from coincli.core.toss.launch import Dist
    from coincli.errors import NotComputable
    from coincli.io.table import Column, Result
    from coincli.reports import calibrate, calibrated, fit, physics

    def fake_design(p, *, targets, psi, **kw):
        if psi == np.pi / 2:  # the tosser of sd 0 (psi = 90 deg): no answer
            raise NotComputable("the simulated P(sides) does not grow with xi; no design found")
        names = ("xi", "xi_low", "xi_high", "thickness_mm", "thickness_low_mm",
                 "thickness_high_mm", "dominant", "tosses", "seed")
        return Result("x", [Column(n, n) for n in names],
                      [(0.5, 0.49, 0.51, 12.0, 11.8, 12.2, "simulation", 1200, 7)])

    monkeypatch.setattr(calibrate, "design", fake_design)
    monkeypatch.setattr(calibrated, "launch_of", lambda cal: (Dist("fixed", 2.4, 0.0, 0.0, 2.4), None, None))
    monkeypatch.setattr(physics, "check_coin", lambda *a, **k: None)
    monkeypatch.setattr(physics, "check_landing", lambda *a, **k: None)
    cal = {"diameter_mm": 24.26, "fitted": ["friction"],
           "parameters": {"friction": {"estimate": 0.3}}}
    phys = SimpleNamespace(calibration=("cal.json", cal))
    cf = SimpleNamespace(rows=np.array([0, 1]), fits=SimpleNamespace(sigma=np.array([0.0, 0.2])))
    exps = SimpleNamespace(diameter=np.array([24.26, 24.26]), line=np.array([2, 3]))
    t = fit._table_designs(phys, cf, exps, 1 / 3, seed="7", design_tosses=None)
    assert t.rows[0][0] is None and t.rows[0][3] == 24.26
    assert t.rows[1][0] == 0.5
    assert "No design on your table (empty table_design_ cells) for line 2: the simulated " \
           "P(sides) does not grow with xi" in t.note
