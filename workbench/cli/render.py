"""Physical values as a terminal shows them and as JSON carries them."""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np

_FORMAT = re.compile(r"%\s*(\d+)(?:\.(\d+))?")


def decimals(format_text: str | None) -> int | None:
    """The decimals of an A2L FORMAT ("%8.3" -> 3), None without one."""
    match = _FORMAT.match(format_text or "")
    return int(match.group(2)) if match and match.group(2) is not None else None


def number(value: Any, places: int | None = None) -> str:
    """A number as text: the A2L's decimals when known, else the shortest text that reads back the same."""
    if isinstance(value, str):
        return value
    if isinstance(value, (bool, np.bool_)):
        return str(int(value))
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    value = float(value)
    if math.isnan(value) or math.isinf(value):
        return str(value)
    if places is not None:
        return f"{value:.{places}f}"
    if value == int(value) and abs(value) < 1e16:
        return str(int(value))
    single = np.float32(value)
    # a float32 ECU value shown as float32 prints it (0.02, not 0.019999999552965164); JSON keeps it exact
    return str(single) if float(single) == value else repr(value)


def value_text(value: Any, unit: str = "", places: int | None = None) -> str:
    """A scalar with its unit, or an array on one line ([1 2 3])."""
    if isinstance(value, np.ndarray):
        if value.ndim > 1:
            return "[" + "; ".join(value_text(row, "", places) for row in value) + "]" + (f" {unit}" if unit else "")
        return "[" + " ".join(number(v, places) for v in value.tolist()) + "]" + (f" {unit}" if unit else "")
    return number(value, places) + (f" {unit}" if unit else "")


def table_lines(value: Any, axes: tuple = (), unit: str = "", places: int | None = None) -> list[str]:
    """A CURVE as two rows (axis, values), a MAP as a grid (X down, Y across), anything else on one line."""
    if not isinstance(value, np.ndarray) or value.ndim == 0:
        return [value_text(value, unit, places)]
    cells = np.vectorize(lambda v: number(v, places), otypes=[object])(value) if value.size else value
    if value.ndim == 1 and len(axes) == 1:
        head = [number(v) for v in axes[0].values.tolist()]
        width = max(len(text) for text in head + list(cells))
        return ["x     " + " ".join(text.rjust(width) for text in head),
                "value " + " ".join(text.rjust(width) for text in cells) + (f"  {unit}" if unit else "")]
    if value.ndim == 2 and len(axes) == 2:
        ys = [number(v) for v in axes[1].values.tolist()]
        xs = [number(v) for v in axes[0].values.tolist()]
        width = max(len(text) for text in ys + xs + [str(c) for c in cells.ravel()])
        lines = ["x \\ y".ljust(width) + " " + " ".join(text.rjust(width) for text in ys) + (f"  {unit}" if unit else "")]
        for x, row in zip(xs, cells):
            lines.append(x.rjust(width) + " " + " ".join(str(c).rjust(width) for c in row))
        return lines
    return [value_text(value, unit, places)]


def jsonable(value: Any) -> Any:
    """Numbers, texts and nested lists: what json.dump takes (NaN stays a float)."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return value
