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

What is refused, with the position: a typedef that does not exist, a component offset beyond its structure's
size, a structure that contains itself, anything reached through a pointer (ADDRESS_TYPE), an array of curves,
maps or axes (their size is the record layout's, not known here).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Mapping
from dataclasses import fields, replace
from typing import TYPE_CHECKING, NamedTuple

from workbench.a2l.objects import (
    AxisPts,
    Blob,
    Characteristic,
    Instance,
    Measurement,
    Overwrite,
    StructureComponent,
)
from workbench.errors import A2lParseError

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument

__all__ = ["LEAF_KINDS", "TYPEDEF_KINDS", "Placed", "expand_instance", "place", "without_indices"]

LEAF_KINDS = {"TYPEDEF_MEASUREMENT": "MEASUREMENT", "TYPEDEF_CHARACTERISTIC": "CHARACTERISTIC",
              "TYPEDEF_AXIS": "AXIS_PTS", "TYPEDEF_BLOB": "BLOB"}
TYPEDEF_KINDS = tuple(LEAF_KINDS) + ("TYPEDEF_STRUCTURE",)
_ARRAYS = ("VALUE", "VAL_BLK")  # characteristic types MATRIX_DIM on a component turns into one VAL_BLK


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


def expand_instance(doc: A2lDocument, instance: Instance, typedef_kinds: Mapping[str, str], get: Get
                    ) -> tuple[dict[str, Placed], dict[str, A2lParseError]]:
    """The objects ``instance`` stands for, by name, in the structure's order; and the components left out, by
    their name without indices (``inst.arr.ptr``), with why (an error at the reference or offset).

    :raises A2lParseError: the instance itself cannot be placed (see the module's docstring).
    """
    walk = _Walk(doc, instance, typedef_kinds, get)
    walk.walk(instance.name, instance.typedef, instance, instance.address, instance.matrix_dim, instance.layout, ())
    return walk.found, walk.left_out


class _Walk:
    def __init__(self, doc, instance: Instance, typedef_kinds: Mapping[str, str], get: Get):
        self.doc, self.instance, self.typedef_kinds, self.get = doc, instance, typedef_kinds, get
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
                              "supported (the pointer's target is known only at run time)")
        path = name[len(self.instance.name):].lstrip(".")
        if kind != "TYPEDEF_STRUCTURE":
            self._check_leaf(holder, kind, typedef, dims)
            self.found[name] = Placed(self.instance.name, kind, typedef, address, path, dims, layout)
            return
        if typedef in chain:
            raise self._error(holder, "TYPEDEF_STRUCTURE contains itself: " + " -> ".join(chain + (typedef,)),
                              "typedef")
        structure = self.get("TYPEDEF_STRUCTURE", typedef)
        if structure.address_type not in (None, "DIRECT"):
            raise self._error(holder, f"TYPEDEF_STRUCTURE {typedef} is reached through a pointer (ADDRESS_TYPE "
                              f"{structure.address_type}): not supported")
        for index in itertools.product(*(range(d) for d in dims)):
            element = name + "".join(f"[{i}]" for i in index)
            base = address + _flat(index, dims) * structure.size
            for component in structure.components:
                inner = f"{element}.{component.name}"
                try:
                    if structure.size and component.offset >= structure.size:
                        raise self._error(component, f"offset {component.offset:#x} is beyond the size of "
                                          f"TYPEDEF_STRUCTURE {typedef} ({structure.size:#x} bytes)", "offset")
                    self.walk(inner, component.typedef, component, base + component.offset, component.matrix_dim,
                              component.layout, chain + (typedef,))
                except A2lParseError as error:  # the component is left out, the rest of the instance placed
                    self.left_out.setdefault(without_indices(inner), error)

    def _check_leaf(self, holder, kind: str, typedef: str, dims: tuple[int, ...]) -> None:
        if not dims or kind in ("TYPEDEF_MEASUREMENT", "TYPEDEF_BLOB"):
            return
        if kind == "TYPEDEF_CHARACTERISTIC" and self.get(kind, typedef).type in _ARRAYS:
            return
        shown = getattr(self.get(kind, typedef), "type", "AXIS")
        raise self._error(holder, f"an array (MATRIX_DIM) of {shown} typedef {typedef} is not supported", "typedef")

    def _error(self, holder, message: str, field: str | None = None) -> A2lParseError:
        if isinstance(holder, Instance):
            label = f"INSTANCE {holder.name}"
        else:
            label = f"INSTANCE {self.instance.name}: STRUCTURE_COMPONENT {holder.name}"
        token = (holder.ref_tokens or {}).get(field) if field else None
        if token is None:
            return A2lParseError(f"{label}: {message}", *(holder.location or (self.doc.name, 0, 0)))
        return self.doc.error(f"{label}: {message}", token)


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
