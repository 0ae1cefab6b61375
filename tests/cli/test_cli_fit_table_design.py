"""``coin fit FILE --design 1/3 --calibration CAL.json`` (issue 27): each tosser's fair
three-sided coin designed on a calibrated table, with the launch's psi spread the tosser's own.
Small: a calibration written here (friction fitted, as tests/cli/test_cli_calibrate.py makes
one), one tosser, the least design budget (180 tosses and 90 on the tables either side of the
calibration): about 10 s of one core for the design, and as much for the cross-check."""

from __future__ import annotations

import json
import math

import pytest
from cli_helpers import error

from coincli import api

pytest.importorskip("mujoco")

#: a calibration as coin fit --landing bounce --save writes it (the parts the commands read)
CAL = {
    "format": "coin-calibration", "version": 1, "coin_version": "0.2.0", "seed": 3,
    "fitted": ["friction"],
    "parameters": {"friction": {"estimate": 0.3, "low": 0.2, "high": 0.45}},
    "covariance": [[0.0025]], "diameter_mm": 24.26, "surface": {}, "data": [],
    "fixed": {"restitution": 0.5, "rolling": 0.0001, "torsional": 0.0001},
    "launch": {
        "dt": 0.0002, "t_max": 2.5,
        "u": {"kind": "normal", "p1": 2.4, "p2": 0.3, "lo": 0.0, "hi": 1e8},
        "omega": {"kind": "normal", "p1": 238.7610416728243, "p2": 25.132741228718345,
                  "lo": 0.0, "hi": None},
        "psi": {"kind": "normal", "p1": math.pi / 2, "p2": 0.17453292519943295, "lo": 0.0,
                "hi": math.pi},
        "release_height_m": {"kind": "fixed", "p1": 0.0, "p2": 0.0, "lo": None, "hi": None},
        "vx_ms": {"kind": "fixed", "p1": 0.0, "p2": 0.0, "lo": None, "hi": None},
    },
}
SAME, N = 560, 1000  # a tosser of a quarter: sd of psi about 20 deg


@pytest.mark.slow
def test_each_tossers_coin_on_the_calibrated_table(coin, tmp_path):
    cal = tmp_path / "table.json"
    cal.write_text(json.dumps(CAL))
    data = tmp_path / "caught.csv"
    data.write_text(f"label,coin,same,n\nann,quarter,{SAME},{N}\n")
    rows = api.fit(str(data), design="1/3", calibration=str(cal), design_tosses=180, seed=2,
                   jobs=1)
    row = next(r for r in rows if r["model"] == "psi-spread" and r["scope"] == "experiment")
    x = row["table_design_xi"]
    assert row["table_design_xi_low"] < x < row["table_design_xi_high"]
    assert row["table_design_thickness_mm"] == pytest.approx(24.26 * x)
    assert row["table_design_diameter_mm"] == 24.26 and row["table_design_seed"] == 2
    assert row["table_design_tosses"] == 180 + 2 * 45
    assert row["table_design_dominant"] in ("simulation", "calibration")
    # the same design from coin design on a calibration whose launch has the tosser's spread
    # (the sd as the fit has it, to the bit: the tosses depend on every digit)
    from coincli.core.stats.caught import fit_rows

    sigma = float(fit_rows([row["xi"]], [SAME], [N]).sigma[0])
    assert math.degrees(sigma) == pytest.approx(row["sigma_deg"], rel=1e-12)
    theirs = json.loads(json.dumps(CAL))
    theirs["launch"]["psi"]["p2"] = sigma
    cal2 = tmp_path / "theirs.json"
    cal2.write_text(json.dumps(theirs))
    rc, out, err = coin("design", "-p", "1/3", "--landing", "bounce", "--calibration", cal2,
                        "--max-tosses", "180", "--seed", "2", "--jobs", "1", "--diameter",
                        "24.26", "-f", "json")
    assert rc == 0, err
    d = json.loads(out)[0]
    assert (d["xi"], d["xi_low"], d["xi_high"]) == (x, row["table_design_xi_low"],
                                                    row["table_design_xi_high"])
    # each model's row of the tosser carries it, as design_xi; the rows across tossers do not
    assert {r["table_design_xi"] for r in rows if r["scope"] == "experiment"} == {x}
    assert all(r["table_design_xi"] is None for r in rows if r["scope"] != "experiment")


def test_calibration_is_refused_where_it_means_nothing(coin, tmp_path):
    cal = tmp_path / "table.json"
    cal.write_text(json.dumps(CAL))
    data = tmp_path / "caught.csv"
    data.write_text(f"label,coin,same,n\nann,quarter,{SAME},{N}\n")
    assert "--calibration goes with --design" in error(
        coin("fit", data, "--calibration", cal), 2)
    assert "fits a calibration" in error(
        coin("fit", data, "--calibration", cal, "--landing", "bounce"), 2)
    error(coin("fit", data, "--design", "1/3", "--calibration", cal, "--fit", "friction"), 2,
          "--fit goes with --landing bounce")
    error(coin("fit", data, "--design", "1/3", "--calibration", cal, "--surface", "felt"), 2,
          "cannot go with --calibration")
    error(coin("fit", data, "--design", "1/3", "--calibration", cal, "--design-tosses", "5"),
          2, "--design-tosses")
