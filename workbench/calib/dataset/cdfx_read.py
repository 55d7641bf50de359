"""Read CDFX files (ASAM CDF 2.0 XML) into a :class:`~workbench.calib.dataset.model.Dataset`.

``MSRSW / SW-SYSTEMS / SW-SYSTEM / SW-INSTANCE-SPEC / SW-INSTANCE-TREE / SW-INSTANCE``, one
instance per object:

* categories VALUE, DEPENDENT_VALUE, BOOLEAN (one ``V`` or ``VT``), ASCII (one ``VT``), VAL_BLK
  (``SW-ARRAYSIZE``, x first), CURVE, MAP, and the axis objects COM_AXIS, RES_AXIS, CURVE_AXIS;
* values in ``SW-VALUE-CONT / SW-VALUES-PHYS`` as ``V`` (numbers, also ``0x`` hex), ``VT``
  (texts, kept exactly, spaces included) and ``VG`` groups. Document order is x fastest: a MAP
  has one ``VG`` per Y point holding the values along X, a 2-D VAL_BLK one per y index (as the
  rows of DCM and the CDF 2.0 examples); ``LABEL`` s of groups are not kept;
* axes in ``SW-AXIS-CONTS / SW-AXIS-CONT`` (CATEGORY STD_AXIS, FIX_AXIS, COM_AXIS, RES_AXIS,
  CURVE_AXIS, UNIT-DISPLAY-NAME, SW-INSTANCE-REF, SW-VALUES-PHYS). A referenced axis without
  its own points takes them from the referenced instance in the same file;
* LONG-NAME, DISPLAY-NAME, SW-FEATURE-REF, SW-CS-HISTORY (CS-ENTRY, also spelled SW-CS-ENTRY),
  SW-CS-FLAGS, the functions of SW-CS-COLLECTIONS (FEATURE), SW-INSTANCE-TREE-ORIGIN, comments;
* SW-INSTANCE-PROPS-VARIANTS holding a single variant without criteria (INCA writes every
  instance so) is read as the instance's values.

Refused with a :class:`~workbench.errors.DatasetParseError` naming ``file:line``: anything else
inside these elements, structures and arrays of instances (CDF 2.1 categories, nested
SW-INSTANCEs, SW-ARRAY-INDEX), variant-coded values, counts that do not match. Administrative
elements that hold no value (ADMIN-DATA, SDGS, LOCS, SD, collections of other categories, long
names of the system and tree) are read past and listed in ``Dataset.notes``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from workbench.calib.dataset.cdfx_xml import children, comments_in, content, file_comments, local_name, parse
from workbench.calib.dataset.model import CsFlag, Dataset, FunctionInfo, HistoryEntry, ObjectInfo
from workbench.calib.dataset.numbers import NumberError, parse_number, scalar, to_array
from workbench.calib.values import Axis, CalValue
from workbench.errors import DatasetParseError
from workbench.findings import Finding, Severity

__all__ = ["read"]

SCALAR_CATEGORIES = ("VALUE", "DEPENDENT_VALUE", "BOOLEAN")
AXIS_CATEGORIES = ("COM_AXIS", "RES_AXIS", "CURVE_AXIS")
AXIS_KINDS = ("STD_AXIS", "FIX_AXIS") + AXIS_CATEGORIES
CATEGORIES = SCALAR_CATEGORIES + ("ASCII", "VAL_BLK", "CURVE", "MAP") + AXIS_CATEGORIES
HISTORY_DETAILS = ("CSPR", "CSWP", "CSTO", "CSTV", "CSPI", "CSDI")
_ADMINISTRATIVE = ("ADMIN-DATA", "SDGS", "LOCS")


@dataclass
class _AxisCont:
    line: int
    kind: str = ""
    unit: str = ""
    ref: str | None = None
    size: int | None = None
    points: list | None = None


@dataclass
class _Instance:
    """One SW-INSTANCE as read, before references between instances are resolved."""

    name: str
    line: int
    category: str = ""
    long_name: str = ""
    display_name: str = ""
    feature: str = ""
    unit: str = ""
    size: list[int] | None = None
    values: list | None = None
    axes: list[_AxisCont] = field(default_factory=list)
    history: tuple[HistoryEntry, ...] = ()
    flags: tuple[CsFlag, ...] = ()
    comments: tuple[str, ...] = ()


def read(data: bytes, path: str = "<string>") -> Dataset:
    """The dataset a CDFX file holds.

    :raises DatasetParseError: not well-formed XML, or not CDF 2.0 as the module docstring says.
    """
    return _Reader(path).read(parse(data, path))


class _Reader:
    def __init__(self, path: str):
        self.path = path
        self.dataset = Dataset(source=path, format="cdfx")
        self.instances: dict[str, _Instance] = {}

    def error(self, message: str, element) -> DatasetParseError:
        return DatasetParseError(message, self.path, element.sourceline or 0)

    def unexpected(self, name: str, element, parent: str, expected: str) -> DatasetParseError:
        return self.error(f"unexpected <{name}> in <{parent}> (expected {expected})", element)

    def note(self, name: str, element, what: str) -> None:
        self.dataset.notes.append(Finding("not-kept", name, f"<{name}> {what} is not kept", self.path,
                                          element.sourceline or 0, severity=Severity.WARNING))

    def read(self, root) -> Dataset:
        if local_name(root) != "MSRSW":
            raise self.error(f"not a CDF file: the root element is <{local_name(root)}>, expected <MSRSW>", root)
        self.dataset.comments = file_comments(root)
        systems = []
        for name, child in children(root):
            if name == "SHORT-NAME":
                self.dataset.title = content(child).strip()
            elif name == "CATEGORY":
                category = content(child).strip()
                if category not in ("CDF20", "CDF21"):
                    raise self.error(f"MSRSW CATEGORY {category!r}: expected CDF20 (or CDF21)", child)
            elif name == "SW-SYSTEMS":
                systems += [self.expect(c, "SW-SYSTEM", "SW-SYSTEMS") for _, c in children(child)]
            elif name in _ADMINISTRATIVE:
                self.note(name, child, "(administrative data)")
            else:
                raise self.unexpected(name, child, "MSRSW", "SHORT-NAME, CATEGORY, SW-SYSTEMS")
        if len(systems) > 1:
            raise self.error(f"{len(systems)} SW-SYSTEMs; one dataset per file is supported", systems[1])
        if systems:
            self.system(systems[0])
        for instance in self.instances.values():
            self.add(instance)
        return self.dataset

    def expect(self, element, name: str, parent: str):
        if local_name(element) != name:
            raise self.unexpected(local_name(element), element, parent, name)
        return element

    def system(self, system) -> None:
        for name, child in children(system):
            if name == "SHORT-NAME":
                self.dataset.system = content(child).strip()
            elif name in ("LONG-NAME", "CATEGORY"):
                self.note(name, child, "of the SW-SYSTEM")
            elif name == "SW-INSTANCE-SPEC":
                for inner, tree in children(child):
                    self.tree(self.expect(tree, "SW-INSTANCE-TREE", "SW-INSTANCE-SPEC"))
            else:
                raise self.unexpected(name, child, "SW-SYSTEM", "SHORT-NAME, SW-INSTANCE-SPEC")

    def tree(self, tree) -> None:
        for name, child in children(tree):
            if name == "SHORT-NAME":
                self.dataset.name = content(child).strip()
            elif name == "CATEGORY":
                pass  # VCD / NO_VCD: what the instances show (variant-coded values are refused one by one)
            elif name == "LONG-NAME":
                self.note(name, child, "of the SW-INSTANCE-TREE")
            elif name == "SW-INSTANCE-TREE-ORIGIN":
                self.origin(child)
            elif name == "SW-CS-COLLECTIONS":
                for _, collection in children(child):
                    self.collection(self.expect(collection, "SW-CS-COLLECTION", "SW-CS-COLLECTIONS"))
            elif name == "SW-INSTANCE":
                self.instance(child)
            else:
                raise self.unexpected(name, child, "SW-INSTANCE-TREE",
                                      "SHORT-NAME, CATEGORY, SW-INSTANCE-TREE-ORIGIN, SW-CS-COLLECTIONS, SW-INSTANCE")

    def origin(self, origin) -> None:
        for name, child in children(origin):
            if name == "SYMBOLIC-FILE":
                self.dataset.a2l_file = content(child).strip()
            elif name == "DATA-FILE":
                self.dataset.data_file = content(child).strip()
            else:
                raise self.unexpected(name, child, "SW-INSTANCE-TREE-ORIGIN", "SYMBOLIC-FILE, DATA-FILE")

    def collection(self, collection) -> None:
        fields = {}
        history: tuple[HistoryEntry, ...] = ()
        for name, child in children(collection):
            if name in ("CATEGORY", "SW-FEATURE-REF", "REVISION", "SW-COLLECTION-REF"):
                fields[name] = content(child).strip()
            elif name == "SW-CS-HISTORY":
                history = self.history(child)
            else:
                raise self.unexpected(name, child, "SW-CS-COLLECTION",
                                      "CATEGORY, SW-FEATURE-REF, REVISION, SW-COLLECTION-REF, SW-CS-HISTORY")
        if fields.get("CATEGORY") == "FEATURE" and fields.get("SW-FEATURE-REF"):
            self.dataset.functions[fields["SW-FEATURE-REF"]] = FunctionInfo(version=fields.get("REVISION", ""),
                                                                            history=history)
        else:
            self.note("SW-CS-COLLECTION", collection, f"of category {fields.get('CATEGORY', '(none)')}")

    # ---- one instance ----

    def instance(self, element) -> None:
        line = element.sourceline or 0
        found = dict(children(element))
        if "SW-ARRAY-INDEX" in found or "SW-INSTANCE" in found:
            raise self.error("arrays and structures of instances (SW-ARRAY-INDEX, nested SW-INSTANCE) "
                             "are not supported", element)
        if "SHORT-NAME" not in found or not content(found["SHORT-NAME"]).strip():
            raise self.error("SW-INSTANCE without a SHORT-NAME", element)
        instance = _Instance(content(found["SHORT-NAME"]).strip(), line, comments=tuple(comments_in(element)))
        if instance.name in self.instances:
            raise self.error(f"{instance.name} is defined twice (first at line {self.instances[instance.name].line})",
                             element)
        for name, child in children(element):
            if name in ("SHORT-NAME",):
                continue
            if name == "LONG-NAME":
                instance.long_name = content(child).strip()
            elif name == "DISPLAY-NAME":
                instance.display_name = content(child).strip()
            elif name == "CATEGORY":
                instance.category = content(child).strip()
            elif name == "SW-FEATURE-REF":
                instance.feature = content(child).strip()
            elif name == "SW-INSTANCE-PROPS-VARIANTS":
                self.single_variant(instance, child)
            elif name in ("SW-VALUE-CONT", "SW-AXIS-CONTS", "SW-CS-HISTORY", "SW-CS-FLAGS"):
                self.contents(instance, name, child)
            else:
                raise self.unexpected(name, child, "SW-INSTANCE", "SHORT-NAME, LONG-NAME, DISPLAY-NAME, CATEGORY, "
                                      "SW-FEATURE-REF, SW-VALUE-CONT, SW-AXIS-CONTS, SW-CS-HISTORY, SW-CS-FLAGS")
        if instance.category not in CATEGORIES:
            what = f"category {instance.category!r}" if instance.category else "no CATEGORY"
            raise self.error(f"{instance.name}: {what}; supported: {', '.join(CATEGORIES)}", element)
        if instance.values is None:
            raise self.error(f"{instance.name}: no SW-VALUE-CONT/SW-VALUES-PHYS with its values", element)
        self.instances[instance.name] = instance

    def single_variant(self, instance: _Instance, element) -> None:
        variants = [self.expect(v, "SW-INSTANCE-PROPS-VARIANT", "SW-INSTANCE-PROPS-VARIANTS") for _, v in children(element)]
        criteria = [c for v in variants for name, c in children(v) if name == "SW-VCD-CRITERION-VALUES" and len(c)]
        if len(variants) != 1 or criteria:
            raise self.error(f"{instance.name}: variant-coded values ({len(variants)} variants) are not supported",
                             element)
        for name, child in children(variants[0]):
            if name == "SW-VCD-CRITERION-VALUES":
                continue
            if name not in ("SW-VALUE-CONT", "SW-AXIS-CONTS", "SW-CS-HISTORY", "SW-CS-FLAGS"):
                raise self.unexpected(name, child, "SW-INSTANCE-PROPS-VARIANT",
                                      "SW-VALUE-CONT, SW-AXIS-CONTS, SW-CS-HISTORY, SW-CS-FLAGS")
            self.contents(instance, name, child)

    def contents(self, instance: _Instance, name: str, element) -> None:
        if name == "SW-VALUE-CONT":
            instance.unit, instance.size, instance.values = self.value_cont(element, "SW-VALUE-CONT")
        elif name == "SW-AXIS-CONTS":
            instance.axes = [self.axis_cont(self.expect(a, "SW-AXIS-CONT", "SW-AXIS-CONTS")) for _, a in children(element)]
        elif name == "SW-CS-HISTORY":
            instance.history = self.history(element)
        else:
            instance.flags = tuple(self.flag(self.expect(f, "SW-CS-FLAG", "SW-CS-FLAGS")) for _, f in children(element))

    def value_cont(self, element, parent: str) -> tuple[str, list[int] | None, list | None]:
        unit, size, values = "", None, None
        for name, child in children(element):
            if name == "UNIT-DISPLAY-NAME":
                unit = content(child).strip()
            elif name == "SW-ARRAYSIZE":
                size = [self.count(v) for _, v in children(child)]
            elif name == "SW-VALUES-PHYS":
                values = self.values(child)
            else:
                raise self.unexpected(name, child, parent, "UNIT-DISPLAY-NAME, SW-ARRAYSIZE, SW-VALUES-PHYS")
        return unit, size, values

    def axis_cont(self, element) -> _AxisCont:
        axis = _AxisCont(element.sourceline or 0)
        for name, child in children(element):
            if name == "CATEGORY":
                axis.kind = content(child).strip()
                if axis.kind not in AXIS_KINDS:
                    raise self.error(f"axis CATEGORY {axis.kind!r}; expected one of {', '.join(AXIS_KINDS)}", child)
            elif name == "UNIT-DISPLAY-NAME":
                axis.unit = content(child).strip()
            elif name == "SW-INSTANCE-REF":
                axis.ref = content(child).strip()
            elif name == "SW-ARRAYSIZE":
                sizes = [self.count(v) for _, v in children(child)]
                if len(sizes) != 1:
                    raise self.error("an axis's SW-ARRAYSIZE holds one count", child)
                axis.size = sizes[0]
            elif name == "SW-VALUES-PHYS":
                axis.points = self.values(child)
                if any(isinstance(p, list) for p in axis.points):
                    raise self.error("axis points in VG groups (pairs of a rescale axis) are not supported", child)
            else:
                raise self.unexpected(name, child, "SW-AXIS-CONT",
                                      "CATEGORY, UNIT-DISPLAY-NAME, SW-INSTANCE-REF, SW-ARRAYSIZE, SW-VALUES-PHYS")
        return axis

    def values(self, element) -> list:
        """The V/VT/VG content of ``element``: numbers, texts and nested lists (one per VG)."""
        items: list = []
        for name, child in children(element):
            if name == "V":
                text = content(child).strip()
                try:
                    items.append(parse_number(text))
                except NumberError as exc:
                    raise self.error(f"<V>: {exc}" if text else "<V> without a number", child) from None
            elif name == "VT":
                items.append(content(child))
            elif name == "VG":
                items.append(self.values(child))
            elif name == "LABEL" and local_name(element) == "VG":
                continue
            else:
                raise self.unexpected(name, child, local_name(element), "V, VT, VG")
        return items

    def count(self, element) -> int:
        text = content(element).strip()
        if not text.isdigit() or int(text) == 0:
            raise self.error(f"SW-ARRAYSIZE: {text!r} is not a count above 0", element)
        return int(text)

    def history(self, element) -> tuple[HistoryEntry, ...]:
        entries = []
        for name, entry in children(element):
            if name not in ("CS-ENTRY", "SW-CS-ENTRY"):
                raise self.unexpected(name, entry, "SW-CS-HISTORY", "CS-ENTRY")
            fields: dict[str, str] = {}
            details = []
            for tag, child in children(entry):
                if tag in HISTORY_DETAILS:
                    details.append((tag, content(child).strip()))
                elif tag == "REMARK":
                    fields[tag] = "\n".join(content(p).strip() for _, p in children(child))
                elif tag in ("STATE", "DATE", "CSUS"):
                    fields[tag] = content(child).strip()
                elif tag == "SD":
                    self.note(tag, child, "(special data of a history entry)")
                else:
                    raise self.unexpected(tag, child, name, "STATE, DATE, CSUS, CSPR ... CSDI, REMARK")
            entries.append(HistoryEntry(fields.get("STATE", ""), fields.get("DATE", ""), fields.get("CSUS", ""),
                                        fields.get("REMARK", ""), tuple(details)))
        return tuple(entries)

    def flag(self, element) -> CsFlag:
        fields: dict[str, str] = {}
        for tag, child in children(element):
            if tag == "REMARK":
                fields[tag] = "\n".join(content(p).strip() for _, p in children(child))
            elif tag in ("CATEGORY", "FLAG", "CSUS", "DATE"):
                fields[tag] = content(child).strip()
            else:
                raise self.unexpected(tag, child, "SW-CS-FLAG", "CATEGORY, FLAG, CSUS, DATE, REMARK")
        return CsFlag(fields.get("CATEGORY", ""), fields.get("FLAG", ""), fields.get("CSUS", ""), fields.get("DATE", ""),
                      fields.get("REMARK", ""))

    # ---- from instances to values ----

    def add(self, instance: _Instance) -> None:
        info = ObjectInfo(display_name=instance.display_name, functions=(instance.feature,) if instance.feature else (),
                          comments=instance.comments, history=instance.history, flags=instance.flags,
                          category=instance.category, line=instance.line)
        try:
            value = self.value(instance)
        except NumberError as exc:
            raise DatasetParseError(f"{instance.name}: {exc}", self.path, instance.line) from None
        self.dataset.add(value, info)

    def fail(self, instance: _Instance, message: str) -> DatasetParseError:
        return DatasetParseError(f"{instance.name}: {message}", self.path, instance.line)

    def value(self, instance: _Instance) -> CalValue:
        category, items = instance.category, instance.values
        common = {"unit": instance.unit, "comment": instance.long_name}
        if category in SCALAR_CATEGORIES + ("ASCII",):
            if len(items) != 1 or isinstance(items[0], list):
                raise self.fail(instance, f"a {category} holds one value, found {len(_flat(items))}")
            if category == "ASCII":
                if not isinstance(items[0], str):
                    raise self.fail(instance, "an ASCII holds its text in <VT>")
                return CalValue(instance.name, "ASCII", items[0], comment=instance.long_name)
            item = items[0] if isinstance(items[0], str) else scalar(items[0])
            return CalValue(instance.name, "VALUE", item, **common)
        if category == "VAL_BLK":
            return CalValue(instance.name, "VAL_BLK", self.block(instance), **common)
        axes = tuple(self.axis(instance, a) for a in instance.axes)
        if category in AXIS_CATEGORIES and not axes:
            if any(isinstance(i, list) for i in items):
                raise self.fail(instance, "axis points in VG groups (pairs of a rescale axis) are not supported")
            return CalValue(instance.name, "AXIS_PTS", to_array(items), **common)
        expected = 2 if category == "MAP" else 1
        if len(axes) != expected:
            raise self.fail(instance, f"a {category} has {expected} SW-AXIS-CONT, found {len(axes)}")
        shape = tuple(len(a.values) for a in axes)
        return CalValue(instance.name, "MAP" if category == "MAP" else "CURVE", self.grid(instance, shape), axes=axes,
                        **common)

    def block(self, instance: _Instance) -> np.ndarray:
        items = instance.values
        shape = tuple(instance.size) if instance.size else _nested_shape(items)
        if shape is None:
            raise self.fail(instance, "VG groups of different lengths and no SW-ARRAYSIZE")
        return self.grid(instance, shape)

    def grid(self, instance: _Instance, shape: tuple[int, ...]) -> np.ndarray:
        """The values in ``shape`` (x first), read x fastest; VG groups must match the shape."""
        items = instance.values
        flat = _flat(items)
        if len(flat) != int(np.prod(shape)):
            raise self.fail(instance, f"{len(flat)} values for the shape {' x '.join(map(str, shape))}")
        if any(isinstance(i, list) for i in items) and _squeezed(_nested_shape(items)) != _squeezed(shape):
            rows = "one VG per Y point holding the values along X" if len(shape) == 2 else "innermost VGs along x"
            raise self.fail(instance, f"its VG groups do not make {' x '.join(map(str, shape))} values ({rows})")
        return to_array(flat).reshape(shape, order="F").copy()

    def axis(self, instance: _Instance, axis: _AxisCont) -> Axis:
        kind = axis.kind
        referenced = self.instances.get(axis.ref) if axis.ref else None
        if not kind:
            kind = referenced.category if referenced and referenced.category in AXIS_CATEGORIES else "STD_AXIS"
        points = axis.points
        if points is None:
            if kind == "CURVE_AXIS":
                raise DatasetParseError(f"{instance.name}: its CURVE_AXIS lists no axis points (SW-VALUES-PHYS); "
                                        f"computing them from {axis.ref} needs the A2L", self.path, axis.line)
            if referenced is None:
                what = f"references {axis.ref!r}, which the file does not hold," if axis.ref else "has"
                raise DatasetParseError(f"{instance.name}: an axis that {what} no SW-VALUES-PHYS", self.path, axis.line)
            points = referenced.values
            if any(isinstance(p, list) for p in points):
                raise DatasetParseError(f"{instance.name}: its axis {axis.ref} holds rescale pairs (VG groups), not axis points; "
                                        f"computing the points needs the A2L",
                                        self.path, axis.line)
        if axis.size is not None and axis.size != len(points):
            raise DatasetParseError(f"{instance.name}: the axis's SW-ARRAYSIZE says {axis.size}, it has {len(points)} "
                                    f"points", self.path, axis.line)
        unit = axis.unit or (referenced.unit if referenced is not None and axis.points is None else "")
        return Axis(to_array(points), kind=kind, name=axis.ref, unit=unit)


def _flat(items: list) -> list:
    out: list = []
    for item in items:
        if isinstance(item, list):
            out += _flat(item)
        else:
            out.append(item)
    return out


def _squeezed(shape: tuple[int, ...] | None) -> tuple[int, ...] | None:
    """``shape`` without trailing 1s: a curve's values in one VG group are still a curve."""
    while shape and len(shape) > 1 and shape[-1] == 1:
        shape = shape[:-1]
    return shape


def _nested_shape(items: list) -> tuple[int, ...] | None:
    """The shape of nested VG groups, x first (innermost group along x); None when ragged."""
    if not any(isinstance(i, list) for i in items):
        return (len(items),)
    if not all(isinstance(i, list) for i in items):
        return None
    shapes = {_nested_shape(i) for i in items}
    if len(shapes) != 1 or None in shapes:
        return None
    return shapes.pop() + (len(items),)
