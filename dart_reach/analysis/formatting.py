"""How the report and the results pages write numbers: one place for every page. A missing
value (None, NaN) is an en dash, ``MISSING``, unless a page names another mark."""

from __future__ import annotations

import math

#: What a missing value is written as.
MISSING = "–"


def _missing(value) -> bool:
    return value is None or math.isnan(value)


def number(value) -> str:
    """A number to 3 significant digits, a small one (below 0.001) in exponent form with 2
    (a p-value such as 1.2e-05); infinite as ``inf``."""
    if _missing(value):
        return MISSING
    return f"{value:.3g}" if abs(value) >= 1e-3 or value == 0 else f"{value:.1e}"


def significant(value) -> str:
    """A finite number to 3 significant digits in Python's ``g`` form (exponent form only
    below 1e-4); anything not finite as ``MISSING``."""
    if value is None or not math.isfinite(value):
        return MISSING
    return f"{value:.3g}"


def decimals(value, digits: int = 3, missing: str = "n/a") -> str:
    """A number with ``digits`` decimals; a missing one as ``missing``."""
    return missing if _missing(value) else f"{value:.{digits}f}"


def percent(value) -> str:
    """A share in whole per cent, with a space before the sign (0.5: "50 %")."""
    return f"{value:.0%}".replace("%", " %")


def rate(hits: int, total: int) -> str:
    """A count of ``total`` and its share in whole per cent (``percent``): 1 of 2 is
    "1/2 (50 %)"; ``MISSING`` when ``total`` is 0."""
    return f"{hits}/{total} ({percent(hits / total)})" if total else MISSING


def effect(value, low, high) -> str:
    """"effect [low, high]" (``number``), the interval left out where there is none."""
    if _missing(value):
        return MISSING
    interval = f" [{number(low)}, {number(high)}]" if not _missing(low) else ""
    return number(value) + interval
