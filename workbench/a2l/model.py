"""The typed, read-only view of one A2L MODULE: objects by name, built on first access.

::

    doc = load_a2l("assets/FLCU.a2l")
    model = doc.model()                          # the only MODULE (or doc.model("name"))
    thr = model.characteristic("xsSWITCH_TANK_THR")
    thr.address, thr.upper_limit, model.datatype_of(thr), model.unit_of(thr)
    model.conversion(thr).to_physical(raw)      # see workbench.a2l.compu
    [c.name for c in model.find("xs*", kind="CHARACTERISTIC")]

Opening a model indexes the MODULE's names with the reader's vectorized helpers (a 10 MB file:
tens of milliseconds); an object is read from its tokens the first time it is asked for and
kept. Names follow ASAP2's namespaces: MEASUREMENT, CHARACTERISTIC, AXIS_PTS, BLOB and
INSTANCE share one ("objects"); COMPU_METHOD, RECORD_LAYOUT, FUNCTION, GROUP, UNIT each have
their own; COMPU_TAB, COMPU_VTAB and COMPU_VTAB_RANGE share one. An unknown name raises
:class:`UnknownSymbolError` naming the closest known ones; a reference to a name the module does
not define raises :class:`A2lParseError` at the reference.
"""

from __future__ import annotations

import difflib
import fnmatch
import re
from collections.abc import Iterable, Iterator
from typing import TYPE_CHECKING, NamedTuple, Union

import numpy as np

from workbench.a2l.display_format import format_parts
from workbench.a2l.instances import (
    TYPEDEF_KINDS,
    NotSupported,
    Placed,
    TypedefSizes,
    expand_instance,
    place,
    without_indices,
)
from workbench.a2l.objects import (
    NO_COMPU_METHOD, AxisDescr, AxisPts, Blob, Characteristic, CompuMethod, CompuTab, CompuVtab, CompuVtabRange,
    Function, Group, Instance, Location, Measurement, ModCommon, RecordLayout, Unit,
)
from workbench.a2l.readers import READERS, read_mod_common
from workbench.errors import A2lParseError, InputError, UnknownSymbolError, WorkbenchError

if TYPE_CHECKING:
    from workbench.a2l.compu import Conversion
    from workbench.a2l.document import A2lDocument, Block, EpkAddress

_AXIS_LETTERS = "xyz"

__all__ = ["A2lModel", "OBJECT_KINDS", "ObjectSummary", "axis_decimals", "closest_names", "is_glob", "name_pattern",
           "value_decimals"]

OBJECT_KINDS = ("CHARACTERISTIC", "MEASUREMENT", "AXIS_PTS", "BLOB", "INSTANCE")  # the shared "objects" namespace
_TABLE_KINDS = ("COMPU_TAB", "COMPU_VTAB", "COMPU_VTAB_RANGE")
_INDEXED = OBJECT_KINDS + _TABLE_KINDS + TYPEDEF_KINDS + ("COMPU_METHOD", "RECORD_LAYOUT", "FUNCTION", "GROUP", "UNIT")
_ADDRESSED = OBJECT_KINDS[:4]  # what has an address; an INSTANCE stands for objects of these kinds
_LISTS = {  # name-list blocks: which kind of owner names which kind of member
    "FUNCTION": ("DEF_CHARACTERISTIC", "REF_CHARACTERISTIC", "IN_MEASUREMENT", "OUT_MEASUREMENT", "LOC_MEASUREMENT"),
    "GROUP": ("REF_CHARACTERISTIC", "REF_MEASUREMENT"),
}
_SUGGESTIONS = 3
_GLOB_CHARACTERS = frozenset("*?[")

# positional parameter index (name = 0) of what a summary shows, per kind
_SUMMARY_SLOTS = {
    "CHARACTERISTIC": {"long_identifier": 1, "type": 2, "address": 3, "conversion": 6},
    "MEASUREMENT": {"long_identifier": 1, "type": 2, "conversion": 3},
    "AXIS_PTS": {"long_identifier": 1, "address": 2, "conversion": 6},
    "BLOB": {"long_identifier": 1, "address": 2},
}


class ObjectSummary(NamedTuple):
    """One line of a listing (:meth:`A2lModel.summaries`)."""

    name: str
    kind: str  # CHARACTERISTIC, MEASUREMENT, AXIS_PTS, BLOB
    type: str  # a characteristic's type (VALUE, MAP ...), a measurement's data type, else the kind
    long_identifier: str
    conversion: str  # the COMPU_METHOD name ("" for a blob)
    unit: str
    address: int | None


A2lObject = Union[Characteristic, Measurement, AxisPts, Blob]
Referrer = Union[Characteristic, Measurement, AxisPts, AxisDescr, CompuMethod]


class A2lModel:
    """One MODULE of an :class:`A2lDocument` as objects. Get it with ``doc.model(module=None)``.

    :raises A2lParseError: (when built) the document has no MODULE, or several and none is named.
    """

    def __init__(self, doc: "A2lDocument", module: str | None = None):
        self.doc = doc
        self.module: Block = doc.module(module)
        self.name: str = self.module.name or ""
        self.mod_common: ModCommon = read_mod_common(doc, self.module.first("MOD_COMMON"))
        self._names: dict[str, list[str]] = {}  # kind -> names in document order
        self._blocks: dict[str, dict[str, int]] = {}  # kind -> name -> block index (the first of a duplicate)
        self._built: dict[tuple[str, str], object] = {}
        self._conversions: dict[str, "Conversion"] = {}
        self._members: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] | None = None
        self._placed: dict[str, Placed] | None = None  # the objects INSTANCEs stand for, on first need
        self._placed_names: dict[str, list[str]] = {}  # kind -> those names, in document order
        self._instance_errors: dict[str, A2lParseError] = {}  # INSTANCE or component (no indices) -> why left out
        self._sizes: TypedefSizes | None = None
        self._index()

    def __repr__(self) -> str:
        return f"<A2lModel {self.name} of {self.doc.name}: {len(self)} objects>"

    # -- the index -----------------------------------------------------------------------
    def _index(self) -> None:
        doc = self.doc
        table = doc.blocks
        children = table.children(self.module.index)
        ids = table.keyword_id[children]
        for kind in _INDEXED:
            if kind not in table.keyword_names:
                self._names[kind], self._blocks[kind] = [], {}
                continue
            rows = children[ids == table.keyword_names.index(kind)]
            names = doc.block_names(rows)
            rows_list = rows.tolist()
            self._names[kind] = [name for name in names if name is not None]
            blocks: dict[str, int] = {}
            for name, row in zip(reversed(names), reversed(rows_list)):  # the first definition wins
                if name is not None:
                    blocks[name] = row
            self._blocks[kind] = blocks
        self._object_kind = {name: kind for kind in reversed(OBJECT_KINDS) for name in self._blocks[kind]}
        self._table_kind = {name: kind for kind in reversed(_TABLE_KINDS) for name in self._blocks[kind]}
        self._typedef_kind = {name: kind for kind in reversed(TYPEDEF_KINDS) for name in self._blocks[kind]}

    def _instances(self) -> dict[str, Placed]:
        """The objects the INSTANCEs stand for (:mod:`workbench.a2l.instances`), placed on first need; an
        INSTANCE that cannot be placed is kept with its error (raised when one of its names is asked for)."""
        if self._placed is None:
            placed: dict[str, Placed] = {}
            for name in dict.fromkeys(self._names["INSTANCE"]):  # document order
                try:
                    found, left_out = expand_instance(self.doc, self._get("INSTANCE", name), self.typedef_sizes())
                except A2lParseError as error:
                    self._instance_errors[name] = error
                    continue
                self._instance_errors.update(left_out)
                for object_name, where in found.items():  # a plain object of the same name wins
                    if self._object_kind.get(object_name, "INSTANCE") == "INSTANCE":
                        placed.setdefault(object_name, where)
            self._placed = placed
            self._placed_names = {kind: [name for name, where in placed.items() if where.kind == kind]
                                  for kind in _ADDRESSED}
        return self._placed

    def _placed_of(self, name: str) -> Placed | None:
        return self._instances().get(name) if self._blocks["INSTANCE"] else None

    def _of_kind(self, kind: str) -> list[str]:
        """The names of one object kind, the objects INSTANCEs stand for after the plain ones."""
        if kind in _ADDRESSED and self._blocks["INSTANCE"]:
            self._instances()
            return self._names[kind] + self._placed_names[kind]
        return self._names[kind]

    def names(self, kind: str | None = None) -> list[str]:
        """Names in document order: of one block kind (``"CHARACTERISTIC"``, ``"COMPU_METHOD"`` ...),
        or (None) of every object that has an address (characteristics, measurements, axis points, blobs)."""
        if kind is None:
            return [name for kind_ in _ADDRESSED for name in self._of_kind(kind_)]
        if kind not in self._names:
            raise ValueError(f"unknown kind {kind!r}; expected one of {', '.join(_INDEXED)}")
        return list(self._of_kind(kind))

    def kind_of(self, name: str) -> str:
        """The block keyword of an object (CHARACTERISTIC, MEASUREMENT, AXIS_PTS, BLOB, INSTANCE); an object an
        INSTANCE stands for (``inst.member``, or the instance of a measurement typedef itself) is of its kind.

        :raises UnknownSymbolError: no such object.
        :raises A2lParseError: the name belongs to an INSTANCE that cannot be placed (why, where).
        """
        kind = self._object_kind.get(name)
        if kind is None or kind == "INSTANCE":
            placed = self._placed_of(name)
            if placed is not None:
                return placed.kind
        if kind is None:
            bare = without_indices(name)
            for left_out, error in self._instance_errors.items():
                if bare == left_out or bare.startswith(left_out + "."):
                    raise error
            raise self._unknown(name, {**self._object_kind, **(self._placed or {})}, "objects")
        return kind

    def __contains__(self, name: object) -> bool:
        return name in self._object_kind or self._placed_of(name) is not None

    def __len__(self) -> int:
        return len(self.names())

    def __iter__(self) -> Iterator[A2lObject]:
        """Every characteristic, measurement, axis points and blob object (with those INSTANCEs stand for),
        kind by kind in document order."""
        for kind in _ADDRESSED:
            for name in self._of_kind(kind):
                yield self._get(kind, name)

    def __getitem__(self, name: str) -> A2lObject:
        return self.object(name)

    # -- lookups ---------------------------------------------------------------------------
    def object(self, name: str) -> A2lObject:
        """The CHARACTERISTIC, MEASUREMENT, AXIS_PTS or BLOB called ``name``, also one an INSTANCE stands for.

        :raises UnknownSymbolError: no such object (the closest names suggested).
        :raises InputError: it names an INSTANCE of a structure (its components are the objects).
        :raises A2lParseError: it is malformed, or its INSTANCE cannot be placed.
        """
        kind = self.kind_of(name)
        if kind == "INSTANCE":
            if name in self._instance_errors:
                raise self._instance_errors[name]
            members = [member for member, where in self._instances().items() if where.instance == name]
            # an array of a CURVE/MAP/axis typedef is one object per element (convs[0], convs[1]), without members
            what = "a structure" if any("." in member[len(name):] for member in members) else "an array"
            raise InputError(f"INSTANCE {name} is {what}: name one of its {len(members)} objects ("
                             + ", ".join(members[:3]) + (" ..." if len(members) > 3 else "") + ")")
        return self._get(kind, name)

    def instance(self, name: str) -> Instance:
        """The INSTANCE block called ``name`` as read (its typedef, address, OVERWRITEs)."""
        return self._get("INSTANCE", name)

    def placed(self, name: str) -> Placed | None:
        """Where an object an INSTANCE stands for comes from (its instance, typedef, path); None for a plain one."""
        return None if self._object_kind.get(name, "INSTANCE") != "INSTANCE" else self._placed_of(name)

    def instance_errors(self) -> list[A2lParseError]:
        """The errors in the file that leave INSTANCEs, or components of them, out of the listings (a typedef that
        does not exist, a component beyond its structure, a structure that contains itself)."""
        self._instances()
        return [error for error in self._instance_errors.values() if not isinstance(error, NotSupported)]

    def instance_limits(self) -> list[NotSupported]:
        """The INSTANCEs, or components of them, left out because the workbench does not support what they use
        (a pointer, ADDRESS_TYPE; an array of objects whose record layout's size it cannot tell)."""
        self._instances()
        return [error for error in self._instance_errors.values() if isinstance(error, NotSupported)]

    def typedef(self, name: str):
        """A TYPEDEF_STRUCTURE, or a TYPEDEF_MEASUREMENT, _CHARACTERISTIC, _AXIS, _BLOB read as its object without
        an address.

        :raises UnknownSymbolError: no typedef of that name.
        """
        kind = self._typedef_kind.get(name)
        if kind is None:
            raise self._unknown(name, self._typedef_kind, "typedefs")
        return self._get(kind, name)

    def typedef_sizes(self) -> TypedefSizes:
        """The bytes an object of each typedef takes (:class:`~workbench.a2l.instances.TypedefSizes`)."""
        if self._sizes is None:
            self._sizes = TypedefSizes(self._get, self._typedef_kind, self.mod_common.alignments)
        return self._sizes

    def characteristic(self, name: str) -> Characteristic:
        return self._get("CHARACTERISTIC", name)

    def block(self, name: str) -> "Block":
        """The block an object is read from (for what the model does not interpret, e.g. its IF_DATA); for an object
        an INSTANCE stands for, the INSTANCE's (whose IF_DATA, e.g. its DAQ events, applies to it)."""
        row = self._blocks[self.kind_of(name)].get(name)
        if row is None:
            row = self._blocks["INSTANCE"][self._instances()[name].instance]
        return self.doc.block(row)

    def measurement(self, name: str) -> Measurement:
        return self._get("MEASUREMENT", name)

    def axis_pts(self, name: str) -> AxisPts:
        return self._get("AXIS_PTS", name)

    def blob(self, name: str) -> Blob:
        return self._get("BLOB", name)

    def compu_method(self, name: str) -> CompuMethod:
        return self._get("COMPU_METHOD", name)

    def compu_table(self, name: str) -> CompuTab | CompuVtab | CompuVtabRange:
        """The COMPU_TAB, COMPU_VTAB or COMPU_VTAB_RANGE called ``name`` (one namespace)."""
        kind = self._table_kind.get(name)
        if kind is None:
            raise self._unknown(name, self._table_kind, "conversion tables")
        return self._get(kind, name)

    def record_layout(self, name: str) -> RecordLayout:
        return self._get("RECORD_LAYOUT", name)

    def function(self, name: str) -> Function:
        return self._get("FUNCTION", name)

    def group(self, name: str) -> Group:
        return self._get("GROUP", name)

    def unit(self, name: str) -> Unit:
        return self._get("UNIT", name)

    def find(self, pattern: str, kind: str | tuple[str, ...] | None = None, *, regex: bool = False,
             ignore_case: bool = False) -> list[A2lObject]:
        """The objects whose name matches ``pattern``: a glob (``xs*``, ``zf?ANK*``) or, with ``regex``,
        a regular expression that must match the whole name. ``kind``: one block keyword or several
        (default: characteristics, measurements, axis points, blobs); document order per kind.

        :raises ValueError: a malformed regular expression.
        """
        kinds = _ADDRESSED if kind is None else (kind,) if isinstance(kind, str) else tuple(kind)
        matcher = name_pattern(pattern, regex=regex, ignore_case=ignore_case)
        return [self._get(kind_, name) for kind_ in kinds if kind_ in self._names for name in self._of_kind(kind_)
                if matcher.fullmatch(name)]

    def expand(self, names: Iterable[str], kind: str | tuple[str, ...] | None = None, *, what: str = "object"
               ) -> list[str]:
        """``names`` as the object names they stand for, in the order given, each once: a name stays (it must
        exist), a glob (:func:`is_glob`: ``xsPRV_*``, ``zf?ANK*``) becomes the names of ``kind`` it matches, in
        document order. The CLI's name arguments and datasets take names this way; the window's search uses the
        same glob rule (:func:`name_pattern`). An object's own name is that object even when it reads as a
        glob: ASAP2 names may hold ``[`` and ``]`` (``arr[3]``, an element as generators name it).

        :raises UnknownSymbolError: a name the module lacks (the closest suggested).
        :raises InputError: a glob that matches no object of ``kind`` (``what`` names them in the message).
        """
        found: list[str] = []
        for name in names:
            if is_glob(name) and name not in self:
                matches = [obj.name for obj in self.find(name, kind)]
                if not matches:
                    raise InputError(f"no {what} matches {name!r}")
                found += matches
            else:
                self.kind_of(name)
                found.append(name)
        return list(dict.fromkeys(found))

    def summaries(self, kind: str | tuple[str, ...] | None = None) -> list["ObjectSummary"]:
        """Name, kind, type, description, conversion, unit and address of every object of ``kind``
        (default: characteristics, measurements, axis points, blobs), read as columns from the tokens
        without building the objects: a listing of a 10 MB file's 65,000 objects costs a fraction of
        a second. Objects whose positional parameters are missing come from the full reader (which
        raises :class:`A2lParseError` at them)."""
        kinds = _ADDRESSED if kind is None else (kind,) if isinstance(kind, str) else tuple(kind)
        rows: list[ObjectSummary] = []
        for kind_ in kinds:
            rows.extend(self._summaries(kind_))
            if kind_ in _ADDRESSED and self._blocks["INSTANCE"]:  # few, built as objects
                rows.extend(self._summary_of(self._get(kind_, name)) for name in self._of_kind(kind_)[
                    len(self._names[kind_]):])
        return rows

    def _summaries(self, kind: str) -> list["ObjectSummary"]:
        from workbench.a2l.values import int_or_none, int_values

        doc = self.doc
        names = self._names[kind]
        blocks = np.array([self._blocks[kind][name] for name in names], dtype=np.int64)
        if not len(blocks):
            return []
        slots = _SUMMARY_SLOTS[kind]
        first = doc.blocks.begin[blocks] + 2
        complete = first + max(slots.values()) < doc.parameter_limits()[blocks]
        rows: list[ObjectSummary | None] = [None] * len(blocks)
        for row in np.flatnonzero(~complete).tolist():
            rows[row] = self._summary_of(self._get(kind, names[row]))
        good = np.flatnonzero(complete)
        texts = {field: doc.texts(first[good] + slot, quoted=field == "long_identifier")
                 for field, slot in slots.items() if field != "address"}
        if "address" in slots:
            address_tokens = first[good] + slots["address"]
        else:  # MEASUREMENT: the ECU_ADDRESS option
            found_blocks, found_tokens = doc.option_tokens(kind, "ECU_ADDRESS")
            by_block = dict(zip(found_blocks.tolist(), (found_tokens + 1).tolist()))
            address_tokens = np.array([by_block.get(block, -1) for block in blocks[good].tolist()], dtype=np.int64)
        addresses: list[int | None] = [None] * len(good)
        present = np.flatnonzero(address_tokens >= 0)
        if len(present):
            values, read = int_values(doc.data, doc.tokens.starts[address_tokens[present]],
                                      doc.tokens.ends[address_tokens[present]])
            for slot, value, ok, token in zip(present.tolist(), values.tolist(), read.tolist(),
                                              address_tokens[present].tolist()):
                addresses[slot] = value if ok else int_or_none(doc.raw(token))
        phys_blocks, phys_tokens = doc.option_tokens(kind, "PHYS_UNIT")
        phys_units = dict(zip(phys_blocks.tolist(), doc.texts(phys_tokens + 1, quoted=True)))
        conversions = texts.get("conversion", [""] * len(good))
        method_units = {name: self._method_unit(name) for name in set(conversions)}
        types = texts.get("type", [kind] * len(good))
        for i, row in enumerate(good.tolist()):
            block = int(blocks[row])
            unit = phys_units.get(block)
            rows[row] = ObjectSummary(names[row], kind, types[i], texts["long_identifier"][i], conversions[i],
                                      unit if unit is not None else method_units[conversions[i]], addresses[i])
        return rows

    def _summary_of(self, obj: A2lObject) -> "ObjectSummary":
        conversion = getattr(obj, "conversion", "")
        kind_type = getattr(obj, "type", None) or getattr(obj, "datatype", obj.kind)
        unit = "" if isinstance(obj, Blob) else getattr(obj, "phys_unit", None) or self._method_unit(conversion)
        return ObjectSummary(obj.name, obj.kind, kind_type, obj.long_identifier, conversion, unit, obj.address)

    def _method_unit(self, name: str) -> str:
        """A COMPU_METHOD's unit for listings ("" for none, an unknown name or a broken reference)."""
        if not name or name == NO_COMPU_METHOD or name not in self._blocks["COMPU_METHOD"]:
            return ""
        method = self.compu_method(name)
        if method.unit or not method.ref_unit or method.ref_unit not in self._blocks["UNIT"]:
            return method.unit
        return self.unit(method.ref_unit).display

    # -- references ------------------------------------------------------------------------
    def conversion(self, what: "str | Referrer") -> "Conversion":
        """The :class:`~workbench.a2l.compu.Conversion` of an object (its COMPU_METHOD) or of a
        COMPU_METHOD name (``NO_COMPU_METHOD``: the identity).

        :raises A2lParseError: the COMPU_METHOD (or its table) is not defined, at the reference.
        """
        from workbench.a2l.compu import conversion_for

        name = what if isinstance(what, str) else what.conversion
        found = self._conversions.get(name)
        if found is None:
            if name == NO_COMPU_METHOD:
                method = None
            elif isinstance(what, str):
                method = self.compu_method(name)
            else:
                method = self.resolve(what, "conversion", "COMPU_METHOD")
            table = None
            if method is not None and method.compu_tab_ref:
                table = self.resolve(method, "compu_tab_ref", "COMPU_TAB")
            found = self._conversions[name] = conversion_for(method, table, self._system_constants())
        return found

    def resolve(self, referrer: Referrer, field: str, kind: str, owner: str = ""):
        """The object that ``referrer.<field>`` names (``kind``: the block keyword it must be;
        ``COMPU_TAB`` stands for any conversion table, ``AXIS_PTS``/``CHARACTERISTIC`` for an object).
        ``owner`` names what holds the referrer in the error (``"CHARACTERISTIC m"`` for its AXIS_DESCR).

        :raises A2lParseError: at the reference when the name is not defined (closest names suggested).
        """
        name = getattr(referrer, field)
        if kind == "COMPU_TAB":
            known = self._table_kind
            if name in known:
                return self._get(known[name], name)
        else:
            known = self._blocks.get(kind, {})
            placed = self._placed_of(name) if kind in _ADDRESSED and name not in known else None
            if name in known or (placed is not None and placed.kind == kind):
                return self._get(kind, name)
        token = (referrer.ref_tokens or {}).get(field)
        where = (Location(*self.doc.token_position(token)) if token is not None else referrer.location
                 or Location(self.doc.name, 0, 0))
        if isinstance(referrer, AxisDescr):
            label = (f"{owner} " if owner else "") + f"AXIS_DESCR {referrer.axis}"
        else:
            label = f"{getattr(referrer, 'kind', 'COMPU_METHOD')} {referrer.name}"
        close = closest_names(name, known)
        hint = f" (did you mean {', '.join(close)}?)" if close else ""
        raise A2lParseError(f"{label}: {kind} {name!r} is not defined{hint}", *where)

    def record_layout_of(self, obj: Characteristic | AxisPts) -> RecordLayout:
        return self.resolve(obj, "record_layout", "RECORD_LAYOUT")

    def datatype_of(self, obj: A2lObject) -> str:
        """The element data type: a MEASUREMENT's own, a CHARACTERISTIC's FNC_VALUES, an AXIS_PTS' AXIS_PTS_X
        (from the record layout); ``"UBYTE"`` for a BLOB.

        :raises A2lParseError: the record layout is undefined or lacks that item.
        """
        if isinstance(obj, Measurement):
            return obj.datatype
        if isinstance(obj, Blob):
            return "UBYTE"
        layout = self.record_layout_of(obj)
        entry = layout.fnc_values if isinstance(obj, Characteristic) else layout.entry("AXIS_PTS", "X")
        if entry is None or entry.datatype is None:
            item = "FNC_VALUES" if isinstance(obj, Characteristic) else "AXIS_PTS_X"
            raise A2lParseError(f"RECORD_LAYOUT {layout.name} (used by {obj.kind} {obj.name}) has no {item}",
                                *(layout.location or Location(self.doc.name, 0, 0)))
        return entry.datatype

    def format_of(self, obj: "A2lObject | AxisDescr") -> str | None:
        """The display format: the object's FORMAT, else its COMPU_METHOD's (``"%8.3"``: width 8, 3
        decimals; :func:`workbench.a2l.display_format.format_parts` reads it); None for neither."""
        if getattr(obj, "format", None):
            return obj.format
        conversion = getattr(obj, "conversion", NO_COMPU_METHOD)
        if conversion == NO_COMPU_METHOD:
            return None
        return self.resolve(obj, "conversion", "COMPU_METHOD").format

    def unit_of(self, obj: "A2lObject | AxisDescr") -> str:
        """The physical unit to show: PHYS_UNIT, else the COMPU_METHOD's unit, else its REF_UNIT's display."""
        if getattr(obj, "phys_unit", None):
            return obj.phys_unit
        if isinstance(obj, Blob) or obj.conversion == NO_COMPU_METHOD:
            return ""
        method = self.resolve(obj, "conversion", "COMPU_METHOD")
        if method.unit or not method.ref_unit:
            return method.unit
        unit = self.resolve(method, "ref_unit", "UNIT")
        return unit.display

    def epk(self) -> str | None:
        return self.doc.epk(self.name)

    def addr_epk(self) -> int | None:
        """The first ADDR_EPK (GET_ID type 5's EPK; :meth:`epk_addresses` has every one)."""
        return self.doc.addr_epk(self.name)

    def epk_addresses(self) -> tuple[EpkAddress, ...]:
        """Every MOD_PAR ADDR_EPK in order with the MEMORY_SEGMENT (the part of the software) it lies in."""
        return self.doc.epk_addresses(self.name)

    def epk_parts(self) -> tuple[EpkAddress, ...]:
        """The ADDR_EPKs of the parts that keep an EPK of their own (empty: one EPK for the whole software)."""
        return self.doc.epk_parts(self.name)

    def memory_segments(self):
        return self.doc.memory_segments(self.name)

    # -- building ---------------------------------------------------------------------------
    def _get(self, kind: str, name: str):
        key = (kind, name)
        found = self._built.get(key)
        if found is None:
            row = self._blocks[kind].get(name)
            if row is not None:
                found = READERS[kind](self.doc, self.doc.block(row), self.mod_common, self.membership)
            else:
                placed = self._placed_of(name) if kind in _ADDRESSED else None
                if placed is None or placed.kind != kind:
                    raise self._unknown(name, self._blocks[kind], f"{kind} names")
                found = place(self._get(placed.typedef_kind, placed.typedef), name, placed,
                              self._get("INSTANCE", placed.instance), self.membership(name))
            self._built[key] = found
        return found

    def membership(self, name: str) -> tuple[tuple[str, ...], tuple[str, ...]]:
        """(FUNCTIONs, GROUPs) whose lists name ``name``, in document order. The reverse index of every list is built
        on the first call, in one pass: a listing of every object's functions costs that, not a FUNCTION built each."""
        if self._members is None:
            self._members = self._member_index()
        return self._members.get(name, ((), ()))

    def _member_index(self) -> dict[str, tuple[tuple[str, ...], tuple[str, ...]]]:
        doc = self.doc
        table = doc.blocks
        members: dict[str, tuple[list[str], list[str]]] = {}
        for slot, (owner_kind, list_kinds) in enumerate(_LISTS.items()):
            owners = self._blocks[owner_kind]
            if not owners:
                continue
            owner_names = {row: name for name, row in owners.items()}
            lists = np.sort(np.concatenate([table.having_keyword(list_kind) for list_kind in list_kinds]))
            for row in lists.tolist():  # the owners' lists in document order: a member's owners in theirs
                owner = owner_names.get(int(table.parent[row]))
                if owner is None:
                    continue
                for member in doc.texts(np.arange(table.begin[row] + 2, table.end[row])):
                    entry = members.setdefault(member, ([], []))
                    if owner not in entry[slot]:
                        entry[slot].append(owner)
        return {member: (tuple(functions), tuple(groups)) for member, (functions, groups) in members.items()}

    def _system_constants(self) -> dict[str, str]:
        mod_par = self.module.first("MOD_PAR")
        if mod_par is None:
            return {}
        return {self.doc.text(tokens[0]): self.doc.text(tokens[1])
                for tokens in mod_par.options("SYSTEM_CONSTANT") if len(tokens) >= 2}

    def _unknown(self, name: str, known, what: str) -> UnknownSymbolError:
        return UnknownSymbolError(name, f"{what} of {self.doc.name}", closest_names(name, known))


def axis_decimals(model, axis) -> int | None:
    """The decimals of an axis' points (an AXIS_DESCR): its FORMAT, else its AXIS_PTS' (a COM_AXIS), else its
    conversion's; the rule of every view that shows breakpoints (editor headers, heat map, 3D view, compare)."""
    shown = axis.format
    if not shown and axis.axis_pts_ref:
        try:
            shown = model.axis_pts(axis.axis_pts_ref).format
        except (WorkbenchError, KeyError):
            shown = None
    return format_parts(shown or model.format_of(axis))[1]


def value_decimals(model, name: str, where: str = "value") -> int | None:
    """The decimals the views show an element of calibration ``name`` with (its FORMAT, else its conversion's), as
    a :class:`~workbench.calib.dataset.DatasetDiff` names the element: ``value[2, 1]`` the values', ``x[4]`` or
    ``y`` an axis' points (:func:`axis_decimals`). None: no such object in the A2L, or no format."""
    try:
        obj = model.object(name)
        axis = _AXIS_LETTERS.find(where[:1]) if where[1:2] in ("", "[", ".") else -1
        axes = getattr(obj, "axes", ())
        return axis_decimals(model, axes[axis]) if 0 <= axis < len(axes) else format_parts(model.format_of(obj))[1]
    except (WorkbenchError, KeyError):
        return None


def is_glob(text: str) -> bool:
    """Whether ``text`` is a glob (holds ``*``, ``?`` or ``[``) rather than a name: one rule for every face."""
    return not _GLOB_CHARACTERS.isdisjoint(text)


def name_pattern(pattern: str, *, regex: bool = False, ignore_case: bool = False) -> re.Pattern:
    """The compiled pattern whose ``fullmatch`` tells the names ``pattern`` (a glob, or with ``regex`` a regular
    expression) matches.

    :raises ValueError: a malformed regular expression.
    """
    source = pattern if regex else fnmatch.translate(pattern)
    try:
        return re.compile(source, re.IGNORECASE if ignore_case else 0)
    except re.error as error:
        raise ValueError(f"bad pattern {pattern!r}: {error}") from None


def closest_names(name: str, known, count: int = _SUGGESTIONS) -> list[str]:
    """The known names most like ``name`` (difflib), best first; a case-insensitive match comes first.

    A large module is narrowed first to the names sharing a 3-letter piece with ``name``, so the
    suggestion costs milliseconds, not seconds.
    """
    folded = name.casefold()
    exact = [candidate for candidate in known if candidate.casefold() == folded]
    candidates: list[str] = list(known)
    if len(candidates) > 2000:
        pieces = {folded[i:i + 3] for i in range(max(len(folded) - 2, 1))}
        candidates = [c for c in candidates if any(piece in c.casefold() for piece in pieces)]
    close = difflib.get_close_matches(name, candidates, count, 0.6)
    return (exact + [c for c in close if c not in exact])[:count]
