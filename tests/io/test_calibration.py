"""The calibration file: written atomically, read back, and one line for a file that is not
one or is of another version (coincli.io.calibration)."""

from __future__ import annotations

import json
import math

import pytest

from coincli.io import calibration as IO


def _cal():
    """A calibration as coin fit --landing bounce --save writes it (the fields a command
    reads; the response surface and the profiles left out)."""
    hand = {"u": {"kind": "normal", "p1": 2.4, "p2": 0.3, "lo": 0.0, "hi": 1e8},
            "omega": {"kind": "normal", "p1": 238.76, "p2": 25.13, "lo": 0.0, "hi": None},
            "psi": {"kind": "normal", "p1": math.pi / 2, "p2": 0.1745, "lo": 0.0,
                    "hi": math.pi}}
    fixed = {"kind": "fixed", "p1": 0.0, "p2": 0.0, "lo": None, "hi": None}
    return {"format": IO.FORMAT, "version": IO.VERSION, "coin_version": "0.2.0", "seed": 3,
            "fitted": ["friction"], "parameters": {"friction": {"estimate": 0.3, "low": 0.2,
                                                                "high": math.nan}},
            "covariance": [[0.01]],
            "launch": {**hand, "release_height_m": dict(fixed), "vx_ms": dict(fixed),
                       "dt": 1e-4, "t_max": 10.0, "text": "the hand toss"},
            "fixed": {"restitution": 0.5, "torsional": 1e-4, "rolling": 1e-4},
            "surface": {}, "data": [], "diameter_mm": 24.26}


def test_save_then_load(tmp_path):
    path = tmp_path / "cal.json"
    IO.save(str(path), _cal())
    back = IO.load(str(path))
    assert json.loads(path.read_text())["parameters"]["friction"]["high"] is None  # no NaN
    assert math.isnan(back["parameters"]["friction"]["high"])  # read back as NaN
    assert back["seed"] == 3 and back["fitted"] == ["friction"]
    assert [p.name for p in tmp_path.iterdir()] == ["cal.json"]  # no temporary file left


@pytest.mark.parametrize("text, words", [
    ("label,xi,sides,n\na,0.5,3,10\n", "is not a table calibration"),
    (json.dumps({"format": "something else"}), "is not a table calibration"),
    (json.dumps({"format": IO.FORMAT, "version": 2}), "format version 2; this coin reads "
                                                     "version 1"),
    (json.dumps({**_cal(), "fitted": "friction"}), "'fitted' is missing or malformed"),
    (json.dumps({**_cal(), "parameters": {}}), "parameters.friction must be an object"),
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


# --------------------------------------------------------------------------- a hand edit
# (issue 38, item 4): every field a command uses is checked, type, kind and range, in one line
# naming the field and what is allowed, with the ranges of the options (coincli.limits)


def _edit(how):
    cal = json.loads(json.dumps(IO._clean(_cal())))
    L = cal["launch"]
    if how == "no torsional":
        del cal["fixed"]["torsional"]
    elif how == "fitted nested":
        cal["fitted"] = [["friction"]]
    elif how == "fitted unknown":
        cal["fitted"] = ["bounciness"]
    elif how == "fitted twice":
        cal["fitted"] = ["friction", "friction"]
        cal["covariance"] = [[0.01, 0], [0, 0.01]]
    elif how == "unknown kind":
        L["u"]["kind"] = "lognormal"
    elif how == "dt 0":
        L["dt"] = 0
    elif how == "dt 1e-9":
        L["dt"] = 1e-9
    elif how == "dt text":
        L["dt"] = "1e-4"
    elif how == "t_max 0":
        L["t_max"] = 0
    elif how == "height 1e9":
        L["release_height_m"]["p1"] = 1e9
    elif how == "negative sd":
        L["u"]["p2"] = -0.3
    elif how == "omega too fast":
        L["omega"]["p1"] = 1e5
    elif how == "u no mass":
        L["u"]["p1"] = -100.0
    elif how == "uniform reversed":
        L["vx_ms"] = {"kind": "uniform", "p1": 2.0, "p2": 1.0, "lo": None, "hi": None}
    elif how == "psi density bad":
        L["psi"] = {"kind": "density", "spec": "wobbly"}
    elif how == "vx out of range":
        L["vx_ms"]["p1"] = 1000.0
    elif how == "estimate out of range":
        cal["parameters"]["friction"]["estimate"] = 50.0
    elif how == "estimate text":
        cal["parameters"]["friction"]["estimate"] = "0.3"
    elif how == "low text":
        cal["parameters"]["friction"]["low"] = "0.2"
    elif how == "restitution 2":
        cal["fixed"]["restitution"] = 2.0
    elif how == "rolling negative":
        cal["fixed"]["rolling"] = -1e-4
    elif how == "covariance shape":
        cal["covariance"] = [0.01]
    elif how == "covariance negative":
        cal["covariance"] = [[-0.01]]
    elif how == "seed negative":
        cal["seed"] = -1
    elif how == "diameter 0":
        cal["diameter_mm"] = 0
    elif how == "launch text number":
        L["text"] = 5
    elif how == "launch missing u":
        del L["u"]
    return json.dumps(cal)


HAND_EDITS = [
    ("no torsional", "fixed.torsional must be a number from 0 to 0.1 m (the range of "
                     "--torsional), got nothing"),
    ("fitted nested", "fitted must be a list of one to three distinct names from restitution, "
                      "friction, psi_sd_deg, got [[\"friction\"]]"),
    ("fitted unknown", "fitted must be"),
    ("fitted twice", "fitted must be"),
    ("unknown kind", "launch.u.kind must be one of fixed, normal, uniform, got \"lognormal\""),
    ("dt 0", "launch.dt must be a number from 1e-06 to 0.001 s (the range of --dt), got 0"),
    ("dt 1e-9", "launch.dt must be a number from 1e-06 to 0.001 s (the range of --dt), got "
                "1e-09"),
    ("dt text", "launch.dt must be a number"),
    ("t_max 0", "launch.t_max must be a number from 0.01 to 1000 s (the range of --t-max)"),
    ("height 1e9", "launch.release_height_m.p1 must be in [0, 100] m (the range of "
                   "--release-height), got 1000000000.0"),
    ("negative sd", "launch.u.p2 (a normal's sd) must be a finite number >= 0, got -0.3"),
    ("omega too fast", "launch.omega must be at most 10000 rad/s at its largest"),
    ("u no mass", "launch.u: 'normal:-100:0.3' puts no probability in the allowed range"),
    ("uniform reversed", "launch.vx_ms.p1 and .p2 must be LOW <= HIGH of a uniform"),
    ("psi density bad", "launch.psi.spec must be a psi density --psi-dist reads"),
    ("vx out of range", "launch.vx_ms.p1 must be in [0, 100] m/s (the range of --vx)"),
    ("estimate out of range", "parameters.friction.estimate must be a number from 0.05 to 1 "
                              "(the designed range), got 50.0"),
    ("estimate text", "parameters.friction.estimate must be a number"),
    ("low text", "parameters.friction.low must be a number or null, got \"0.2\""),
    ("restitution 2", "fixed.restitution must be a number from 0.06 to 0.95 (the range of "
                      "--restitution), got 2.0"),
    ("rolling negative", "fixed.rolling must be a number from 0 to 0.1 m"),
    ("covariance shape", "covariance must be a 1 x 1 list of lists of finite numbers"),
    ("covariance negative", "covariance must be a matrix whose diagonal"),
    ("seed negative", "seed must be a whole number >= 0"),
    ("diameter 0", "diameter_mm must be a finite number > 0"),
    ("launch text number", "launch.text must be a text"),
    ("launch missing u", "launch.u must be an object with a kind"),
]


@pytest.mark.parametrize("how, words", HAND_EDITS, ids=[h for h, _ in HAND_EDITS])
def test_a_hand_edited_field_is_one_line_naming_it(tmp_path, how, words):
    path = tmp_path / "cal.json"
    path.write_text(_edit(how))
    with pytest.raises(IO.CalibrationError) as exc:
        IO.load(str(path))
    msg = str(exc.value)
    assert msg.startswith(f"--calibration {path}: ") and "\n" not in msg, msg
    assert words in msg, msg


@pytest.mark.parametrize("where", ["whole", "field"])
def test_deeply_nested_json_is_not_a_calibration(tmp_path, where):
    deep = "[" * 200_000 + "]" * 200_000
    path = tmp_path / "cal.json"
    path.write_text(deep if where == "whole" else
                    json.dumps(IO._clean(_cal())).replace('"data": []', f'"data": {deep}'))
    with pytest.raises(IO.CalibrationError, match="is not a table calibration"):
        IO.load(str(path))


def test_a_fixed_launch_value_written_as_the_file_writes_fixed_values(tmp_path):
    """A fixed u with no bounds (as the file writes release_height_m) is read as a fixed
    launch: its bounds are u's range, so that the commands take it as a distribution."""
    cal = json.loads(_edit("none"))
    cal["launch"]["u"] = {"kind": "fixed", "p1": 2.4, "p2": 0.0, "lo": None, "hi": None}
    path = tmp_path / "cal.json"
    path.write_text(json.dumps(cal))
    back = IO.load(str(path))
    assert back["launch"]["u"] == {"kind": "fixed", "p1": 2.4, "p2": 0.0, "lo": 0.0,
                                   "hi": 1e8}
    assert back["launch"]["release_height_m"]["lo"] is None  # a number, as before


def test_a_file_without_the_launch_text_is_read(tmp_path):
    """A calibration of 0.2.0 has no launch.text (it was the hand toss): still read."""
    cal = json.loads(_edit("none"))
    del cal["launch"]["text"]
    path = tmp_path / "cal.json"
    path.write_text(json.dumps(cal))
    assert "text" not in IO.load(str(path))["launch"]


CLI_EDITS = ["no torsional", "fitted nested", "unknown kind", "dt 0", "dt 1e-9", "height 1e9",
             "negative sd", "omega too fast", "nested"]


@pytest.mark.parametrize("how", CLI_EDITS)
def test_a_hand_edited_calibration_on_the_command_line(coin, tmp_path, how):
    """Each was an internal error, a message blaming an option never typed, or (an unknown
    kind) read as a normal: now one line, exit 2, ``--calibration FILE: ...``."""
    pytest.importorskip("mujoco")
    from cli_helpers import error

    path = tmp_path / "cal.json"
    path.write_text("[" * 200_000 + "]" * 200_000 if how == "nested" else _edit(how))
    err = error(coin("simulate", "--landing", "bounce", "--calibration", path, "-n", "8",
                     "--xi", "0.5", "--seed", "1", "--jobs", "1"), 2)
    assert err.startswith(f"coin: error: --calibration {path}"), err
    words = dict(HAND_EDITS).get(how, "is not a table calibration")
    assert words in err, err


def test_a_fixed_u_on_the_command_line(coin, tmp_path):
    """A fixed launch.u without bounds was an internal AttributeError; it is a fixed toss."""
    pytest.importorskip("mujoco")
    cal = json.loads(_edit("none"))
    cal["launch"]["u"] = {"kind": "fixed", "p1": 2.4, "p2": 0.0, "lo": None, "hi": None}
    path = tmp_path / "cal.json"
    path.write_text(json.dumps(cal))
    rc, out, err = coin("simulate", "--landing", "bounce", "--calibration", path, "-n", "8",
                        "--xi", "0.5", "--seed", "1", "--jobs", "1", "-f", "csv")
    assert rc == 0 and err == "" and out.startswith("outcome,")


@pytest.mark.parametrize("field, value, words", [
    ("u", {"kind": "normal", "p1": 30.0, "p2": 0.3, "lo": 0.0, "hi": 1e8},
     "got \"the calibration's launch.u ("),
    ("release_height_m", {"kind": "fixed", "p1": 50.0, "p2": 0.0, "lo": None, "hi": None},
     "got \"50000 mm (the calibration's)\""),
])
def test_a_launch_in_range_that_cannot_land_names_the_calibration(coin, tmp_path, field, value,
                                                                  words):
    """In the options' range, but the coin cannot land in half of t_max: the line names the
    calibration's value (it said `got 'None'`, or the hand toss's u, never typed)."""
    pytest.importorskip("mujoco")
    from cli_helpers import error

    cal = json.loads(_edit("none"))
    cal["launch"][field] = value
    cal["launch"]["t_max"] = 2.5
    path = tmp_path / "cal.json"
    path.write_text(json.dumps(cal))
    err = error(coin("simulate", "--landing", "bounce", "--calibration", path, "-n", "8",
                     "--xi", "0.5", "--seed", "1", "--jobs", "1"), 2, words)
    assert "None" not in err and "normal:2.4:0.3" not in err
