"""The one number formatter of the pages."""

from __future__ import annotations

import math

from dart_reach.analysis import formatting as fmt


def test_numbers_percent_and_missing_values():
    assert fmt.number(0.012345) == "0.0123" and fmt.number(1.234e-5) == "1.2e-05"
    assert fmt.number(0.0) == "0" and fmt.number(math.nan) == fmt.MISSING == "–"
    assert fmt.number(None) == "–"
    assert fmt.significant(1.234e-5) == "1.23e-05" and fmt.significant(math.inf) == "–"
    assert fmt.decimals(0.5, 2) == "0.50" and fmt.decimals(math.nan) == "n/a"
    assert fmt.percent(0.5) == "50 %"
    assert fmt.rate(1, 2) == "1/2 (50 %)" and fmt.rate(2, 3) == "2/3 (67 %)"
    assert fmt.rate(0, 0) == fmt.MISSING
    assert fmt.effect(0.7, 0.55, 0.9) == "0.7 [0.55, 0.9]"
    assert fmt.effect(0.7, math.nan, math.nan) == "0.7" and fmt.effect(math.nan, 0, 1) == "–"
