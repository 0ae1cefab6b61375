"""Assertions shared by the in-process CLI tests (the ``coin`` fixture lives in conftest.py)."""

from __future__ import annotations


def ok(result) -> str:
    """Exit 0 and nothing on stderr; return stdout."""
    rc, out, err = result
    assert (rc, err) == (0, ""), err
    return out


def error(result, code: int, *words: str, longest: int | None = None) -> str:
    """One error line with ``code`` naming every word, nothing on stdout, no traceback (and at
    most ``longest`` characters when given); return the line."""
    rc, out, err = result
    assert rc == code, (rc, out[:200], err[:500])
    assert out == ""
    assert err.startswith("coin: error: ") and err.endswith("\n"), err[:500]
    assert err.count("\n") == 1, err[:500]
    assert "Traceback" not in err, err[:500]
    for w in words:
        assert w in err, (w, err[:500])
    if longest is not None:
        assert len(err) <= longest, f"{len(err)} characters: {err[:300]}..."
    return err


def sigint_default() -> None:
    """``preexec_fn`` of a child a test sends SIGINT: SIGINT back to its default action there.
    A shell starts a background job with SIGINT ignored, a child inherits that, and Python (so
    coin) keeps an ignored SIGINT ignored, as a program started in the background should; the
    test is of Ctrl-C on a terminal, whatever the test run itself was started from."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_DFL)
