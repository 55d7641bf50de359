"""Write a :class:`~workbench.calib.dataset.model.Dataset` as CDFX (ASAM CDF 2.0, valid against its DTD).

UTF-8, the ASAM DOCTYPE, one SW-SYSTEM and SW-INSTANCE-TREE (category NO_VCD), the functions as
SW-CS-COLLECTIONs of category FEATURE, and one SW-INSTANCE per object in dataset order with the
elements in the DTD's order: SHORT-NAME, LONG-NAME, DISPLAY-NAME, CATEGORY, SW-FEATURE-REF,
SW-VALUE-CONT (UNIT-DISPLAY-NAME, SW-ARRAYSIZE, SW-VALUES-PHYS), SW-AXIS-CONTS, SW-CS-HISTORY,
SW-CS-FLAGS. Values are written x fastest: one VG per Y point of a MAP, per y index of a 2-D
VAL_BLK. A shared axis (COM_AXIS, RES_AXIS, CURVE_AXIS) names its object in SW-INSTANCE-REF and
repeats the points, so the file can be read without the referenced instance. Comments become XML
comments (file comments before the root, an object's inside its SW-INSTANCE).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from lxml import etree

from workbench.calib.dataset.cdfx_read import AXIS_CATEGORIES, HISTORY_DETAILS, SCALAR_CATEGORIES
from workbench.calib.dataset.cdfx_xml import DOCTYPE
from workbench.calib.dataset.model import Dataset, HistoryEntry, ObjectInfo
from workbench.calib.dataset.numbers import format_number
from workbench.calib.values import Axis, CalValue
from workbench.calib.dataset.losses import loss, refuse_errors
from workbench.findings import Finding, Severity

__all__ = ["losses", "write"]


def write(dataset: Dataset, encoding: str = "utf-8") -> bytes:
    """The CDFX document of ``dataset`` in ``encoding`` (a character it cannot hold becomes a character reference).

    :raises InputError: an object CDF 2.0 cannot hold (see :func:`losses`, severity error).
    """
    refuse_errors(losses(dataset))
    root = etree.Element("MSRSW")
    _sub(root, "SHORT-NAME", dataset.title or _default_name(dataset))
    _sub(root, "CATEGORY", "CDF20")
    system = _sub(_sub(root, "SW-SYSTEMS"), "SW-SYSTEM")
    _sub(system, "SHORT-NAME", dataset.system or "ECU")
    tree = _sub(_sub(system, "SW-INSTANCE-SPEC"), "SW-INSTANCE-TREE")
    _sub(tree, "SHORT-NAME", dataset.name or _default_name(dataset))
    _sub(tree, "CATEGORY", "NO_VCD")
    if dataset.a2l_file or dataset.data_file:
        origin = _sub(tree, "SW-INSTANCE-TREE-ORIGIN")
        if dataset.a2l_file:
            _sub(origin, "SYMBOLIC-FILE", dataset.a2l_file)
        if dataset.data_file:
            _sub(origin, "DATA-FILE", dataset.data_file)
    if dataset.functions:
        collections = _sub(tree, "SW-CS-COLLECTIONS")
        for name, function in dataset.functions.items():
            collection = _sub(collections, "SW-CS-COLLECTION")
            _sub(collection, "CATEGORY", "FEATURE")
            _sub(collection, "SW-FEATURE-REF", name)
            if function.version:
                _sub(collection, "REVISION", function.version)
            _history(collection, function.history)
    for name, value in dataset.items():
        _instance(tree, value, dataset.info_of(name))
    for line in dataset.comments:
        root.addprevious(etree.Comment(_comment_text(line)))
    return etree.tostring(root.getroottree(), encoding=encoding.upper(), xml_declaration=True, pretty_print=True,
                          doctype=DOCTYPE)


def losses(dataset: Dataset) -> list[Finding]:
    """What CDF 2.0 cannot keep of ``dataset``: warnings (kept in part) and errors (cannot be written)."""
    found: list[Finding] = []

    def lose(name: str, message: str, severity: Severity = Severity.WARNING) -> None:
        found.append(loss("not-in-cdfx", name, message, severity))

    where = dataset.source or "dataset"
    if dataset.module_header:
        lose(where, "the MODULKOPF lines have no place in CDF")
    if dataset.variant_criteria:
        lose(where, "the variant coding (VARIANTENKODIERUNG) is not written")
    with_long_names = [name for name, function in dataset.functions.items() if function.long_name]
    if with_long_names:
        lose(", ".join(with_long_names), "the long names of these functions have no place in CDF "
                                         "(their versions are written as REVISION)")
    for line in dataset.comments:
        if "--" in line:
            lose(where, f"the comment {line!r} is written with '- -' (XML comments cannot hold '--')")
    for name, value in dataset.items():
        info = dataset.info_of(name)
        if value.kind == "CUBOID":
            lose(name, "a CUBOID cannot be written to CDF 2.0", Severity.ERROR)
        if len(info.functions) > 1:
            lose(name, f"only the first of its functions ({info.functions[0]}) is written (one SW-FEATURE-REF)")
        if info.variants:
            lose(name, "its variant dependency (VAR) is not written")
        if any("--" in line for line in info.comments):
            lose(name, "a comment with '--' is written with '- -' (XML comments cannot hold '--')")
        if any(not _xml_text(t) for t in _texts(value, info)):
            lose(name, "a text holds a control character XML cannot hold", Severity.ERROR)
    return found


def _default_name(dataset: Dataset) -> str:
    return Path(dataset.source).stem if dataset.source else "dataset"


def _texts(value: CalValue, info: ObjectInfo):
    yield from (value.name, value.comment, value.unit, info.display_name, *info.functions, *info.comments)
    for axis in value.axes:
        yield axis.unit
        yield axis.name or ""
    yield from (v for v in np.ravel(np.asarray(value.value, dtype=object)) if isinstance(v, str))
    for axis in value.axes:
        yield from (v for v in np.ravel(np.asarray(axis.values, dtype=object)) if isinstance(v, str))


def _xml_text(text: str) -> bool:
    return all(c in "\t\n\r" or ord(c) >= 0x20 for c in text) and "\ufffe" not in text and "\uffff" not in text


def _sub(parent, tag: str, text: str | None = None):
    element = etree.SubElement(parent, tag)
    if text is not None:
        element.text = text
    return element


def _comment_text(line: str) -> str:
    text = line
    while "--" in text:  # once is not enough: "---" would become "- --"
        text = text.replace("--", "- -")
    return f" {text}{' ' if text.endswith('-') else ''} "


def _category(value: CalValue, info: ObjectInfo) -> str:
    if value.kind == "VALUE":
        return info.category if info.category in SCALAR_CATEGORIES else "VALUE"
    if value.kind == "AXIS_PTS":
        return info.category if info.category in AXIS_CATEGORIES else "COM_AXIS"
    if value.kind == "CURVE" and info.category == "CURVE_AXIS":
        return "CURVE_AXIS"
    return value.kind  # ASCII, VAL_BLK, CURVE, MAP


def _instance(tree, value: CalValue, info: ObjectInfo) -> None:
    instance = _sub(tree, "SW-INSTANCE")
    _sub(instance, "SHORT-NAME", value.name)
    for line in info.comments:
        instance.append(etree.Comment(_comment_text(line)))
    if value.comment:
        _sub(instance, "LONG-NAME", value.comment)
    if info.display_name:
        _sub(instance, "DISPLAY-NAME", info.display_name)
    _sub(instance, "CATEGORY", _category(value, info))
    if info.functions:
        _sub(instance, "SW-FEATURE-REF", info.functions[0])
    cont = _sub(instance, "SW-VALUE-CONT")
    if value.unit:
        _sub(cont, "UNIT-DISPLAY-NAME", value.unit)
    if value.kind == "VAL_BLK":
        size = _sub(cont, "SW-ARRAYSIZE")
        for n in value.shape:
            _sub(size, "V", str(n))
    phys = _sub(cont, "SW-VALUES-PHYS")
    if value.kind in ("VALUE", "ASCII"):
        _item(phys, value.value)
    else:
        _grid(phys, np.asarray(value.value))
    if value.axes:
        axes = _sub(instance, "SW-AXIS-CONTS")
        for axis in value.axes:
            _axis(axes, axis)
    _history(instance, info.history)
    if info.flags:
        flags = _sub(instance, "SW-CS-FLAGS")
        for flag in info.flags:
            element = _sub(flags, "SW-CS-FLAG")
            for tag, text in (("CATEGORY", flag.category), ("FLAG", flag.flag), ("CSUS", flag.user), ("DATE", flag.date)):
                if text:
                    _sub(element, tag, text)
            _remark(element, flag.remark)


def _axis(parent, axis: Axis) -> None:
    cont = _sub(parent, "SW-AXIS-CONT")
    _sub(cont, "CATEGORY", axis.kind)
    if axis.unit:
        _sub(cont, "UNIT-DISPLAY-NAME", axis.unit)
    if axis.name and axis.kind in AXIS_CATEGORIES:
        _sub(cont, "SW-INSTANCE-REF", axis.name)
    _grid(_sub(cont, "SW-VALUES-PHYS"), np.asarray(axis.values))


def _grid(parent, array: np.ndarray) -> None:
    """``array`` x fastest: its values along x, in one VG per index of each further dimension."""
    if array.ndim <= 1:
        for item in array.reshape(-1):
            _item(parent, item)
        return
    for k in range(array.shape[-1]):
        _grid(_sub(parent, "VG"), array[..., k])


def _item(parent, item) -> None:
    if isinstance(item, str):
        _sub(parent, "VT", item)
    else:
        _sub(parent, "V", format_number(item, nan="NaN", inf="INF"))


def _history(parent, history: tuple[HistoryEntry, ...]) -> None:
    if not history:
        return
    element = _sub(parent, "SW-CS-HISTORY")
    for entry in history:
        cs = _sub(element, "CS-ENTRY")
        _sub(cs, "STATE", entry.state)
        _sub(cs, "DATE", entry.date)
        _sub(cs, "CSUS", entry.user)
        details = dict(entry.details)
        for tag in HISTORY_DETAILS:
            if tag in details:
                _sub(cs, tag, details[tag])
        _remark(cs, entry.remark)


def _remark(parent, remark: str) -> None:
    if remark:
        element = _sub(parent, "REMARK")
        for paragraph in remark.split("\n"):
            _sub(element, "P", paragraph)
