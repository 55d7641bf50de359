"""The EPK check: the software in the ECU must be the one the A2L describes before anything is written.

The ECU's EPK is read with GET_ID type 5 when the slave offers it, else from ADDR_EPK (the
A2L's address of the EPK string). On a mismatch the session stays read-only unless the caller
explicitly accepts the risk (thesis figure 37: flash the matching software, or work read-only).

An A2L may name ADDR_EPK more than once (ASAP2), one in each part of the software (the demo: CALIB's FC0000h,
the application header's 840008h). Then each part's EPK is read where it lies (UPLOAD) and the check fails when
any part is another build's: a calibration flashed onto another application is seen, although GET_ID reports
the EPK of the calibration data just flashed.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from workbench.errors import XcpCommandError, epk_text, same_epk
from workbench.logs import logger
from workbench.xcp.master import XcpMaster
from workbench.xcp_protocol import IdType

log = logger(__name__)

__all__ = ["EpkCheck", "EpkPart", "check_epk"]


@dataclass(frozen=True)
class EpkPart:
    """The EPK one part of the software keeps at its own ADDR_EPK."""

    segment: str  # the MEMORY_SEGMENT holding it (CALIB, APPLICATIVE ...)
    address: int  # its ADDR_EPK
    a2l: str  # MOD_PAR EPK
    ecu: str | None  # what the ECU holds there (None: it could not be read)

    @property
    def matches(self) -> bool | None:
        return None if self.ecu is None else same_epk(self.a2l, self.ecu)

    def describe(self) -> str:
        ecu = "unreadable" if self.ecu is None else epk_text(self.ecu)
        verdict = {True: "match", False: "MISMATCH", None: "not checked"}[self.matches]
        return f"{self.segment} ({self.address:X}h): ECU {ecu}, A2L {epk_text(self.a2l)}: {verdict}"

    def to_dict(self) -> dict:
        return {"segment": self.segment, "address": self.address, "a2l": self.a2l, "ecu": self.ecu,
                "matches": self.matches}


@dataclass(frozen=True)
class EpkCheck:
    a2l: str | None  # MOD_PAR EPK (None: the A2L states none)
    ecu: str | None  # what the ECU reports (None: it could not be read)
    source: str  # "GET_ID", "ADDR_EPK" or "" (not read)
    parts: tuple[EpkPart, ...] = ()  # each part's own EPK, when the A2L names ADDR_EPK in several segments

    @property
    def matches(self) -> bool | None:
        """True/False (False also when a part is another build's), or None when there is nothing to compare."""
        if self.a2l is None or self.ecu is None:
            return None
        return same_epk(self.a2l, self.ecu) and not self.mismatched_parts

    @property
    def mismatched_parts(self) -> tuple[EpkPart, ...]:
        return tuple(part for part in self.parts if part.matches is False)

    def describe(self) -> str:
        if self.a2l is None:
            return "the A2L states no EPK: not checked"
        if self.ecu is None:
            return f"the ECU's EPK could not be read (A2L: {epk_text(self.a2l)})"
        verdict = "match" if self.matches else "MISMATCH"
        text = f"EPK {verdict}: A2L {epk_text(self.a2l)}, ECU {epk_text(self.ecu)} ({self.source})"
        return text + "".join(f"; {p.segment} ({p.address:X}h) holds {epk_text(p.ecu or '')}"
                              for p in self.mismatched_parts if not same_epk(p.ecu or "", self.ecu))



def check_epk(master: XcpMaster, a2l_epk: str | None, addr_epk: int | None,
              parts: Sequence[tuple[int, str]] = ()) -> EpkCheck:
    """Read the ECU's EPK (GET_ID 5, else ADDR_EPK) for comparison with ``a2l_epk``, and the EPK of each part
    (``parts``: its ADDR_EPK and MEMORY_SEGMENT, e.g. from :meth:`A2lDocument.epk_parts`) by UPLOAD."""
    if a2l_epk is None:
        return EpkCheck(None, None, "")
    size = len(a2l_epk.encode("latin-1"))
    text, source = None, ""
    try:
        reported = master.get_id(IdType.EPK)
        if reported:
            text, source = reported.decode("latin-1"), "GET_ID"
    except XcpCommandError as exc:
        log.debug("GET_ID EPK: %s", exc)
    if text is None and addr_epk is not None:
        text = _read(master, addr_epk, size)
        source = "ADDR_EPK" if text is not None else ""
    read_at = {addr_epk: text} if source == "ADDR_EPK" else {}  # without GET_ID, ADDR_EPK's part is read already
    read = tuple(EpkPart(segment, address, a2l_epk, read_at[address] if address in read_at
                         else _read(master, address, size)) for address, segment in parts)
    return EpkCheck(a2l_epk, text, source, read)


def _read(master: XcpMaster, address: int, size: int) -> str | None:
    try:
        return master.read(address, size).decode("latin-1")
    except XcpCommandError as exc:
        log.debug("EPK at %Xh: %s", address, exc)
        return None
