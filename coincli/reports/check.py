"""What ``coin check`` prints: one experiment's real tosses against the models.

:func:`check` parses its options' text, calls :mod:`coincli.core.stats.tests` and returns
:class:`coincli.io.table.Result` tables (:mod:`coincli.reports.check_tables`: a few short
tables for ``--format table``, one long table with stable column names,
:data:`MACHINE_COLUMNS`, for every machine format).  ``coin fit`` is
:mod:`coincli.reports.fit`.  numpy and scipy load when a report runs, never at import.
"""

from __future__ import annotations

import math

from coincli.errors import compute_error, shown, usage_error
from coincli.io import grammar as parse
from coincli.io import options
from coincli.io.experiments import check_total
from coincli.io.options import level_value
from coincli.io.table import Result, check_format
from coincli.reports.check_tables import (
    CAUGHT_MACHINE_COLUMNS,
    MACHINE_COLUMNS,
    bound_note,
    deg_text,
    machine_chunks,
    observed_result,
    percent_text,
    plural,
    psi_densities_by_spec,
    test_note,
    tests_result,
    warn_thick,
)

__all__ = ["check", "MACHINE_COLUMNS", "SIM_TOSSES"]


def _whole(text: str | None, what: str) -> int | None:
    """A count of tosses: a whole number from 0 to :data:`parse.MAX_COUNT` (2**53)."""
    if text is None:
        return None
    digits = text.strip().removeprefix("+")
    if not (digits.isascii() and digits.isdigit()):
        raise usage_error(f"{what} must be a whole number >= 0, got {shown(text)}")
    digits = digits.lstrip("0") or "0"
    if len(digits) > 16 or int(digits) > parse.MAX_COUNT:  # and no int() of 5000 digits
        raise usage_error(f"{what} must be a whole number from 0 to {parse.MAX_COUNT} (2**53), "
                          f"got {shown(text)}")
    return int(digits)


def _xi_from_options(xi, quarters, coin, count, diameter, thickness) -> tuple[float, str]:
    """The coin tossed (the shared coin group) and its label."""
    c = options.resolve_coin(xi, coin, count, quarters, diameter, thickness,
                             xi_rule="finite", command="coin check")
    return c.xi, c.label()


def check(*, xi: str | None = None, quarters: str | None = None, coin: str | None = None,
          count: str | None = None, diameter: str | None = None, thickness: str | None = None,
          heads: str | None = None, sides: str | None = None, tails: str | None = None,
          tosses: str | None = None, same: str | None = None, different: str | None = None,
          psi_dist: str | None = None, expect: str | None = None, fair: bool = False,
          landing: str = "catch", surface=None, restitution=None, friction=None,
          torsional=None, rolling=None, release_height=None, vx=None, u=None, omega=None,
          psi=None, seed=None, jobs=None, dt=None, t_max=None, calibration=None,
          scheduler=None, checkpoint=None, timeout=None, alpha: str = "0.05",
          confidence: str = "0.95", fmt: str = "table", quiet: bool = False):
    """What ``coin check`` prints: the observed frequencies with their intervals, and for each
    model the expected counts, the exact test's p-value, the log-likelihood and a verdict.

    The options' text as ``coin check`` takes it (the coin group, ``--heads``, ``--sides``,
    ``--tails``, ``-n/--tosses``, ``--psi-dist``, ``--alpha``, ``--confidence``).  ``expect``
    (``1/3,1/3,1/3``) or ``fair``: also a test against stated chances (the row ``expected``;
    the coin is then optional).  ``landing="bounce"``: also a test against a table simulated
    with the surface and launch options (:func:`_bounce_row`: the two sets of counts tested for
    one set of chances, so the simulation's own sampling error is counted).  Returns two human
    tables (a list) for ``fmt="table"``, else the one machine :class:`Result` (its ``quiet``
    the p-values, one per model).  Raises InputError for a wrong input, NotComputable when the
    models cannot be evaluated.
    """
    from coincli.core.stats import tests as stats_tests
    from coincli.core.stats.counts import make_counts

    fmt = check_format(fmt)
    a = level_value(alpha, "--alpha")
    conf = level_value(confidence, "--confidence")
    expected = _expectation(expect, fair)
    bounce = _bounce_options(landing, surface=surface, restitution=restitution,
                             friction=friction, torsional=torsional, rolling=rolling,
                             height=release_height, vx=vx, jobs=jobs, dt=dt, t_max=t_max,
                             calibration=calibration, scheduler=scheduler,
                             checkpoint=checkpoint, timeout=timeout, u=u, omega=omega, psi=psi,
                             seed=seed)
    if bounce is not None and (same is not None or different is not None):
        raise usage_error("--same/--different are caught flips: caught in the hand, they never "
                          "met a table; --landing bounce checks tosses that landed on one")
    coin_given = any(v is not None for v in (xi, quarters, coin, count, diameter, thickness))
    if expected is not None and not coin_given and bounce is None:
        x, label = math.nan, ""  # stated chances need no coin
    else:
        x, label = _xi_from_options(xi, quarters, coin, count, diameter, thickness)
    if same is not None or different is not None:
        counts = _caught_counts(x, same, different, tosses, (heads, sides, tails))
    else:
        vals = {name: _whole(v, f"--{name}")
                for name, v in (("heads", heads), ("sides", sides), ("tails", tails))}
        vals["n"] = None if tosses is None else options.tosses_value(tosses)  # as everywhere
        try:
            counts = make_counts(**vals)
        except ValueError as exc:
            raise usage_error(str(exc)) from None
    check_total(counts)
    dens = psi_densities_by_spec(psi_dist) if bounce is None else {}
    sim = None
    if bounce is not None:  # its own errors: a wrong option is exit 2, no settled toss exit 1
        sim = _simulate_table(bounce, x, counts, xi=xi, diameter=diameter, thickness=thickness,
                              coin_texts=(quarters, coin, count),
                              launch=(u, omega, psi, psi_dist, seed))
    try:
        chances = stats_tests.model_chances(x, dens) if math.isfinite(x) else {}
        if expected is not None:
            chances["expected"] = expected
        if sim is not None:
            chances[sim.name] = sim.chances
        ch = stats_tests.check_many([counts], x, chances, confidence=conf, alpha=a, labels=[label])
    except ValueError as exc:
        raise compute_error(str(exc)) from None
    if sim is not None:
        _two_sample(ch, sim, counts, a)
    caught = bool(ch.cc.caught[0])
    if quiet or fmt != "table":
        if sim is not None:  # the note that names the seed is not printed: say a drawn one
            options.report_seed(sim.seed, seed is not None)
        return Result("coin check", MACHINE_COLUMNS + (CAUGHT_MACHINE_COLUMNS if caught else []),
                      [], data=next(machine_chunks(ch, None)),
                      quiet=[float(t.p_value[0]) for t in ch.tests])
    coin_text = (f"xi = {x:.6g}" if xi is not None else f"{label} (xi = {x:.6g})"
                 if math.isfinite(x) else "against stated chances")
    title = f"coin check: {coin_text}, {plural(counts.n, 'toss', 'tosses')}"
    if caught:
        title = f"coin check: {coin_text}, {plural(counts.n, 'caught flip', 'caught flips')}"
    note = test_note(ch) + (_models_note(dens) if math.isfinite(x) else "")
    if expected is not None:
        note += (f"  expected = the chances you stated: heads {expected.heads:.6g}, sides "
                 f"{expected.sides:.6g}, tails {expected.tails:.6g}.")
    if sim is not None:
        note += "\n" + sim.note
    if caught:
        note += "\n" + _caught_note(x, counts, conf)
    return [
        observed_result(title, ch, None, conf),
        tests_result("models", ch, None, note),
    ]


def _expectation(expect: str | None, fair: bool):
    """The chances ``--expect H,S,T`` states (each 0.3, 1/3 or 30%; they must sum to 1) or
    ``--fair`` (1/3 each), as an Outcome; None when neither is given."""
    from coincli.core.models import Outcome

    if fair and expect is not None:
        raise usage_error("--fair is --expect 1/3,1/3,1/3: give one of them")
    if fair:
        return Outcome(1 / 3, 1 / 3, 1 / 3)
    if expect is None:
        return None
    parts = expect.split(",")
    if len(parts) != 3:
        raise usage_error(f"--expect takes the chances of heads, sides and tails, three numbers "
                          f"a,b,c (0.3, 1/3 or 30% each), got {shown(expect)}")
    try:
        ps = [parse.parse_probability(t, "--expect") for t in parts]
    except ValueError as exc:
        raise usage_error(str(exc)) from None
    total = math.fsum(ps)
    if abs(total - 1.0) > 1e-6:
        raise usage_error(f"--expect: the three chances must add up to 1, got {shown(expect)} "
                          f"(sum {total:.10g})")
    return Outcome(*(p / total for p in ps))


class _Simulated:
    """The simulated table a check compares with: its name, chances (the frequencies among the
    settled tosses), counts (heads, sides, tails), and the note that says how it was made."""

    def __init__(self, name, chances, counts, note, seed):
        self.name, self.chances, self.counts, self.note = name, chances, counts, note
        self.seed = seed


#: the simulated tosses of ``coin check --landing bounce``: ten times the experiment's, at
#: least 4000 (so the simulation adds little to the experiment's own error), at most 10^5
SIM_TOSSES = (4000, 10, 100_000)


def _bounce_options(landing, *, u, omega, psi, seed, **surface):
    """The table of ``--landing bounce`` (a :class:`coincli.reports.physics.Physics`), or None
    for the catch (then no table or launch option may be given)."""
    if landing.strip().lower() == "catch" and all(v is None for v in (
            *surface.values(), u, omega, psi, seed)):
        return None
    from coincli.reports.landing import landing_of, parse_physics

    physics = parse_physics(landing_of(landing), **surface)
    if physics is None:
        extra = [name for name, v in (("--u", u), ("--omega", omega), ("--psi", psi),
                                      ("--seed", seed)) if v is not None]
        raise usage_error(f"{', '.join(extra)} go{'es' if len(extra) == 1 else ''} with "
                          "--landing bounce (the tosses simulated on a table)")
    return physics


def _simulate_table(physics, x, counts, *, xi, diameter, thickness, coin_texts, launch):
    """Toss the coin on the table (:func:`coincli.core.bounce.runs.simulate`), as many tosses
    as :data:`SIM_TOSSES` says for this experiment."""
    from coincli.core.bounce import runs
    from coincli.core.models import Outcome
    from coincli.limits import STANDARD_G
    from coincli.reports.calibrated import bounce_launch_for
    from coincli.reports.launch import U_MAX, core_call, reach
    from coincli.reports.phase import diameter_m
    from coincli.reports.physics import check_coin, check_landing

    u, omega, psi, psi_dist, seed = launch
    coins = options.resolve_coin(xi, coin_texts[1], coin_texts[2], coin_texts[0], diameter,
                                 thickness, xi_rule="finite", command="coin check")
    dia = diameter_m(coins, diameter)
    check_coin(physics, x, dia, xi_text=xi, diameter_text=diameter, thickness_text=thickness)
    u_spec, w_spec, psi_spec, labels = bounce_launch_for(physics, psi, psi_dist, u, omega)
    check_landing(physics, u_top=reach(u_spec, U_MAX), g=STANDARD_G, xi=x, dia=dia,
                  u_text=u or "the hand toss's")
    least, times, most = SIM_TOSSES
    n = min(max(least, times * counts.n), most)
    seed_v = options.seed_value(seed)
    from coincli.reports.executor import executor

    with executor(physics, "coin check --landing bounce", **{
            "-n": n, "--seed": seed_v, "--xi": x, "--u": u_spec, "--omega": w_spec,
            "--psi": psi_spec, "--diameter": dia, "--g": STANDARD_G}) as run:
        sim = core_call(runs.simulate, n, seed_v, xi=x, u=u_spec, omega=w_spec, psi=psi_spec,
                        surf=physics.surface, landing="bounce", height=physics.height,
                        vx=physics.vx, diameter=dia, g=STANDARD_G, dt=physics.dt,
                        t_max=physics.t_max, jobs=physics.jobs, executor=run)
    h, s, t, unsettled = sim.counts
    if h + s + t == 0:
        raise compute_error(f"none of the {n} tosses simulated on {physics.surface.name} "
                            f"settled within --t-max {physics.t_max:g} s: no table to compare "
                            "with")
    name = f"bounce on {physics.surface.name}"
    note = (f"{name}: {n} tosses simulated (MuJoCo; seed {seed_v}; {labels}; "
            f"{physics.describe()}), {h + s + t} settled ({unsettled} still moving at "
            f"{physics.t_max:g} s left out): heads {h}, sides {s}, tails {t}.  Its p-value is "
            "the test that your counts and the simulated counts share one set of chances (a 2 x "
            "3 table: exact conditional, Freeman-Halton; a G-test when too large to "
            "enumerate), so the simulation's own sampling error is counted, not ignored.")
    total = h + s + t
    return _Simulated(name, Outcome(h / total, s / total, t / total), (h, s, t), note, seed_v)


def _two_sample(ch, sim: _Simulated, counts, alpha: float) -> None:
    """Replace the simulated table's test (a point null at the simulated frequencies) by the
    two-sample test of homogeneity (:func:`coincli.core.stats.homogeneity.homogeneity`)."""
    from coincli.core.stats import tests as stats_tests
    from coincli.core.stats.homogeneity import homogeneity

    test = next(t for t in ch.tests if t.model == sim.name)
    h, s, t = sim.counts
    if counts.faces:
        mine, theirs = (counts.heads, counts.sides, counts.tails), (h, s, t)
    else:  # sides and n: sides against faces
        mine, theirs = (counts.sides, counts.n - counts.sides), (s, h + t)
    r = homogeneity(mine, theirs)
    test.p_value[0] = r.p_value
    test.exact[0] = r.exact
    test.g[0] = r.g
    test.df[0] = r.df
    test.method[0] = ("exact conditional (Freeman-Halton), your counts against the simulated"
                      if r.exact else f"{r.method}, your counts against the simulated")
    test.verdict[0] = stats_tests.verdict(r.p_value, alpha, exact=r.exact)


def _caught_counts(x: float, same, different, tosses, three):
    """``--same``/``--different`` (``-n`` optional): caught flips, faces only."""
    from coincli.core.stats.counts import make_caught

    if any(v is not None for v in three):
        raise usage_error("--same/--different are caught flips (faces only); they cannot go "
                          "with --heads, --sides or --tails")
    vals = {name: _whole(v, f"--{name}" if name != "n" else "-n")
            for name, v in (("same", same), ("different", different), ("n", tosses))}
    try:
        counts = make_caught(**vals)
    except ValueError as exc:
        raise usage_error(_option_words(str(exc))) from None
    warn_thick(x, "")
    return counts


def _option_words(message: str) -> str:
    """A core message about same/different/n in the words of the options."""
    import re

    message = re.sub(r"\b(?<!-)(same|different)\b(?= (\+|=|must|was|exceeds|and))", r"--\1",
                     message)
    for a, b in (("but n =", "but -n ="), ("exceeds n =", "exceeds -n ="),
                 ("without different", "without --different"), ("without same", "without --same"),
                 ("or n", "or -n"), ("and different are", "and --different are")):
        message = message.replace(a, b)
    return message


def _caught_note(x: float, counts, conf: float) -> str:
    """What a caught check means, and this tosser's own spread of psi."""
    from coincli.core.stats import caught as stats_caught

    text = ("caught flips (faces only): each model is tested on the chance of landing on the "
            "side it started on given that it landed on a face, P(H) / (P(H) + P(T)) with the "
            "start side as heads (a caught coin never shows a side, so P(sides) is conditioned "
            "away).  Every model of a Keller flip gives 1/2; a spread of psi favours the "
            "starting side.  ")
    if not math.isfinite(x):  # --fair or --expect alone: no coin, so no spread of psi
        return text + ("This tosser's spread of psi is not fitted: it needs the coin (--xi, "
                       "--coin, --quarters or --diameter and --thickness).")
    f = stats_caught.fit_rows([x], [counts.same], [counts.n], confidence=conf)
    text += (f"This tosser's spread: sd of psi {deg_text(float(f.sigma[0]))} "
            f"deg, {percent_text(conf)} profile-likelihood interval "
            f"{deg_text(float(f.low[0]))} to {deg_text(float(f.high[0]))} deg")
    bound = bound_note(int(f.at_bound[0]))
    return text + (f" ({bound})" if bound else "") + "."


def _models_note(dens) -> str:
    base = "  geometric = eq. 11, dynamic = eq. 12 (Keller flip, psi = 90 deg)"
    return base + "".join(f"; {name} = psi-averaged (eq. 15)" for name in dens) + "."
