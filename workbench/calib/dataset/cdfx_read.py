"""Read CDFX files (ASAM CDF 2.0 and 2.1 XML) into a :class:`~workbench.calib.dataset.model.Dataset`.

``MSRSW / SW-SYSTEMS / SW-SYSTEM / SW-INSTANCE-SPEC / SW-INSTANCE-TREE / SW-INSTANCE``, one
instance per object; what each category becomes is :mod:`~workbench.calib.dataset.cdfx_values`'
business. Read here:

* values in ``SW-VALUE-CONT / SW-VALUES-PHYS`` as ``V`` (numbers, also ``0x`` hex), ``VT``
  (texts, kept exactly, spaces included) and ``VG`` groups (their ``LABEL`` s are not kept);
* axes in ``SW-AXIS-CONTS / SW-AXIS-CONT`` (CATEGORY, UNIT-DISPLAY-NAME, SW-INSTANCE-REF,
  SW-ARRAYSIZE, SW-VALUES-PHYS);
* structures and arrays of instances: an SW-INSTANCE inside another is a member (``outer.member``)
  or, named by SW-ARRAY-INDEX instead of SHORT-NAME, an element (``outer[i]``); the enclosing
  instances are kept in ``ObjectInfo.container``;
* LONG-NAME, DISPLAY-NAME, SW-FEATURE-REF, SW-MODEL-LINK (CDF 2.1), SW-CS-HISTORY (CS-ENTRY, also
  spelled SW-CS-ENTRY), SW-CS-FLAGS, the functions of SW-CS-COLLECTIONS (FEATURE),
  SW-INSTANCE-TREE-ORIGIN, comments;
* SW-INSTANCE-PROPS-VARIANTS holding a single variant without criteria (INCA writes every
  instance so) is read as the instance's values; other variant-coded values are left out with a note.

Refused with a :class:`~workbench.errors.DatasetParseError` naming ``file:line``: XML that is not
well-formed, an element the CDF DTDs do not allow where it stands, numbers that are not numbers.
Administrative elements that hold no value (ADMIN-DATA, SDGS, LOCS, SD, collections of other
categories, long names of the system and tree) are read past and listed in ``Dataset.notes``.
"""

from __future__ import annotations

from workbench.calib.dataset.cdfx_values import AXIS_KINDS, AxisCont, Instance, add_instances
from workbench.calib.dataset.cdfx_xml import children, comments_in, content, file_comments, local_name, parse
from workbench.calib.dataset.model import (CsFlag, Dataset, FunctionInfo, HistoryEntry, InstancePart, member_name,
                                          value_runs)
from workbench.calib.dataset.numbers import NumberError, parse_number
from workbench.errors import DatasetParseError
from workbench.findings import Finding, Severity

__all__ = ["HISTORY_DETAILS", "read"]

HISTORY_DETAILS = ("CSPR", "CSWP", "CSTO", "CSTV", "CSPI", "CSDI")
_ADMINISTRATIVE = ("ADMIN-DATA", "SDGS", "LOCS")
_CONTENTS = ("SW-VALUE-CONT", "SW-AXIS-CONTS", "SW-CS-HISTORY", "SW-CS-FLAGS")
_TEXTS = {"LONG-NAME": "long_name", "DISPLAY-NAME": "display_name", "CATEGORY": "category",
          "SW-FEATURE-REF": "feature", "SW-MODEL-LINK": "model_link"}


def read(data: bytes, path: str = "<string>") -> Dataset:
    """The dataset a CDFX file holds.

    :raises DatasetParseError: not well-formed XML, or not CDF 2.0 as the module docstring says.
    """
    return _Reader(path).read(parse(data, path))


class _Reader:
    def __init__(self, path: str):
        self.path = path
        self.dataset = Dataset(source=path, format="cdfx")
        self.instances: dict[str, Instance] = {}

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
        add_instances(self.dataset, self.instances, self.path)
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
                pass  # VCD / NO_VCD: what the instances show (variant-coded values are left out one by one)
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

    def instance(self, element, container: tuple[InstancePart, ...] = ()) -> None:
        """Read ``element`` (with the instances nested in it) into :attr:`instances`."""
        line = element.sourceline or 0
        found = dict(children(element))
        part = self.part(element, found)
        name = member_name(container + (part,))
        instance = Instance(name, line, container, comments=tuple(comments_in(element)))
        nested = []
        for tag, child in children(element):
            if tag in ("SHORT-NAME", "SW-ARRAY-INDEX"):
                continue
            if tag in _TEXTS:
                setattr(instance, _TEXTS[tag], content(child).strip())
            elif tag == "SW-INSTANCE-PROPS-VARIANTS":
                self.variants(instance, child)
            elif tag in _CONTENTS:
                self.contents(instance, tag, child)
            elif tag == "SW-INSTANCE":
                nested.append(child)
            else:
                raise self.unexpected(tag, child, "SW-INSTANCE", "SHORT-NAME or SW-ARRAY-INDEX, LONG-NAME, DISPLAY-NAME, "
                                      "CATEGORY, SW-FEATURE-REF, SW-MODEL-LINK, SW-VALUE-CONT, SW-AXIS-CONTS, "
                                      "SW-CS-HISTORY, SW-CS-FLAGS, SW-INSTANCE-PROPS-VARIANTS, SW-INSTANCE")
        if instance.values is not None or instance.left_out:
            if name in self.instances:
                raise self.error(f"{name} is defined twice (first at line {self.instances[name].line})", element)
            self.instances[name] = instance
        elif not nested:
            self.dataset.notes.append(Finding("left-out", name, f"{name}: no SW-VALUE-CONT/SW-VALUES-PHYS with its "
                                              f"values; left out", self.path, line, severity=Severity.WARNING))
        inner = container + (InstancePart(part.name, instance.category, instance.long_name, part.index),)
        for child in nested:
            self.instance(child, inner)

    def part(self, element, found: dict) -> InstancePart:
        """The instance's own name: its SHORT-NAME, or its SW-ARRAY-INDEX (``[2]`` or ``2``) in an array."""
        if "SHORT-NAME" in found and content(found["SHORT-NAME"]).strip():
            return InstancePart(content(found["SHORT-NAME"]).strip())
        if "SW-ARRAY-INDEX" in found and content(found["SW-ARRAY-INDEX"]).strip():
            return InstancePart(content(found["SW-ARRAY-INDEX"]).strip().strip("[]").strip(), index=True)
        raise self.error("SW-INSTANCE without a SHORT-NAME or SW-ARRAY-INDEX", element)

    def variants(self, instance: Instance, element) -> None:
        variants = [self.expect(v, "SW-INSTANCE-PROPS-VARIANT", "SW-INSTANCE-PROPS-VARIANTS") for _, v in children(element)]
        criteria = [c for v in variants for name, c in children(v) if name == "SW-VCD-CRITERION-VALUES" and len(c)]
        if len(variants) != 1 or criteria:
            instance.left_out = f"variant-coded values ({len(variants)} variants) are not supported"
            return
        for name, child in children(variants[0]):
            if name == "SW-VCD-CRITERION-VALUES":
                continue
            if name not in _CONTENTS:
                raise self.unexpected(name, child, "SW-INSTANCE-PROPS-VARIANT", ", ".join(_CONTENTS))
            self.contents(instance, name, child)

    def contents(self, instance: Instance, name: str, element) -> None:
        if name == "SW-VALUE-CONT":
            instance.unit, instance.size, instance.values, instance.value_line, instance.value_runs = \
                self.value_cont(element)
        elif name == "SW-AXIS-CONTS":
            instance.axes = [self.axis_cont(self.expect(a, "SW-AXIS-CONT", "SW-AXIS-CONTS")) for _, a in children(element)]
        elif name == "SW-CS-HISTORY":
            instance.history = self.history(element)
        else:
            instance.flags = tuple(self.flag(self.expect(f, "SW-CS-FLAG", "SW-CS-FLAGS")) for _, f in children(element))

    def value_cont(self, element) -> tuple[str, list[int] | None, list | None, int, tuple[tuple[int, int], ...]]:
        unit, size, values, line, runs = "", None, None, 0, ()
        for name, child in children(element):
            if name == "UNIT-DISPLAY-NAME":
                unit = content(child).strip()
            elif name == "SW-ARRAYSIZE":
                size = [self.count(v) for _, v in children(child)]
            elif name == "SW-VALUES-PHYS":  # its line: that of its first value, where a refusal points
                first = next((value for _, value in children(child)), child)
                values, line = self.values(child), first.sourceline or child.sourceline or 0
                runs = value_runs(value.sourceline or 0 for value in child.iter("{*}V", "{*}VT"))
            else:
                raise self.unexpected(name, child, "SW-VALUE-CONT", "UNIT-DISPLAY-NAME, SW-ARRAYSIZE, SW-VALUES-PHYS")
        return unit, size, values, line, runs

    def axis_cont(self, element) -> AxisCont:
        axis = AxisCont(element.sourceline or 0)
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
                    raise self.error("axis points in VG groups: an axis lists its points as V or VT", child)
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
