"""Messages that point the user on (issue 38): a file given to ``coin check`` names ``coin fit
FILE``; ``coin design --help`` says what ``--tol`` means under each landing."""

from __future__ import annotations


def test_a_file_given_to_check_points_to_fit(coin):
    code, out, err = coin("check", "mytosses.csv")
    assert code == 2 and out == ""
    assert err.count("\n") == 1
    assert "unexpected extra argument(s) (mytosses.csv)" in err
    assert "a file of experiments is read by coin fit FILE" in err


def test_another_extra_argument_has_no_such_hint(coin):
    code, _, err = coin("fair", "x")
    assert code == 2 and "coin fit" not in err


def test_design_tol_says_both_meanings(coin):
    code, out, _ = coin("design", "--help")
    text = " ".join(out.split())
    assert code == 0
    assert "the absolute error wanted on each psi-averaged chance" in text
    assert "With --landing bounce: the half-width wanted of each 95% interval of xi (default " \
           "0.01)" in text
