"""Write a :class:`~workbench.calib.dataset.model.Dataset` as CDFX (ASAM CDF 2.0, or 2.1 where needed).

UTF-8, the ASAM DOCTYPE, one SW-SYSTEM and SW-INSTANCE-TREE (category NO_VCD), the functions as
SW-CS-COLLECTIONs of category FEATURE, and one SW-INSTANCE per object in dataset order with the
elements in the DTD's order: SHORT-NAME, LONG-NAME, DISPLAY-NAME, CATEGORY, SW-FEATURE-REF,
SW-MODEL-LINK, SW-VALUE-CONT (UNIT-DISPLAY-NAME, SW-ARRAYSIZE, SW-VALUES-PHYS), SW-AXIS-CONTS,
SW-CS-HISTORY, SW-CS-FLAGS. Values are written x fastest: one VG per Y point of a MAP, per y index
of a 2-D VAL_BLK, nested one level more per further axis of a CUBOID, CUBE_4, CUBE_5. A shared
axis (COM_AXIS, RES_AXIS, CURVE_AXIS) names its object in SW-INSTANCE-REF and repeats the points,
so the file can be read without the referenced instance. Members of structures and elements of
arrays of instances (``ObjectInfo.container``) are written nested in their enclosing SW-INSTANCEs
again. Comments become XML comments (file comments before the root, an object's inside its
SW-INSTANCE).

The file is CDF 2.0 (category CDF20, the 2.0 DOCTYPE, valid against its DTD) unless it holds what
only CDF 2.1 has: a CUBOID, CUBE_4 or CUBE_5, a SW-MODEL-LINK; then CDF21 with the 2.1 DOCTYPE.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from lxml import etree

from workbench.calib.dataset.cdfx_read import HISTORY_DETAILS
from workbench.calib.dataset.cdfx_values import AXIS_CATEGORIES, SCALAR_CATEGORIES
from workbench.calib.dataset.cdfx_xml import DOCTYPE, DOCTYPE_21
from workbench.calib.dataset.losses import LEFT_OUT, left_out, loss
from workbench.calib.dataset.model import Dataset, HistoryEntry, InstancePart, ObjectInfo, member_name
from workbench.calib.dataset.numbers import format_number
from workbench.calib.values import Axis, CalValue
from workbench.findings import Finding

__all__ = ["losses", "write"]


def write(dataset: Dataset, encoding: str = "utf-8") -> bytes:
    """The CDFX document of ``dataset`` in ``encoding`` (a character it cannot hold becomes a character reference).

    What CDF cannot hold at all is left out (see :func:`losses`).
    """
    skipped = left_out(losses(dataset))
    written = [name for name in dataset if name not in skipped]
    cdf21 = any(_needs_cdf21(dataset[name], dataset.info_of(name)) for name in written)
    root = etree.Element("MSRSW")
    _sub(root, "SHORT-NAME", dataset.title or _default_name(dataset))
    _sub(root, "CATEGORY", "CDF21" if cdf21 else "CDF20")
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
    nesting = _Nesting(tree)
    for name in written:
        info = dataset.info_of(name)
        parent, part = nesting.parent_of(name, info.container)
        _instance(parent, part, dataset[name], info)
    for line in dataset.comments:
        root.addprevious(etree.Comment(_comment_text(line)))
    return etree.tostring(root.getroottree(), encoding=encoding.upper(), xml_declaration=True, pretty_print=True,
                          doctype=DOCTYPE_21 if cdf21 else DOCTYPE)


def losses(dataset: Dataset) -> list[Finding]:
    """What CDF cannot keep of ``dataset``, as warnings; kind ``left-out``: an object not written at all."""
    found: list[Finding] = []

    def lose(name: str, message: str, kind: str = "not-in-cdfx") -> None:
        found.append(loss(kind, name, message))

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
        if len(info.functions) > 1:
            lose(name, f"only the first of its functions ({info.functions[0]}) is written (one SW-FEATURE-REF)")
        if info.variants:
            lose(name, "its variant dependency (VAR) is not written")
        if any("--" in line for line in info.comments):
            lose(name, "a comment with '--' is written with '- -' (XML comments cannot hold '--')")
        if any(not _xml_text(t) for t in _texts(value, info)):
            lose(name, "a text holds a control character XML cannot hold", LEFT_OUT)
        elif value.kind == "VALUE" and info.category not in SCALAR_CATEGORIES + ("", "FESTWERT"):
            lose(name, f"its category {info.category} is written as VALUE")
    return found


_CDF21_KINDS = ("CUBOID", "CUBE_4", "CUBE_5")


def _needs_cdf21(value: CalValue, info: ObjectInfo) -> bool:
    return value.kind in _CDF21_KINDS or bool(info.model_link)


class _Nesting:
    """The SW-INSTANCEs of structures and arrays of instances that enclose the objects being written."""

    def __init__(self, tree):
        self.tree = tree
        self.open: list[tuple[InstancePart, etree._Element]] = []

    def parent_of(self, name: str, container: tuple[InstancePart, ...]) -> tuple[etree._Element, InstancePart]:
        """The element to write ``name`` into and the object's own part (its SHORT-NAME or SW-ARRAY-INDEX)."""
        leaf = _leaf(name, container)
        if leaf is None:
            container, leaf = (), InstancePart(name)
        common = 0
        while common < min(len(self.open), len(container)) and self.open[common][0] == container[common]:
            common += 1
        del self.open[common:]
        for part in container[common:]:
            parent = self.open[-1][1] if self.open else self.tree
            element = _sub(parent, "SW-INSTANCE")
            _sub(element, "SW-ARRAY-INDEX" if part.index else "SHORT-NAME", part.name)
            if part.long_name:
                _sub(element, "LONG-NAME", part.long_name)
            if part.category:
                _sub(element, "CATEGORY", part.category)
            self.open.append((part, element))
        return (self.open[-1][1] if self.open else self.tree), leaf


def _leaf(name: str, container: tuple[InstancePart, ...]) -> InstancePart | None:
    """The object's own part when ``name`` is its container's name and one member or index more."""
    if not container:
        return None
    prefix = member_name(container)
    rest = name[len(prefix):] if name.startswith(prefix) else ""
    if rest.startswith(".") and len(rest) > 1 and not any(c in rest[1:] for c in ".[]"):
        return InstancePart(rest[1:])
    if rest.startswith("[") and rest.endswith("]") and len(rest) > 2 and not any(c in rest[1:-1] for c in ".[]"):
        return InstancePart(rest[1:-1], index=True)
    return None


def _default_name(dataset: Dataset) -> str:
    return Path(dataset.source).stem if dataset.source else "dataset"


def _texts(value: CalValue, info: ObjectInfo):
    yield from (value.name, value.comment, value.unit, info.display_name, info.model_link, *info.functions,
                *info.comments)
    for part in info.container:
        yield from (part.name, part.category, part.long_name)
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
    if value.kind == "VAL_BLK" and info.category in _BLOCK_CATEGORIES:
        return info.category
    return value.kind  # ASCII, VAL_BLK, CURVE, MAP, CUBOID, CUBE_4, CUBE_5


_BLOCK_CATEGORIES = ("VALUE_ARRAY", "RES_AXIS", "BLOB")


def _instance(parent, part: InstancePart, value: CalValue, info: ObjectInfo) -> None:
    instance = _sub(parent, "SW-INSTANCE")
    _sub(instance, "SW-ARRAY-INDEX" if part.index else "SHORT-NAME", part.name)
    for line in info.comments:
        instance.append(etree.Comment(_comment_text(line)))
    if value.comment:
        _sub(instance, "LONG-NAME", value.comment)
    if info.display_name:
        _sub(instance, "DISPLAY-NAME", info.display_name)
    _sub(instance, "CATEGORY", _category(value, info))
    if info.functions:
        _sub(instance, "SW-FEATURE-REF", info.functions[0])
    if info.model_link:
        _sub(instance, "SW-MODEL-LINK", info.model_link)
    cont = _sub(instance, "SW-VALUE-CONT")
    if value.unit:
        _sub(cont, "UNIT-DISPLAY-NAME", value.unit)
    if value.kind == "VAL_BLK" and _category(value, info) != "RES_AXIS":
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
