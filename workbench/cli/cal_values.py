"""The value ``cal set`` writes, as typed or held in a file, oriented as ``cal get`` shows it.

- Typed: a number, an enum's text, a list (``[1, 2, 3]`` or ``1,2,3``), a nested list indexed ``[x][y]``.
- ``.json``: the same, or what ``cal get NAME --json`` printed (``{NAME: {"value": ..., "axes": [...]}}``,
  the value indexed ``[x][y]``): its axis points are written too where they differ.
- ``.csv``: the grid as ``cal get`` prints it (cells apart by commas, or by spaces as printed, the legend line
  included). A curve, a 1-D value block or an axis is one row; a map
  has X across and Y down (one row per Y point, as the window and CANape show it); a 2-D value block
  one row per first index. Curves and maps may carry their axis points as ``cal get`` labels them (a
  curve's rows ``x,...`` and ``value,...``; a map's first row ``y\\x,x0,x1,...`` and each Y point
  before its row): those are written too where they differ. A grid of another shape than the A2L
  gives the object is refused naming the rows x columns it takes, before anything is sent.
"""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from workbench.errors import InputError

if TYPE_CHECKING:
    from workbench.a2l.model import A2lModel

__all__ = ["split_cell", "typed_value", "value_from_file"]

_DECIMAL_COMMA = re.compile(r"[+-]?\d+,\d+")
_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")
_MAP_CORNER = ("y\\x", "y \\ x", "")  # the corner cell of a map printed with its axes (cal get), or left empty
_CURVE_LABELS = ("x", "value")
_CELL = re.compile(r"(?P<name>[^\[\]\s]+)(?P<index>(\[\s*\d+\s*(,\s*\d+\s*)*\])+)")
_LAST_INDEX = re.compile(r"\[\s*\d+\s*(,\s*\d+\s*)*\]\Z")


def split_cell(model: A2lModel, text: str) -> tuple[str, tuple[int, ...] | None]:
    """NAME, or NAME[x,y] / NAME[x][y]: one value of an array (unless the A2L has an object of that very name);
    NAME may hold indices itself (an INSTANCE's element: ``convs[1][3]`` is value 3 of the curve ``convs[1]``)."""
    name, index = text.strip(), ""
    while name not in model and (last := _LAST_INDEX.search(name)):
        name, index = name[:last.start()], last.group() + index
    if index and name in model:
        return name, tuple(int(number) for number in re.findall(r"\d+", index))
    match = _CELL.fullmatch(text.strip())
    if match is None or text in model:
        return text, None
    return match["name"], tuple(int(number) for number in re.findall(r"\d+", match["index"]))


def typed_value(text: str | None, *, single: bool = False, unit: str = "") -> Any:
    """A value as typed on the command line: a number, a text, a list or a nested list (JSON).
    ``single``: the object takes one number, so ``3,5`` is a decimal comma, refused as such; a number followed
    by the object's ``unit`` (``25.5 bar``, as cal get prints it) is that number."""
    if text is None:
        raise InputError("give the value to write (or --from FILE)")
    stripped = text.strip()
    if single and unit and stripped.endswith(unit) and _NUMBER.fullmatch(stripped[:-len(unit)].rstrip()):
        stripped = stripped[:-len(unit)].rstrip()  # "25.5 bar" or "25.5bar"
    if single and _DECIMAL_COMMA.fullmatch(stripped):
        raise InputError(f"{text!r} is not a number: write a decimal point ({stripped.replace(',', '.')})")
    if stripped.startswith("["):
        try:
            return json.loads(stripped)
        except json.JSONDecodeError as exc:
            raise InputError(f"VALUE {text!r} is not a list: {exc.msg} at column {exc.colno}") from None
    if "," in stripped:
        return [_scalar(part) for part in stripped.split(",")]
    return _scalar(stripped)


def value_from_file(path: Path, model: A2lModel, name: str, *, cell: bool = False) -> Any:
    """The value for ``name`` (one of its values when ``cell``) held in a .json or .csv file, as
    ``cal set`` takes it: a number or text, a nested list indexed ``[x][y]``, or a
    :class:`~workbench.calib.values.CalValue` when the file gives axis points too.

    :raises InputError: not .json/.csv, malformed (file:line:column), or a grid of another shape.
    """
    from workbench.fileio import read_text_input

    data = read_text_input(path, "a value file")
    suffix = path.suffix.lower()
    if suffix == ".json":
        try:
            value = json.loads(data)
        except json.JSONDecodeError as exc:
            raise InputError(f"{path}:{exc.lineno}:{exc.colno}: {exc.msg}") from None
        return _json_value(path, model, name, value)
    if suffix == ".csv":
        text = getattr(model.object(name), "type", None) == "ASCII"  # its one cell may hold spaces
        rows = _csv_rows(path, data, None if text else f"{name}:")
        if cell:
            if _size(rows) != (1, 1):
                raise InputError(f"{path}: {_extent(_size(rows))}; one value of {name} is one number")
            return rows[0][0]
        return _grid_value(path, model, name, rows)
    raise InputError(f"{path}: a value file is .json or .csv")


def _scalar(text: str) -> Any:
    try:
        return int(text, 0) if text.strip().lstrip("+-").isdigit() else float(text)
    except ValueError:
        return text.strip()


# --- JSON -----------------------------------------------------------------------------------------


def _json_value(path: Path, model: A2lModel, name: str, value: Any) -> Any:
    """A bare value, or ``cal get --json``'s ``{NAME: value or {"value", "axes"}}``."""
    if not isinstance(value, dict):
        return value
    if name not in value:
        raise InputError(f"{path} holds {', '.join(map(str, value)) or 'no object'}, not {name}")
    entry = value[name]
    if not isinstance(entry, dict):
        return entry
    if "value" not in entry:
        raise InputError(f"{path}: {name} has no \"value\"")
    axes = entry.get("axes") or []
    if not axes:
        return entry["value"]
    try:
        points = [axis["points"] for axis in axes]
    except (TypeError, KeyError):
        raise InputError(f"{path}: each of {name}'s axes needs its \"points\"") from None
    return _with_axes(model, name, entry["value"], points)


def _with_axes(model: A2lModel, name: str, values: Any, points: list) -> Any:
    from workbench.calib.values import Axis, CalValue

    obj = model.object(name)
    axes = tuple(Axis(_array(p)) for p in points)
    return CalValue(name, getattr(obj, "type", "AXIS_PTS"), _array(values), axes, model.unit_of(obj))


def _array(values: Any) -> np.ndarray:
    array = np.asarray(values, dtype=object)
    if any(isinstance(v, str) for v in array.reshape(-1).tolist()):
        return array
    try:
        return array.astype(float)
    except (TypeError, ValueError):
        raise InputError(f"not a list of numbers or texts: {values!r}") from None


# --- CSV ------------------------------------------------------------------------------------------


def _csv_rows(path: Path, data: str, legend: str | None = None) -> list[list[Any]]:
    """The cells, numbers converted, trailing empty cells and blank lines at the end left out (row N is
    line N); an empty cell is refused but for the first (a map's corner). With ``legend`` (``NAME:``) a
    table as ``cal get`` prints it is taken too: cells apart by spaces (no comma after the legend line, which
    is left out when the file starts with it)."""
    lines = data.splitlines()
    skip = 1 if legend is not None and lines and lines[0].startswith(legend) else 0
    semicolons = next((number for number, line in enumerate(lines, start=1) if ";" in line), None)
    if semicolons is not None:  # a spreadsheet's CSV in a decimal-comma locale: 1,5;2,5
        raise InputError(f"{path}:{semicolons}: values apart by ';' (a spreadsheet's CSV with decimal commas?): "
                         "write them apart by ',' with decimal points, or as cal get prints them")
    if legend is None or any("," in line for line in lines[skip:]):
        parsed = enumerate(csv.reader(lines), start=1)
    else:
        parsed = ((number, line.split()) for number, line in enumerate(lines[skip:], start=1))
    rows = []
    for line, row in parsed:
        cells = [cell.strip() for cell in row]
        while cells and not cells[-1]:
            cells.pop()
        for column, cell in enumerate(cells, start=1):
            if not cell and (line, column) != (1, 1):
                raise InputError(f"{path}:{line}:{column}: an empty cell")
        rows.append([_scalar(cell) if cell else cell for cell in cells])
    while rows and not rows[-1]:
        rows.pop()
    if not rows:
        raise InputError(f"{path}: no values")
    if not all(rows):
        raise InputError(f"{path}:{rows.index([]) + 1}: a blank line between the rows")
    return rows


def _grid_value(path: Path, model: A2lModel, name: str, rows: list[list[Any]]) -> Any:
    """The value a CSV grid gives ``name``, turned into ``[x][y]`` for a map (see the module docstring)."""
    obj = model.object(name)
    kind = getattr(obj, "type", "AXIS_PTS")
    if kind in ("VALUE", "ASCII"):
        if _size(rows) != (1, 1):
            raise InputError(f"{path}: {_extent(_size(rows))}; {name} is a {kind}, one value")
        return rows[0][0]
    if kind == "MAP":
        return _map_value(path, model, name, rows)
    if rows[0][0] == "":
        raise InputError(f"{path}:1:1: an empty cell")
    shape = _static_shape(model, name)
    if kind == "CURVE" and len(rows) == 2 and [row[0] for row in rows] == list(_CURVE_LABELS):
        _rectangular(path, rows)
        _expect(path, name, (1, len(rows[1]) - 1), (1, shape[0]) if shape else None,
                "after its row of x points, as `workbench cal get` prints it")
        return _with_axes(model, name, rows[1][1:], [_numbers(path, 1, rows[0][1:], "x")])
    if kind in ("CURVE", "AXIS_PTS") or (kind == "VAL_BLK" and len(obj.shape) <= 1):
        _rectangular(path, rows)
        _expect(path, name, _size(rows), (1, shape[0]) if shape else None, "one row")
        return rows[0]
    if kind == "VAL_BLK" and len(obj.shape) == 2:
        _rectangular(path, rows)
        _expect(path, name, _size(rows), shape, "one row per first index, as `workbench cal get` prints it")
        return rows
    raise InputError(f"{path}: a {kind} is not read from a CSV; give {name} as JSON (indexed [x][y][z]...)")


def _map_value(path: Path, model: A2lModel, name: str, rows: list[list[Any]]) -> Any:
    shape = _static_shape(model, name)
    expected = (shape[1], shape[0]) if shape else None  # rows = Y points, columns = X points
    how = "X across, Y down, as `workbench cal get` prints it"
    if rows[0][0] in _MAP_CORNER and len(rows) > 1:  # with the axis points, as cal get prints them
        body = [row[1:] for row in rows[1:]]
        _rectangular(path, rows)
        _expect(path, name, _size(body), expected, how + " (here below a row of X points, each row after its Y point)")
        xs = _numbers(path, 1, rows[0][1:], "x")
        ys = _numbers(path, 2, [row[0] for row in rows[1:]], "y", down=True)
        return _with_axes(model, name, [list(column) for column in zip(*body)], [xs, ys])
    _rectangular(path, rows)
    _expect(path, name, _size(rows), expected, how)
    return [list(column) for column in zip(*rows)]


def _static_shape(model: A2lModel, name: str) -> tuple[int, ...] | None:
    """The value's shape ``(nx, ny, ...)`` where the A2L alone fixes it (None: a count lies in ECU memory)."""
    from workbench.calib.layout import object_layout

    layout = object_layout(model, name)
    return None if layout.needs_counts else layout.resolve().shape


def _expect(path: Path, name: str, size: tuple[int, int], expected: tuple[int, ...] | None, how: str) -> None:
    if expected is None or size == tuple(expected):
        return
    turned = " (the file holds it turned)" if size == tuple(reversed(expected)) else ""
    raise InputError(f"{path}: {_extent(size)} of values{turned}; {name} takes {_extent(expected)}, {how}")


def _rectangular(path: Path, rows: list[list[Any]]) -> None:
    first = len(rows[0])
    for line, row in enumerate(rows, start=1):
        if len(row) != first:
            raise InputError(f"{path}:{line}: {len(row)} cells, line 1 has {first}: every row needs as many")


def _numbers(path: Path, line: int, cells: list[Any], axis: str, down: bool = False) -> list[float]:
    for offset, cell in enumerate(cells):
        if isinstance(cell, str):
            where = f"{line + offset}:1" if down else f"{line}:{offset + 2}"  # after the label or corner cell
            raise InputError(f"{path}:{where}: the {axis} axis point {cell!r} is not a number")
    return cells


def _size(rows: list[list[Any]]) -> tuple[int, int]:
    return len(rows), len(rows[0]) if rows else 0


def _extent(size: tuple[int, ...]) -> str:
    rows, columns = size
    return f"{rows} row{'s' * (rows != 1)} x {columns} column{'s' * (columns != 1)}"
