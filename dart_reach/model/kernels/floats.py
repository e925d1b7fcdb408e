"""The scalar float functions the kernels share, each written to give the same bits on every
processor (``model.compiled``: the rounding rules): the exponential of the network's logistic
(section III-B) from +, -, * and exact scaling by powers of 2, and the clip of the sensors'
scaling and the motor commands (section III-B) as ``np.clip`` of one float."""

from __future__ import annotations

import math

from numba import njit

#: ln 2 split in two (fdlibm's constants): k * _LN2_HI is exact for |k| < 2^11.
_LN2_HI = 6.93147180369123816490e-01
_LN2_LO = 1.90821492927058770002e-10
_INV_LN2 = 1.44269504088896338700e+00
#: Below this exp(x) is 0 in float64 (the smallest subnormal is 4.9e-324 = exp(-744.4)).
_EXP_UNDERFLOW = -745.2
#: 1 / n! for n = 2..13: the Taylor series of exp(r) - 1 - r on |r| <= ln(2) / 2, whose
#: truncation error (<= 0.347^14 / 14! = 4e-18) lies far below float64's half ulp.
_INV_FACTORIALS = (1.0 / 2, 1.0 / 6, 1.0 / 24, 1.0 / 120, 1.0 / 720, 1.0 / 5040, 1.0 / 40320,
                   1.0 / 362880, 1.0 / 3628800, 1.0 / 39916800, 1.0 / 479001600,
                   1.0 / 6227020800)


@njit(cache=True)
def exp_nonpositive(x: float) -> float:
    """exp(x) for x <= 0 from +, -, * and ``ldexp`` only (the same bits on every processor):
    x = k ln 2 + r with |r| <= ln(2) / 2 (Cody and Waite's two-part ln 2), exp(r) by its
    Taylor series to r^13 in Horner's form, times 2^k. Within 2 ulp of the correctly rounded
    value (tested against ``math.exp``); 0.0 below -745.2; NaN for NaN."""
    if x != x:
        return x
    if x < _EXP_UNDERFLOW:
        return 0.0
    k = math.floor(x * _INV_LN2 + 0.5)
    r = (x - k * _LN2_HI) - k * _LN2_LO
    c = _INV_FACTORIALS
    p = c[11]
    for i in range(10, -1, -1):
        p = p * r + c[i]
    return math.ldexp(1.0 + (r + r * r * p), int(k))


@njit(cache=True)
def clip(v, lo, hi):
    """``np.clip`` of one float ``v`` to [``lo``, ``hi``], to the last bit (``sensors.clip``
    compiled): NaN stays NaN, else min(max(v, lo), hi). The proprioceptors' scaling to
    [-1, 1] and the motor commands' ranges and speed cap (section III-B)."""
    if v != v:
        return v
    v = v if v > lo else lo
    return v if v < hi else hi
