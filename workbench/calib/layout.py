"""Where a calibration object's items lie in ECU memory: its RECORD_LAYOUT placed at its address.

Two steps, because some layouts store their number of axis points in memory::

    layout = object_layout(model, "xvPRV_DC_FF")       # an ObjectLayout
    first = read_spans(layout.fixed_part(), read)        # the NO_AXIS_PTS counts ([] if none)
    resolved = layout.resolve(first)                     # a ResolvedLayout: every field placed
    data = read_spans(resolved.spans(), read)            # the object and the axes it uses
    value = resolved.decode(data)                        # CalValue (workbench.calib.codec)
    edits = resolved.encode(new_value, current=data)     # ByteEdits of what changed

The rules:

- Items are placed in the order of their position numbers. The first starts at the object's
  address; each following one at the next address aligned for its data type (ALIGNMENT_* of the
  RECORD_LAYOUT, else of MOD_COMMON, else ASAP2's natural alignment).
- An axis' number of points is, in this order: the count of the AXIS_PTS it refers to (COM_AXIS,
  RES_AXIS), NO_AXIS_PTS_<axis> read from memory (at most MAX_AXIS_POINTS), FIX_NO_AXIS_PTS_<axis>,
  the number a FIX_AXIS_PAR/_DIST/_LIST gives, MAX_AXIS_POINTS. A CURVE_AXIS counts its own points:
  its rescale curve maps inputs to indices of this object and may have another number of points
  (see :mod:`workbench.calib.codec`).
- Without STATIC_RECORD_LAYOUT, items follow each other at the actual number of points; with it
  (and with STATIC_ADDRESS_OFFSETS) every item keeps the place it has at MAX_AXIS_POINTS.
  STATIC_ADDRESS_OFFSETS also keeps each value at its place in the full MAX_AXIS_POINTS array.
- Values have the shape ``(nx, ny, ...)`` (X first, as :class:`~workbench.calib.values.CalValue`
  holds them). **COLUMN_DIR** stores them in Fortran order over that shape: the X index varies
  fastest, i.e. the C array ``v[ny][nx]`` (what Simulink's column-major code and the demo's
  ``xvPRV_DC_FF[manifold][target]`` hold); **ROW_DIR** in C order: the last index (Y of a MAP)
  varies fastest, ``v[nx][ny]``. pya2ldb and asamint read the two modes so (``"F"``/``"C"``);
  a VAL_BLK's MATRIX_DIM and a measurement's LAYOUT follow the same rule.
  **Not settled**: other tools store ROW_DIR with X fastest and COLUMN_DIR with Y fastest. Vector's
  XCPlite writes a C ``float m[4][8]`` as ``MATRIX_DIM 8 4`` and a ``[4][8]`` MAP with an 8-point X
  axis (all its layouts ROW_DIR; its C++ map macro though puts the outer extent on X), xcp-lite
  writes ``[[T; X]; Y]`` as ``MATRIX_DIM X Y``, ZF's openxilenv reads ROW_DIR at ``y*nx + x`` and
  COLUMN_DIR at ``x*ny + y`` (VAL_BLK too). a2ltool and our ``a2l insert``/``update --types`` write
  the outer C extent first, as read here. The ASAM text was not at hand; README "Memory order of
  arrays" has the sources. Such an XCPlite array reads here with its elements out of place: compare
  ``cal get`` with the C source before writing it.
- AXIS_PTS items with INDEX_DECR hold the points last to first. DEPOSIT DIFFERENCE (of the
  axis, else MOD_COMMON) stores each point as its difference to the previous one (the first to 0).
- Supported items: FNC_VALUES, AXIS_PTS_*, NO_AXIS_PTS_*, FIX_NO_AXIS_PTS_*, SRC_ADDR_*,
  RIP_ADDR_*, SHIFT_OP_*, OFFSET_*, DIST_OP_*, IDENTIFICATION, RESERVED (BYTE/WORD/LONG); a FIX_AXIS
  whose layout holds OFFSET_<axis> with DIST_OP_<axis> or SHIFT_OP_<axis> takes its points from
  memory. Refused with a clear error: addressing other than DIRECT (PBYTE, PWORD, PLONG:
  pointers to the values), AXIS_RESCALE_*, the ALTERNATE_* index modes.
"""

from __future__ import annotations

from dataclasses import dataclass
from math import prod
from typing import TYPE_CHECKING, Any, Mapping

from workbench.a2l.objects import AxisDescr, AxisPts, Characteristic, RecordLayout
from workbench.calib import rawtypes
from workbench.calib.memory import ByteEdit, MemoryBytes, Span
from workbench.errors import A2lParseError, ConversionError

if TYPE_CHECKING:
    from workbench.a2l.model import A2lModel
    from workbench.calib.values import CalValue

__all__ = ["Field", "ObjectLayout", "ResolvedLayout", "object_layout"]

_ONE_ELEMENT = ("NO_AXIS_PTS", "SRC_ADDR", "RIP_ADDR", "SHIFT_OP", "OFFSET", "DIST_OP", "IDENTIFICATION", "RESERVED")
_RESERVED_TYPES = {"BYTE": "UBYTE", "WORD": "UWORD", "LONG": "ULONG"}
_AXES_OF = {"CURVE": 1, "MAP": 2, "CUBOID": 3, "CUBE_4": 4, "CUBE_5": 5}
_INDEX_MODES = ("ROW_DIR", "COLUMN_DIR")


@dataclass(frozen=True)
class Field:
    """One RECORD_LAYOUT item placed in memory: ``count`` elements of ``datatype`` at ``offset``
    bytes from the object's address, ``size`` bytes reserved (more than ``count`` elements when a
    static layout keeps room for MAX_AXIS_POINTS)."""

    keyword: str  # FNC_VALUES, AXIS_PTS, NO_AXIS_PTS, ... (LayoutEntry.keyword)
    axis: str | None
    datatype: str
    count: int
    offset: int
    size: int
    byte_order: str
    mode: str | None = None  # FNC_VALUES: ROW_DIR / COLUMN_DIR; AXIS_PTS: INDEX_INCR / INDEX_DECR

    @property
    def spelled(self) -> str:
        return f"{self.keyword}_{self.axis}" if self.axis else self.keyword

    @property
    def used_size(self) -> int:
        return self.count * rawtypes.element_size(self.datatype)


@dataclass(frozen=True)
class _Axis:
    """How one axis of an object gets its points and their number."""

    name: str  # X, Y, Z, 4, 5
    attribute: str  # STD_AXIS, FIX_AXIS, COM_AXIS, RES_AXIS, CURVE_AXIS (AXIS_PTS objects: STD_AXIS)
    descr: AxisDescr | None  # None for an AXIS_PTS object's own axis
    max_points: int
    fixed_count: int | None  # known without reading memory (FIX_NO_AXIS_PTS, FIX_AXIS_PAR ...)
    in_memory: bool  # NO_AXIS_PTS_<axis> holds the count
    reference: "ObjectLayout | None" = None  # COM_AXIS / RES_AXIS / CURVE_AXIS


def object_layout(model: "A2lModel", obj: "str | Characteristic | AxisPts") -> "ObjectLayout":
    """The memory layout of a CHARACTERISTIC or AXIS_PTS (by name or object).

    :raises UnknownSymbolError: no such object. :raises A2lParseError: its record layout or a
        referenced axis object is missing or malformed (located). :raises ConversionError: the
        layout uses something not supported (see the module docstring).
    """
    if isinstance(obj, str):
        obj = model.object(obj)
    return ObjectLayout(model, obj)


class ObjectLayout:
    """A CHARACTERISTIC's or AXIS_PTS' layout before the counts stored in ECU memory are read."""

    def __init__(self, model: "A2lModel", obj: Characteristic | AxisPts, _seen: tuple[str, ...] = ()):
        if not isinstance(obj, (Characteristic, AxisPts)):
            raise ConversionError(f"{obj.kind} {obj.name} is not a calibration object")
        if obj.name in _seen:
            raise A2lParseError(f"{obj.kind} {obj.name}: its axes refer back to it ({' -> '.join(_seen + (obj.name,))})",
                                *obj.location)
        self.model = model
        self.obj = obj
        self.name = obj.name
        self.kind = obj.type if isinstance(obj, Characteristic) else "AXIS_PTS"
        self.record_layout: RecordLayout = model.record_layout_of(obj)
        self.alignments = self.record_layout.alignments_over(model.mod_common.alignments)
        self.static = self.record_layout.static_record_layout or self.record_layout.static_address_offsets
        self._check_entries()
        self.axes: tuple[_Axis, ...] = self._axes(_seen + (obj.name,))

    def __repr__(self) -> str:
        return f"<ObjectLayout {self.kind} {self.name} ({self.record_layout.name})>"

    @property
    def address(self) -> int:
        return self.obj.address

    @property
    def extension(self) -> int:
        return self.obj.address_extension

    def error(self, message: str) -> ConversionError:
        return ConversionError(f"{self.kind} {self.name} (RECORD_LAYOUT {self.record_layout.name}): {message}")

    # -- what the layout holds ---------------------------------------------------------------------
    def _check_entries(self) -> None:
        for entry in self.record_layout.entries:
            if entry.addressing not in (None, "DIRECT"):
                raise self.error(f"{entry.spelled} is addressed {entry.addressing} (a pointer to the values); only "
                                 "DIRECT is supported")
            if entry.keyword in ("AXIS_RESCALE", "NO_RESCALE"):
                raise self.error(f"{entry.spelled}: rescale axes are not supported")
            if entry.keyword == "FNC_VALUES" and entry.mode not in _INDEX_MODES:
                raise self.error(f"FNC_VALUES index mode {entry.mode} is not supported (only ROW_DIR, COLUMN_DIR)")
            if entry.keyword == "AXIS_PTS" and entry.mode not in ("INDEX_INCR", "INDEX_DECR"):
                raise self.error(f"{entry.spelled} index mode {entry.mode} is not supported")
            if entry.position is not None and entry.datatype is not None and entry.keyword != "RESERVED":
                rawtypes.element_size(entry.datatype)  # an unknown data type fails here, named
        main = "FNC_VALUES" if self.kind != "AXIS_PTS" else "AXIS_PTS"
        if self.record_layout.entry(main, None if main == "FNC_VALUES" else "X") is None:
            raise self.error(f"no {main}{'' if main == 'FNC_VALUES' else '_X'} item")

    def _axes(self, seen: tuple[str, ...]) -> tuple[_Axis, ...]:
        layout = self.record_layout
        if isinstance(self.obj, AxisPts):
            return (self._axis("X", "STD_AXIS", None, self.obj.max_axis_points, None),)
        descrs = self.obj.axes
        wanted = _AXES_OF.get(self.obj.type, 0)
        if self.obj.type not in _AXES_OF and self.obj.type not in ("VALUE", "VAL_BLK", "ASCII"):
            raise self.error(f"type {self.obj.type} is not supported")
        if len(descrs) != wanted:
            raise A2lParseError(f"CHARACTERISTIC {self.name}: a {self.obj.type} needs {wanted} AXIS_DESCR, it has "
                                f"{len(descrs)}", *self.obj.location)
        axes = []
        for descr in descrs:
            fixed = None
            reference = None
            if descr.attribute in ("COM_AXIS", "RES_AXIS"):
                if descr.axis_pts_ref is None:
                    raise A2lParseError(f"CHARACTERISTIC {self.name}: {descr.attribute} {descr.axis} needs AXIS_PTS_REF",
                                        *descr.location)
                target = self.model.resolve(descr, "axis_pts_ref", "AXIS_PTS", f"CHARACTERISTIC {self.name}")
                reference = ObjectLayout(self.model, target, seen)
            elif descr.attribute == "CURVE_AXIS":
                if descr.curve_axis_ref is None:
                    raise A2lParseError(f"CHARACTERISTIC {self.name}: CURVE_AXIS {descr.axis} needs CURVE_AXIS_REF",
                                        *descr.location)
                target = self.model.resolve(descr, "curve_axis_ref", "CHARACTERISTIC", f"CHARACTERISTIC {self.name}")
                if target.type != "CURVE":
                    raise A2lParseError(f"CHARACTERISTIC {self.name}: CURVE_AXIS_REF {target.name} is a {target.type}, "
                                        "not a CURVE", *descr.location)
                reference = ObjectLayout(self.model, target, seen)
            elif descr.attribute == "FIX_AXIS":
                points = descr.fix_axis_points
                fixed = len(points) if points is not None else None
                if points is None and not self._fix_axis_in_memory(descr.axis):
                    raise A2lParseError(f"CHARACTERISTIC {self.name}: FIX_AXIS {descr.axis} has neither FIX_AXIS_PAR, "
                                        f"_DIST, _LIST nor OFFSET_{descr.axis} in RECORD_LAYOUT {layout.name}",
                                        *descr.location)
            elif descr.attribute != "STD_AXIS":
                raise self.error(f"axis {descr.axis}: attribute {descr.attribute} is not supported")
            axes.append(self._axis(descr.axis, descr.attribute, descr, descr.max_axis_points, fixed, reference))
        return tuple(axes)

    def _axis(self, name: str, attribute: str, descr: AxisDescr | None, max_points: int, fixed: int | None,
              reference: "ObjectLayout | None" = None) -> _Axis:
        layout = self.record_layout
        fix_no = layout.entry("FIX_NO_AXIS_PTS", name)
        in_memory = layout.entry("NO_AXIS_PTS", name) is not None and (reference is None or attribute == "CURVE_AXIS")
        if fixed is None and fix_no is not None:
            fixed = fix_no.count
        if attribute == "STD_AXIS" and layout.entry("AXIS_PTS", name) is None:
            raise self.error(f"a STD_AXIS {name} needs AXIS_PTS_{name} in the record layout")
        return _Axis(name, attribute, descr, max_points, fixed, in_memory and fixed is None, reference)

    def _fix_axis_in_memory(self, axis: str) -> bool:
        layout = self.record_layout
        return layout.entry("OFFSET", axis) is not None and (
            layout.entry("DIST_OP", axis) is not None or layout.entry("SHIFT_OP", axis) is not None)

    # -- the two steps ------------------------------------------------------------------------------
    @property
    def needs_counts(self) -> bool:
        """Whether a count lies in memory (here or in an axis object this one uses)."""
        return any(axis.in_memory or (axis.reference is not None and axis.reference.needs_counts)
                   for axis in self.axes)

    def fixed_part(self) -> list[Span]:
        """What to read before :meth:`resolve`: from this object's address to the end of its last
        NO_AXIS_PTS item as placed with MAX_AXIS_POINTS (never less than where they really lie),
        and the same of the axis objects it uses. Empty when no count lies in memory."""
        spans: list[Span] = []
        if any(axis.in_memory for axis in self.axes):
            fields, _ = self._place({axis.name: axis.max_points for axis in self.axes}, reserve_max=True)
            end = max(f.offset + f.size for f in fields if f.keyword == "NO_AXIS_PTS")
            spans.append(Span(self.address, end, self.extension))
        for axis in self.axes:
            if axis.reference is not None:
                spans.extend(axis.reference.fixed_part())
        return list(dict.fromkeys(spans))

    def resolve(self, data: Mapping[Span, bytes] | MemoryBytes | None = None) -> "ResolvedLayout":
        """Place every field; ``data`` holds the bytes of :meth:`fixed_part` (may be omitted when that
        is empty).

        :raises ConversionError: a count in memory is 0 or beyond MAX_AXIS_POINTS (not a valid object).
        :raises WorkbenchError: ``data`` lacks bytes of :meth:`fixed_part`.
        """
        references = {axis.name: axis.reference.resolve(data) for axis in self.axes if axis.reference}
        known: dict[str, int] = {}
        for axis in self.axes:
            if axis.reference is not None and axis.attribute != "CURVE_AXIS":
                known[axis.name] = references[axis.name].counts[0]
            elif axis.fixed_count is not None:
                known[axis.name] = axis.fixed_count
            elif not axis.in_memory:
                known[axis.name] = axis.max_points
        fields, known = self._place(known, self.static, MemoryBytes(data or {}))
        return ResolvedLayout(self, tuple(fields), tuple(known[axis.name] for axis in self.axes), references)

    def _place(self, counts: Mapping[str, int], reserve_max: bool, memory: MemoryBytes | None = None
               ) -> tuple[list[Field], dict[str, int]]:
        """The fields in position order, each at the next aligned offset; with ``memory``, the counts
        not in ``counts`` are read from their NO_AXIS_PTS items on the way. Returns the fields and
        every axis' count."""
        counts = dict(counts)
        fields: list[Field] = []
        offset = 0
        for entry in self.record_layout.entries:
            if entry.position is None:
                continue
            datatype = self._datatype(entry)
            size = rawtypes.element_size(datatype)
            if fields:
                offset = self._aligned(offset, datatype)
            if memory is not None and entry.keyword == "NO_AXIS_PTS" and entry.axis not in counts:
                raw = memory.read(self.address + offset, size, self.extension)
                counts[entry.axis] = self._checked_count(entry.axis, rawtypes.decode(raw, datatype,
                                                                                      self._byte_order(entry))[0])
            used = self._elements(entry, counts, reserve_max=False)
            reserved = self._elements(entry, counts, reserve_max=reserve_max)
            if used is None:
                missing = next(axis.name for axis in self.axes if axis.name not in counts)
                raise self.error(f"{entry.spelled} comes before NO_AXIS_PTS_{missing}, so its size is not known")
            fields.append(Field(entry.keyword, entry.axis, datatype, used, offset, reserved * size,
                                self._byte_order(entry), entry.mode))
            offset += reserved * size
        return fields, counts

    def _checked_count(self, axis: str, count) -> int:
        maximum = next(a.max_points for a in self.axes if a.name == axis)
        if not 0 < count <= maximum:
            raise self.error(f"{count} points on axis {axis} in memory, MAX_AXIS_POINTS is {maximum}")
        return int(count)

    def _elements(self, entry, counts: Mapping[str, int], reserve_max: bool) -> int | None:
        """Elements of one item: None when it needs a count not known yet."""
        maxima = {axis.name: axis.max_points for axis in self.axes}
        pick = maxima if reserve_max else counts
        if entry.keyword in _ONE_ELEMENT:
            return 1
        if entry.keyword == "AXIS_PTS":
            return pick.get(entry.axis, counts.get(entry.axis))
        if entry.keyword == "FNC_VALUES":
            if self.kind in ("VALUE", "AXIS_PTS"):
                return 1
            if self.kind in ("VAL_BLK", "ASCII"):
                return max(prod(self.obj.shape), 1)
            if any(axis.name not in counts for axis in self.axes):
                return None
            both = [pick.get(axis.name, counts[axis.name]) for axis in self.axes]
            return prod(both)
        raise self.error(f"{entry.spelled} is not supported")

    def _datatype(self, entry) -> str:
        if entry.keyword == "RESERVED":
            if entry.datatype not in _RESERVED_TYPES:
                raise self.error(f"RESERVED size {entry.datatype} (expected BYTE, WORD or LONG)")
            return _RESERVED_TYPES[entry.datatype]
        return entry.datatype

    def _aligned(self, offset: int, datatype: str) -> int:
        alignment = max(self.alignments.of(datatype), 1)
        address = self.address + offset
        return offset + (-address) % alignment

    def _byte_order(self, entry) -> str:
        if entry.keyword == "AXIS_PTS" and isinstance(self.obj, Characteristic):
            descr = next((axis.descr for axis in self.axes if axis.name == entry.axis), None)
            if descr is not None and descr.byte_order:
                return descr.byte_order
        return self.obj.byte_order


class ResolvedLayout:
    """An object's fields at their addresses, with its actual numbers of axis points."""

    def __init__(self, plan: ObjectLayout, fields: tuple[Field, ...], counts: tuple[int, ...],
                 references: dict[str, "ResolvedLayout"]):
        self.plan = plan
        self.model = plan.model
        self.obj = plan.obj
        self.name = plan.name
        self.kind = plan.kind
        self.fields = fields
        self.counts = counts  # actual points per axis, X first
        self.references = references  # axis -> the AXIS_PTS / CURVE it uses

    def __repr__(self) -> str:
        return f"<ResolvedLayout {self.kind} {self.name}: {', '.join(f'{f.spelled}@{f.offset}' for f in self.fields)}>"

    @property
    def address(self) -> int:
        return self.plan.address

    @property
    def extension(self) -> int:
        return self.plan.extension

    @property
    def size(self) -> int:
        """Bytes from the address to the end of the last field."""
        return max((f.offset + f.size for f in self.fields), default=0)

    @property
    def shape(self) -> tuple[int, ...]:
        """The value's shape: () for a VALUE, the axis counts of a CURVE/MAP, MATRIX_DIM of a VAL_BLK."""
        if self.kind in ("VALUE",):
            return ()
        if self.kind in ("VAL_BLK", "ASCII"):
            return self.obj.shape
        return self.counts

    def with_counts(self, counts: Mapping[str, int]) -> "ResolvedLayout":
        """The object placed with other numbers of points (axis -> count), as writing them will
        make it; the axis objects it uses stay as they are."""
        fields, _ = self.plan._place(counts, reserve_max=self.plan.static)
        return ResolvedLayout(self.plan, tuple(fields), tuple(counts[axis.name] for axis in self.plan.axes),
                              self.references)

    def field(self, keyword: str, axis: str | None = None) -> Field | None:
        return next((f for f in self.fields if f.keyword == keyword and f.axis == axis), None)

    def span(self) -> Span:
        return Span(self.address, self.size, self.extension)

    def spans(self) -> list[Span]:
        """This object's bytes and those of the axis objects it uses (each once)."""
        spans = [self.span()]
        for reference in self.references.values():
            spans.extend(reference.spans())
        return list(dict.fromkeys(spans))

    def decode(self, data: Mapping[Span, bytes] | MemoryBytes) -> "CalValue":
        """The physical value from the bytes of :meth:`spans` (see :mod:`workbench.calib.codec`)."""
        from workbench.calib.codec import decode

        return decode(self, MemoryBytes(data))

    def encode(self, value: Any, current: Mapping[Span, bytes] | None = None) -> list[ByteEdit]:
        """The byte edits that write ``value`` (a CalValue, or the bare value/array/text);
        ``current``: the bytes of :meth:`spans` now, to write only what changes and keep the other
        bits of a BIT_MASK (required then). See :mod:`workbench.calib.codec`."""
        from workbench.calib.codec import encode

        return encode(self, value, MemoryBytes(current) if current is not None else None)
