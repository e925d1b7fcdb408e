"""Statistics of Figs. 9, 10: Kruskal-Wallis, pairwise two-tailed Mann-Whitney U, the
significance matrix. Expected values worked out by hand in each test."""

from __future__ import annotations

import math

import numpy as np
import polars as pl
import pytest

from dart_reach.analysis.stats import (holm, holm_adjusted, kruskal_wallis, mann_whitney,
                                       significance_matrix)


def long(**groups) -> pl.DataFrame:
    """Long table (value, group) from group name = values."""
    return pl.DataFrame({"value": [float(v) for g in groups.values() for v in g],
                         "group": [k for k, g in groups.items() for _ in g]})


# ------------------------------------------------------------------ Mann-Whitney

def test_mann_whitney_u_and_exact_p_by_hand():
    # a = 1, 2, 3 all below b = 4, 5: U_a = 0. Exact null: the 2 b's take 2 of the 5 ranks,
    # C(5, 2) = 10 equally likely arrangements, U_a = 0 for one of them (and U_a = 6 for one):
    # two-tailed p = 2 / 10.
    r = mann_whitney(long(a=[1, 2, 3], b=[4, 5]), "value", "group")
    assert r.columns == ["a", "b", "n_a", "n_b", "U", "p", "significant"]
    row = r.row(0, named=True)
    assert (row["a"], row["b"], row["n_a"], row["n_b"]) == ("a", "b", 3, 2)
    assert row["U"] == 0.0 and row["p"] == pytest.approx(0.2)
    assert row["significant"] is False


def test_mann_whitney_u_counts_pairs_and_half_ties():
    # a = 1, 4, 6 vs b = 2, 3, 5: 1 beats none, 4 beats 2 and 3, 6 beats all three: U = 5
    assert mann_whitney(long(a=[1, 4, 6], b=[2, 3, 5]), "value", "group")["U"][0] == 5.0
    # a = 1, 2 vs b = 2, 3: only the tie 2 = 2 counts, as 1/2
    assert mann_whitney(long(a=[1, 2], b=[2, 3]), "value", "group")["U"][0] == 0.5


def test_mann_whitney_clearly_different_samples_are_significant():
    rng = np.random.default_rng(1)
    df = long(low=rng.normal(0.0, 1.0, 20), high=rng.normal(3.0, 1.0, 20))
    row = mann_whitney(df, "value", "group").row(0, named=True)
    assert row["p"] < 1e-4 and row["significant"] is True
    assert row["U"] < 20  # "low" is below "high" in nearly all of the 400 pairs


def test_mann_whitney_constant_samples():
    df = long(a=[0] * 10, b=[0] * 7, c=[1] * 10)
    r = mann_whitney(df, "value", "group")
    assert list(zip(r["a"], r["b"])) == [("a", "b"), ("a", "c"), ("b", "c")]
    ab = r.row(0, named=True)
    assert ab["p"] == 1.0 and ab["U"] == 35.0 and ab["significant"] is False
    ac = r.row(1, named=True)  # all 0 vs all 1: clearly different
    assert ac["U"] == 0.0 and ac["significant"] is True


def test_mann_whitney_order_alpha_and_nan():
    df = long(x=[1, 2, 3, float("nan")], y=[4, 5, 6], z=[7, 8, 9])
    r = mann_whitney(df, "value", "group", order=["z", "x"], alpha=0.5)
    assert r.height == 1 and (r["a"][0], r["b"][0]) == ("z", "x")
    assert r["n_a"][0] == 3 and r["n_b"][0] == 3  # NaN dropped
    assert r["U"][0] == 9.0  # z above x in all 9 pairs
    # exact p: 2 / C(6, 3) = 0.1 < 0.5
    assert r["p"][0] == pytest.approx(0.1) and r["significant"][0]
    assert mann_whitney(df, "value", "group", alpha=0.05)["significant"].to_list() == [
        False, False, False]


def test_mann_whitney_group_without_values_gives_nan():
    df = long(a=[1, 2, 3], b=[float("nan")] * 2)
    row = mann_whitney(df, "value", "group").row(0, named=True)
    assert math.isnan(row["U"]) and math.isnan(row["p"]) and row["significant"] is False


def test_mann_whitney_errors():
    df = long(a=[1, 2], b=[3, 4])
    with pytest.raises(ValueError, match="fitness"):
        mann_whitney(df, "fitness", "group")
    with pytest.raises(ValueError, match="nope"):
        mann_whitney(df, "value", "group", order=["a", "nope"])
    with pytest.raises(ValueError, match="at least 2"):
        mann_whitney(df, "value", "group", order=["a"])
    with pytest.raises(ValueError, match="alpha"):
        mann_whitney(df, "value", "group", alpha=1.5)


# ------------------------------------------------------------------ Kruskal-Wallis

def test_kruskal_wallis_h_by_hand():
    # ranks 1..6 without ties: H = 12 / (N (N + 1)) * sum(R_i^2 / n_i) - 3 (N + 1)
    # two groups: R = 6, 15 -> 12/42 * (36 + 225) / 3 - 21 = 27/7; chi2(1) sf = erfc(sqrt(H/2))
    r = kruskal_wallis(long(a=[1, 2, 3], b=[4, 5, 6]), "value", "group")
    assert r.columns == ["groups", "n", "H", "p"] and r.height == 1
    assert r["groups"][0] == 2 and r["n"][0] == 6
    assert r["H"][0] == pytest.approx(27 / 7)
    assert r["p"][0] == pytest.approx(math.erfc(math.sqrt(27 / 14)))
    # three groups: R = 3, 7, 11 -> 12/42 * (9 + 49 + 121) / 2 - 21 = 32/7; chi2(2) sf = e^(-H/2)
    r3 = kruskal_wallis(long(a=[2, 1], b=[3, 4], c=[6, 5]), "value", "group")
    assert r3["groups"][0] == 3
    assert r3["H"][0] == pytest.approx(32 / 7)
    assert r3["p"][0] == pytest.approx(math.exp(-16 / 7))


def test_kruskal_wallis_constant_and_errors():
    r = kruskal_wallis(long(a=[0, 0, 0], b=[0, 0]), "value", "group")
    assert r["H"][0] == 0.0 and r["p"][0] == 1.0
    with pytest.raises(ValueError, match="at least 2"):
        kruskal_wallis(long(a=[1, 2, 3]), "value", "group")
    with pytest.raises(ValueError, match="at least 2"):  # b has no value left after NaN
        kruskal_wallis(long(a=[1, 2, 3], b=[float("nan")]), "value", "group")
    with pytest.raises(ValueError, match="senses"):
        kruskal_wallis(long(a=[1], b=[2]), "value", "senses")


# ------------------------------------------------------------------ significance matrix

def test_significance_matrix_by_hand():
    pairs = pl.DataFrame({"a": ["pre", "pre", "gross"], "b": ["gross", "fine", "fine"],
                          "significant": [True, False, True]})
    mat = significance_matrix(pairs)
    assert mat.columns == ["group", "pre", "gross", "fine"]
    assert mat["group"].to_list() == ["pre", "gross", "fine"]
    expected = np.array([[0, 1, 0], [1, 0, 1], [0, 1, 0]], bool)
    np.testing.assert_array_equal(mat.drop("group").to_numpy(), expected)
    sub = significance_matrix(pairs, order=["fine", "gross"])
    assert sub.columns == ["group", "fine", "gross"]
    np.testing.assert_array_equal(sub.drop("group").to_numpy(), [[False, True], [True, False]])


def test_significance_matrix_from_samples_is_symmetric():
    rng = np.random.default_rng(7)
    df = long(a=rng.normal(0, 1, 30), b=rng.normal(0, 1, 30), c=rng.normal(4, 1, 30),
              d=rng.normal(0, 1, 30))
    pairs = mann_whitney(df, "value", "group")
    assert pairs.height == 6
    mat = significance_matrix(pairs)
    s = mat.drop("group").to_numpy()
    assert s.dtype == bool and (s == s.T).all() and not s.diagonal().any()
    # c differs from every other group; a, b, d come from one distribution
    np.testing.assert_array_equal(s[2], [True, True, False, True])
    assert s.sum() == 6  # only the three pairs with c, counted twice


def test_holm_adjusts_every_tested_pair_step_down():
    pairs = pl.DataFrame({"a": list("wxyzv"), "b": list("WXYZV"),
                          "p": [0.01, 0.04, 0.03, float("nan"), 0.005]})
    out = holm(pairs, alpha=0.05)
    # 4 tested: sorted 0.005, 0.01, 0.03, 0.04 -> 0.02, 0.03, 0.06, 0.06 (monotone)
    assert out["p_holm"].to_list()[:3] == pytest.approx([0.03, 0.06, 0.06])
    assert out["p_holm"][4] == pytest.approx(0.02) and math.isnan(out["p_holm"][3])
    assert out["significant_holm"].to_list() == [True, False, False, False, True]
    matrix = significance_matrix(out, column="significant_holm")
    assert matrix.filter(pl.col("group") == "v")["V"].item() is True
    assert matrix.filter(pl.col("group") == "y")["Y"].item() is False


def test_holm_is_one_correction_for_tables_and_arrays():
    """``holm`` is ``holm_adjusted`` on the table's p column; as statsmodels'
    ``multipletests(method="holm")``: ties keep one value, an infinite p counts in the family
    and is capped at 1 (only a NaN p is left out); an empty table gets the columns."""
    p = [0.02, 0.01, 0.02, math.nan, math.inf, 0.0]
    adjusted = holm_adjusted(p)
    # 5 tested: sorted 0, 0.01, 0.02, 0.02, inf -> 0, 0.04, 0.06, 0.06 (running max), 1
    np.testing.assert_allclose(adjusted, [0.06, 0.04, 0.06, math.nan, 1.0, 0.0])
    table = holm(pl.DataFrame({"p": p}))
    np.testing.assert_array_equal(table["p_holm"].to_numpy(), adjusted)
    empty = holm(pl.DataFrame(schema={"a": pl.Utf8, "b": pl.Utf8, "p": pl.Float64}))
    assert empty.height == 0
    assert empty.schema["p_holm"] == pl.Float64 and empty.schema["significant_holm"] == pl.Boolean
