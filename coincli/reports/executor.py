"""Where the tosses of a bouncing run are computed: ``--scheduler``, ``--checkpoint`` and
``--timeout`` of every command that runs them (``simulate``, ``design``, ``plot sides``,
``table``, ``check`` and ``fit`` with ``--landing bounce``), parsed (:func:`parse_run`) and
turned into the executor that :func:`coincli.core.bounce.runs.simulate` and
:func:`coincli.core.bounce.calibrate.run_design` take (:func:`executor`): None (the local pool
of ``--jobs``), a checkpoint (:mod:`coincli.io.checkpoint`), a Dask cluster
(:mod:`coincli.core.bounce.cluster`), or a checkpoint in front of a cluster.

``DASK_SCHEDULER_ADDRESS`` is honoured as Dask's own tools honour it: the scheduler of a run
that names neither ``--scheduler`` nor ``--jobs``.  Nothing here imports ``distributed``; a
missing ``distributed`` is the one-line install hint of the ``cluster`` extra.
"""

from __future__ import annotations

import contextlib
import math
import os
import re

from coincli.errors import compute_error, install_hint, shown, usage_error

__all__ = ["parse_run", "executor", "scheduler_of", "options_of", "ENV", "DEFAULT_TIMEOUT",
           "FROM_ENV"]

ENV = "DASK_SCHEDULER_ADDRESS"  #: Dask's variable naming the scheduler
DEFAULT_TIMEOUT = 15.0  #: s to reach a scheduler, see a worker, or miss a lost one
_ADDRESS = re.compile(r"(?:(tcp|tls|ws|wss)://)?(\[[0-9a-fA-F:.]+\]|[A-Za-z0-9_.-]+):([0-9]{1,5})")


def _address(text: str, what: str) -> str:
    """``local``, or ``[tcp|tls|ws|wss://]host:port`` (tcp when no scheme is given)."""
    t = text.strip()
    if t.lower() == "local":
        return "local"
    m = _ADDRESS.fullmatch(t)
    if m is None or not 1 <= int(m.group(3)) <= 65535:
        raise usage_error(f"{what} must be tcp://HOST:PORT (as dask scheduler prints it; "
                          f"HOST:PORT, tls://, ws:// too) or local, got {shown(text)}")
    return t if m.group(1) else f"tcp://{t}"


def parse_run(*, jobs=None, scheduler=None, checkpoint=None, timeout=None) -> tuple:
    """Where a run's tosses are computed, from the options as typed: ``(scheduler, checkpoint,
    timeout)``, the scheduler an address, ``local``, None or :data:`FROM_ENV`, the checkpoint a
    path or None, the timeout in s, refusing what cannot work (they become the fields of the
    :class:`coincli.reports.physics.Physics`)."""
    from coincli.reports.launch import bounded_number

    if scheduler is not None and jobs is not None:
        raise usage_error("--scheduler and --jobs do not go together: the cluster's workers "
                          "run the tosses (drop --jobs, or --scheduler to run here)")
    if scheduler is not None:
        address = _address(scheduler, "--scheduler")
        _require_distributed()
    else:  # DASK_SCHEDULER_ADDRESS, read when a run starts (:func:`executor`), unless --jobs
        address = FROM_ENV if jobs is None else None
    seconds = DEFAULT_TIMEOUT if timeout is None else bounded_number(timeout, "--timeout",
                                                                     1.0, 3600.0)
    if timeout is not None and scheduler is None and not _env():
        raise usage_error("--timeout goes with --scheduler (it bounds the waits for a cluster)")
    path = None
    if checkpoint is not None:
        from coincli.io.files import refuse_unwritable

        if not checkpoint.strip():
            raise usage_error("--checkpoint needs a file name")
        refuse_unwritable(checkpoint, "--checkpoint")
        path = checkpoint
    return address, path, seconds


FROM_ENV = object()  #: the scheduler when DASK_SCHEDULER_ADDRESS decides it at the start of a run


def _env() -> str | None:
    return os.environ.get(ENV, "").strip() or None


def _require_distributed(what: str = "--scheduler") -> None:
    import importlib.util

    if importlib.util.find_spec("distributed") is None:
        raise compute_error(f"{what} needs Dask distributed, an optional extra: "
                            + install_hint("cluster"))


def scheduler_of(p) -> str | None:
    """The scheduler of a run: ``--scheduler``, else ``DASK_SCHEDULER_ADDRESS`` (when no
    ``--jobs`` was given), else None (the local pool)."""
    if p.scheduler is not FROM_ENV:
        return p.scheduler
    env = _env()
    if env is None:
        return None
    address = _address(env, ENV)
    _require_distributed(ENV)
    return address


def _text(v, scale: float = 1.0) -> str:
    """A value of the header, as text: numbers exactly (repr), distributions as typed."""
    if isinstance(v, (list, tuple)):
        return ",".join(_text(x, scale) for x in v)
    if isinstance(v, float):
        return repr(v * scale)
    if hasattr(v, "scaled") and scale != 1.0 and getattr(v, "kind", None) != "density":
        return str(v.scaled(scale))  # a psi density is shown as its spec, in degrees
    return str(v)


def options_of(p, **named) -> dict:
    """The header's options: ``named`` (option name -> value; psi in radians, shown in
    degrees) and the surface and step of ``p``, as text."""
    s = p.surface
    named.update({"--surface": s.name, "--restitution": s.restitution,
                  "--friction": s.friction, "--torsional": s.torsional, "--rolling": s.rolling,
                  "--release-height": p.height, "--vx": p.vx, "--dt": p.dt, "--t-max": p.t_max})
    return {name: _text(v, _SHOWN.get(name, 1.0)) for name, v in named.items()}


#: the options a header shows in the unit they are typed in (mm, degrees), not SI
_SHOWN = {"--psi": math.degrees(1.0), "--diameter": 1000.0, "--torsional": 1000.0,
          "--rolling": 1000.0, "--release-height": 1000.0}


@contextlib.contextmanager
def executor(p, command: str, **named):
    """The executor of a run of ``command`` (``coin simulate --landing bounce``...) whose
    tosses are decided by ``named`` options (see :func:`options_of`): None for the local pool
    without a checkpoint; the checkpoint is opened (and checked) before the cluster is
    reached, and both are closed on the way out, whatever happens."""
    scheduler = scheduler_of(p)
    if scheduler is None and p.checkpoint is None:
        yield None
        return
    with contextlib.ExitStack() as stack:
        run = None
        if p.checkpoint is not None:
            from coincli.core.bounce.cluster import versions
            from coincli.io.checkpoint import Checkpoint

            header = {"versions": versions(), "command": command,
                      "options": options_of(p, **named)}
            ck = stack.enter_context(Checkpoint(p.checkpoint, header))
        if scheduler is not None:
            from coincli.core.bounce.cluster import Cluster

            run = stack.enter_context(Cluster(scheduler, timeout=p.timeout))
        if p.checkpoint is not None:
            ck.inner = run
            run = ck
        yield run
