"""Write a :class:`~workbench.calib.dataset.model.Dataset` as DCM (KONSERVIERUNG_FORMAT 2.0), INCA's layout.

File comments first, then KONSERVIERUNG_FORMAT 2.0, MODULKOPF, FUNKTIONEN, VARIANTENKODIERUNG and
one block per object in dataset order: LANGNAME, DISPLAYNAME, VAR, FUNKTION, the object's
comments, the units, the axis points and values, six to a line (WERT/ST/X for numbers,
TEXT/ST_TX/X for texts). Numbers are written so that they read back to the same value
(:mod:`~workbench.calib.dataset.numbers`); lines end in ``\\n``.

What DCM cannot keep is listed by :func:`losses` as warnings; objects it cannot hold at all (a
CUBOID, CUBE_4, CUBE_5, a VAL_BLK of more than two dimensions, a name DCM cannot spell) are left
out of the file, each named. Members of CDF structures and arrays of instances keep their names
(``outer.member``, ``outer[2]``). The names CDF gives its containers (MSRSW, SW-SYSTEM,
SW-INSTANCE-TREE) are labels, not data, and are not listed.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

import numpy as np

from workbench.calib.dataset.dcm_lines import quote
from workbench.calib.dataset.model import Dataset, ObjectInfo
from workbench.calib.dataset.numbers import format_number
from workbench.calib.values import CalValue
from workbench.calib.dataset.losses import LEFT_OUT, left_out, loss
from workbench.errors import InputError
from workbench.findings import Finding

__all__ = ["losses", "write"]

VALUES_PER_LINE = 6
_NAME = re.compile(r"[A-Za-z_][\w.\[\]]*\Z")
_GROUP_AXES = ("COM_AXIS", "RES_AXIS", "CURVE_AXIS")
_CURVE_KEYWORD = {"STD_AXIS": "KENNLINIE", "FIX_AXIS": "FESTKENNLINIE"}
_MAP_KEYWORD = {"STD_AXIS": "KENNFELD", "FIX_AXIS": "FESTKENNFELD"}


def write(dataset: Dataset, encoding: str = "utf-8") -> bytes:
    """The DCM text of ``dataset`` in ``encoding`` (e.g. ``"cp1252"`` for tools that want ANSI).

    What DCM cannot hold at all is left out (see :func:`losses`).

    :raises InputError: a character ``encoding`` cannot hold (naming its line).
    """
    skipped = left_out(losses(dataset))
    lines = [line for c in dataset.comments for line in _comment(c)]
    lines += ["", "KONSERVIERUNG_FORMAT 2.0", ""] if lines else ["KONSERVIERUNG_FORMAT 2.0", ""]
    if dataset.module_header:
        lines += [f"MODULKOPF {name} {quote(text)}" if name else f"MODULKOPF {quote(text)}"
                  for name, text in dataset.module_header] + [""]
    if dataset.functions:
        lines.append("FUNKTIONEN")
        lines += [f"  FKT {name} {quote(f.version)} {quote(f.long_name)}" for name, f in dataset.functions.items()]
        lines += ["END", ""]
    if dataset.variant_criteria:
        lines.append("VARIANTENKODIERUNG")
        lines += [f"  KRITERIUM {' '.join((name, *values))}" for name, values in dataset.variant_criteria.items()]
        lines += ["END", ""]
    for name, value in dataset.items():
        if name not in skipped:
            lines += _block(value, dataset.info_of(name)) + [""]
    text = "\n".join(lines)
    try:
        return text.encode(encoding)
    except UnicodeEncodeError as exc:
        line = text[:exc.start].count("\n") + 1
        raise InputError(f"line {line}: {text[exc.start]!r} cannot be written in {encoding}; choose UTF-8") from None


def losses(dataset: Dataset) -> list[Finding]:
    """What DCM cannot keep of ``dataset``, as warnings; kind ``left-out``: an object not written at all."""
    found: list[Finding] = []

    def lose(name: str, message: str, kind: str = "not-in-dcm") -> None:
        found.append(loss(kind, name, message))

    for label, text in (("A2L file name", dataset.a2l_file), ("data file name", dataset.data_file)):
        if text:
            lose(dataset.source or "dataset", f"the {label} {text!r} has no place in DCM")
    with_history = [name for name, function in dataset.functions.items() if function.history]
    if with_history:
        lose(", ".join(with_history), "the history of these functions has no place in DCM")
    containers: set[str] = set()
    for name, value in dataset.items():
        info = dataset.info_of(name)
        if not _NAME.match(name):
            lose(name, "this name cannot be written to DCM (DCM names are identifiers)", LEFT_OUT)
            continue
        if value.kind in _BEYOND_DCM or (value.kind == "VAL_BLK" and value.value.ndim > 2):
            shape = " x ".join(map(str, value.shape))
            lose(name, f"a {value.kind} of {shape} values cannot be written to DCM (one or two dimensions)", LEFT_OUT)
            continue
        if info.container and info.container[0].name not in containers:
            containers.add(info.container[0].name)
            lose(info.container[0].name, "DCM has no structures or arrays of instances: their members are written "
                                         "as objects of their own (names kept, the enclosing instances' categories "
                                         "and long names not)")
        if info.model_link:
            lose(name, "its model link (SW-MODEL-LINK) has no place in DCM")
        if info.history or info.flags:
            lose(name, "the calibration history and flags have no place in DCM")
        if any("\n" in t or "\r" in t for t in _texts(value, info)):
            lose(name, "line breaks in texts are written as spaces")
        kinds = {a.kind for a in value.axes}
        if kinds & {"RES_AXIS", "CURVE_AXIS"}:
            lose(name, f"the {'/'.join(sorted(kinds & {'RES_AXIS', 'CURVE_AXIS'}))} is written as a group axis (COM_AXIS)")
        if value.kind == "MAP" and len(kinds) > 1:
            lose(name, f"the axes' kinds {' and '.join(a.kind for a in value.axes)} cannot both be kept; "
                       f"written as {_keyword(value)}")
        if value.kind == "VALUE" and info.category not in ("", "VALUE", "FESTWERT"):
            lose(name, f"its category {info.category} is written as FESTWERT")
        if value.kind == "VAL_BLK" and info.category not in ("", "VAL_BLK", "FESTWERTEBLOCK"):
            lose(name, f"its category {info.category} is written as FESTWERTEBLOCK")
    return found


_BEYOND_DCM = ("CUBOID", "CUBE_4", "CUBE_5")


def _texts(value: CalValue, info: ObjectInfo) -> Iterable[str]:
    yield value.comment
    yield value.unit
    yield info.display_name
    yield from info.comments
    for axis in value.axes:
        yield axis.unit
    for item in np.ravel(np.asarray(value.value, dtype=object)):
        if isinstance(item, str):
            yield item


def _keyword(value: CalValue) -> str:
    if value.kind == "VALUE":
        return "FESTWERT"
    if value.kind == "ASCII":
        return "TEXTSTRING"
    if value.kind == "VAL_BLK":
        return "FESTWERTEBLOCK"
    if value.kind == "AXIS_PTS":
        return "STUETZSTELLENVERTEILUNG"
    kinds = [a.kind for a in value.axes]
    table = _CURVE_KEYWORD if value.kind == "CURVE" else _MAP_KEYWORD
    prefix = "GRUPPEN" + ("KENNLINIE" if value.kind == "CURVE" else "KENNFELD")
    if any(k in _GROUP_AXES for k in kinds):
        return prefix
    return table["FIX_AXIS"] if all(k == "FIX_AXIS" for k in kinds) else table["STD_AXIS"]


def _block(value: CalValue, info: ObjectInfo) -> list[str]:
    keyword = _keyword(value)
    counts = " @ ".join(str(n) for n in value.shape) if value.kind == "VAL_BLK" else " ".join(map(str, value.shape))
    lines = [f"{keyword} {value.name}" + (f" {counts}" if counts else "")]
    lines.append(f"  LANGNAME {_text(value.comment)}")
    if info.display_name:
        name = info.display_name
        lines.append(f"  DISPLAYNAME {name if _NAME.match(name) else _text(name)}")
    if info.variants:
        lines.append("  VAR " + ", ".join(f"{c}={v}" for c, v in info.variants))
    if info.functions:
        lines.append("  FUNKTION " + " ".join(info.functions))
    lines += [line for c in info.comments for line in _comment(c)]
    if value.kind in ("CURVE", "MAP", "AXIS_PTS"):
        unit_x = value.unit if value.kind == "AXIS_PTS" else value.axes[0].unit
        lines.append(f"  EINHEIT_X {_text(unit_x)}")
    if value.kind == "MAP":
        lines.append(f"  EINHEIT_Y {_text(value.axes[1].unit)}")
    if value.kind in ("VALUE", "VAL_BLK", "CURVE", "MAP"):
        lines.append(f"  EINHEIT_W {_text(value.unit)}")
    for letter, axis in zip("XY", value.axes):
        if axis.kind in _GROUP_AXES and axis.name:
            lines.append(f"*SST{letter} {axis.name}")
    lines += _BODY[value.kind](value)
    lines.append("END")
    return lines


def _value_body(value: CalValue) -> list[str]:
    return _rows([value.value], "WERT", "TEXT")


def _ascii_body(value: CalValue) -> list[str]:
    return [f"  TEXT {_text(value.value)}"]


def _val_blk_body(value: CalValue) -> list[str]:
    array = value.value
    if array.ndim == 1:
        return _rows(list(array), "WERT", "TEXT")
    return [line for y in range(array.shape[1]) for line in _rows(list(array[:, y]), "WERT", "TEXT")]


def _curve_body(value: CalValue) -> list[str]:
    return _rows(list(value.axes[0].values), "ST/X", "ST_TX/X") + _rows(list(value.value), "WERT", "TEXT")


def _map_body(value: CalValue) -> list[str]:
    lines = _rows(list(value.axes[0].values), "ST/X", "ST_TX/X")
    for y, point in enumerate(value.axes[1].values):
        lines += _rows([point], "ST/Y", "ST_TX/Y")
        lines += _rows(list(value.value[:, y]), "WERT", "TEXT")
    return lines


def _axis_pts_body(value: CalValue) -> list[str]:
    return _rows(list(value.value), "ST/X", "ST_TX/X")


_BODY = {"VALUE": _value_body, "ASCII": _ascii_body, "VAL_BLK": _val_blk_body, "CURVE": _curve_body,
         "MAP": _map_body, "AXIS_PTS": _axis_pts_body}


def _rows(items: list, number_keyword: str, text_keyword: str) -> list[str]:
    """``items`` as lines of at most six, numbers after ``number_keyword``, texts after ``text_keyword``."""
    lines: list[str] = []
    run: list[str] = []
    run_keyword = ""
    for item in items:
        keyword = text_keyword if isinstance(item, str) else number_keyword
        if run and (keyword != run_keyword or len(run) == VALUES_PER_LINE):
            lines.append(f"  {run_keyword} {' '.join(run)}")
            run = []
        run_keyword = keyword
        run.append(_text(item) if isinstance(item, str) else format_number(item))
    if run:
        lines.append(f"  {run_keyword} {' '.join(run)}")
    return lines


def _text(text: str) -> str:
    return quote(text.replace("\r\n", " ").replace("\r", " ").replace("\n", " "))


def _comment(text: str) -> list[str]:
    """A comment as ``*`` lines, one per line of ``text``."""
    return [f"* {line}" if line else "*" for line in text.splitlines() or [""]]
