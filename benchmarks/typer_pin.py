"""Why ``typer<0.29`` (pyproject.toml): the cost of typer 0.29 for a two-command typer program.

    python benchmarks/typer_pin.py        # installs typer 0.29 into a temporary directory (pip)

Runs ``import typer`` and a tiny typer program (two commands, one float option, one run)
against the typer of this environment and against typer 0.29 (``pip install --target`` into a
temporary directory, with its dependencies: 0.29 builds each parameter through pydantic),
alternately, and prints the median CPU time (user + system of the child) of each.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile

APP = """import typer
app = typer.Typer()
@app.command()
def main(x: float = typer.Option(1.0, "--x")):
    print(x)
@app.command()
def other(y: int = 1):
    print(y)
app()
"""


def main(repeat: int = 15) -> int:
    with tempfile.TemporaryDirectory(prefix="typer-pin-") as tmp:
        target = os.path.join(tmp, "typer29")
        subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--target", target,
                        "typer>=0.29,<0.30"], check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        app = os.path.join(tmp, "app.py")
        with open(app, "w") as f:
            f.write(APP)
        base = {k: v for k, v in os.environ.items()
                if k not in ("PYTHONPATH", "PYTHONDONTWRITEBYTECODE")}
        base["PYTHONPYCACHEPREFIX"] = os.path.join(tmp, "pycache")
        new = dict(base, PYTHONPATH=target)
        version = "import typer; print(typer.__version__)"
        here = subprocess.run([sys.executable, "-c", version], env=base, capture_output=True,
                              text=True).stdout.strip()
        there = subprocess.run([sys.executable, "-c", version], env=new, capture_output=True,
                               text=True).stdout.strip()
        cases = {f"import typer ({here})": (base, ["-c", "import typer"]),
                 f"import typer ({there})": (new, ["-c", "import typer"]),
                 f"two-command app, one run ({here})": (base, [app, "main", "--x", "2"]),
                 f"two-command app, one run ({there})": (new, [app, "main", "--x", "2"])}
        times = {k: [] for k in cases}
        for r in range(repeat + 1):  # the first round warms the caches
            for k, (env, argv) in cases.items():
                p = subprocess.Popen([sys.executable, *argv], env=env, stdout=subprocess.DEVNULL)
                _, _, ru = os.wait4(p.pid, 0)
                if r:
                    times[k].append(ru.ru_utime + ru.ru_stime)
    for k, v in times.items():
        print(f"{k}: {statistics.median(v) * 1e3:.1f} ms CPU (median of {repeat})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
