"""Each part's EPK as the proof that the part is whole, the rule production flashers follow.

A flash programs the EPK of a part (the bytes at its ADDR_EPK: CALIB's FC0000h, the application
header's 840008h in the demo) last within that part, after every other byte of it was programmed and
verified (:func:`epk_ranges` says which bytes to hold back). So a part whose flash broke off keeps its
EPK erased (0xFF, as the erase left it). Before the application-valid key is set, every part the
application needs, flashed now or not, is read at its ADDR_EPK (:func:`read_part_epks`: UPLOAD, else
BUILD_CHECKSUM where the boot loader refuses UPLOAD), and the key is not set over a part whose EPK is
erased or another build's: the ECU stays in its boot loader, where the boot never starts a half-written
application.
"""

from __future__ import annotations

from dataclasses import dataclass

from workbench.errors import XcpCommandError, epk_text, same_epk
from workbench.flash.checksums import ChecksumVerifier
from workbench.flash.layout import FlashLayout, FlashRegion
from workbench.image import ERASED, AddressRange
from workbench.logs import logger
from workbench.xcp.master import XcpMaster

log = logger(__name__)

__all__ = ["PartEpk", "epk_ranges", "read_part_epks"]


@dataclass(frozen=True)
class PartEpk:
    """What one part holds at its ADDR_EPK."""

    region: FlashRegion
    address: int
    a2l: bytes  # MOD_PAR EPK
    held: bytes | None  # None: the boot loader refused UPLOAD (``same`` then says what BUILD_CHECKSUM found)
    same: bool  # the A2L's EPK is there

    @property
    def complete(self) -> bool:
        """Every byte of the EPK is programmed (an erased byte where the A2L's EPK has another: not yet)."""
        if self.held is None:
            return self.same  # the checksum only tells same or not: not the same counts as unfinished
        return not any(h == ERASED and a != ERASED for h, a in zip(self.held, self.a2l))

    @property
    def found(self) -> str:
        if self.held is None:
            return "the A2L's EPK" if self.same else "not the A2L's EPK (BUILD_CHECKSUM; UPLOAD refused)"
        return epk_text(self.held.decode("latin-1"))

    def unfinished(self, chosen: list[str], ecu_state: str, flashed_without_epk: bool = False) -> str:
        """Why the key is not set over this part, and what to do ("flash ..."), for one line."""
        name = self.region.name
        why = "the file holds no EPK there" if flashed_without_epk else f"a flash of {name} probably broke off"
        whole = " ".join(f"-r {r}" for r in dict.fromkeys([*chosen, name]))
        return (f"{name}'s EPK at {self.address:X}h reads {self.found}: {why}, so the application key is not set "
                f"and {ecu_state}: flash the whole software ({whole}), or {name} again from a file with its EPK")

    def other_build(self, a2l_epk: str) -> str:
        return (f"{self.region.name}'s EPK at {self.address:X}h reads {self.found}, not the A2L's "
                f"{epk_text(a2l_epk)}: another build's")


def epk_ranges(layout: FlashLayout, granularity: int = 1) -> list[AddressRange]:
    """Where the parts keep their EPKs, widened to whole elements of the address granularity (programmed last)."""
    if layout.epk is None:
        return []
    size = len(layout.epk.encode("latin-1"))
    return [AddressRange(a - a % granularity, -(-(a + size) // granularity) * granularity)
            for a in _addresses(layout)]


def read_part_epks(master: XcpMaster, layout: FlashLayout) -> list[PartEpk]:
    """The EPK of every part the application needs (each ADDR_EPK in a flash region), as the ECU holds it now."""
    if layout.epk is None:
        return []
    a2l = layout.epk.encode("latin-1")
    parts = []
    for address in _addresses(layout):
        try:
            held = master.read(address, len(a2l))
        except XcpCommandError as exc:  # a boot loader that refuses UPLOAD: the checksum says same or not
            log.info("EPK at %Xh: %s; comparing by BUILD_CHECKSUM", address, exc)
            held = None
        same = same_epk(held.decode("latin-1"), layout.epk) if held is not None else \
            not ChecksumVerifier(master).differing(address, a2l)
        parts.append(PartEpk(layout.region_at(address), address, a2l, held, same))
    return parts


def _addresses(layout: FlashLayout) -> list[int]:
    """Each ADDR_EPK that lies in a region flashed by users (CALIB, APPLICATIVE ...)."""
    return [a for a in layout.epk_addresses or ((layout.addr_epk,) if layout.addr_epk is not None else ())
            if (region := layout.region_at(a)) is not None and region.selectable]
