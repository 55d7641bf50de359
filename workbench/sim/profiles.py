"""Slave profiles: the demo ECU served through other, equally conforming implementations of ASAM XCP's options.

A real ECU implements the optional parts of XCP its own way: its DAQ lists numbered after predefined
ones, its calibrations in segment 1, Motorola byte order, a seed longer than a frame, a boot loader with
few programming commands. A :class:`SlaveProfile` is one such way, stated as a small difference from the
demo's :class:`~workbench.sim.xcp.parameters.XcpParameters`: fields replaced for every transport, for XCP
on CAN or on Ethernet only, in the DAQ processor, in programming (PgmParameters), the flash's sector
sizes, and (for a slow slave or flash) the A2L's timeouts. Where the difference is
something the A2L states (byte order, granularity, segments, DAQ, packet sizes, commands), the profile's
A2L says so too (:mod:`workbench.sim.profile_a2l`): a master reads the truth from it, as from a real ECU's.

``workbench sim --profile NAME`` and ``serve_demo(profile=NAME)`` serve one; docs/slave-profiles.md
lists them with the option each exercises.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

from workbench.errors import InputError
from workbench.image import AddressRange, ChecksumType
from workbench.sim.memory_map import MemoryMap
from workbench.sim.xcp.parameters import DEMO_STATIC_LISTS, PredefinedDaqList, XcpParameters
from workbench.xcp_protocol import CanId, Cmd, Resource

__all__ = ["PROFILES", "SlaveProfile", "profile"]


@dataclass(frozen=True)
class SlaveProfile:
    """How one slave differs from the demo's; every mapping names fields of the parameter class it replaces."""

    name: str
    changes: str  # what differs from the demo, in a line
    exercises: str  # the part of ASAM XCP a master must get right for it
    xcp: Mapping[str, Any] = field(default_factory=dict)  # XcpParameters, every transport
    daq: Mapping[str, Any] = field(default_factory=dict)  # DaqParameters
    can: Mapping[str, Any] = field(default_factory=dict)  # XcpParameters, XCP on CAN only
    ethernet: Mapping[str, Any] = field(default_factory=dict)  # XcpParameters, XCP on UDP/TCP only
    pgm: Mapping[str, Any] = field(default_factory=dict)  # PgmParameters: programming, every transport
    sector_sizes: Mapping[str, int] = field(default_factory=dict)  # flash regions in sectors of this size (bytes)
    timeouts_ms: Mapping[str, int] = field(default_factory=dict)  # the A2L's T1..T7 that differ from the demo's

    def parameters(self, base: XcpParameters, transport: str) -> XcpParameters:
        """``base`` (the demo's parameters for ``transport``: "CAN", "UDP" or "TCP") with this profile's changes."""
        on_transport = self.can if transport.upper() == "CAN" else self.ethernet
        return replace(base, **self.xcp, **on_transport, daq=replace(base.daq, **self.daq),
                       pgm=replace(base.pgm, **self.pgm))

    def memory_map(self, base: MemoryMap) -> MemoryMap:
        """``base`` (the demo's chip, one sector a region) with this profile's flash sectors."""
        return base.with_sector_sizes(dict(self.sector_sizes)) if self.sector_sizes else base

    @property
    def changes_a2l(self) -> bool:
        """Whether a master needs this profile's own A2L (anything but the slow pace, chatter, seeds and locks)."""
        quiet = {"response_delay_s", "delayed_every", "busy_every", "service_packets", "seed_length", "protected"}
        return bool(set(self.xcp) - quiet or set(self.can) - quiet or set(self.ethernet) - quiet or self.daq
                    or self.pgm or self.sector_sizes or self.timeouts_ms)


# The HDS9's CAL RAM: the EPK's copy (16 bytes, as at 0xFC0000 in CAL ROM), then the calibrations.
_EPK_SEGMENT = AddressRange(0x40000000, 0x40000010)
_CAL_SEGMENT = AddressRange(0x40000010, 0x40020000)
# Two lists the slave configured itself: the first RAM words on the 4 ms and the 100 ms event.
_PREDEFINED = (PredefinedDaqList(0, ((0x40020000, 4), (0x40020004, 4))), PredefinedDaqList(2, ((0x40020008, 4),)))
# Flash in small sectors, as most microcontrollers have: 64 KiB in code flash, 16 KiB in data flash.
_SMALL_SECTORS = {"APPLICATIVE": 0x10000, "CALIB": 0x4000, "SHARED": 0x4000}
# What a small boot loader leaves out: all but the four mandatory programming commands, and checksums.
_BOOT_LOADER_LACKS = frozenset({Cmd.GET_PGM_PROCESSOR_INFO, Cmd.GET_SECTOR_INFO, Cmd.PROGRAM_NEXT, Cmd.PROGRAM_MAX,
                                Cmd.BUILD_CHECKSUM})

# What a slave may leave out of the optional commands a master would use (it has the alternatives).
_FEW_COMMANDS_LACK = frozenset({Cmd.SHORT_UPLOAD, Cmd.GET_COMM_MODE_INFO, Cmd.GET_DAQ_PROCESSOR_INFO,
                                Cmd.GET_DAQ_RESOLUTION_INFO, Cmd.GET_DAQ_EVENT_INFO})

PROFILES: dict[str, SlaveProfile] = {p.name: p for p in (
    SlaveProfile("demo", "nothing: the demo ECU as docs/demo-ecu.md describes it",
                 "the reference: dynamic DAQ (MAX_DAQ 16), absolute ODT numbers, one segment, Intel, BYTE"),
    SlaveProfile("daq-counted",
                 "GET_DAQ_PROCESSOR_INFO's MAX_DAQ counts the lists allocated so far: 0 before ALLOC_DAQ",
                 "MAX_DAQ = MIN_DAQ + DAQ_COUNT of a dynamic configuration (the limit shows only as "
                 "ERR_MEMORY_OVERFLOW)", daq={"max_daq_counts_allocated": True}),
    SlaveProfile("daq-predefined", "two predefined DAQ lists (MIN_DAQ 2, on the 4 ms and 100 ms events) before the "
                 "allocated ones; MAX_DAQ counts them and the allocated lists",
                 "MIN_DAQ > 0: dynamic lists numbered from MIN_DAQ, PIDs after the predefined ODTs",
                 daq={"predefined": _PREDEFINED, "max_daq_counts_allocated": True}),
    SlaveProfile("static-daq", "four static DAQ lists (two fixed to the 4 ms and 50 ms events), no ALLOC_*",
                 "DAQ_CONFIG_TYPE static: GET_DAQ_LIST_INFO, CLEAR_DAQ_LIST", daq={"static_lists": DEMO_STATIC_LISTS}),
    SlaveProfile("segments", "the EPK in segment 0 of its own, the calibrations in segment 1",
                 "pages by segment: SET_CAL_PAGE 'all segments' (mode 0x80), GET/SET_CAL_PAGE of the object's "
                 "segment", xcp={"segments": (_EPK_SEGMENT, _CAL_SEGMENT)}),
    SlaveProfile("segments-one-by-one", "as 'segments', and SET_CAL_PAGE's 'all segments' mode is refused "
                 "(ERR_MODE_NOT_VALID)", "switching every segment that holds calibrations, one by one",
                 xcp={"segments": (_EPK_SEGMENT, _CAL_SEGMENT), "all_segments_mode": False}),
    SlaveProfile("motorola", "XCP's own byte order is Motorola (BYTE_ORDER_MSB_FIRST); the data stay Intel "
                 "(MOD_COMMON); BUILD_CHECKSUM sums DWORDs (ADD_44) in Motorola order, at most 0xFFFF bytes at once",
                 "multi-byte command and response fields, DTO timestamps and list numbers in the slave's byte "
                 "order; a checksum's words too, and blocks no larger than its ERR_OUT_OF_RANGE (or A2L) says",
                 xcp={"byte_order": ">", "checksum_type": ChecksumType.ADD_44, "max_checksum_block": 0xFFFF}),
    SlaveProfile("granularity-word", "address granularity WORD: transfers count 2-byte elements from even addresses",
                 "ADDRESS_GRANULARITY_WORD: element counts, alignment bytes, reads and writes widened to whole "
                 "elements", xcp={"address_granularity": 2}, daq={"granularity": 2}),
    SlaveProfile("granularity-dword", "address granularity DWORD: transfers count 4-byte elements from addresses "
                 "divisible by 4", "ADDRESS_GRANULARITY_DWORD (two alignment bytes in DOWNLOAD, three in UPLOAD)",
                 xcp={"address_granularity": 4}, daq={"granularity": 4}),
    SlaveProfile("motorola-word", "Motorola byte order (BYTE_ORDER_MSB_FIRST) and address granularity WORD together, "
                 "as a 16-bit big-endian controller's XCP: counts in 2-byte elements, every field and timestamp "
                 "MSB first", "both options at once: element counts and alignment bytes in the slave's byte order",
                 xcp={"byte_order": ">", "address_granularity": 2}, daq={"granularity": 2}),
    SlaveProfile("few-commands", "optional commands left out: SHORT_UPLOAD, GET_COMM_MODE_INFO (CONNECT says so), "
                 "GET_DAQ_PROCESSOR_INFO, GET_DAQ_RESOLUTION_INFO, GET_DAQ_EVENT_INFO (ERR_CMD_UNKNOWN; not in "
                 "OPTIONAL_CMD)", "SET_MTA + UPLOAD for every read; the DAQ processor, resolution and events from the "
                 "A2L (ASAM: 'use the A2L'); no master block mode without GET_COMM_MODE_INFO",
                 xcp={"without": _FEW_COMMANDS_LACK}),
    SlaveProfile("busy", "every 7th command (a master block's first frame too) is refused with ERR_CMD_BUSY before it "
                 "runs (T7 10 ms)",
                 "ERR_CMD_BUSY: wait T7 and send the command again (ASAM's error matrix), never an error for people",
                 xcp={"busy_every": 7}, timeouts_ms={"t7": 10}),
    SlaveProfile("no-get-id", "GET_ID is not implemented (ERR_CMD_UNKNOWN)", "the EPK read at ADDR_EPK",
                 xcp={"get_id": False}),
    SlaveProfile("odt-relative-byte", "DTOs name their ODT relative to the list, then the list in a byte",
                 "IDENTIFICATION_FIELD_TYPE_RELATIVE_BYTE", daq={"identification_field": "RELATIVE_BYTE"}),
    SlaveProfile("odt-relative-word", "DTOs name their ODT relative to the list, then the list in a word",
                 "IDENTIFICATION_FIELD_TYPE_RELATIVE_WORD", daq={"identification_field": "RELATIVE_WORD"}),
    SlaveProfile("odt-relative-word-aligned", "as odt-relative-word with a fill byte before the list's word",
                 "IDENTIFICATION_FIELD_TYPE_RELATIVE_WORD_ALIGNED",
                 daq={"identification_field": "RELATIVE_WORD_ALIGNED"}),
    SlaveProfile("timestamp-byte", "1-byte DAQ timestamps in 1 ms units (they wrap every 256 ms)",
                 "TIMESTAMP_SUPPORTED SIZE_BYTE: unwrapping a fast-wrapping counter",
                 daq={"timestamp_size": 1, "timestamp_unit": 6, "timestamp_ticks": 1}),
    SlaveProfile("timestamp-word-fixed", "2-byte DAQ timestamps counting 10 ticks of 1 us, always sent",
                 "TIMESTAMP_SUPPORTED SIZE_WORD, TIMESTAMP_TICKS > 1, TIMESTAMP_FIXED",
                 daq={"timestamp_size": 2, "timestamp_unit": 3, "timestamp_ticks": 10, "timestamp_fixed": True}),
    SlaveProfile("sporadic-events", "the events state no cycle (A2L EVENT cycle 0, GET_DAQ_EVENT_INFO not cyclic) "
                 "though they are raised as the tasks run; 4-byte timestamps counting 1 ns (they wrap every 4.3 s): "
                 "as XCPlite's (docs/slave-profiles.md)",
                 "no silence to expect from a cyclic event: a lost ECU is found by asking it (GET_STATUS after 1 s "
                 "without a DTO); TIMESTAMP UNIT_1NS", xcp={"events_cyclic": False},
                 daq={"timestamp_size": 4, "timestamp_unit": 0, "timestamp_ticks": 1}),
    SlaveProfile("no-timestamp", "no DAQ timestamps at all", "no TIMESTAMP_SUPPORTED: samples timed by their arrival",
                 daq={"timestamp_size": 0}),
    SlaveProfile("no-block-mode", "no slave block mode, no master block mode (GET_COMM_MODE_INFO says MAX_BS 1), "
                 "one frame a PROGRAM", "one UPLOAD, DOWNLOAD or PROGRAM per packet",
                 xcp={"slave_block_mode": False, "master_block_mode": False, "max_bs": 1}),
    SlaveProfile("large-packets", "CAN FD with 64-byte frames (MAX_CTO = MAX_DTO = 64); on Ethernet the demo's "
                 "MAX_CTO 255 and MAX_DTO 1024", "XCP on CAN FD (CAN_FD MAX_DLC 64), large packets",
                 can={"can_fd": True, "max_cto": 64, "max_dto": 64, "max_dlc_required": False}),
    SlaveProfile("daq-can-ids", "DAQ lists 0 and 1 send their DTOs on CAN ids of their own, 0x7F2 and 0x7F3 "
                 "(DAQ_LIST_CAN_ID FIXED); the other lists on CAN_ID_SLAVE; on Ethernet the demo",
                 "DTOs on ids beside CAN_ID_SLAVE (the A2L's DAQ_LIST_CAN_ID, GET_DAQ_ID)",
                 can={"daq_can_ids": ((0, CanId(0x7F2)), (1, CanId(0x7F3)))}),
    SlaveProfile("daq-can-ids-variable", "DAQ lists 0 and 1 send on CAN ids the master sets with SET_DAQ_ID "
                 "(DAQ_LIST_CAN_ID VARIABLE; until then on 0x7F4/0x7F5, which the A2L does not state), list 2 on "
                 "0x7F3 (FIXED: SET_DAQ_ID refused, ERR_OUT_OF_RANGE); the other lists on CAN_ID_SLAVE; on "
                 "Ethernet the demo",
                 "SET_DAQ_ID for VARIABLE lists after their setup and before START_STOP, the link listening there; "
                 "GET_DAQ_ID (fixed or configurable)",
                 can={"daq_can_ids": ((2, CanId(0x7F3)),),
                      "variable_daq_can_ids": ((0, CanId(0x7F4)), (1, CanId(0x7F5)))}),
    SlaveProfile("long-seed", "seeds (and keys) of 20 bytes on CAN, 255 on Ethernet: more than one packet carries",
                 "GET_SEED mode 1 for the rest of a seed, a key in several UNLOCKs",
                 can={"seed_length": 20}, ethernet={"seed_length": 255}),
    SlaveProfile("unlocked", "no seed & key: CAL/PAG, DAQ and PGM are open at CONNECT",
                 "resources unprotected (GET_STATUS says none; no GET_SEED needed)", xcp={"protected": Resource(0)}),
    SlaveProfile("slow", "every 16th response leaves 150 ms late, half the A2L's T1 of 300 ms (a slave busy now "
                 "and then; the answers after a late one wait their turn)",
                 "waiting out T1 as the A2L states it; a late answer never taken for the next command's",
                 xcp={"response_delay_s": 0.15, "delayed_every": 16}, timeouts_ms={"t1": 300}),
    SlaveProfile("chatty", "an EV_USER or a SERV_TEXT packet before every response",
                 "EV and SERV packets between responses (they are no answers)", xcp={"service_packets": True}),
    SlaveProfile("boot-minimal", "a small boot loader: of the programming commands only the mandatory PROGRAM_START, "
                 "PROGRAM_CLEAR, PROGRAM and PROGRAM_RESET, no BUILD_CHECKSUM; flash sectors of 64 KiB (APPLICATIVE) "
                 "and 16 KiB (CALIB, SHARED) that only its A2L states, written a 256-byte page at a time (a page's "
                 "data wait in RAM until it is full or a PROGRAM with size 0 ends the segment)",
                 "the A2L's SECTORs without GET_PGM_PROCESSOR_INFO/GET_SECTOR_INFO; one PROGRAM a frame; PROGRAM "
                 "with size 0 after each range; verification (and cache sync) by UPLOAD",
                 xcp={"without": _BOOT_LOADER_LACKS}, pgm={"master_block_mode": False, "page_size": 256},
                 sector_sizes=_SMALL_SECTORS),
    SlaveProfile("slow-flash", "PROGRAM_CLEAR answers 0.6 s late, longer than its A2L's T4 (400 ms; T1 300 ms), with "
                 "an EV_CMD_PENDING every 150 ms meanwhile; the ECU boots 1 s after PROGRAM_RESET answering nothing "
                 "(T6 400 ms); PROGRAM in master blocks of its own (MAX_BS_PGM 8, MIN_ST_PGM 0.5 ms, MAX_CTO_PGM 32 "
                 "on Ethernet) while DOWNLOAD has no master block mode",
                 "T4 (not T1) for an erase, restarted by EV_CMD_PENDING; CONNECT tried again (T6 each) until the ECU "
                 "has booted; PROGRAM_START's MAX_CTO_PGM, MAX_BS_PGM and MIN_ST_PGM, not the other commands'",
                 xcp={"master_block_mode": False, "max_bs": 1},
                 pgm={"master_block_mode": True, "max_bs": 8, "min_st_100us": 5, "max_cto": 32, "erase_s": 0.6,
                      "pending_s": 0.15, "boot_s": 1.0}, timeouts_ms={"t1": 300, "t4": 400, "t6": 400}),
)}


def profile(name: str) -> SlaveProfile:
    """The profile called ``name``. :raises InputError: no such profile (the message lists them)."""
    try:
        return PROFILES[name]
    except KeyError:
        raise InputError(f"no slave profile {name!r}; the profiles are: {', '.join(PROFILES)}") from None
