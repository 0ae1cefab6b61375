"""The calibration file: written atomically, read back, and one line for a file that is not
one or is of another version (coincli.io.calibration)."""

from __future__ import annotations

import json
import math

import pytest

from coincli.io import calibration as IO


def _cal():
    return {"format": IO.FORMAT, "version": IO.VERSION, "coin_version": "0.2.0", "seed": 3,
            "fitted": ["friction"], "parameters": {"friction": {"estimate": 0.3, "low": 0.2,
                                                                "high": math.nan}},
            "covariance": [[0.01]], "launch": {}, "fixed": {"restitution": 0.5},
            "surface": {}, "data": [], "diameter_mm": 24.26}


def test_save_then_load(tmp_path):
    path = tmp_path / "cal.json"
    IO.save(str(path), _cal())
    back = IO.load(str(path))
    assert back["parameters"]["friction"]["high"] is None  # JSON has no NaN: null
    assert back["seed"] == 3 and back["fitted"] == ["friction"]
    assert [p.name for p in tmp_path.iterdir()] == ["cal.json"]  # no temporary file left


@pytest.mark.parametrize("text, words", [
    ("label,xi,sides,n\na,0.5,3,10\n", "is not a table calibration"),
    (json.dumps({"format": "something else"}), "is not a table calibration"),
    (json.dumps({"format": IO.FORMAT, "version": 2}), "format version 2; this coin reads "
                                                     "version 1"),
    (json.dumps({**_cal(), "fitted": "friction"}), "'fitted' is missing or malformed"),
    (json.dumps({**_cal(), "parameters": {}}), "parameter 'friction' is missing"),
])
def test_load_refuses_in_one_line(tmp_path, text, words):
    path = tmp_path / "x.json"
    path.write_text(text)
    with pytest.raises(IO.CalibrationError) as exc:
        IO.load(str(path))
    msg = str(exc.value)
    assert words in msg and "\n" not in msg and msg.startswith("--calibration ")


def test_load_names_a_missing_file(tmp_path):
    with pytest.raises(IO.CalibrationError, match="No such file"):
        IO.load(str(tmp_path / "none.json"))
