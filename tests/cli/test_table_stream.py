"""coin table over many coins with psi-averaged models: streamed a chunk at a time."""

from __future__ import annotations

import csv
import io
import json

import pytest
from test_cli_out import _peak_kib


def _rows(coin, *argv):
    code, out, err = coin("table", *argv, "-f", "csv")
    assert code == 0 and err == "", err
    return list(csv.DictReader(io.StringIO(out)))


def test_a_streamed_density_batch_gives_each_coins_own_rows(coin, monkeypatch):
    import coincli.reports.design as design

    xs = ["1e-300", "0.05", "0.5773502691896258", "3", "1e300"]
    argv = ("--xi", ",".join(xs), "--psi-dist", "normal:30:5,uniform", "--psi", "90")
    whole = _rows(coin, *argv)
    monkeypatch.setattr(design, "CHUNK_ROWS", 8)  # several chunks (of 2 coins here)
    assert _rows(coin, *argv) == whole
    one = [r for x in xs for r in _rows(coin, "--xi", x, *argv[2:])]  # the scalar path
    assert [(r["xi"], r["model"]) for r in one] == [(r["xi"], r["model"]) for r in whole]
    for a, b in zip(one, whole, strict=True):
        for k in ("p_heads", "p_sides", "p_tails"):
            assert float(a[k]) == pytest.approx(float(b[k]), rel=4e-16, abs=0), (a, b)
    stacked = _rows(coin, "--coin", "quarter", "--count", "1:4:1", "--psi-dist", "cosine")
    assert [r["count"] for r in stacked] == [str(k) for k in range(1, 5) for _ in range(3)]
    assert stacked[2:3] == _rows(coin, "--coin", "quarter", "--count", "1", "--psi-dist",
                                 "cosine")[2:3]


def test_a_table_density_is_bounded_for_the_whole_streamed_run(coin, tmp_path):
    pts = tmp_path / "t.tab"
    pts.write_text("".join(f"{k * 180 / 9999!r},1\n" for k in range(10000)))
    code, out, err = coin("table", "--xi", "0.001:10:0.001", "--psi-dist", f"table:{pts}",
                          "-f", "csv")
    assert code == 1 and out == ""
    assert err.count("\n") == 1 and "give at most" in err and "10000 xi values" in err


@pytest.mark.slow
def test_density_batches_stream_in_flat_memory():
    # 200,000 coins and three densities: within 10 MiB of the peak of 20,000 (was 1.4 GB at
    # 10^6 coins: every row held before the first was written)
    for fmt in ("csv", "json"):
        code_s, base = _peak_kib(["table", "--xi", "0.0001:2:0.0001", "--all", "-f", fmt])
        code_b, peak = _peak_kib(["table", "--xi", "0.00001:2:0.00001", "--all", "-f", fmt])
        assert code_s == code_b == 0
        assert peak - base < 10 * 1024, (fmt, base, peak)


def test_streamed_density_json_parses(coin):
    code, out, _ = coin("table", "--xi", "0.1:0.5:0.1", "--all", "-f", "json")
    rows = json.loads(out)
    assert len(rows) == 25 and {row["model"] for row in rows} == {
        "geometric", "dynamic", "uniform", "cosine", "normal"}
    assert all(0 <= row[k] <= 1 for row in rows for k in ("p_heads", "p_sides", "p_tails"))


@pytest.mark.parametrize("deg", ["0.5", "0.001953125", "30", "60.123456789", "89.99"])
def test_psi_and_its_mirror_are_one_model_to_the_last_bit(coin, deg):
    # Table I is symmetric in psi <-> 180 - psi; the mirror is taken in degrees (exact), so
    # design and table give the same numbers both ways (were 3e-15 apart at 0.5 deg)
    mirror = repr(180.0 - float(deg))
    for p in ("1e-300", "0.3", "0.9999999999999999"):
        a = coin("design", "-p", p, "--psi", deg, "-q")
        b = coin("design", "-p", p, "--psi", mirror, "-q")
        assert a[0] == b[0] == 0 and a[1] == b[1], (deg, p, a, b)
    rows = _rows(coin, "--xi", "1e-3,0.5,57,1e16", "--psi", f"{deg},{mirror}")
    ours = [r for r in rows if r["model"].startswith("psi=")]
    assert [r["model"] for r in ours[:2]] == [f"psi={float(deg):.10g}", f"psi={float(mirror):.10g}"]
    for a, b in zip(ours[::2], ours[1::2], strict=True):
        assert (a["p_heads"], a["p_sides"], a["p_tails"]) == (b["p_heads"], b["p_sides"],
                                                              b["p_tails"])


def test_design_never_prints_an_overflowed_length_as_inf(coin):
    # D/h = 1e323 and a thickness of 5.7e315 mm are finite: past the largest double they are
    # empty cells; inf stays where it is exact (xi = 0: D/h; xi = inf: the thickness)
    cases = [(("-p", "5e-324"), "d_over_h"), (("-p", "5e-324,0.3"), "d_over_h"),
             (("-p", "0.9999999999999999", "--diameter", "1e300"), "thickness_mm"),
             (("-p", "0.9999999999999999,0.5", "--diameter", "1e300"), "thickness_mm"),
             (("-p", "1e-300", "--thickness", "1e300"), "diameter_mm"),
             (("-p", "1e-300,0.5", "--thickness", "1e300"), "diameter_mm")]
    for argv, col in cases:
        code, out, err = coin("design", *argv, "-f", "csv")
        assert code == 0 and err == ""
        rows = list(csv.DictReader(io.StringIO(out)))
        assert rows[0][col] == "", (argv, rows[0])
        assert "inf" not in out and "nan" not in out, (argv, out)
        assert float(rows[0]["xi"]) > 0
    code, out, _ = coin("design", "-p", "0,1", "-f", "csv")
    rows = list(csv.DictReader(io.StringIO(out)))
    assert (rows[0]["xi"], rows[0]["d_over_h"]) == ("0.0", "inf")
    assert (rows[1]["xi"], rows[1]["thickness_mm"]) == ("inf", "inf")


def test_stack_counts_under_a_density_stream(coin, monkeypatch):
    # many counts under a psi density: arrays a chunk at a time (was one scalar quadrature a
    # row held in memory: 24 s of CPU and 167 MB for 200,000 counts; bench_mc_limit)
    import coincli.io.batches as common

    argv = ("stack", "--count", "1,2,40,1000,100000", "--psi-dist", "normal:30:0.05", "-f",
            "csv")
    whole = coin(*argv)
    assert whole[0] == 0
    monkeypatch.setattr(common.Values.chunks, "__defaults__", (2,))  # chunks of 2 counts
    assert coin(*argv) == whole
    rows = list(csv.DictReader(io.StringIO(whole[1])))
    for r in rows:
        one = coin("stack", "--count", r["count"], "--psi-dist", "normal:30:0.05", "-f", "csv")
        (single,) = csv.DictReader(io.StringIO(one[1]))
        for k in ("height_mm", "xi"):
            assert single[k] == r[k]
        for k in ("p_heads", "p_sides", "p_tails"):
            assert float(single[k]) == pytest.approx(float(r[k]), rel=4e-16, abs=0)


def test_plot_psi_marks_what_table_prints_past_90_degrees(coin):
    # plot psi took 180 deg as the double nearest pi: at xi = 1e16 it marked heads 0.2677,
    # sides 0.7323 where table (and its own legend: heads only above 180 - t) says heads 1
    code, out, err = coin("plot", "psi", "--xi", "1e16", "--psi", "179.5,180,100")
    assert code == 0, err
    text = out + err
    rows = {r["model"]: r for r in _rows(coin, "--xi", "1e16", "--psi", "179.5,180,100")}
    for deg in ("179.5", "180", "100"):
        r = rows[f"psi={deg}"]
        want = (f"your toss psi = {deg} deg: heads {float(r['p_heads']):.4g}, sides "
                f"{float(r['p_sides']):.4g}, tails {float(r['p_tails']):.4g}")
        assert want in text, (want, text)
    assert "psi = 180 deg: heads 1, sides 0, tails 0" in text


@pytest.mark.parametrize("deg", ["100.1", "120", "179.5", "180"])
def test_a_too_narrow_normal_past_90_is_psi_at_its_mean(coin, deg):
    # normal:MEAN:1e-30 inverts through Table I at its mean; past 90 deg at the same mirror
    # angle as --psi MEAN (it was pi - mean in radians: 1e-15 relative apart)
    for p in ("1e-300", "0.3", "0.9999999999999999"):
        a = coin("design", "-p", p, "--psi", deg, "-q")
        b = coin("design", "-p", p, "--psi-dist", f"normal:{deg}:1e-30", "-q")
        assert a[0] == b[0] and a[1] == b[1], (deg, p, a, b)
