"""How ``coin``'s click tree is shown: plain help laid out for the terminal, options in panels,
whole command summaries, and shell completion of the values that are names.

The option panels are declared here once (:data:`PANELS`) and apply to every command that takes
the option: a command added later gets them too.  Nothing here runs unless help is shown or a
shell asks for completions, except :func:`prepare`'s few assignments.
"""

from __future__ import annotations

from coincli.requests.common import completions

#: the option panels of ``--help``, in order: a title and the options it holds (any of an
#: option's names).  An option in none of them is listed under "Options".
PANELS = (
    ("Coin", ("--xi", "--coin", "--count", "--quarters", "--diameter", "--thickness",
              "--p-sides", "--size", "--moments")),
    ("Model", ("--model", "--psi", "--psi-dist", "--all", "--vs", "--no-spread", "--style",
               "--expect", "--fair", "--layout")),
    ("Toss", ("--u", "--omega", "--g", "--contact", "--z0", "--tosses", "--seed", "--stream",
              "--trajectory", "--spin", "--times", "--toss", "--flight", "--start", "--rule")),
    ("Phase grid", ("--cols", "--rows", "--resolution", "--u-range", "--omega-range", "--exact",
                    "--exact-curves", "--no-curves")),
    ("Your tosses", ("--heads", "--sides", "--tails", "--same", "--different", "--data",
                     "--delimiter")),
    ("Table (--landing bounce)", ("--landing", "--surface", "--restitution", "--friction",
                                  "--torsional", "--rolling", "--release-height", "--vx", "--dt",
                                  "--t-max", "--jobs", "--scheduler", "--checkpoint",
                                  "--timeout", "--max-tosses", "--time-limit",
                                  "--calibration", "--no-table", "--fit", "--save",
                                  "--design-tosses")),
    ("Accuracy", ("--tol", "--method", "--alpha", "--confidence")),
    ("Figure", ("--log", "--xi-range", "--terminal", "--dpi", "--width", "--height", "--title")),
    ("Output", ("--format", "--no-headers", "--quiet", "--out")),
)
BOUNCE_PANEL = "Table (--landing bounce)"
#: options that belong to the bouncing table in a command where they mean nothing else
BOUNCE_ONLY = {"design": ("--u", "--omega", "--seed"), "sides": ("--seed", "--tosses"),
               "table": ("--u", "--omega", "--tosses"),
               "check": ("--u", "--omega", "--seed", "--psi"), "fit": ("--seed",)}
SUMMARY_LIMIT = 200  #: a command summary in a listing is its first sentence, up to this long

#: the values an option completes to (shell completion); files complete as files
_FILES = ("--data", "--out", "file", "--calibration", "--save")


def _panel_of(command: str, param) -> str:
    names = set(param.opts) | set(getattr(param, "secondary_opts", ()))
    if names & set(BOUNCE_ONLY.get(command, ())):
        return BOUNCE_PANEL
    for title, options in PANELS:
        if names & set(options):
            return title
    return "Options"


def _paneled(cmd):
    """``cmd.format_options`` writing the arguments, then each panel of options in the order
    of :data:`PANELS` (then the rest), then a group's commands."""

    def format_options(ctx, formatter):
        args, panels, last = [], {}, []
        for param in cmd.get_params(ctx):
            rv = param.get_help_record(ctx)
            if rv is None:
                continue
            if param.param_type_name == "argument":
                args.append(rv)
            elif "--help" in param.opts:
                last.append(rv)  # under Output where there is one, else under Options
            else:
                panels.setdefault(_panel_of(cmd.name or "", param), []).append(rv)
        panels.setdefault("Output" if "Output" in panels else "Options", []).extend(last)
        if args:
            with formatter.section("Arguments"):
                formatter.write_dl(args)
        order = [t for t, _ in PANELS] + ["Options"]
        for title in sorted(panels, key=lambda t: order.index(t) if t in order else len(order)):
            with formatter.section(title):
                formatter.write_dl(panels[title])
        if hasattr(cmd, "format_commands"):
            cmd.format_commands(ctx, formatter)

    return format_options


def _completions(cmd) -> None:
    """Value completion for the options of ``cmd`` that take names or files."""
    from typer._click.shell_completion import CompletionItem

    for param in cmd.params:
        names = set(param.opts) | {param.name or ""}
        if names & set(_FILES):
            param._custom_shell_complete = lambda ctx, p, inc: [CompletionItem(inc, type="file")]
            continue
        for option in param.opts:
            values = completions(option)
            if values:
                param._custom_shell_complete = (
                    lambda ctx, p, inc, values=values: [v for v in values if v.startswith(inc)])
                break


NO_HEADERS_HELP = "With --format csv or tsv: leave out the header line."


def prepare(root, complete: bool = False):
    """The click tree as ``coin`` shows it: plain click help (no rich panels: a third of the
    time of ``--help``, and no second wrapping) laid out in the terminal's width, and every
    command that takes the shared ``--format`` option also takes ``--no-headers`` (one
    definition here, so a command added later has it too; :func:`coincli.io.table.emit`
    reads it through :func:`coincli.io.table.headers_left_out`).  Options are shown in panels (:data:`PANELS`), command summaries whole, and with
    ``complete`` (shell completion) the options that take names complete them."""
    from coincli.io.terminal import terminal_width

    root.context_settings = {**(root.context_settings or {}),
                             "terminal_width": terminal_width(), "max_content_width": 80}
    stack = [root]
    while stack:
        cmd = stack.pop()
        cmd.rich_markup_mode = None
        cmd.help = _plain_help(cmd.help)
        cmd.get_short_help_str = _short_help(cmd)
        for p in cmd.params:
            if getattr(p, "help", None):
                p.help = p.help.replace("\\[", "[")
            if p.param_type_name == "option" and not getattr(p, "is_flag", False) and \
                    p.metavar is None:
                p.metavar = _METAVARS.get(type(p.type).__name__) or p.name.upper()
        stack.extend(getattr(cmd, "commands", {}).values())
        cmd.format_options = _paneled(cmd)
        if complete:
            _completions(cmd)
        fmt = next((p for p in cmd.params if "--format" in getattr(p, "opts", ())), None)
        if fmt is None or any(p.name == "no_headers" for p in cmd.params):
            continue
        from typer.core import TyperOption

        flag = TyperOption(param_decls=["no_headers", "--no-headers"], is_flag=True,
                           default=False, help=NO_HEADERS_HELP)
        cmd.params.insert(cmd.params.index(fmt) + 1, flag)
        cmd.callback = _with_no_headers(cmd.callback, fmt.name)
    return root


_METAVARS = {"IntParamType": "N", "IntRange": "N", "FloatParamType": "X", "FloatRange": "X"}

#: a word ending in '.' that does not end a sentence (click's short help stops at the first)
_ABBREVIATIONS = r"\b(?:Figs?|[Ee]qs?|Secs?|Refs?|Tab|vs|cf|e\.g|i\.e|No)\. (?=\S)"


def _short_help(cmd):
    """``cmd.get_short_help_str`` for a command listing that reads past an abbreviation: the
    first sentence of 'The pre-images ... (u, omega): Fig. 3 of the paper.' is not '...: Fig.'.
    """
    whole = cmd.get_short_help_str

    def short_help(limit: int = 45) -> str:
        limit = max(limit, SUMMARY_LIMIT)  # a listing wraps a summary; it never cuts one short
        if cmd.short_help or not cmd.help:
            return whole(limit)
        import re

        saved = cmd.help  # the abbreviation's blank, a non-blank for click, back after
        cmd.help = re.sub(_ABBREVIATIONS, lambda m: m.group()[:-1] + "\0", saved)
        try:
            return whole(limit).replace("\0", " ")
        finally:
            cmd.help = saved

    return short_help


def _plain_help(text):
    """A docstring for click's plain help: rich's escaped brackets unescaped, and an
    ``Examples:`` paragraph (examples apart by ' ; ') set one example a line, unwrapped."""
    if not text:
        return text
    import re

    text = text.replace("\\[", "[")
    paras = re.split(r"\n\s*\n", text)
    out = []
    k = 0
    while k < len(paras):
        para = paras[k]
        body = " ".join(para.split())
        k += 1
        if not body.startswith("Examples:") or para.startswith("\b"):
            out.append(para)
            continue
        examples = [e.strip() for e in re.split(r"\s;\s+", body[len("Examples:"):])]
        while k < len(paras) and _is_example(paras[k]):  # one example a paragraph
            examples.append(" ".join(paras[k].split()))
            k += 1
        out.append("\b\nExamples:\n" + "\n".join(_example_lines(e) for e in examples if e))
    return "\n\n".join(out)


def _is_example(para: str) -> bool:
    """A paragraph that is a command line (an example after an ``Examples:`` line)."""
    body = " ".join(para.split())
    return body.startswith("coin ") or (" coin " in body and len(body.split("coin ")[0]) < 40
                                        and any(c in body for c in "|$="))


EXAMPLE_WIDTH = 74  #: an example line, indented 4 in an 80-column help screen


def _example_lines(example: str) -> str:
    """One example, indented; a long one continued on the next lines with a shell ``\\``."""
    lines, cur = [], ""
    for word in example.split():
        if cur and len(cur) + 1 + len(word) > EXAMPLE_WIDTH - 2:
            lines.append(cur + " \\")
            cur = "  " + word
        else:
            cur = f"{cur} {word}" if cur else word
    lines.append(cur)
    return "\n".join(f"  {line}" for line in lines)


def _with_no_headers(callback, fmt_name):
    from coincli.errors import InputError
    from coincli.io.table import headers_left_out

    def run_command(*args, no_headers=False, **kwargs):
        if no_headers:
            fmt = str(kwargs.get(fmt_name) or "table").strip().lower()
            if fmt not in ("csv", "tsv"):
                raise InputError(f"--no-headers goes with --format csv or tsv, not {fmt!r}")
        with headers_left_out(no_headers):
            return callback(*args, **kwargs)

    return run_command
