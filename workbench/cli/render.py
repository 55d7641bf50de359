"""Physical values as a terminal shows them and as JSON carries them."""

from __future__ import annotations

from typing import Any

import numpy as np

from workbench.calib.dataset.numbers import shown_value as number

__all__ = ["jsonable", "table_lines", "value_block", "value_text"]


def value_text(value: Any, unit: str = "", places: int | None = None) -> str:
    """A scalar with its unit, or an array on one line ([1 2 3]); a map's values ``[x, y]`` a row per Y point, as
    its table shows them (X across, Y down)."""
    if isinstance(value, np.ndarray):
        if value.ndim > 1:
            rows = value.T if value.ndim == 2 else value
            return "[" + "; ".join(value_text(row, "", places) for row in rows) + "]" + (f" {unit}" if unit else "")
        return "[" + " ".join(number(v, places) for v in value.tolist()) + "]" + (f" {unit}" if unit else "")
    return number(value, places) + (f" {unit}" if unit else "")


def table_lines(value: Any, axes: tuple = (), unit: str = "", places: int | None = None,
                axis_places: tuple[int | None, ...] = ()) -> list[str]:
    """A CURVE as two rows (axis, values), a MAP as a grid with X across and Y down (as the window and CANape
    show it), each after a legend line naming the axes and units; anything else on one line. Each row of a
    table, split at its spaces, is a CSV row ``cal set --from`` takes (a cell holds no space). ``axis_places``:
    the decimals of each axis' points (X first), as the window shows them."""
    x_places, y_places = (*axis_places, None, None)[:2]
    if not isinstance(value, np.ndarray) or value.ndim == 0:
        return [value_text(value, unit, places)]
    cells = np.vectorize(lambda v: number(v, places), otypes=[object])(value) if value.size else value
    values = _label("values", None, unit)
    if value.ndim == 1 and len(axes) == 1:
        xs = [number(v, x_places) for v in axes[0].values.tolist()]
        width = max(len(text) for text in xs + list(cells))
        return [f"{_axis_label('x', axes[0])}, {values}",
                "x     " + " ".join(text.rjust(width) for text in xs),
                "value " + " ".join(text.rjust(width) for text in cells)]
    if value.ndim == 2 and len(axes) == 2:
        xs = [number(v, x_places) for v in axes[0].values.tolist()]
        ys = [number(v, y_places) for v in axes[1].values.tolist()]
        width = max(len(text) for text in ys + xs + [str(c) for c in cells.ravel()])
        lines = [f"{_axis_label('x', axes[0])} across, {_axis_label('y', axes[1])} down, {values}",
                 "y\\x".ljust(width) + " " + " ".join(text.rjust(width) for text in xs)]
        for y, column in zip(ys, cells.T):
            lines.append(y.rjust(width) + " " + " ".join(str(c).rjust(width) for c in column))
        return lines
    return [value_text(value, unit, places)]


def value_block(name: str, value: Any, axes: tuple = (), unit: str = "", places: int | None = None,
                note: str = "", axis_places: tuple[int | None, ...] = ()) -> str:
    """``name = value unit`` on one line, or ``name: legend`` and the table of a curve or map indented below it."""
    lines = table_lines(value, axes, unit, places, axis_places)
    if len(lines) == 1:
        return f"{name} = {lines[0]}{note}"
    return "\n".join([f"{name}{note}: {lines[0]}"] + [f"  {line}" for line in lines[1:]])


def _axis_label(letter: str, axis) -> str:
    return _label(letter, axis.name, axis.unit)


def _label(what: str, name: str | None, unit: str) -> str:
    """``x = xaNAME [bar]``, ``x [V]``, ``values [%]``: what a row or column holds."""
    return what + (f" = {name}" if name else "") + (f" [{unit}]" if unit else "")


def jsonable(value: Any) -> Any:
    """Numbers, texts and nested lists: what json.dump takes (NaN stays a float)."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return value
