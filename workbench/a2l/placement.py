"""Where a MODULE's objects lie in memory: their sizes, objects that overlap, objects outside every
MEMORY_SEGMENT and calibrations outside the CAL RAM (part of ``check``).

Bitfields (MEASUREMENT and CHARACTERISTIC with a BIT_MASK, up to 64 bits) that share their bytes
overlap only when their masks share a bit. Each ECU_ADDRESS_EXTENSION is an address space
of its own (XCPlite, for one, addresses stack and event-relative variables so); the
MEMORY_SEGMENTs describe extension 0. An object at address 0 is not placed yet (the
placeholder of a file before its update): it takes part in neither the overlap nor the
segment check. An INSTANCE is checked against the ELF (its symbol, its address); the objects it stands for
(:mod:`workbench.a2l.instances`: ``inst.member``, ``inst[2].x``) take part in the overlap, segment and CAL RAM
checks, each its typedef's size (times the MATRIX_DIM the instance or component adds; one whose size is not
known, an instance limit ``check`` reports, is left out), located at the INSTANCE's address; objects of one
INSTANCE do not overlap each other (a union's members share their bytes by its typedef). Without the ELF, a
file whose every object is at 0 gets one warning (a build that forgot its update; a file that places others has its
reasons for one at 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from workbench.a2l.addressed import AddressedObjects
from workbench.a2l.datatypes import DATATYPES
from workbench.a2l.document import A2lDocument, Block
from workbench.a2l.grammar import ADDRESSED_OBJECTS, MAX_ADDRESS
from workbench.a2l.readers import read_mod_common
from workbench.a2l.reports import finding_at
from workbench.a2l.values import int_or_none
from workbench.elf.debugdata import DebugData
from workbench.elf.suggest import MOST_SUGGESTED, missing_symbol_reason
from workbench.errors import A2lParseError
from workbench.findings import Report, Severity

__all__ = ["check_placement"]

_CALIBRATIONS = ("CHARACTERISTIC", "AXIS_PTS")
_MASKED = ("MEASUREMENT", "CHARACTERISTIC")


@dataclass(frozen=True)
class _Placed:
    name: str
    keyword: str
    address: int
    size: int
    token: int
    bit_mask: int | None = None
    extension: int = 0  # ECU_ADDRESS_EXTENSION: objects of different extensions never overlap
    instance: str = ""  # the INSTANCE an object stands for is part of

    @property
    def label(self) -> str:
        return f"{self.keyword} {self.name}" + (f" of INSTANCE {self.instance}" if self.instance else "")


def _placements(doc: A2lDocument, module: Block, objects: AddressedObjects, debug: DebugData | None,
                report: Report) -> list[_Placed]:
    """Address and size of every object that has both (sizes from the ELF when given, else the A2L)."""
    layouts = _record_layout_sizes(doc)
    masks = _option_values(doc, "BIT_MASK", _MASKED)
    extensions = _option_values(doc, "ECU_ADDRESS_EXTENSION", ADDRESSED_OBJECTS)
    placed, unplaced, addressed = [], [], 0
    instances: dict[str, tuple[int, int]] = {}  # the placed INSTANCEs: name -> (address token, extension)
    suggested = 0  # close names given for missing symbols: the first few (a wrong ELF lacks them all)
    parents = doc.blocks.parent
    for row in range(len(objects)):
        target = objects.target(row)
        keyword = target.keyword
        if target.address_token is None or parents[target.block] != module.index:
            continue
        try:
            address = doc.int_value(target.address_token)
        except A2lParseError:
            continue  # already a syntax finding
        if address > MAX_ADDRESS:
            report.add(finding_at(doc, target.address_token, "address-out-of-range", target.name,
                                  f"{keyword} {target.name}: address 0x{address:X} does not fit the 32 bits of an "
                                  "A2L address", keyword, Severity.ERROR))
            continue
        size = None
        if debug is not None:
            symbol = debug.find(target.symbol)
            if symbol is None:
                suggested += 1
                why = missing_symbol_reason(debug, target.symbol) if suggested <= MOST_SUGGESTED \
                    else debug.resolve_error(target.symbol)
                report.add(finding_at(doc, target.name_token, "symbol-not-found", target.name,
                                      f"{keyword} {target.name}: {why}", keyword, Severity.ERROR))
            else:
                size = symbol.size
                expected = symbol.address + target.symbol_offset
                if expected != address:
                    report.add(finding_at(doc, target.address_token, "address-mismatch", target.name,
                                          f"{keyword} {target.name}: the A2L says 0x{address:X}, "
                                          f"{debug.path.name} says 0x{expected:X}", keyword, Severity.ERROR))
        addressed += 1
        if address == 0:  # not placed yet: the placeholder before an update (no C object lies at address 0)
            unplaced.append(target)
            continue
        if keyword == "INSTANCE":  # its objects are placed below, each its typedef's size
            instances[target.name] = (target.address_token, extensions.get(target.block, 0))
            continue
        if size is None:
            size = _a2l_size(doc, doc.block(target.block), layouts)
        if size:
            placed.append(_Placed(target.name, keyword, address, size, target.address_token, masks.get(target.block),
                                  extensions.get(target.block, 0)))
    if instances:
        placed.extend(_instance_objects(doc, module, instances))
    if unplaced and len(unplaced) == addressed and debug is None:  # with the ELF, each has its address mismatch
        first = unplaced[0]
        shown = ", ".join(target.name for target in unplaced[:3])
        shown += f" and {len(unplaced) - 3} more" if len(unplaced) > 3 else ""
        report.add(finding_at(doc, first.address_token, "placeholder-address", first.name,
                              f"{len(unplaced)} object(s) still at address 0, the placeholder of an A2L not updated "
                              f"from its ELF ({shown}): workbench a2l update IN.a2l ELF -o OUT.a2l, or check --elf ELF",
                              first.keyword, Severity.WARNING))
    return placed


def _instance_objects(doc: A2lDocument, module: Block, instances: dict[str, tuple[int, int]]) -> list[_Placed]:
    """The objects the ``instances`` stand for (a component left out is ``check``'s error or limit already)."""
    model = doc.model(module.name)
    sizes = model.typedef_sizes()
    found = []
    for keyword in ("MEASUREMENT", "CHARACTERISTIC", "AXIS_PTS", "BLOB"):
        for name in model.names(keyword):
            where = model.placed(name)
            if where is None or where.instance not in instances:
                continue
            size = sizes.of(where.typedef)
            if not size:
                continue  # a record layout whose size depends on more than itself (AXIS_RESCALE ...)
            mask = None
            if keyword in _MASKED:
                try:
                    mask = model.measurement(name).bit_mask if keyword == "MEASUREMENT" else \
                        model.characteristic(name).bit_mask
                except A2lParseError:
                    continue  # its typedef is malformed: a syntax finding already
            token, extension = instances[where.instance]
            found.append(_Placed(name, keyword, where.address, size * math.prod(where.dims), token, mask, extension,
                                 where.instance))
    return found


def _a2l_size(doc: A2lDocument, block: Block, layouts: dict[str, int]) -> int | None:
    args = block.args
    keyword = block.keyword
    if keyword == "BLOB":
        return doc.int_value(args[3]) if len(args) > 3 else None
    if keyword == "MEASUREMENT":
        element = DATATYPES.get(doc.text(args[2]), (None,))[0] if len(args) > 2 else None
    elif keyword == "CHARACTERISTIC" and len(args) > 4 and doc.text(args[2]) in ("VALUE", "VAL_BLK"):
        element = layouts.get(doc.text(args[4]))
    else:
        return None  # curves, maps and axes: only the ELF knows their size
    if element is None:
        return None
    count = 1
    for option in ("MATRIX_DIM", "ARRAY_SIZE", "NUMBER"):
        params = block.option(option)
        if params:
            for token in params:
                count *= max(doc.int_value(token), 1)
            break
    return element * count


def _record_layout_sizes(doc: A2lDocument) -> dict[str, int]:
    sizes = {}
    for block in doc.blocks_named("RECORD_LAYOUT"):
        params = block.option("FNC_VALUES")
        if params and len(params) > 1 and doc.text(params[1]) in DATATYPES:
            sizes[block.name] = DATATYPES[doc.text(params[1])][0]
    return sizes


def _option_values(doc: A2lDocument, option: str, keywords) -> dict[int, int]:
    """Block index -> the non-zero integer of ``option`` (BIT_MASK ...) of every ``keywords`` block that has one."""
    values = {}
    for keyword in keywords:
        blocks, tokens = doc.option_tokens(keyword, option)
        for block, token in zip(blocks.tolist(), tokens.tolist()):
            if token + 1 < len(doc.tokens):
                value = int_or_none(doc.raw(token + 1))
                if value:
                    values[block] = value
    return values


def _overlaps(doc: A2lDocument, placed: list[_Placed], big_endian: bool, report: Report) -> None:
    """Partial overlaps are errors; an object that only repeats another's bytes is a warning.
    An object inside a larger one (a struct member, an array element) is a deliberate view, and
    so is a bitfield of a whole object's bytes; bitfields of the same bytes with disjoint masks
    do not overlap, nor do bitfields of partly shared bytes (a packed struct's) whose masks, in
    the module's byte order, cover different bits of memory."""
    ordered = sorted(placed, key=lambda p: (p.extension, p.address, -p.size))
    reach: _Placed | None = None  # the object reaching furthest so far (in the item's address space)
    group = _SameBytes(None)  # the objects on exactly reach's bytes
    for item in ordered:
        if reach is not None and reach.extension == item.extension and item.address < reach.address + reach.size:
            end, reach_end = item.address + item.size, reach.address + reach.size
            if item.address == reach.address and item.size == reach.size:
                clash = group.add(item)
                if clash is not None and not _one_instance(item, clash):
                    report.add(finding_at(doc, item.token, "same-address", item.name,
                                          f"{item.label}{_bits(item)} occupies the same {item.size} "
                                          f"byte(s) at 0x{item.address:X} as {clash.label}"
                                          f"{_bits(clash)}", item.keyword, Severity.WARNING))
            elif end > reach_end and not _one_instance(item, reach) and _share_bits(item, reach, big_endian):
                report.add(finding_at(doc, item.token, "overlap", item.name,
                                      f"{item.label} (0x{item.address:X}, {item.size} bytes) overlaps "
                                      f"{reach.label} (0x{reach.address:X}, {reach.size} bytes)",
                                      item.keyword, Severity.ERROR))
            if end <= reach_end:
                continue
        reach = item
        group = _SameBytes(item)


def _one_instance(item: _Placed, other: _Placed) -> bool:
    """Whether both are objects of one INSTANCE: where its components share bytes, its typedef says so (a union;
    a component beyond its structure is ``check``'s structure error)."""
    return bool(item.instance) and item.instance == other.instance


def _share_bits(item: _Placed, other: _Placed, big_endian: bool) -> bool:
    """Whether two objects on partly shared bytes cover a common bit of memory (whole objects always do)."""
    base = min(item.address, other.address)
    covered = []
    for placed in (item, other):
        mask = placed.bit_mask
        if mask is None or mask >= 1 << 8 * placed.size:
            return True
        in_memory = int.from_bytes(mask.to_bytes(placed.size, "big" if big_endian else "little"), "little")
        covered.append(in_memory << 8 * (placed.address - base))
    return bool(covered[0] & covered[1])


class _SameBytes:
    """The objects on one range of bytes: the first whole one, and the bitfields."""

    def __init__(self, first: _Placed | None):
        self.whole: _Placed | None = None
        self.bitfields: list[_Placed] = []
        if first is not None:
            self.add(first)

    def add(self, item: _Placed) -> _Placed | None:
        """Take ``item``; returns the object whose bits it repeats (None: it repeats none)."""
        if item.bit_mask is None:
            if self.whole is None:
                self.whole = item
            return self.whole if self.whole is not item else None
        for bitfield in self.bitfields:
            if bitfield.bit_mask & item.bit_mask:
                return bitfield
        self.bitfields.append(item)
        return None


def _bits(item: _Placed) -> str:
    return f" (BIT_MASK 0x{item.bit_mask:X})" if item.bit_mask is not None else ""


def _segments(doc: A2lDocument, module: Block, placed: list[_Placed], report: Report) -> None:
    segments = doc.memory_segments(module.name)
    if not segments:
        return
    cal_ram = [s for s in segments if s.memory_type == "RAM" and s.prg_type in ("DATA", "CALIBRATION_VARIABLES")]
    for item in placed:
        if item.extension:
            continue  # another address space than the segments'
        inside = [s for s in segments if s.contains(item.address, item.size)]
        if not inside:
            report.add(finding_at(doc, item.token, "outside-memory", item.name,
                                  f"{item.label} (0x{item.address:X}, {item.size} bytes) lies outside "
                                  "every MEMORY_SEGMENT", item.keyword, Severity.ERROR))
        elif item.keyword in _CALIBRATIONS and cal_ram and not any(s in cal_ram for s in inside):
            report.add(finding_at(doc, item.token, "calibration-outside-cal-ram", item.name,
                                  f"{item.label} at 0x{item.address:X} is in {inside[0].name} "
                                  f"({inside[0].prg_type} {inside[0].memory_type}), not in a DATA RAM segment "
                                  f"({', '.join(s.name for s in cal_ram)})", item.keyword, Severity.ERROR))


def check_placement(doc: A2lDocument, module: Block, objects: AddressedObjects, debug: DebugData | None,
                    report: Report) -> list[_Placed]:
    """Report the module's objects that overlap or lie outside memory (and, with ``debug``, whose
    symbol is missing or whose address differs from the ELF's); returns the objects placed (name, keyword, address,
    size, extension, token of the address), for the EPK's check."""
    placed = _placements(doc, module, objects, debug, report)
    # which bits of memory a BIT_MASK covers: by the ELF's byte order (check reports a MOD_COMMON that differs)
    big_endian = (not debug.elf.little_endian if debug is not None else
                  read_mod_common(doc, module.first("MOD_COMMON")).byte_order.startswith("MSB_FIRST"))
    _overlaps(doc, placed, big_endian, report)
    _segments(doc, module, placed, report)
    return placed
