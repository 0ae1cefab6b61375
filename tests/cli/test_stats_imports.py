"""The import budget of ``coin check`` and ``coin fit``, in a real process (no timing).

Their answers need numpy and scipy.special (binomial tails, beta quantiles, chi-square tails)
and, for ``fit``, a one-dimensional optimizer (pure Python in coincli.core._numerics.roots).
scipy.stats costs 0.6 s of import, scipy.optimize 0.1-0.2 s; rich draws nothing in a pipe;
matplotlib draws nothing here at all.  Style of tests/test_cli_subprocess.py: one process runs
the commands one after another through coincli.cli.run with stdout a pipe, then reports which
modules were loaded.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

TOSSES = str(Path(__file__).resolve().parents[1] / "data" / "tosses.csv")

FORBIDDEN = ("scipy.stats", "scipy.optimize", "scipy.integrate", "scipy.linalg", "rich",
             "matplotlib")

_PROBE = r"""
import json, sys
from coincli.cli import run
report = []
for argv in json.loads(sys.argv[1]):
    code = run(argv)
    sys.stdout.flush()
    loaded = sorted(m for m in sys.modules
                    if m.split(".")[0] in ("numpy", "scipy", "rich", "matplotlib"))
    report.append([argv, code, loaded])
print(json.dumps(report), file=sys.stderr)
"""


def _probe(commands):
    p = subprocess.run([sys.executable, "-c", _PROBE, json.dumps(commands)],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stderr.strip().splitlines()[-1]), p.stdout


def _bad(loaded):
    return sorted({m for m in loaded for f in FORBIDDEN if m == f or m.startswith(f + ".")})


CHECK = [
    ["check", "--xi", "0.5", "--heads", "30", "--sides", "30", "--tails", "30"],
    ["check", "--xi", "0.583", "--sides", "33", "-n", "100", "--format", "csv"],
    ["check", "--quarters", "8", "--heads", "35", "--sides", "33", "--tails", "32", "-q"],
    ["check", "--xi", "0.5", "--sides", "3", "-n", "9", "--confidence", "0.9999999999999999"],
    ["check", "--xi", "0.5", "--heads", "3", "--sides", "3", "--tails", "3", "--psi-dist",
     "normal:90:18,uniform", "--format", "json"],
]
FIT = [
    ["fit", TOSSES],
    ["fit", TOSSES, "--format", "csv"],
    ["fit", TOSSES, "-q"],
    ["fit", TOSSES, "--psi-dist", "cosine", "--format", "jsonl"],
    ["fit", TOSSES, "--no-spread", "--format", "tsv"],
]


@pytest.mark.slow
@pytest.mark.parametrize("commands", [CHECK, FIT], ids=["check", "fit"])
def test_check_and_fit_load_only_numpy_and_scipy_special(commands):
    # each command runs in a fresh process: a module loaded by one must not hide another's
    for argv in commands:
        report, out = _probe([argv])
        (_, code, loaded), = report
        assert code == 0, argv
        assert "\x1b" not in out  # piped: no colour codes
        assert "numpy" in loaded and "scipy.special" in loaded, (argv, loaded)  # the probe works
        assert _bad(loaded) == [], f"coin {' '.join(argv)} imported {_bad(loaded)}"


@pytest.mark.slow
def test_the_probe_sees_a_forbidden_module_when_it_is_loaded(tmp_path):
    # control: a figure file needs matplotlib
    pytest.importorskip("matplotlib")
    report, _ = _probe([["plot", "sides", "--out", str(tmp_path / "s.png")]])
    (_, code, loaded), = report
    assert code == 0 and "matplotlib" in _bad(loaded)
