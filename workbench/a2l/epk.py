"""The EPK (EPROM identifier): read it from the ELF, set MOD_PAR ``EPK`` and ``ADDR_EPK`` to it.

The ELF holds the EPK as a string variable (``EPK``/``epk``, or one named by the
caller) or in a section ``.epk``; the A2L must state both the string and where the
ECU keeps it, so that a master can compare the two before writing anything.

MOD_PAR may name ADDR_EPK more than once (ASAP2), e.g. the calibration data's EPK and the application
header's copy of it: the one in the MEMORY_SEGMENT of the symbol or section above (else the first) is set to
its address; each other one stays where the ELF holds the EPK string, or moves to the one place in its
MEMORY_SEGMENT that does.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

from workbench.a2l.edits import Edit, indentation_of, newline_bytes, replace_token
from workbench.a2l.reports import finding_at
from workbench.a2l.values import format_int_like, is_int, quote_string
from workbench.errors import InputError
from workbench.findings import Finding, Severity

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument, Block, EpkAddress, MemorySegment
    from workbench.elf.debugdata import DebugData

__all__ = ["ElfEpk", "epk_address_edits", "epk_edits", "holds_epk", "read_elf_epk"]

DEFAULT_EPK_SYMBOLS = ("EPK", "epk")
EPK_SECTIONS = (".epk", "epk")


class ElfEpk(NamedTuple):
    text: str
    address: int
    source: str  # the symbol or section it was read from


def read_elf_epk(debug: "DebugData", symbol: str | None = None) -> ElfEpk | None:
    """The EPK string of the ELF and its address, or None when the ELF has none.

    ``symbol`` names the variable to read; by default ``EPK``/``epk``, then a section
    ``.epk``. Raises :class:`InputError` when the named symbol is missing or its bytes
    are not printable ASCII.
    """
    candidates = [symbol] if symbol else list(DEFAULT_EPK_SYMBOLS)
    for name in candidates:
        found = debug.extent(name)
        if found is None or not found[1]:
            continue
        raw = debug.elf.read(*found)
        if raw is not None:
            return ElfEpk(_text(raw, name, debug), found[0], name)
    if symbol:
        raise InputError(f"{debug.path}: no initialised EPK variable {symbol!r}")
    for name in EPK_SECTIONS:
        section = debug.elf.sections.get(name)
        if section is not None and section.loaded and section.size:
            raw = debug.elf.read(section.address, section.size)
            if raw is not None:
                return ElfEpk(_text(raw, name, debug), section.address, name)
    return None


def _text(raw: bytes, name: str, debug: "DebugData") -> str:
    text = raw.split(b"\0", 1)[0]
    if not text or any(byte < 0x20 or byte > 0x7E for byte in text):
        raise InputError(f"{debug.path}: the EPK in {name!r} is not a printable ASCII string: {raw!r}")
    return text.decode("ascii")


def epk_edits(doc: "A2lDocument", epk: ElfEpk, module: "Block") -> tuple[list[Edit], list[Finding]]:
    """Edits that make MOD_PAR's EPK and ADDR_EPK state ``epk`` (inserted when missing)."""
    mod_par = module.first("MOD_PAR")
    if mod_par is None:
        file, line, column = module.position
        return [], [Finding("epk-not-set", module.name or "", "the MODULE has no MOD_PAR to hold the EPK",
                            file, line, column, "MODULE", Severity.INFO)]
    edits: list[Edit] = []
    findings: list[Finding] = []
    inserts: list[bytes] = []
    comment = mod_par.keyword_token + 1
    if doc.raw(comment)[:1] != b'"':  # without its comment, EPK would be read as the comment and inserted again
        raise doc.error(f"MOD_PAR: its comment (a string) expected first, found '{doc.text(comment)}'", comment)
    _check_option(doc, mod_par, "EPK", "a string in quotes", lambda raw: raw[:1] == b'"')
    _check_option(doc, mod_par, "ADDR_EPK", "an integer address", is_int)
    current_text = mod_par.option("EPK")
    if current_text:
        token = current_text[0]
        if doc.text(token) != epk.text:
            findings.append(finding_at(doc, token, "epk-updated", "EPK",
                                       f"EPK {doc.text(token)!r} -> {epk.text!r} (from {epk.source})", "MOD_PAR"))
            edits.append(replace_token(doc, token, quote_string(epk.text, doc.encoding)))
    else:
        inserts.append(b"EPK " + quote_string(epk.text, doc.encoding))
        findings.append(finding_at(doc, mod_par.keyword_token, "epk-inserted", "EPK",
                                   f"EPK {epk.text!r} added (from {epk.source})", "MOD_PAR"))
    current_address = _set_by_symbol(doc, epk, module)
    if current_address is not None:
        token = current_address.token
        old = doc.int_value(token)
        if old != epk.address:
            findings.append(finding_at(doc, token, "epk-updated", "ADDR_EPK",
                                       f"ADDR_EPK 0x{old:X} -> 0x{epk.address:X}", "MOD_PAR"))
            edits.append(replace_token(doc, token, format_int_like(doc.raw(token), epk.address)))
    else:
        inserts.append(f"ADDR_EPK 0x{epk.address:X}".encode("ascii"))
        findings.append(finding_at(doc, mod_par.keyword_token, "epk-inserted", "ADDR_EPK",
                                   f"ADDR_EPK 0x{epk.address:X} added", "MOD_PAR"))
    if inserts:
        args = mod_par.args
        anchor = doc.tokens.span(args[-1] if args else mod_par.keyword_token)[1]
        indent = indentation_of(doc.data, doc.tokens.span(mod_par.begin_token)[0]) + b"  "
        newline = newline_bytes(doc)
        edits.append(Edit(anchor, anchor, b"".join(newline + indent + line for line in inserts)))
    return edits, findings


def epk_address_edits(doc: A2lDocument, debug: DebugData, epk: ElfEpk, module: Block
                      ) -> tuple[list[Edit], list[Finding]]:
    """Edits that keep each further ADDR_EPK of MOD_PAR (all but the one :func:`epk_edits` sets) where
    the ELF holds the EPK string: unchanged when it does, else moved to the one place in the same MEMORY_SEGMENT
    that holds it; a warning when there is none or more than one."""
    chosen = _set_by_symbol(doc, epk, module)
    further = [place for place in doc.epk_addresses(module.name) if place != chosen]
    if not further:
        return [], []
    text = epk.text.encode("ascii")
    named = {epk.address} | {place.address for place in further}
    edits: list[Edit] = []
    findings: list[Finding] = []
    for old, segment, token in further:
        if holds_epk(debug.elf.read(old, len(text) + 1), text):
            continue
        found = [a for a in _occurrences(debug, text, segment) if a not in named] if segment is not None else []
        if len(found) == 1:
            named.add(found[0])
            findings.append(finding_at(doc, token, "epk-updated", "ADDR_EPK",
                                       f"ADDR_EPK 0x{old:X} -> 0x{found[0]:X} (where {debug.path.name} holds the EPK "
                                       f"in {segment.name})", "MOD_PAR"))
            edits.append(replace_token(doc, token, format_int_like(doc.raw(token), found[0])))
            continue
        where = f"in {segment.name}" if segment is not None else "in no MEMORY_SEGMENT"
        why = "nowhere" if not found else "at " + ", ".join(f"0x{a:X}" for a in found)
        findings.append(finding_at(doc, token, "epk-address-unknown", "ADDR_EPK",
                                   f"ADDR_EPK 0x{old:X}: {debug.path.name} does not hold the EPK {epk.text!r} there, "
                                   f"and {why} else {where}: left unchanged", "MOD_PAR", Severity.WARNING))
    return edits, findings


def _set_by_symbol(doc: A2lDocument, epk: ElfEpk, module: Block) -> EpkAddress | None:
    """The ADDR_EPK the ELF's EPK symbol (or section) sets: the one in the same MEMORY_SEGMENT (the part of the
    software it belongs to, whichever place MOD_PAR gives it), else the first; None: MOD_PAR names none."""
    places = doc.epk_addresses(module.name)
    return next((p for p in places if p.segment is not None and p.segment.contains(epk.address)),
                places[0] if places else None)


def holds_epk(raw: bytes | None, text: bytes) -> bool:
    """``raw`` (the EPK's length + 1 bytes) starts with the EPK string, ended by NUL, padding or the data's end."""
    return raw is not None and raw.startswith(text) and raw[len(text):] in (b"", b"\0", b"\xff", b" ")


def _occurrences(debug: DebugData, text: bytes, segment: MemorySegment) -> list[int]:
    """Where the ELF's loaded sections inside ``segment`` hold the EPK string."""
    found = []
    for section in debug.elf.sections.values():
        if not (section.loaded and section.allocated and section.size and segment.contains(section.address)):
            continue
        data = debug.elf.section_bytes(section.name) or b""
        at = data.find(text)
        while at >= 0:
            if holds_epk(data[at:at + len(text) + 1], text):
                found.append(section.address + at)
            at = data.find(text, at + 1)
    return found


def _check_option(doc: "A2lDocument", mod_par: "Block", option: str, expected: str, fits) -> None:
    """Raise :class:`A2lParseError` at an ``option`` of MOD_PAR without its value: the update would insert
    another one beside it."""
    word = option.encode("ascii")
    for keyword in [token for token in mod_par.own_tokens[1:] if doc.raw(token) == word]:  # after its comment
        value = keyword + 1
        if value >= doc.block_end[mod_par.index] or not fits(doc.raw(value)):
            found = doc.raw(min(value, doc.block_end[mod_par.index])).decode(doc.encoding)
            raise doc.error(f"MOD_PAR: {option} needs {expected}, found '{found}'", keyword)
