"""The benchmark's machinery: paired timing in alternating order, ratios with quartiles, and
tiny real runs of its figures (their values are for `dart-reach bench`, not for tests)."""

from __future__ import annotations

from dart_reach import bench


def test_pairs_alternate_their_order_and_time_each_side():
    calls = []
    a, b = bench.paired(lambda: calls.append("a"), lambda: calls.append("b"), 4)
    assert calls == ["a", "b", "b", "a", "a", "b", "b", "a"]
    assert a.shape == b.shape == (4,) and (a > 0).all() and (b > 0).all()


def test_ratio_is_the_median_with_quartiles():
    r = bench.ratio("x", [1.0, 2.0, 3.0, 4.0, 100.0])
    assert r == {"x": 3.0, "x_iqr": [2.0, 4.0]}


def test_check_against_targets():
    met = bench.check({"controlled_over_limit": 0.95, "recording_overhead": 1.2})
    assert met == {"controlled_over_limit": True, "recording_overhead": False}


def test_tiny_real_figures():
    w = bench.world_rtf(seconds=0.2, pairs=2)
    assert w["ball_in_hand"] and w["limit_rtf"] > 0 and w["controlled_over_limit"] > 0
    p = bench.parallel(jobs=4, trials=1, pairs=1)
    assert p["parallel_efficiency"] > 0 and p["worker_peak_rss_mb"] > 50
    assert bench.panel_genomes("evolved", 3).shape == (3, bench.panel_genomes("random", 1).shape[1])
