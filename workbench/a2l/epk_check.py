"""Where MOD_PAR's ADDR_EPKs may lie (part of ``check``).

MOD_PAR's EPK and ADDR_EPK come together (either alone is a warning: a master compares the EPK it reads at ADDR_EPK
with MOD_PAR's). Each ADDR_EPK must lie in a MEMORY_SEGMENT, the EPK string whole inside it: a master reads a part's
EPK from a flash file or image by its segment, and a flash decides by it which part of the software stays. Two
ADDR_EPKs in one segment are a warning: a part keeps one EPK, so one of them is likely stale (an address the update
did not move). With the ELF, the bytes at every ADDR_EPK must be MOD_PAR's EPK (ended by NUL, padding or the section's
end; a RAM section's initial bytes count at their load address too): an A2L whose EPK the build does not put there
fails every connect, or passes with another build's addresses. Flash (ROM, EEPROM) the ELF puts nothing at stays
erased: an error too; RAM it does not initialise (``.bss``) is an info: the EPK cannot be compared there. An ADDR_EPK
in CAL RAM is compared where its IF_DATA XCP ADDRESS_MAPPING loads it from (CAL ROM), as the sync and the offline
calibration read it. A flash file (s19/hex) given to the check must hold the EPK at every ADDR_EPK it has bytes at
(an s19 of the calibration data holds CALIB's only: the others are an info). A CHARACTERISTIC or AXIS_PTS on the
EPK's bytes (there, or in the CAL RAM an ADDRESS_MAPPING loads them to) is a warning: writing it would change the
identifier of the software (the offline calibration refuses such a write).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from workbench.a2l.document import A2lDocument, Block
from workbench.a2l.epk import holds_epk
from workbench.a2l.reports import finding_at
from workbench.elf.debugdata import DebugData
from workbench.errors import A2lParseError, epk_text
from workbench.findings import Report, Severity

if TYPE_CHECKING:
    from workbench.a2l.xcp import XcpAddressMapping
    from workbench.image import MemoryImage

__all__ = ["check_epk_addresses"]

_PROGRAMMED = frozenset({"FLASH", "EEPROM", "EPROM", "ROM"})  # what a build's file fills: nothing there stays erased
_CALIBRATIONS = ("CHARACTERISTIC", "AXIS_PTS")


def check_epk_addresses(doc: A2lDocument, module: Block, debug: DebugData | None, report: Report,
                        image: tuple[str, MemoryImage] | None = None, placed: Sequence = ()) -> None:
    """Report the module's ADDR_EPKs that lie outside memory, hold no room for the EPK, share a segment, or (with
    ``debug``) where the ELF holds another EPK; ``image``: (its name, its bytes) of a flash file that must hold the
    EPK at every ADDR_EPK it has bytes at; ``placed``: the objects :func:`~workbench.a2l.placement.check_placement`
    placed, of which no calibration may lie on the EPK's bytes.

    :raises A2lParseError: a MEMORY_SEGMENT without its parameters (the caller reports it).
    """
    places = doc.epk_addresses(module.name)
    epk = doc.epk(module.name)
    if not places or epk is None:
        _without_its_pair(doc, module, places, epk, report)
        return
    text = epk.encode("latin-1") if epk else b""
    has_segments = bool(doc.memory_segments(module.name))
    first_in: dict[str, int] = {}  # segment name -> the first ADDR_EPK's token there
    mappings: list[XcpAddressMapping] | None = None  # read when a file is compared

    def add(place, kind: str, message: str, severity: Severity) -> None:
        report.add(finding_at(doc, place.token, kind, "ADDR_EPK", f"ADDR_EPK 0x{place.address:X}: {message}",
                              "MOD_PAR", severity))

    for place in places:
        segment = place.segment
        if segment is None:
            if has_segments:
                add(place, "epk-outside-memory", "lies outside every MEMORY_SEGMENT: no part of the software holds "
                    "the EPK there, so neither a flash file nor an image can show it", Severity.ERROR)
        elif text and not segment.contains(place.address, len(text)):
            beyond = place.address + len(text) - segment.address - segment.size
            add(place, "epk-beyond-segment", f"the EPK {epk_text(epk)} ({len(text)} bytes) runs {beyond} byte(s) "
                f"beyond {segment.name} (which ends at 0x{segment.address + segment.size - 1:X})", Severity.ERROR)
        if segment is not None:
            first = first_in.setdefault(segment.name, place.token)
            if first != place.token:
                again = "the same address as" if doc.int_value(first) == place.address else "in the same part as"
                add(place, "epk-same-segment", f"lies in {segment.name}, {again} the ADDR_EPK at line "
                    f"{doc.token_position(first)[1]}: a part of the software keeps one EPK, so one of them is likely "
                    "stale", Severity.WARNING)
        if (debug is not None or image is not None or placed) and text:
            if mappings is None:
                mappings = _address_mappings(doc, module)
            where = _where(place.address, mappings)
            _calibrations_on(doc, place, where + _loaded_at(place.address, mappings), len(text), placed, report)
            if debug is not None:
                _compare_with_elf(place, where, text, epk, debug, add)
            if image is not None:
                _compare_with_image(place, where, text, epk, *image, add)


def _without_its_pair(doc: A2lDocument, module: Block, places: Sequence, epk: str | None, report: Report) -> None:
    """MOD_PAR's EPK without ADDR_EPK, or ADDR_EPK without EPK: a master compares the EPK it reads at ADDR_EPK with
    MOD_PAR's, so either alone identifies nothing."""
    if epk is not None:
        report.add(finding_at(doc, doc.epk_token(module.name), "epk-without-address", "EPK",
                              f"EPK {epk_text(epk)} without ADDR_EPK: a master cannot read the ECU's EPK where it lies "
                              "to compare it with the A2L's (CANape reads it at ADDR_EPK): add ADDR_EPK (workbench a2l "
                              "update sets it from the ELF)", "MOD_PAR", Severity.WARNING))
    elif places:
        report.add(finding_at(doc, places[0].token, "addr-epk-without-epk", "ADDR_EPK",
                              f"ADDR_EPK 0x{places[0].address:X} without MOD_PAR EPK: the bytes there are compared "
                              "with nothing, so an ECU or a file of another build is taken for this A2L's: add EPK "
                              "\"...\" (workbench a2l update inserts it from the ELF)", "MOD_PAR", Severity.WARNING))


def _address_mappings(doc: A2lDocument, module: Block) -> list[XcpAddressMapping]:
    """The IF_DATA XCP SEGMENTs' ADDRESS_MAPPINGs (CAL RAM onto the CAL ROM it is loaded from); none without XCP."""
    from workbench.a2l.xcp import read_xcp_config

    try:
        return [mapping for segment in read_xcp_config(doc, module.name).segments
                for mapping in segment.address_mappings]
    except A2lParseError:  # no IF_DATA XCP, or one the check reports elsewhere
        return []


def _where(address: int, mappings: list[XcpAddressMapping]) -> list[int]:
    """Where a file holds the bytes of ``address``: there, then where an ADDRESS_MAPPING loads it from."""
    return [address] + [address - m.source + m.destination for m in mappings
                        if m.source <= address < m.source + m.length]


def _loaded_at(address: int, mappings: list[XcpAddressMapping]) -> list[int]:
    """The working page's (CAL RAM's) addresses of a flash ``address`` an ADDRESS_MAPPING loads there."""
    return [address - m.destination + m.source for m in mappings if m.destination <= address < m.destination + m.length]


def _calibrations_on(doc: A2lDocument, place, where: list[int], size: int, placed: Sequence, report: Report) -> None:
    """A calibration on the EPK's bytes (at ADDR_EPK, or where an ADDRESS_MAPPING puts them): writing it changes the
    identifier that says which build the software is (a view of the EPK as an ASCII CHARACTERISTIC, too)."""
    line = doc.token_position(place.token)[1]
    for item in placed:
        if item.keyword in _CALIBRATIONS and not item.extension and any(
                at < item.address + item.size and item.address < at + size for at in where):
            report.add(finding_at(doc, item.token, "calibration-on-epk", item.name,
                                  f"{item.label} (0x{item.address:X}, {item.size} bytes) lies on the EPK's bytes "
                                  f"(ADDR_EPK 0x{place.address:X} at line {line}, {size} bytes): a write to it would "
                                  "change the identifier of the software", item.keyword, Severity.WARNING))


def _mapped(place, at: int) -> str:
    return "" if at == place.address else f" (at 0x{at:X}, where the ADDRESS_MAPPING loads it from)"


def _compare_with_elf(place, where: list[int], text: bytes, epk: str, debug: DebugData, add) -> None:
    for at in where:
        raw = _initial_bytes(debug, at, len(text) + 1) or _initial_bytes(debug, at, len(text))
        if raw is not None:
            if not holds_epk(raw, text):
                _differs(place, raw, text, epk, debug.path.name + _mapped(place, at), add)
            return
    if place.segment is not None and place.segment.memory_type in _PROGRAMMED:
        add(place, "epk-differs", f"{debug.path.name} puts nothing there (the {place.segment.memory_type} stays "
            f"erased when this build is flashed), MOD_PAR's EPK is {epk_text(epk)}", Severity.ERROR)
    else:
        add(place, "epk-not-in-elf", f"{debug.path.name} holds no initial data there (memory it does not "
            "initialise): the EPK cannot be compared", Severity.INFO)


def _compare_with_image(place, where: list[int], text: bytes, epk: str, name: str, image: MemoryImage, add) -> None:
    for at in where:
        if image.crop(at, at + len(text)).size == len(text):
            raw = image.read(at, len(text) + 1)  # the byte after it: erased (FF) where the file ends
            if not holds_epk(raw, text):
                _differs(place, raw, text, epk, name + _mapped(place, at), add)
            return
    add(place, "epk-not-in-image", f"{name} has no bytes there (or not all {len(text)}): not compared", Severity.INFO)


def _differs(place, raw: bytes, text: bytes, epk: str, name: str, add) -> None:
    held = raw[:len(text)].split(b"\0", 1)[0] or raw[:len(text)]  # the string there, else its bytes
    add(place, "epk-differs", f"{name} holds {epk_text(held.decode('latin-1'))} there, MOD_PAR's EPK is "
        f"{epk_text(epk)} (an A2L of another build, or an ADDR_EPK not updated: workbench a2l update)", Severity.ERROR)


def _initial_bytes(debug: DebugData, address: int, size: int) -> bytes | None:
    """The build's bytes at ``address``: where a section lies, else where one is stored (its load address: the flash
    copy of initialised RAM); None: neither."""
    found = debug.elf.read(address, size)
    if found is not None:
        return found
    for section in debug.elf.sections.values():
        start = section.load_address
        if (section.loaded and section.allocated and start != section.address and start <= address
                and address + size <= start + section.size):
            return debug.elf.read(section.address + address - start, size)
    return None
