"""Single-precision helpers shared by the modules: what ``rt_lookup.c`` and the models' small
static functions do in C, operation by operation, so results match bit for bit.

Every argument and constant is ``numpy.float32``; numpy rounds each operation to float32 as
the C code compiled with SSE math and ``-ffp-contract=off`` does.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["HALF", "HUNDRED", "TWO", "ZERO", "look1", "look2", "saturate"]

f32 = np.float32
ZERO = f32(0.0)
HALF = f32(0.5)
ONE = f32(1.0)
TWO = f32(2.0)
HUNDRED = f32(100.0)


def saturate(value: np.float32, lower: np.float32, upper: np.float32) -> np.float32:
    """``PRVCtrl_saturate``: the upper limit wins when the limits cross."""
    if value > upper:
        return upper
    if value < lower:
        return lower
    return value


def _prelookup(u: np.float32, bp: Sequence[np.float32]) -> tuple[int, np.float32]:
    """``plook_binlc``: index i and fraction f of ``u`` between ``bp[i]`` and ``bp[i + 1]``."""
    max_index = len(bp) - 1
    if u <= bp[0]:
        return 0, ZERO
    if u >= bp[max_index]:
        return max_index - 1, ONE
    left, right = 0, max_index
    while right - left > 1:
        middle = (left + right) >> 1
        if u < bp[middle]:
            right = middle
        else:
            left = middle
    return left, (u - bp[left]) / (bp[left + 1] - bp[left])


def look1(u: np.float32, bp: Sequence[np.float32], table: Sequence[np.float32]) -> np.float32:
    """``look1_iflf_binlc``: linear interpolation in a 1-D table, clamped at its ends."""
    index, frac = _prelookup(u, bp)
    return table[index] + frac * (table[index + 1] - table[index])


def look2(
    u0: np.float32, u1: np.float32, bp0: Sequence[np.float32], bp1: Sequence[np.float32], table: np.ndarray
) -> np.float32:
    """``look2_iflf_binlc``: bilinear interpolation; ``table[i1][i0]`` (the ``bp0`` index fastest)."""
    i0, frac0 = _prelookup(u0, bp0)
    i1, frac1 = _prelookup(u1, bp1)
    low = table[i1][i0] + frac0 * (table[i1][i0 + 1] - table[i1][i0])
    high = table[i1 + 1][i0] + frac0 * (table[i1 + 1][i0 + 1] - table[i1 + 1][i0])
    return low + frac1 * (high - low)
