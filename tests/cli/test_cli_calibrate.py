"""``coin fit --landing bounce`` on the engine, small: one prototype, friction alone, 32
simulated tosses a designed table (160 in all); the calibration file under ``coin simulate``
and ``coin design``; what is refused.  The method's statistics are tests/core/test_calibrate.py;
its round trip on the engine is benchmarks/calibration_roundtrip.py."""

from __future__ import annotations

import json

import pytest
from cli_helpers import error

from coincli import api

pytest.importorskip("mujoco")

FIT = ["--landing", "bounce", "--fit", "friction", "--design-tosses", "32", "--dt", "2e-4",
       "--t-max", "2.5", "--seed", "3"]  # 2.5 s (the least the hand toss allows): a coin
# rolling longer is unsettled, and cheap


@pytest.fixture(scope="module")
def tosses(tmp_path_factory):
    path = tmp_path_factory.mktemp("cal") / "tosses.csv"
    path.write_text("label,coin,count,heads,sides,tails\nthree quarters,quarter,3,14,3,15\n")
    return path


@pytest.mark.slow
def test_fit_saves_a_calibration_the_other_commands_take(coin, tosses, tmp_path):
    """Calibrated for a tumbling toss (psi uniform, the engines' random axis), the table is
    used with that launch by every command, and another launch is refused or noted."""
    cal = tmp_path / "table.json"
    rc, out, err = coin("fit", tosses, *FIT, "--psi-dist", "uniform", "--jobs", "2", "--save",
                        cal, "--checkpoint", tmp_path / "fit.ck", "-f", "json")
    assert rc == 0, err
    row = json.loads(out)[0]
    for key in ("friction", "friction_low", "friction_high", "p_value", "method", "seed"):
        assert key in row
    assert row["friction_low"] <= row["friction"] <= row["friction_high"]
    assert row["restitution"] == 0.5 and row["seed"] == 3  # wood's, fixed
    assert row["simulated"] == 5 * 32 and row["df"] == 1
    # the same seed gives the same row, with one worker or two, from Python too
    assert api.fit(str(tosses), landing="bounce", fit="friction", design_tosses=32, dt=2e-4,
                   t_max=2.5, seed=3, jobs=1, psi_dist="uniform") == [row]
    saved = json.loads(cal.read_text())
    assert saved["format"] == "coin-calibration" and saved["version"] == 1
    # the launch is recorded: the tumbling toss's psi, the hand toss's u and omega
    assert saved["launch"]["psi"]["kind"] == "density"
    assert saved["launch"]["psi"]["spec"] == "uniform"
    assert saved["launch"]["u"] == {"kind": "normal", "p1": 2.4, "p2": 0.3, "lo": 0.0,
                                    "hi": 1e8}
    assert "psi ~ uniform" in saved["launch"]["text"]
    assert saved["parameters"]["friction"]["estimate"] == row["friction"]
    assert saved["diameter_mm"] == 24.26 and saved["data"][0]["heads"] == 14
    # the calibrated table under coin simulate
    rc, out, err = coin("simulate", "--xi", "0.5", "-n", "8", "--seed", "1", "--landing",
                        "bounce", "--calibration", cal, "--jobs", "1", "-f", "json")
    assert rc == 0, err
    sim = json.loads(out)
    assert sim[0]["surface"] == "calibrated" and sim[0]["friction"] == row["friction"]
    # with the calibration's launch, not the hand toss: the same counts as that launch typed
    rc, out2, err = coin("simulate", "--xi", "0.5", "-n", "8", "--seed", "1", "--landing",
                         "bounce", "--calibration", cal, "--psi-dist", "uniform", "--jobs", "1",
                         "-f", "json")
    assert rc == 0 and "not the launch" not in err
    assert [r["count"] for r in json.loads(out2)] == [r["count"] for r in sim]
    # another toss is tossed ("this toss on my table"), with a note that it is another
    rc, out, err = coin("simulate", "--xi", "0.5", "-n", "8", "--seed", "1", "--landing",
                        "bounce", "--calibration", cal, "--psi", "80", "--jobs", "1", "-f",
                        "json")
    assert rc == 0 and "--psi 80 is not the launch the table was calibrated with" in err
    assert [r["count"] for r in json.loads(out)] != [r["count"] for r in sim]
    # design for it: the intervals hold the calibration's uncertainty
    rc, out, err = coin("design", "-p", "1/3", "--landing", "bounce", "--calibration", cal,
                        "--max-tosses", "180", "--seed", "2", "--jobs", "1", "-f", "json")
    assert rc == 0 and "stopped before --tol" in err
    d = json.loads(out)[0]
    assert d["xi_low"] < d["xi"] < d["xi_high"]
    assert d["thickness_low_mm"] == pytest.approx(24.26 * d["xi_low"])
    assert d["thickness_high_mm"] == pytest.approx(24.26 * d["xi_high"])
    assert d["sd_ln_xi_calibration"] > 0 and d["dominant"] in ("simulation", "calibration")
    # coin table and coin check on the calibrated table, with its launch
    rc, out, err = coin("table", "--landing", "bounce", "--xi", "0.5", "-n", "8", "--seed", "1",
                        "--calibration", cal, "--jobs", "1", "-f", "json")
    assert rc == 0, err
    cell = json.loads(out)[0]
    assert cell["surface"] == "calibrated" and cell["friction"] == row["friction"]
    assert cell["settled"] + cell["unsettled"] == 8
    from coincli.reports import check as R

    saved_sims = R.SIM_TOSSES
    R.SIM_TOSSES = (8, 1, 8)
    try:
        rc, out, err = coin("check", "--landing", "bounce", "--calibration", cal, "--xi", "0.5",
                            "--heads", "3", "--sides", "2", "--tails", "3", "--seed", "1",
                            "--jobs", "1", "-f", "json")
    finally:
        R.SIM_TOSSES = saved_sims
    assert rc == 0, err
    assert json.loads(out)[-1]["model"] == "bounce on calibrated"
    for cmd in (["table", "--xi", "0.5"], ["check", "--xi", "0.5", "--heads", "1", "--sides",
                                           "1", "--tails", "1"]):
        error(coin(*cmd, "--landing", "bounce", "--calibration", cal, "--u", "3"), 2,
              "--u 3 m/s differs from the calibration's normal:2.4:0.3 m/s",
              "holds for the launch it was fitted with")
        error(coin(*cmd, "--landing", "bounce", "--calibration", cal, "--psi-dist",
                   "normal:90:10"), 2, "--psi/--psi-dist normal:90:10 deg differs from the "
              "calibration's uniform deg")
        error(coin(*cmd, "--landing", "bounce", "--calibration", cal, "--friction", "0.4"), 2,
              "--friction cannot go with --calibration")
    # what does not go with a calibration
    error(coin("simulate", "--xi", "0.5", "--landing", "bounce", "--calibration", cal,
               "--friction", "0.4"), 2, "--friction cannot go with --calibration")
    error(coin("simulate", "--xi", "0.5", "--landing", "bounce", "--calibration", cal,
               "--release-height", "300"), 2, "--release-height 300 mm differs from the "
          "calibration's 0 mm")
    error(coin("simulate", "--xi", "0.5", "--landing", "bounce", "--calibration", cal,
               "--t-max", "10"), 2, "--t-max 10 s differs from the calibration's 2.5 s")
    error(coin("design", "-p", "1/3", "--landing", "bounce", "--calibration", cal, "--u", "3"),
          2, "--u 3 m/s differs from the calibration's")
    error(coin("design", "-p", "1/3", "--landing", "bounce", "--calibration", cal, "--psi",
               "90"), 2, "--psi/--psi-dist 90 deg differs from the calibration's uniform deg")
    error(coin("simulate", "--xi", "0.5", "--calibration", cal), 2,
          "--calibration goes with --landing bounce")
    saved["launch"]["psi"]["spec"] = "sideways"  # a launch this coin cannot read: one line
    bad = tmp_path / "bad_launch.json"
    bad.write_text(json.dumps(saved))
    error(coin("simulate", "--xi", "0.5", "--landing", "bounce", "--calibration", bad), 2,
          f"--calibration {bad}: launch.psi.spec must be a psi density --psi-dist reads")


def test_fit_refuses_in_one_line(coin, tosses, tmp_path):
    error(coin("fit", tosses, "--landing", "bounce", "--fit", "spin"), 2,
          "--fit takes restitution, friction and psi-spread")
    error(coin("fit", tosses, "--landing", "bounce", "--friction", "0.3"), 2,
          "--friction cannot go with --fit restitution,friction")
    error(coin("fit", tosses, "--seed", "1"), 2, "--seed goes with --landing bounce")
    error(coin("fit", tosses, "--omega", "10"), 2, "--omega goes with --landing bounce")
    error(coin("fit", tosses, "--landing", "bounce", "--fit", "psi-spread", "--psi-dist",
               "uniform"), 2, "--psi and --psi-dist cannot go with --fit psi-spread")
    error(coin("fit", tosses, "--landing", "bounce", "--omega", "20000"), 2,
          "--omega must be at most")
    table = tmp_path / "psi.csv"
    table.write_text("80,1\n100,1\n")
    error(coin("fit", tosses, "--landing", "bounce", "--psi-dist", f"table:{table}"), 2,
          "a table of psi is a file it cannot hold")
    two = tmp_path / "two.csv"
    two.write_text("coin,heads,sides,tails\nquarter,5,5,5\nnickel,5,5,5\n")
    error(coin("fit", two, "--landing", "bounce"), 2, "one table and one coin size")
    bad = tmp_path / "bad.json"
    bad.write_text("{}")
    error(coin("design", "-p", "1/3", "--landing", "bounce", "--calibration", bad), 2,
          "is not a table calibration")


@pytest.mark.slow
def test_psi_spread_calibrated_on_the_engine(coin, tmp_path):
    """``--fit psi-spread`` on the engine, small (160 tosses of data, 5 designed spreads of 32
    tosses): tosses simulated on wood with psi ~ normal(90, 20) deg are calibrated; the 95%
    interval of the spread holds 20 and reaches neither end of the designed range (2 and 30
    deg: the counts pin it), and the calibrated spread is the launch of the commands that take
    the file."""
    common = ["--dt", "2e-4", "--t-max", "2.5", "--jobs", "1"]
    rc, out, err = coin("simulate", "--xi", "0.55", "-n", "160", "--seed", "11", "--landing",
                        "bounce", "--psi-dist", "normal:90:20", *common, "-f", "json")
    assert rc == 0, err
    n = {r["outcome"]: r["count"] for r in json.loads(out)}
    data = tmp_path / "spread.csv"
    data.write_text(f"xi,heads,sides,tails\n0.55,{n['heads']},{n['sides']},{n['tails']}\n")
    cal = tmp_path / "spread.json"
    rc, out, err = coin("fit", data, "--landing", "bounce", "--fit", "psi-spread",
                        "--design-tosses", "32", "--seed", "5", *common, "--save", cal, "-f",
                        "json")
    assert rc == 0, err
    row = json.loads(out)[0]
    assert row["psi_sd_deg_low"] <= 20 <= row["psi_sd_deg_high"], row
    assert 2 < row["psi_sd_deg_low"] and row["psi_sd_deg_high"] < 30, row  # not the range
    assert row["pinned"] == "psi_sd_deg"
    assert row["restitution"] == 0.5 and row["friction"] == 0.3  # wood's, fixed
    saved = json.loads(cal.read_text())
    assert saved["fitted"] == ["psi_sd_deg"]
    rc, out, err = coin("simulate", "--xi", "0.55", "-n", "4", "--seed", "1", "--landing",
                        "bounce", "--calibration", cal, "--jobs", "1")
    assert rc == 0, err
    assert f"psi ~ normal(90, {row['psi_sd_deg']:.3g}) deg (its spread calibrated)" in out
