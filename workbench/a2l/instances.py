"""INSTANCEs as the objects they stand for (ASAP2 1.7 typedefs).

An INSTANCE places a typedef at an address. A TYPEDEF_MEASUREMENT, _CHARACTERISTIC, _AXIS or _BLOB makes one
object named as the instance; a TYPEDEF_STRUCTURE makes one object per component, named as ASAP2 1.7, CANape
and INCA name them: ``inst.member``, ``inst.sub.member``, and for an array (MATRIX_DIM on the instance or on a
structure component) ``inst[2].member``, ``inst.sub[1][0].member``. A component's address is the instance's plus
its STRUCTURE_COMPONENT offset; element ``i`` of an array of structures lies ``i`` structure sizes further
(row-major). MATRIX_DIM on a leaf makes one array object: a measurement of that shape, a VALUE characteristic a
VAL_BLK. OVERWRITE blocks change one component's conversion, limits, format or unit in this instance only;
``THIS.x`` in a component's axis names its sibling ``x``. The objects take the instance's address extension,
READ_WRITE, CALIBRATION_ACCESS and IF_DATA (the model hands out the INSTANCE's block for them).

MATRIX_DIM on a CURVE, MAP, CUBOID ... or an axis typedef makes one object per element (``inst[1]``,
``inst.curves[0][2]``), each its record layout's size further (at MAX_AXIS_POINTS, as a C struct reserves it).

Two kinds of what cannot be placed, each with its position; only that part is left out: an error in the file
(:class:`~workbench.errors.A2lParseError`: a typedef that does not exist, a component that reaches beyond its
structure's size, a structure that contains itself) and what the file may say but the workbench does not
support (:class:`NotSupported`: anything reached through a pointer, ADDRESS_TYPE, whose target is known only at
run time; an array of objects whose RECORD_LAYOUT size cannot be told).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Mapping
from dataclasses import fields, replace
from typing import TYPE_CHECKING, NamedTuple

from workbench.a2l.datatypes import DATATYPES
from workbench.a2l.objects import (
    Alignments,
    AxisPts,
    Blob,
    Characteristic,
    Instance,
    Measurement,
    Overwrite,
    RecordLayout,
    StructureComponent,
    TypedefStructure,
)
from workbench.errors import A2lParseError, UnknownSymbolError

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument

__all__ = ["LEAF_KINDS", "TYPEDEF_KINDS", "NotSupported", "Placed", "TypedefSizes", "expand_instance", "place",
           "without_indices"]

LEAF_KINDS = {"TYPEDEF_MEASUREMENT": "MEASUREMENT", "TYPEDEF_CHARACTERISTIC": "CHARACTERISTIC",
              "TYPEDEF_AXIS": "AXIS_PTS", "TYPEDEF_BLOB": "BLOB"}
TYPEDEF_KINDS = tuple(LEAF_KINDS) + ("TYPEDEF_STRUCTURE",)
_ARRAYS = ("VALUE", "VAL_BLK")  # characteristic types MATRIX_DIM on a component turns into one VAL_BLK
_ONE_ELEMENT = ("NO_AXIS_PTS", "SRC_ADDR", "RIP_ADDR", "SHIFT_OP", "OFFSET", "DIST_OP", "IDENTIFICATION")
_RESERVED = {"BYTE": 1, "WORD": 2, "LONG": 4}
_POINTER_SIZES = {"PBYTE": 1, "PWORD": 2, "PLONG": 4, "PLONGLONG": 8}


class NotSupported(A2lParseError):
    """What an A2L may say but the workbench cannot place (a pointer, a record layout of unknown size): not an
    error in the file; only the objects concerned are left out."""

    instance = ""  # the INSTANCE concerned


class Placed(NamedTuple):
    """One object an INSTANCE stands for: which typedef makes it, where it is."""

    instance: str
    typedef_kind: str  # TYPEDEF_MEASUREMENT ...
    typedef: str
    address: int
    path: str  # the name inside the instance ("" for the instance itself, "lookup.values", "[2].x")
    dims: tuple[int, ...] = ()  # MATRIX_DIM the instance or its component adds to the leaf
    layout: str | None = None  # ROW_DIR / COLUMN_DIR of that array

    @property
    def kind(self) -> str:
        return LEAF_KINDS[self.typedef_kind]


Get = Callable[[str, str], object]  # (block kind, name) -> the object the model reads


class TypedefSizes:
    """The bytes one object of a typedef takes: a TYPEDEF_STRUCTURE's stated size, a measurement's data type
    times its shape, a BLOB's size, a characteristic's or axis' RECORD_LAYOUT at MAX_AXIS_POINTS (what a C
    struct reserves; items aligned as MOD_COMMON or the layout says). None: not known (a layout item whose size
    depends on more than the layout, e.g. AXIS_RESCALE)."""

    def __init__(self, get: Get, typedef_kinds: Mapping[str, str], alignments: Alignments):
        self.get, self.typedef_kinds, self.alignments = get, typedef_kinds, alignments
        self._sizes: dict[str, int | None] = {}

    def of(self, typedef: str) -> int | None:
        if typedef not in self._sizes:
            kind = self.typedef_kinds.get(typedef)
            try:
                self._sizes[typedef] = None if kind is None else self._size(kind, self.get(kind, typedef))
            except (A2lParseError, UnknownSymbolError):  # a record layout missing: check names it
                self._sizes[typedef] = None
        return self._sizes[typedef]

    def _size(self, kind: str, template) -> int | None:
        if kind == "TYPEDEF_STRUCTURE" or isinstance(template, Blob):
            return template.size
        if isinstance(template, Measurement):
            return DATATYPES[template.datatype][0] * math.prod(template.shape) if template.datatype in DATATYPES \
                else None
        layout: RecordLayout = self.get("RECORD_LAYOUT", template.record_layout)
        if isinstance(template, AxisPts):
            points, values = {"X": template.max_axis_points}, 1
        else:
            points = {axis.axis: axis.max_axis_points for axis in template.axes}
            values = math.prod(template.shape) if template.type in ("VAL_BLK", "ASCII", *_LOOKUPS) else 1
        alignments = layout.alignments_over(self.alignments)
        offset = 0
        for entry in sorted((e for e in layout.entries if e.position is not None), key=lambda e: e.position):
            if entry.keyword == "RESERVED":
                size, count = _RESERVED.get(entry.datatype), 1
            else:
                size = DATATYPES.get(entry.datatype, (None,))[0]
                count = values if entry.keyword == "FNC_VALUES" else points.get(entry.axis) \
                    if entry.keyword == "AXIS_PTS" else 1 if entry.keyword in _ONE_ELEMENT else None
            if size is None or count is None:
                return None
            offset += -offset % max(alignments.of(entry.datatype or ""), 1) + size * count
        return offset


_LOOKUPS = ("CURVE", "MAP", "CUBOID", "CUBE_4", "CUBE_5")


def expand_instance(doc: A2lDocument, instance: Instance, sizes: TypedefSizes
                    ) -> tuple[dict[str, Placed], dict[str, A2lParseError]]:
    """The objects ``instance`` stands for, by name, in the structure's order; and the components left out, by
    their name without indices (``inst.arr.ptr``), with why (an error at the reference or offset, or
    :class:`NotSupported`).

    :raises A2lParseError: the instance itself cannot be placed (see the module's docstring).
    """
    walk = _Walk(doc, instance, sizes)
    walk.walk(instance.name, instance.typedef, instance, instance.address, instance.matrix_dim, instance.layout, ())
    return walk.found, walk.left_out


class _Walk:
    def __init__(self, doc, instance: Instance, sizes: TypedefSizes):
        self.doc, self.instance, self.sizes = doc, instance, sizes
        self.typedef_kinds, self.get = sizes.typedef_kinds, sizes.get
        self.found: dict[str, Placed] = {}
        self.left_out: dict[str, A2lParseError] = {}

    def walk(self, name: str, typedef: str, holder: Instance | StructureComponent, address: int,
             dims: tuple[int, ...], layout: str | None, chain: tuple[str, ...]) -> None:
        kind = self.typedef_kinds.get(typedef)
        if kind is None:
            from workbench.a2l.model import closest_names

            close = closest_names(typedef, self.typedef_kinds)
            hint = f" (did you mean {', '.join(close)}?)" if close else ""
            raise self._error(holder, f"typedef {typedef} is not defined{hint}", "typedef")  # as a2l check says
        if holder.address_type not in (None, "DIRECT"):
            raise self._error(holder, f"reached through a pointer (ADDRESS_TYPE {holder.address_type}): not "
                              "supported by the workbench (the pointer's target is known only at run time)",
                              cls=NotSupported)
        path = name[len(self.instance.name):].lstrip(".")
        if kind != "TYPEDEF_STRUCTURE":
            if dims and self._one_per_element(kind, typedef):
                stride = self.sizes.of(typedef)
                if stride is None:
                    raise self._error(holder, f"an array (MATRIX_DIM) of typedef {typedef}: the size of its "
                                      "RECORD_LAYOUT is not supported by the workbench", "typedef", NotSupported)
                for index in itertools.product(*(range(d) for d in dims)):
                    element = name + "".join(f"[{i}]" for i in index)
                    self.found[element] = Placed(self.instance.name, kind, typedef,
                                                 address + _flat(index, dims) * stride,
                                                 element[len(self.instance.name):].lstrip("."))
                return
            self.found[name] = Placed(self.instance.name, kind, typedef, address, path, dims, layout)
            return
        if typedef in chain:
            raise self._error(holder, "TYPEDEF_STRUCTURE contains itself: " + " -> ".join(chain + (typedef,)),
                              "typedef")
        structure = self.get("TYPEDEF_STRUCTURE", typedef)
        if structure.address_type not in (None, "DIRECT"):
            raise self._error(holder, f"TYPEDEF_STRUCTURE {typedef} is reached through a pointer (ADDRESS_TYPE "
                              f"{structure.address_type}): not supported by the workbench", cls=NotSupported)
        for index in itertools.product(*(range(d) for d in dims)):
            element = name + "".join(f"[{i}]" for i in index)
            base = address + _flat(index, dims) * structure.size
            for component in structure.components:
                inner = f"{element}.{component.name}"
                try:
                    beyond = component.typedef not in chain + (typedef,) and component_beyond(structure, component,
                                                                                              self.sizes)
                    if beyond:
                        raise self._error(component, beyond, "offset")
                    self.walk(inner, component.typedef, component, base + component.offset, component.matrix_dim,
                              component.layout, chain + (typedef,))
                except A2lParseError as error:  # the component is left out, the rest of the instance placed
                    self.left_out.setdefault(without_indices(inner), error)

    def _one_per_element(self, kind: str, typedef: str) -> bool:
        """Whether MATRIX_DIM on this leaf makes one object per element (curves, maps, axes), not one array."""
        return kind == "TYPEDEF_AXIS" or (kind == "TYPEDEF_CHARACTERISTIC"
                                          and self.get(kind, typedef).type not in _ARRAYS)

    def _error(self, holder, message: str, field: str | None = None, cls=A2lParseError) -> A2lParseError:
        if isinstance(holder, Instance):
            label = f"INSTANCE {holder.name}"
        else:
            label = f"INSTANCE {self.instance.name}: STRUCTURE_COMPONENT {holder.name}"
        token = (holder.ref_tokens or {}).get(field) if field else None
        where = (holder.location or (self.doc.name, 0, 0)) if token is None else self.doc.token_position(token)
        error = cls(f"{label}: {message}", *where)
        error.instance = self.instance.name
        return error


def component_beyond(structure: TypedefStructure, component: StructureComponent, sizes: TypedefSizes) -> str | None:
    """Why ``component`` reaches beyond its structure's size (its offset, plus its size where known), or None."""
    if not structure.size:
        return None
    pointer = component.address_type not in (None, "DIRECT")
    size = _POINTER_SIZES.get(component.address_type) if pointer else sizes.of(component.typedef)
    end = component.offset + (size or 1) * math.prod(component.matrix_dim)
    if component.offset < structure.size and (size is None or end <= structure.size):
        return None
    what = f"offset {component.offset:#x}" + (f" + {end - component.offset} bytes" if size else "")
    return f"{what} is beyond the size of TYPEDEF_STRUCTURE {structure.name} ({structure.size:#x} bytes)"


def _flat(index: tuple[int, ...], dims: tuple[int, ...]) -> int:
    """The row-major position of ``index`` in an array of ``dims``."""
    flat = 0
    for i, d in zip(index, dims):
        flat = flat * d + i
    return flat


def place(template, name: str, placed: Placed, instance: Instance,
          membership: tuple[tuple[str, ...], tuple[str, ...]]):
    """The object ``placed`` stands for: ``template`` (the typedef read as an object without an address) at
    its address, named ``name``, with what the instance adds (address extension, access, its OVERWRITEs)."""
    functions, groups = membership
    changes: dict = {
        "name": name, "address": placed.address, "address_extension": instance.address_extension,
        "long_identifier": template.long_identifier or instance.long_identifier,
        "display_identifier": instance.display_identifier if not placed.path else None, "symbol_link": None,
        "functions": tuple(dict.fromkeys(functions + instance.functions)),
        "groups": tuple(dict.fromkeys(groups + instance.groups)), "location": instance.location,
    }
    dims = placed.dims
    if isinstance(template, Measurement):
        changes.update(read_write=template.read_write or instance.read_write,
                       max_refresh=instance.max_refresh or template.max_refresh)
        if dims:
            changes.update(matrix_dim=dims + template.shape, array_size=None,
                           layout=placed.layout or template.layout)
    elif isinstance(template, Characteristic):
        if instance.calibration_access:
            changes["calibration_access"] = instance.calibration_access
        if dims:
            changes.update(type="VAL_BLK", matrix_dim=dims + (template.shape if template.type == "VAL_BLK" else ()),
                           number=None)
        parent = name.rpartition(".")[0]
        changes["axes"] = tuple(replace(axis, **{field: f"{parent}.{value[5:]}" for field in
                                                 ("axis_pts_ref", "curve_axis_ref", "input_quantity")
                                                 if (value := getattr(axis, field)) and value.startswith("THIS.")})
                                for axis in template.axes)
    elif isinstance(template, AxisPts):
        if instance.calibration_access:
            changes["calibration_access"] = instance.calibration_access
    elif isinstance(template, Blob) and dims:
        changes["size"] = template.size * math.prod(dims)
    return _overwritten(replace(template, **changes), instance, placed)


_OVERWRITTEN = ("conversion", "extended_limits", "format", "input_quantity", "monotony", "phys_unit")


def _overwritten(obj, instance: Instance, placed: Placed):
    """``obj`` with the instance's OVERWRITEs that name its component applied."""
    for overwrite in instance.overwrites:
        if not _names(overwrite, instance.name, placed.path):
            continue
        if overwrite.axis_number == 0:
            obj = replace(obj, **_changes(obj, overwrite))
        elif isinstance(obj, Characteristic) and overwrite.axis_number <= len(obj.axes):
            axes = list(obj.axes)
            axes[overwrite.axis_number - 1] = replace(axes[overwrite.axis_number - 1],
                                                      **_changes(axes[overwrite.axis_number - 1], overwrite))
            obj = replace(obj, axes=tuple(axes))
    return obj


def _names(overwrite: Overwrite, instance: str, path: str) -> bool:
    """Whether an OVERWRITE's name is this component: its path in the instance, with or without the
    instance's name before it; without indices it names the component in every element of an array."""
    wanted = overwrite.name[len(instance):].lstrip(".") if overwrite.name.startswith(instance) else overwrite.name
    return wanted == path or ("[" not in wanted and without_indices(path) == wanted)


def without_indices(path: str) -> str:
    """``path`` without its array indices (``a[2].b[0][1].c`` -> ``a.b.c``)."""
    out, depth = [], 0
    for char in path:
        depth += char == "["
        if not depth:
            out.append(char)
        depth -= char == "]"
    return "".join(out).lstrip(".")


def _changes(target, overwrite: Overwrite) -> dict:
    names = {f.name for f in fields(target)}
    changes = {key: getattr(overwrite, key) for key in _OVERWRITTEN
               if key in names and getattr(overwrite, key) is not None}
    if overwrite.limits is not None:
        changes.update(lower_limit=overwrite.limits[0], upper_limit=overwrite.limits[1])
    return changes
