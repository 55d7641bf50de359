"""Where calibrations live in the ECU, and how a flash image (s19/hex) lies over those addresses.

A :class:`CalibrationArea` is a calibration MEMORY_SEGMENT: its XCP SEGMENT when the A2L gives one
(number for the pages, CHECKSUM MAX_BLOCK_SIZE, the ADDRESS_MAPPING from the working page to the
flash it is loaded from), else a DATA MEMORY_SEGMENT as it stands. On the demo ECU the one area is
CAL RAM 0x40000000..0x4001FFFF, mapped 1:1 onto CAL ROM 0xFC0000..0xFDFFFF.

An :class:`ImageView` reads an image at the ECU's addresses: through the area's ADDRESS_MAPPING
(an s19 of the build holds CAL ROM), or as it stands when the image holds the area's own
addresses (a dump of the RAM). Bytes the image does not hold read as erased flash (0xFF), what
the boot copies from CAL ROM where nothing was programmed.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

from workbench.calib.memory import Span
from workbench.image import ERASED, AddressRange, MemoryImage

if TYPE_CHECKING:
    from workbench.a2l import A2lDocument
    from workbench.a2l.document import EpkAddress
    from workbench.a2l.xcp import XcpAddressMapping, XcpConfig

__all__ = ["CalibrationArea", "ImageEpk", "ImageView", "calibration_areas", "image_epks"]

_CALIBRATION_PRG_TYPES = {"DATA", "OFFLINE_DATA", "CALIBRATION_VARIABLES", "SERAM"}


@dataclass(frozen=True)
class CalibrationArea:
    """A calibration segment at the ECU's addresses (the working page's, when it has pages)."""

    name: str  # the MEMORY_SEGMENT's
    span: Span
    segment: int | None = None  # the XCP SEGMENT number (pages); None: no pages
    mappings: tuple["XcpAddressMapping", ...] = ()
    max_checksum_block: int | None = None  # bytes one BUILD_CHECKSUM may cover (None: not stated)

    def contains(self, span: Span) -> bool:
        return (span.extension == self.span.extension and self.span.address <= span.address
                and span.end <= self.span.end)

    def flash_address(self, address: int) -> int:
        """Where the byte at ECU ``address`` lies in the flash the page is loaded from (the address itself
        when no ADDRESS_MAPPING covers it)."""
        for mapping in self.mappings:
            if mapping.source <= address < mapping.source + mapping.length:
                return address - mapping.source + mapping.destination
        return address

    def flash_ranges(self) -> list[tuple[int, int, int]]:
        """``(ecu address, flash address, length)`` of every piece of the area, mapped or not."""
        pieces = []
        cursor = self.span.address
        for mapping in sorted(self.mappings, key=lambda m: m.source):
            low = max(cursor, mapping.source)
            high = min(self.span.end, mapping.source + mapping.length)
            if low >= high:
                continue
            if low > cursor:
                pieces.append((cursor, cursor, low - cursor))
            pieces.append((low, low - mapping.source + mapping.destination, high - low))
            cursor = high
        if cursor < self.span.end:
            pieces.append((cursor, cursor, self.span.end - cursor))
        return pieces

    def __str__(self) -> str:
        return f"{self.name} {self.span}"


def calibration_areas(doc: "A2lDocument", config: "XcpConfig | None", module: str | None = None
                      ) -> list[CalibrationArea]:
    """The A2L's calibration segments: those with an XCP SEGMENT, else (or without IF_DATA XCP: ``config`` None) its
    DATA MEMORY_SEGMENTs."""
    segments = config.segments if config is not None else ()
    areas = [CalibrationArea(s.memory_segment, Span(s.address, s.size, s.address_extension), s.number,
                             tuple(s.address_mappings), s.checksum_max_block_size) for s in segments]
    if areas:
        return areas
    return [CalibrationArea(s.name, Span(s.address, s.size)) for s in doc.memory_segments(module)
            if s.prg_type in _CALIBRATION_PRG_TYPES]


class ImageView:
    """``image`` read at the ECU's addresses of ``areas`` (see the module docstring)."""

    def __init__(self, image: MemoryImage, areas: list[CalibrationArea]):
        self.image = image
        self.areas = areas
        # an image that holds an area's own addresses is a dump of that memory, not of its flash
        self._as_is = {area.name for area in areas if image.crop(area.span.address, area.span.end).size}

    def image_address(self, address: int, extension: int = 0) -> int:
        """Where the byte at ECU ``address`` lies in the image."""
        for area in self.areas:
            if area.contains(Span(address, 1, extension)):
                return address if area.name in self._as_is else area.flash_address(address)
        return address

    def read(self, span: Span) -> bytes:
        """The span's bytes (erased flash where the image holds none); a span may cross mappings."""
        return b"".join(self.image.read(start, size, ERASED) for start, size in self.pieces(span))

    def write(self, span: Span, data: bytes) -> None:
        """Put ``data`` (``span.size`` bytes) at the span's place in the image, over what it held."""
        offset = 0
        for start, size in self.pieces(span):
            self.image.add(start, data[offset:offset + size], overwrite=True)
            offset += size

    def lacking(self, span: Span) -> list[AddressRange]:
        """The image addresses of the span's bytes the image does not hold (empty: it holds them all)."""
        held = self.image.ranges
        return [part for start, size in self.pieces(span) for part in AddressRange(start, start + size).outside(held)]

    def pieces(self, span: Span) -> list[tuple[int, int]]:
        """``(image address, size)`` of the span's bytes, in order (a span may cross mappings)."""
        found = []
        address = span.address
        while address < span.end:
            step = self._run(address, span.end, span.extension)
            found.append((self.image_address(address, span.extension), step))
            address += step
        return found

    def fetch(self, spans: list[Span]) -> dict[Span, bytes]:
        return {span: self.read(span) for span in spans}

    def held(self, area: CalibrationArea) -> list[Span]:
        """The parts of ``area`` the image holds, at ECU addresses, in address order."""
        if area.name in self._as_is:
            pieces = [(area.span.address, area.span.address, area.span.size)]
        else:
            pieces = area.flash_ranges()
        held = []
        for ecu, flash, length in pieces:
            for start, data in self.image.crop(flash, flash + length).segments:
                held.append(Span(start - flash + ecu, len(data), area.span.extension))
        return sorted(held)

    def _run(self, address: int, end: int, extension: int) -> int:
        """How many bytes from ``address`` (before ``end``) map in one piece."""
        for area in self.areas:
            if area.contains(Span(address, 1, extension)):
                if area.name in self._as_is:
                    return min(end, area.span.end) - address
                for ecu, _, length in area.flash_ranges():
                    if ecu <= address < ecu + length:
                        return min(end, ecu + length) - address
        following = [a.span.address for a in self.areas if a.span.extension == extension and a.span.address > address]
        return min([end] + following) - address


class ImageEpk(NamedTuple):
    """What an image holds at one ADDR_EPK."""

    place: EpkAddress
    span: Span  # the EPK's bytes at the ECU's addresses (as long as MOD_PAR's EPK)
    text: str | None  # latin-1; None: the image lacks a byte of it

    @property
    def label(self) -> str:
        """Where it lies, for a message: "CALIB (FC0000h)"."""
        return f"{self.place.part or 'ADDR_EPK'} ({self.place.address:X}h)"


def image_epks(view: ImageView, doc: "A2lDocument", module: str | None = None) -> list[ImageEpk]:
    """The EPK ``view`` holds at each MOD_PAR ADDR_EPK, read through the calibration areas' mapping as every address
    (an ADDR_EPK naming CAL RAM is read in the s19's CAL ROM); empty when the A2L states no EPK. Every ADDR_EPK counts,
    whichever comes first: an s19 of the calibration data holds CALIB's only, a whole build's each part's."""
    expected = doc.epk(module)
    if expected is None:
        return []
    size = len(expected.encode("latin-1"))
    found = []
    for place in doc.epk_addresses(module):
        span = Span(place.address, size)
        found.append(ImageEpk(place, span, None if view.lacking(span) else view.read(span).decode("latin-1")))
    return found
