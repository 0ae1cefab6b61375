"""The wheel installs and runs: what README's install lines promise (issue 38, item 18).

A wheel is built from this checkout (``pip wheel --no-deps``: the build backend, hatchling, in
pip's isolated build environment, so no new dependency here), installed with the ``physics``
extra in a fresh virtual environment (numpy, scipy, typer, rich and mujoco-core come from the
package index), and its ``coin`` designs a bouncing coin from the table shipped inside the
wheel, without simulating every toss.  Slow: a minute or two, most of it the installation.
"""

from __future__ import annotations

import csv
import io
import os
import shutil
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
VERSION = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]


def _run(args, cwd, timeout=900):
    """``args`` run outside this checkout: no PYTHONPATH, so only the installed coin is seen."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME",
                                                              "VIRTUAL_ENV", "COIN_TRACEBACK")}
    env.update(NO_COLOR="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
    return subprocess.run([str(a) for a in args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=timeout)


@pytest.mark.slow
def test_the_wheel_installs_in_a_fresh_venv_and_designs_from_the_shipped_table(tmp_path):
    dist, venv = tmp_path / "dist", tmp_path / "venv"
    try:
        built = _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", dist, ROOT],
                     cwd=tmp_path)
        assert built.returncode == 0, built.stdout + built.stderr
        (wheel,) = dist.glob("thickcoin-*.whl")
        assert wheel.name.startswith(f"thickcoin-{VERSION}-")
        with zipfile.ZipFile(wheel) as zf:
            assert "coincli/core/bounce/tables.json" in zf.namelist()

        made = _run([sys.executable, "-m", "venv", venv], cwd=tmp_path)
        assert made.returncode == 0, made.stderr
        bindir = venv / ("Scripts" if os.name == "nt" else "bin")
        python, coin = bindir / "python", bindir / "coin"
        installed = _run([python, "-m", "pip", "install", "-q", f"{wheel}[physics]"],
                         cwd=tmp_path)
        assert installed.returncode == 0, installed.stdout + installed.stderr

        where = _run([python, "-c", "import coincli; print(coincli.__file__)"], cwd=tmp_path)
        assert Path(where.stdout.strip()).resolve().is_relative_to(venv.resolve()), \
            where.stdout + where.stderr

        version = _run([coin, "--version"], cwd=tmp_path)
        assert (version.returncode, version.stdout) == (0, f"coin {VERSION}\n"), version.stderr

        design = _run([coin, "design", "--p-sides", "1/3", "--landing", "bounce", "--surface",
                       "wood", "--seed", "1", "--format", "csv"], cwd=tmp_path, timeout=300)
        assert design.returncode == 0, design.stdout + design.stderr
        (row,) = csv.DictReader(io.StringIO(design.stdout))
        assert 0.3 < float(row["xi"]) < 0.7
        assert float(row["xi_low"]) < float(row["xi"]) < float(row["xi_high"])
        assert int(row["table_tosses"]) > 0, "the shipped table was not used"
        assert "Traceback" not in design.stderr
    finally:
        shutil.rmtree(venv, ignore_errors=True)
        shutil.rmtree(dist, ignore_errors=True)
    assert not venv.exists() and not dist.exists()
