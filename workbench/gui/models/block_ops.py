"""Block operations on a curve's or map's values, as CANape offers them on a selected range: set every
selected cell to a value, add to them, multiply them, or interpolate between the range's corners.

Plain numpy, no Qt: the table hands in the cells selected (array indices, [x] or [x, y]) and writes
the whole result once; the session checks its limits like any other write.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["OPERATIONS", "block_operation"]

OPERATIONS = ("set", "add", "multiply", "interpolate")


def block_operation(values: np.ndarray, cells: Sequence[tuple[int, ...]], operation: str, operand: float = 0.0,
                    axes: Sequence[np.ndarray] = ()) -> np.ndarray:
    """A copy of ``values`` with ``operation`` done on ``cells``.

    ``interpolate`` fills the range the cells span (their bounding box) linearly between its corners
    (bilinearly on a map), over the axis points ``axes`` (X first) where given, else over the indices.

    :raises ValueError: no cells, an unknown operation, or an interpolation over a range that is not
        the whole rectangle of its corners, or a single cell.
    """
    if operation not in OPERATIONS:
        raise ValueError(f"unknown block operation {operation!r} (choose {', '.join(OPERATIONS)})")
    if not cells:
        raise ValueError("select the cells first")
    result = np.array(values, dtype=np.float64)
    index = tuple(np.array(column) for column in zip(*cells))
    if operation == "set":
        result[index] = operand
    elif operation == "add":
        result[index] += operand
    elif operation == "multiply":
        result[index] *= operand
    else:
        _interpolate(result, cells, axes)
    return result


def _interpolate(result: np.ndarray, cells: Sequence[tuple[int, ...]], axes: Sequence[np.ndarray]) -> None:
    low = np.min(cells, axis=0)
    high = np.max(cells, axis=0)
    box = tuple(slice(a, b + 1) for a, b in zip(low, high))
    if len(set(map(tuple, cells))) != int(np.prod(high - low + 1)):
        raise ValueError("interpolation needs a whole rectangle selected (its corners are kept)")
    if np.all(high - low == 0):
        raise ValueError("select a range: interpolation runs between its corners")
    weights = []
    for dimension, (a, b) in enumerate(zip(low, high)):
        given = dimension < len(axes) and axes[dimension] is not None
        points = np.asarray(axes[dimension] if given else np.arange(result.shape[dimension]), dtype=np.float64)
        span = points[a:b + 1]
        weights.append(np.zeros(1) if b == a else (span - span[0]) / (span[-1] - span[0]))
    corner = result[tuple(low)]
    if result.ndim == 1:
        end = result[high[0]]
        result[box] = corner + weights[0] * (end - corner)
        return
    wx, wy = np.meshgrid(weights[0], weights[1], indexing="ij")
    (x0, y0), (x1, y1) = low, high
    c00, c10, c01, c11 = result[x0, y0], result[x1, y0], result[x0, y1], result[x1, y1]
    result[box] = (c00 * (1 - wx) * (1 - wy) + c10 * wx * (1 - wy) + c01 * (1 - wx) * wy + c11 * wx * wy)
