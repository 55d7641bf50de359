"""A calibration dataset in memory: calibration values by name and what the file said about them.

A :class:`Dataset` maps names to :class:`~workbench.calib.values.CalValue` s in file order and
keeps, per object, an :class:`ObjectInfo` (display name, functions, comments, history, where it
was read) and, for the whole file, its comments, functions and origin. The values are the same
shape whatever the file format (see :mod:`workbench.calib.values`):

==============================  ==================  ===========================================
DCM                             CDFX category       CalValue
==============================  ==================  ===========================================
FESTWERT (WERT or TEXT)         VALUE, BOOLEAN,     ``VALUE``: a number, or a ``str`` (verbal)
                                DEPENDENT_VALUE
TEXTSTRING                      ASCII               ``ASCII``: a ``str``
FESTWERTEBLOCK n [@ m]          VAL_BLK             ``VAL_BLK``: shape ``(n,)`` or ``(n, m)``
KENNLINIE / FESTKENNLINIE /     CURVE               ``CURVE``: axis STD_AXIS / FIX_AXIS /
GRUPPENKENNLINIE                                    COM_AXIS (named by ``*SSTX``)
KENNFELD / FESTKENNFELD /       MAP                 ``MAP``: shape ``(nx, ny)``, indexed ``[x, y]``
GRUPPENKENNFELD
(none)                          CUBOID, CUBE_4,     ``CUBOID``, ``CUBE_4``, ``CUBE_5``: shape
                                CUBE_5              ``(nx, ny, nz[, n4[, n5]])``, one axis each
STUETZSTELLENVERTEILUNG         COM_AXIS, RES_AXIS  ``AXIS_PTS``: the points
FESTWERTEBLOCK 2 @ n            RES_AXIS of rescale ``VAL_BLK`` ``(2, n)``: (axis point, index)
                                pairs               pairs, category RES_AXIS kept
==============================  ==================  ===========================================

The members of a CDF structure (an SW-INSTANCE nested in another) and the elements of an array of
instances (SW-ARRAY-INDEX) are objects of their own, named as A2L instances name them:
``outer.member``, ``outer[2]``, ``outer[2].member``; ``ObjectInfo.container`` keeps the enclosing
instances so that a CDFX file is written nested again.

``CalValue.comment`` holds the long name (DCM LANGNAME, CDFX LONG-NAME), as an A2L object's
long identifier; ``ObjectInfo.comments`` the free comment lines.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, MutableMapping
from dataclasses import dataclass, field

import numpy as np

from workbench.calib.values import CalValue
from workbench.errors import InputError
from workbench.findings import Finding

__all__ = ["CsFlag", "Dataset", "FunctionInfo", "HistoryEntry", "InstancePart", "ObjectInfo", "member_name",
           "value_runs"]


@dataclass(frozen=True)
class HistoryEntry:
    """One step of an object's calibration history (CDFX SW-CS-HISTORY / CS-ENTRY)."""

    state: str = ""  # STATE: the maturity, e.g. "prelimCalibrated", "checked", "released"
    date: str = ""  # DATE as written (ISO 8601 in CDF 2.0)
    user: str = ""  # CSUS: who
    remark: str = ""  # REMARK, its paragraphs joined by "\n"
    details: tuple[tuple[str, str], ...] = ()  # CSPR, CSWP, CSTO, CSTV, CSPI, CSDI, SD: (tag, text) in file order


@dataclass(frozen=True)
class CsFlag:
    """One process flag of an object (CDFX SW-CS-FLAGS / SW-CS-FLAG)."""

    category: str = ""
    flag: str = ""
    user: str = ""
    date: str = ""
    remark: str = ""


@dataclass(frozen=True)
class InstancePart:
    """One SW-INSTANCE that encloses an object of a CDF structure or array of instances."""

    name: str  # its SHORT-NAME, or its SW-ARRAY-INDEX (an element of an array of instances)
    category: str = ""  # STRUCTURE, VALUE_ARRAY ... as its file says
    long_name: str = ""
    index: bool = False  # an element of an array: written as SW-ARRAY-INDEX, named ``outer[name]``


def member_name(parts: "tuple[InstancePart, ...]") -> str:
    """The A2L-style name of nested instances: ``a.b``, ``a[1]``, ``a[1].b``."""
    name = ""
    for part in parts:
        name = f"{name}[{part.name}]" if part.index else f"{name}.{part.name}" if name else part.name
    return name


@dataclass(frozen=True)
class ObjectInfo:
    """What a dataset file says about one object besides its value, unit and long name."""

    display_name: str = ""
    functions: tuple[str, ...] = ()  # DCM FUNKTION names; CDFX SW-FEATURE-REF
    comments: tuple[str, ...] = ()  # free comment lines (DCM '*', '!', '.'; CDFX XML comments)
    history: tuple[HistoryEntry, ...] = ()
    flags: tuple[CsFlag, ...] = ()
    variants: tuple[tuple[str, str], ...] = ()  # DCM VAR criterion=value pairs
    category: str = ""  # the object's keyword or category in its file (FESTKENNLINIE, BOOLEAN ...)
    line: int = 0  # where it starts in its file (1-based; 0: not read from a file)
    value_line: int = 0  # where its values start (DCM: the first WERT/TEXT/ST line; CDFX: SW-VALUES-PHYS)
    value_runs: tuple[tuple[int, int], ...] = ()  # (line, how many values) in file order, X fastest: value_runs()
    container: tuple[InstancePart, ...] = ()  # CDF: the SW-INSTANCEs around it, outermost first
    model_link: str = ""  # CDF 2.1 SW-MODEL-LINK: where the value lives in a simulation model


def value_runs(lines: Iterable[int]) -> tuple[tuple[int, int], ...]:
    """The lines of an object's values in file order as (line, how many values on it) runs."""
    runs: list[list[int]] = []
    for line in lines:
        if runs and runs[-1][0] == line:
            runs[-1][1] += 1
        else:
            runs.append([line, 1])
    return tuple((line, count) for line, count in runs)


def _element_line(info: ObjectInfo, shape: tuple[int, ...], index: tuple[int, ...] | None) -> int:
    """The line of element ``index`` of a value of ``shape`` (0: not known); both formats write X fastest."""
    if index is None or not info.value_runs or len(index) != len(shape) or any(
            not 0 <= i < n for i, n in zip(index, shape)):
        return 0
    position = int(np.ravel_multi_index(index, shape, order="F")) if shape else 0
    for line, count in info.value_runs:
        if position < count:
            return line
        position -= count
    return 0


@dataclass(frozen=True)
class FunctionInfo:
    """A function (DCM FUNKTIONEN / FKT, CDFX SW-CS-COLLECTION of category FEATURE)."""

    version: str = ""
    long_name: str = ""
    history: tuple[HistoryEntry, ...] = ()


@dataclass
class Dataset(MutableMapping):
    """Calibration values by name, in file order, with the metadata of the file they came from.

    ``dataset[name]`` is the :class:`CalValue`, ``dataset.info[name]`` its :class:`ObjectInfo`;
    ``dataset[name] = value`` replaces a value (keeping its metadata) or appends a new one.
    """

    objects: dict[str, CalValue] = field(default_factory=dict)
    info: dict[str, ObjectInfo] = field(default_factory=dict)
    source: str | None = None  # the file it was read from
    format: str | None = None  # "dcm", "cdfx"
    comments: list[str] = field(default_factory=list)  # file-level comments, in order
    functions: dict[str, FunctionInfo] = field(default_factory=dict)
    name: str = ""  # CDFX SW-INSTANCE-TREE SHORT-NAME
    system: str = ""  # CDFX SW-SYSTEM SHORT-NAME (the ECU)
    title: str = ""  # CDFX MSRSW SHORT-NAME
    a2l_file: str = ""  # CDFX SW-INSTANCE-TREE-ORIGIN SYMBOLIC-FILE
    data_file: str = ""  # CDFX SW-INSTANCE-TREE-ORIGIN DATA-FILE
    variant_criteria: dict[str, tuple[str, ...]] = field(default_factory=dict)  # DCM VARIANTENKODIERUNG
    module_header: list[tuple[str, str]] = field(default_factory=list)  # DCM MODULKOPF (name, text) lines
    notes: list[Finding] = field(default_factory=list)  # what the reader found but does not keep, located

    def __getitem__(self, name: str) -> CalValue:
        return self.objects[name]

    def __setitem__(self, name: str, value: CalValue) -> None:
        """:raises InputError: ``value`` has another name."""
        if value.name != name:
            raise InputError(f"{value.name}: stored under the name {name!r}")
        self.objects[name] = value
        self.info.setdefault(name, ObjectInfo())

    def __delitem__(self, name: str) -> None:
        del self.objects[name]
        self.info.pop(name, None)

    def __iter__(self) -> Iterator[str]:
        return iter(self.objects)

    def __len__(self) -> int:
        return len(self.objects)

    def add(self, value: CalValue, info: ObjectInfo | None = None) -> None:
        """Add ``value`` (and what the file said about it) at the end.

        :raises InputError: an object of that name is already there (naming where it was read).
        """
        if value.name in self.objects:
            first = self.info_of(value.name).line
            where = f" (first at line {first})" if first else ""
            raise InputError(f"{value.name}: defined twice{where}")
        self.objects[value.name] = value
        self.info[value.name] = info or ObjectInfo()

    def info_of(self, name: str) -> ObjectInfo:
        """The :class:`ObjectInfo` of ``name`` (an empty one for an object added without)."""
        return self.info.get(name, ObjectInfo())

    def where(self, name: str, *, start: bool = False, index: tuple[int, ...] | None = None) -> str:
        """``file:line`` of the values of ``name`` as read, with ``start`` of the object's first line (its name),
        with ``index`` of that element of its value where the file says (``file`` alone, or ``""``, where not known)."""
        info = self.info_of(name)
        value = self.objects.get(name)
        shape = np.shape(value.value) if value is not None else ()
        line = info.line if start else _element_line(info, shape, index) or info.value_line or info.line
        if not self.source:
            return ""
        return f"{self.source}:{line}" if line else self.source
