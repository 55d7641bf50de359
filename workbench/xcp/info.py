"""What an XCP slave says about itself, decoded from its responses into plain data.

Each ``parse_*`` takes a positive response's payload (the bytes after the 0xFF PID) and the
slave's byte order (``"<"`` little, ``">"`` big: CONNECT's COMM_MODE_BASIC bit 0 says which).
Field names follow the XCP 1.x protocol layer specification.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

from workbench.errors import WorkbenchError
from workbench.xcp_protocol import TIME_UNIT_S, Resource

__all__ = [
    "CONNECT_RESPONSE_SIZE", "CommModeInfo", "ConnectInfo", "DaqEventInfo", "DaqListInfo", "DaqProcessorInfo", "DaqResolutionInfo",
    "PagProcessorInfo",
    "PgmProcessorInfo", "ProgramStartInfo", "SectorInfo", "Status", "data_per_frame", "program_block_size",
]

IDENTIFICATION_FIELDS = ("ABSOLUTE", "RELATIVE_BYTE", "RELATIVE_WORD", "RELATIVE_WORD_ALIGNED")
PID_SIZES = {"ABSOLUTE": 1, "RELATIVE_BYTE": 2, "RELATIVE_WORD": 3, "RELATIVE_WORD_ALIGNED": 4}
_ADDRESS_EXTENSIONS = ("free", "per ODT", "invalid", "per DAQ list")
_OVERLOAD = ("none", "PID", "event", "invalid")


def _unpack(fmt: str, payload: bytes, what: str) -> tuple:
    size = struct.calcsize(fmt)
    if len(payload) < size:
        raise WorkbenchError(f"XCP {what}: the response has {len(payload) + 1} bytes, expected {size + 1}")
    return struct.unpack_from(fmt, payload)


CONNECT_RESPONSE_SIZE = 8  # PID, RESOURCE, COMM_MODE_BASIC, MAX_CTO, MAX_DTO (WORD), protocol and transport versions


@dataclass(frozen=True)
class ConnectInfo:
    resources: Resource  # what the slave offers (CAL/PAG, DAQ, STIM, PGM)
    byte_order: str  # "<" (Intel, MSB_LAST) or ">" (Motorola, MSB_FIRST)
    address_granularity: int  # bytes per address unit
    slave_block_mode: bool
    optional_comm_mode: bool  # GET_COMM_MODE_INFO is available
    max_cto: int
    max_dto: int
    protocol_version: int
    transport_version: int

    @classmethod
    def parse(cls, payload: bytes) -> ConnectInfo:
        resource, basic, max_cto = _unpack("BBB", payload, "CONNECT")
        order = ">" if basic & 0x01 else "<"
        max_dto, protocol, transport = _unpack(f"{order}3xHBB", payload, "CONNECT")
        return cls(Resource(resource & 0x1D), order, 1 << ((basic >> 1) & 0x03), bool(basic & 0x40),
                   bool(basic & 0x80), max_cto, max_dto, protocol, transport)

    @staticmethod
    def problem(packet: bytes, max_packet: int) -> str | None:
        """What makes ``packet`` (PID 0xFF first) no answer to CONNECT on a transport that carries packets of up to
        ``max_packet`` bytes (8 on CAN, a CAN FD frame's MAX_DLC, 0xFFFF on Ethernet); None: it is one.

        A positive response carries no command tag: a late answer to an earlier session's command, or another
        master's, looks the same until its fields are read.
        """
        if len(packet) < CONNECT_RESPONSE_SIZE:
            return f"{len(packet)} bytes, a CONNECT response has {CONNECT_RESPONSE_SIZE}"
        basic, max_cto = packet[2], packet[3]
        max_dto = int.from_bytes(packet[4:6], "big" if basic & 0x01 else "little")
        if (basic >> 1) & 0x03 == 0x03:
            return "address granularity 3, which is reserved"
        for name, size in (("MAX_CTO", max_cto), ("MAX_DTO", max_dto)):
            if size < 8:
                return f"{name} {size}, below 8"
            if size > max_packet:
                fd = (" (XCP on CAN FD? the A2L's XCP_ON_CAN has no CAN_FD block)" if max_packet == 8 < size <= 64
                      else "")
                return f"{name} {size}, more than the {max_packet} bytes the transport carries{fd}"
        if packet[6] == 0:
            return "XCP protocol layer version 0, not 1"
        return None


@dataclass(frozen=True)
class Status:
    session_status: int
    protected: Resource  # the resources that need seed & key now
    session_configuration_id: int

    @property
    def daq_running(self) -> bool:
        return bool(self.session_status & 0x40)

    @classmethod
    def parse(cls, payload: bytes, order: str) -> Status:
        session, protection, config_id = _unpack(f"{order}BBxH", payload, "GET_STATUS")
        return cls(session, Resource(protection & 0x1D), config_id)


@dataclass(frozen=True)
class CommModeInfo:
    master_block_mode: bool
    interleaved_mode: bool
    max_bs: int  # frames in a master block (DOWNLOAD + DOWNLOAD_NEXT ...)
    min_st_s: float  # pause between the frames of a master block
    queue_size: int
    driver_version: int

    @classmethod
    def parse(cls, payload: bytes) -> CommModeInfo:
        optional, max_bs, min_st, queue, version = _unpack("xBxBBBB", payload, "GET_COMM_MODE_INFO")
        return cls(bool(optional & 0x01), bool(optional & 0x02), max_bs, min_st * 100e-6, queue, version)


@dataclass(frozen=True)
class DaqProcessorInfo:
    dynamic: bool
    prescaler_supported: bool
    resume_supported: bool
    timestamp_supported: bool
    pid_off_supported: bool
    overload_indication: str  # none, PID (msb of the PID), event (EV_DAQ_OVERLOAD)
    max_daq: int
    max_event_channels: int  # 0: unknown
    min_daq: int  # predefined, read-only lists
    optimisation_type: int
    address_extension: str  # free, per ODT, per DAQ list
    identification_field: str  # ABSOLUTE, RELATIVE_BYTE, RELATIVE_WORD, RELATIVE_WORD_ALIGNED

    @property
    def pid_size(self) -> int:
        """Bytes in front of a DTO's data (and of its timestamp) that identify list and ODT."""
        return PID_SIZES[self.identification_field]

    @classmethod
    def parse(cls, payload: bytes, order: str) -> DaqProcessorInfo:
        properties, max_daq, max_event, min_daq, key = _unpack(f"{order}BHHBB", payload, "GET_DAQ_PROCESSOR_INFO")
        return cls(
            dynamic=bool(properties & 0x01), prescaler_supported=bool(properties & 0x02),
            resume_supported=bool(properties & 0x04), timestamp_supported=bool(properties & 0x10),
            pid_off_supported=bool(properties & 0x20), overload_indication=_OVERLOAD[(properties >> 6) & 0x03],
            max_daq=max_daq, max_event_channels=max_event, min_daq=min_daq, optimisation_type=key & 0x0F,
            address_extension=_ADDRESS_EXTENSIONS[(key >> 4) & 0x03],
            identification_field=IDENTIFICATION_FIELDS[(key >> 6) & 0x03],
        )


@dataclass(frozen=True)
class DaqResolutionInfo:
    granularity: int  # an ODT entry's size is a multiple of this (bytes)
    max_entry_size: int  # bytes one ODT entry may hold (not an ODT's capacity)
    timestamp_size: int  # bytes: 0 (none), 1, 2 or 4
    timestamp_fixed: bool  # timestamps cannot be switched off
    timestamp_unit_s: float
    timestamp_ticks: int  # units per count

    @property
    def timestamp_resolution_s(self) -> float:
        return self.timestamp_unit_s * self.timestamp_ticks

    @classmethod
    def parse(cls, payload: bytes, order: str) -> DaqResolutionInfo:
        granularity, max_entry, _, _, mode, ticks = _unpack(f"{order}BBBBBH", payload, "GET_DAQ_RESOLUTION_INFO")
        size = mode & 0x07
        if size not in (0, 1, 2, 4):
            raise WorkbenchError(f"XCP GET_DAQ_RESOLUTION_INFO: timestamp size {size} is not 0, 1, 2 or 4")
        unit = (mode >> 4) & 0x0F
        return cls(max(granularity, 1), max_entry, size, bool(mode & 0x08), TIME_UNIT_S.get(unit, 1e-6), max(ticks, 1))


@dataclass(frozen=True)
class DaqListInfo:
    """GET_DAQ_LIST_INFO: what one DAQ list of a static configuration (or a predefined list) can hold."""

    number: int
    predefined: bool  # configured by the slave: the master cannot change it
    fixed_event: int | None  # EVENT_FIXED: the only event the list samples on (None: the master chooses)
    direction: str  # DAQ, STIM, DAQ_STIM
    max_odt: int  # ODTs in the list
    max_odt_entries: int  # entries in each of its ODTs

    @property
    def configurable_daq(self) -> bool:
        """The master can fill it for measuring: not predefined, DAQ direction, room for an entry."""
        return not self.predefined and "DAQ" in self.direction and self.max_odt > 0 and self.max_odt_entries > 0

    @classmethod
    def parse(cls, number: int, payload: bytes, order: str) -> DaqListInfo:
        properties, max_odt, max_entries, event = _unpack(f"{order}BBBH", payload, "GET_DAQ_LIST_INFO")
        direction = {0x08: "STIM", 0x0C: "DAQ_STIM"}.get(properties & 0x0C, "DAQ")  # 0b00 (XCP 1.0 slaves): DAQ
        return cls(number, bool(properties & 0x01), event if properties & 0x02 else None, direction, max_odt,
                   max_entries)


@dataclass(frozen=True)
class DaqEventInfo:
    number: int
    name: str
    direction: str  # DAQ, STIM, DAQ_STIM
    max_daq_lists: int
    period_s: float | None  # None: not cyclic
    priority: int
    consistency: str  # ODT, DAQ, EVENT

    @classmethod
    def parse(cls, number: int, payload: bytes, name: str = "") -> DaqEventInfo:
        properties, max_lists, _, cycle, unit, priority = _unpack("BBBBBB", payload, "GET_DAQ_EVENT_INFO")
        direction = {0x04: "DAQ", 0x08: "STIM", 0x0C: "DAQ_STIM"}.get(properties & 0x0C, "DAQ")
        consistency = {0x00: "ODT", 0x40: "DAQ", 0x80: "EVENT"}.get(properties & 0xC0, "ODT")
        period = cycle * TIME_UNIT_S.get(unit, 1e-3) if cycle else None
        return cls(number, name, direction, max_lists, period, priority, consistency)

    @staticmethod
    def name_length(payload: bytes) -> int:
        return _unpack("BBB", payload, "GET_DAQ_EVENT_INFO")[2]


@dataclass(frozen=True)
class PagProcessorInfo:
    max_segments: int
    freeze_supported: bool

    @classmethod
    def parse(cls, payload: bytes) -> PagProcessorInfo:
        segments, properties = _unpack("BB", payload, "GET_PAG_PROCESSOR_INFO")
        return cls(segments, bool(properties & 0x01))


@dataclass(frozen=True)
class ProgramStartInfo:
    master_block_mode: bool
    interleaved_mode: bool
    slave_block_mode: bool
    max_cto_pgm: int
    max_bs_pgm: int
    min_st_pgm_s: float
    queue_size_pgm: int

    @classmethod
    def parse(cls, payload: bytes) -> ProgramStartInfo:
        mode, max_cto, max_bs, min_st, queue = _unpack("xBBBBB", payload, "PROGRAM_START")
        return cls(bool(mode & 0x01), bool(mode & 0x02), bool(mode & 0x40), max_cto, max_bs, min_st * 100e-6, queue)


def data_per_frame(max_cto: int, granularity: int) -> int:
    """Data bytes of a DOWNLOAD/PROGRAM/_NEXT frame: whole elements after command, count and alignment."""
    return (max_cto - max(2, granularity)) // granularity * granularity


def program_block_size(max_cto: int, granularity: int, *, max_bs: int | None = None, use_max: bool = False) -> int:
    """Bytes programmed per response, in frames of ``max_cto`` (MAX_CTO_PGM): in master block mode (``max_bs``: its
    MAX_BS_PGM) a block of whole frames, at most 1 + ``max_bs`` of them and 255 elements; else one PROGRAM_MAX
    (``use_max``: one byte more a frame) or PROGRAM frame. The rule of the master (from PROGRAM_START) and of the
    flash plan's estimate (from the A2L)."""
    per_frame = data_per_frame(max_cto, granularity)
    if max_bs is not None:
        return min(255 * granularity // per_frame, 1 + max_bs) * per_frame
    return (max_cto - granularity) // granularity * granularity if use_max else per_frame


@dataclass(frozen=True)
class PgmProcessorInfo:
    absolute_mode: bool
    functional_mode: bool
    compression_supported: bool
    encryption_supported: bool
    non_sequential_supported: bool
    max_sectors: int

    @classmethod
    def parse(cls, payload: bytes) -> PgmProcessorInfo:
        properties, sectors = _unpack("BB", payload, "GET_PGM_PROCESSOR_INFO")
        return cls(bool(properties & 0x01), bool(properties & 0x02), bool(properties & 0x0C),
                   bool(properties & 0x30), bool(properties & 0xC0), sectors)


@dataclass(frozen=True)
class SectorInfo:
    number: int
    clear_sequence: int  # the order the master clears sectors in
    program_sequence: int  # the order it programs them in
    program_method: int
    address: int
    length: int  # bytes

    @classmethod
    def parse(cls, number: int, start_payload: bytes, length_payload: bytes, order: str) -> SectorInfo:
        """From GET_SECTOR_INFO mode 0 (start address) and mode 1 (length) of sector ``number``."""
        clear, program, method, address = _unpack(f"{order}BBBI", start_payload, "GET_SECTOR_INFO")
        length = _unpack(f"{order}3xI", length_payload, "GET_SECTOR_INFO")[0]
        return cls(number, clear, program, method, address, length)
