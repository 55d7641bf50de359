"""The XCP slave's published parameters: what the A2L's IF_DATA XCP must state.

These are the simulator's truth (docs/demo-ecu.md); a test checks the demo A2L against them.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from workbench.image import AddressRange, ChecksumType
from workbench.sim.seedkey import SEED_LENGTH
from workbench.xcp_protocol import (
    MAX_DAQ_PID,
    TIME_UNIT_S,
    CanCmd,
    CanId,
    Cmd,
    Resource,
)

__all__ = ["DEMO_STATIC_LISTS", "IDENTIFICATION_FIELDS", "DaqParameters", "EventChannel", "PgmParameters",
           "PredefinedDaqList", "StaticDaqList", "XcpParameters"]

# time unit codes (seconds: TIME_UNIT_S) of GET_DAQ_RESOLUTION_INFO's TIMESTAMP_MODE bits 4..7 and
# of GET_DAQ_EVENT_INFO: code n counts 10**(n - 9) s (0: 1 ns ... 6: 1 ms ... 9: 1 s)
TIMESTAMP_UNIT_10US = 0x4
EVENT_TIME_UNIT_1MS = 6
EVENT_TIME_UNITS = range(10)


@dataclass(frozen=True)
class EventChannel:
    """A DAQ event channel: raised after the task with the same period ran."""

    number: int
    name: str
    period_s: float
    priority: int = 0

    @property
    def cycle(self) -> tuple[int, int]:
        """GET_DAQ_EVENT_INFO's EVENT_CHANNEL_TIME_CYCLE (a byte) and _TIME_UNIT for the period.

        Whole milliseconds up to 255 keep the unit 1 ms, as the A2L states them; other periods
        (a 1000 ms task, a 0.5 ms one) take the finest unit that counts them in a byte. A period
        no unit can express (over 255 s; an A2L cannot state one either) reads as not cyclic (0).
        """
        counts = {unit: self.period_s * 10 ** (9 - unit) for unit in EVENT_TIME_UNITS}
        whole = [unit for unit, count in counts.items() if abs(count - round(count)) < 1e-6 and 0 < round(count) <= 0xFF]
        fitting = [unit for unit, count in counts.items() if 0 < round(count) <= 0xFF]
        if EVENT_TIME_UNIT_1MS in whole:
            unit = EVENT_TIME_UNIT_1MS
        elif whole or fitting:
            unit = min(whole or fitting)
        else:
            return 0, EVENT_TIME_UNIT_1MS
        return round(counts[unit]), unit


@dataclass(frozen=True)
class StaticDaqList:
    """A DAQ list of a static configuration: ``odts`` ODTs of ``entries`` ODT entries each, all there from
    power-on (the master only fills the entries); ``fixed_event``: the one event it samples on (EVENT_FIXED),
    None when the master chooses."""

    odts: int
    entries: int
    fixed_event: int | None = None


@dataclass(frozen=True)
class PredefinedDaqList:
    """A DAQ list the slave configured itself (PREDEFINED, numbered below MIN_DAQ): one ODT of ``entries``
    ((address, size) pairs) sampled on ``event``; the master may start it but not change it."""

    event: int
    entries: tuple[tuple[int, int], ...]


IDENTIFICATION_FIELDS = ("ABSOLUTE", "RELATIVE_BYTE", "RELATIVE_WORD", "RELATIVE_WORD_ALIGNED")
PID_SIZES = {"ABSOLUTE": 1, "RELATIVE_BYTE": 2, "RELATIVE_WORD": 3, "RELATIVE_WORD_ALIGNED": 4}


# The lists `workbench sim --static-daq` offers: one fixed to each of Task4ms and Task50ms, two for any event
# (the 4 ms task's thirteen floats fill list 0 exactly; all Task50ms signals fit list 1).
DEMO_STATIC_LISTS = (
    StaticDaqList(odts=8, entries=3, fixed_event=0),
    StaticDaqList(odts=12, entries=3, fixed_event=1),
    StaticDaqList(odts=16, entries=4),
    StaticDaqList(odts=4, entries=4),
)


@dataclass(frozen=True)
class DaqParameters:
    max_daq: int = 16  # DAQ lists (predefined ones included) a dynamic configuration can hold; static: their number
    max_odt_total: int = MAX_DAQ_PID + 1  # one absolute PID (0x00..0xFB) per ODT of all lists
    max_odt_entry_size: int = 4  # MAX_ODT_ENTRY_SIZE_DAQ, bytes: smaller than a DTO's payload on purpose
    granularity: int = 1  # GRANULARITY_ODT_ENTRY_SIZE_DAQ
    timestamp_size: int = 4  # bytes (0: no timestamps), in the first ODT of each list whose mode asks for them
    timestamp_unit: int = TIMESTAMP_UNIT_10US
    timestamp_ticks: int = 1
    timestamp_fixed: bool = False  # TIMESTAMP_FIXED: every list is timestamped, whatever its mode says
    identification_field: str = "ABSOLUTE"  # how a DTO names its list and ODT (IDENTIFICATION_FIELDS)
    static_lists: tuple[StaticDaqList, ...] = ()  # given: static DAQ configuration (no ALLOC_*), these lists only
    predefined: tuple[PredefinedDaqList, ...] = ()  # MIN_DAQ lists of a dynamic configuration, before the allocated
    max_daq_counts_allocated: bool = False  # GET_DAQ_PROCESSOR_INFO's MAX_DAQ = MIN_DAQ + lists allocated so far

    def __post_init__(self) -> None:
        if sum(daq.odts for daq in self.static_lists) > self.max_odt_total:
            raise ValueError(f"static DAQ lists with more than {self.max_odt_total} ODTs: absolute PIDs run out")
        if any(not (1 <= daq.odts <= 0xFF and 1 <= daq.entries <= 0xFF) for daq in self.static_lists):
            raise ValueError("a static DAQ list has 1..255 ODTs of 1..255 entries")
        if self.static_lists and self.predefined:
            raise ValueError("predefined DAQ lists belong to a dynamic configuration, static lists to a static one")
        if self.identification_field not in PID_SIZES:
            raise ValueError(f"identification field must be one of {', '.join(IDENTIFICATION_FIELDS)}")
        if self.timestamp_size not in (0, 1, 2, 4) or (self.timestamp_fixed and not self.timestamp_size):
            raise ValueError("timestamps are 0 (none), 1, 2 or 4 bytes; TIMESTAMP_FIXED needs some")

    @property
    def min_daq(self) -> int:
        """MIN_DAQ: the predefined lists, numbered 0..MIN_DAQ-1."""
        return len(self.predefined)

    @property
    def pid_size(self) -> int:
        """Bytes of a DTO's identification field (PID, and the list number of a relative one)."""
        return PID_SIZES[self.identification_field]

    @property
    def static(self) -> bool:
        """DAQ_CONFIG_TYPE static: the lists, ODTs and entries are fixed, ALLOC_* do not exist."""
        return bool(self.static_lists)

    @property
    def timestamp_tick_s(self) -> float:
        """Seconds per timestamp count."""
        return TIME_UNIT_S[self.timestamp_unit] * self.timestamp_ticks


@dataclass(frozen=True)
class PgmParameters:
    """How the slave programs flash where that differs from its other commands: PROGRAM_START's MAX_CTO_PGM,
    master block mode, MAX_BS_PGM and MIN_ST_PGM (None: as for DOWNLOAD), and how long its flash takes."""

    max_cto: int | None = None  # MAX_CTO_PGM: PROGRAM frames of at most this many bytes (never more than MAX_CTO)
    master_block_mode: bool | None = None  # PROGRAM + PROGRAM_NEXT blocks
    max_bs: int | None = None  # MAX_BS_PGM
    min_st_100us: int | None = None  # MIN_ST_PGM, 100 us units: the pause the master leaves between a block's frames
    erase_s: float = 0.0  # PROGRAM_CLEAR answers this late (a sector erase takes a while; the A2L's T4 covers it)
    pending_s: float = 0.0  # while it erases, an EV_CMD_PENDING every pending_s (0: none; T4 must cover the erase)
    boot_s: float = 0.0  # after PROGRAM_RESET the ECU boots this long, answering nothing (CONNECT included)
    page_size: int = 0  # bytes its driver writes at once, holding them in RAM until then (0: every frame at once)
    functional_only: bool = False  # GET_PGM_PROCESSOR_INFO: functional access mode only (absolute CLEAR refused)
    counts_sectors: bool = True  # GET_PGM_PROCESSOR_INFO's MAX_SECTOR counts them (False: 0, GET_SECTOR_INFO refused)


@dataclass(frozen=True)
class XcpParameters:
    can_id_master: CanId = CanId(0x7F0)  # master -> slave
    can_id_slave: CanId = CanId(0x7F1)  # slave -> master, responses and DTOs
    can_id_broadcast: CanId | None = None  # CAN_ID_BROADCAST: GET_SLAVE_ID answered there too (None: on can_id_master)
    daq_can_ids: tuple[tuple[int, CanId], ...] = ()  # (DAQ list, CAN id): DAQ_LIST_CAN_ID FIXED, its DTOs go there
    # (DAQ list, CAN id until SET_DAQ_ID moves it): DAQ_LIST_CAN_ID VARIABLE (the A2L states no id for them)
    variable_daq_can_ids: tuple[tuple[int, CanId], ...] = ()
    baudrate: int = 1_000_000
    max_dlc_required: bool = True  # XCP_ON_CAN MAX_DLC_REQUIRED: frames both ways have MAX_DLC (others are ignored)
    can_fd: bool = False  # XCP on CAN FD: frames of up to 64 bytes (MAX_CTO/MAX_DTO up to 64)
    max_cto: int = 8
    max_dto: int = 8
    byte_order: str = "<"  # of XCP's own multi-byte fields ("<" Intel, BYTE_ORDER_MSB_LAST; ">" Motorola)
    address_granularity: int = 1  # bytes per element of UPLOAD/DOWNLOAD/PROGRAM/...: counts and address alignment
    slave_block_mode: bool = True  # an UPLOAD of more than one response's worth is answered in several responses
    master_block_mode: bool = True  # DOWNLOAD/PROGRAM blocks of up to max_bs _NEXT frames (False: one frame each)
    max_bs: int = 42  # _NEXT frames of a master block after its DOWNLOAD/PROGRAM: (1 + 42) * 6 >= 255 bytes
    min_st_100us: int = 0
    protected: Resource = Resource.CAL_PAG | Resource.DAQ | Resource.PGM  # locked at CONNECT until UNLOCK
    seed_length: int = SEED_LENGTH  # bytes of a seed (and of its key): more than MAX_CTO - 2 take several packets
    get_id: bool = True  # GET_ID implemented (False: ERR_CMD_UNKNOWN, the EPK is read at ADDR_EPK)
    without: frozenset[Cmd] = frozenset()  # optional commands the slave does not implement (ERR_CMD_UNKNOWN)
    pgm: PgmParameters = field(default_factory=PgmParameters)
    segments: tuple[AddressRange, ...] = ()  # calibration segments 0, 1, ... in CAL RAM (none: one, all of it)
    all_segments_mode: bool = True  # SET_CAL_PAGE's mode bit 0x80 (every segment at once)
    response_delay_s: float = 0.0  # responses leave this late (a slow slave; the A2L's T1 says how slow is fine)
    delayed_every: int = 1  # ... every n-th of them (1: all)
    busy_every: int = 0  # every n-th command is refused with ERR_CMD_BUSY, once, before it runs (0: never busy)
    service_packets: bool = False  # EV and SERV packets between the responses
    checksum_type: ChecksumType = ChecksumType.CRC_32
    max_checksum_block: int = 0x20000  # BUILD_CHECKSUM limit: the SEGMENT CHECKSUM MAX_BLOCK_SIZE of the A2L
    epk_address: int = 0xFC0000
    epk_length: int = 14
    asam_mc2_name: str = "FLCU"
    ecu_text: str = "FLCU demo ECU (workbench simulated HDS9)"
    daq: DaqParameters = field(default_factory=DaqParameters)
    events_cyclic: bool = True  # False: the events state no cycle (A2L and GET_DAQ_EVENT_INFO), raised as they run
    events: tuple[EventChannel, ...] = (
        EventChannel(0, "Task4ms", 0.004),
        EventChannel(1, "Task50ms", 0.050),
        EventChannel(2, "Task100ms", 0.100),
    )

    def __post_init__(self) -> None:
        if self.byte_order not in "<>" or len(self.byte_order) != 1:
            raise ValueError(f"byte order is '<' (Intel) or '>' (Motorola), not {self.byte_order!r}")
        if self.address_granularity not in (1, 2, 4):
            raise ValueError("address granularity is 1 (BYTE), 2 (WORD) or 4 (DWORD) bytes")
        if not SEED_LENGTH <= self.seed_length <= 0xFF:
            raise ValueError(f"a seed has {SEED_LENGTH} to 255 bytes")

    @property
    def data_offset(self) -> int:
        """Where the data of a DOWNLOAD/PROGRAM/…_NEXT frame start: after command and count, on an element."""
        return max(2, self.address_granularity)

    @property
    def max_data_per_frame(self) -> int:
        """Data bytes of a DOWNLOAD/…_NEXT frame: whole elements after command, count and alignment."""
        return self._per_frame(self.max_cto)

    def _per_frame(self, max_cto: int) -> int:
        ag = self.address_granularity
        return (max_cto - self.data_offset) // ag * ag

    @property
    def max_data_per_response(self) -> int:
        """Data bytes of an UPLOAD response: whole elements after the PID and its alignment bytes."""
        ag = self.address_granularity
        return (self.max_cto - ag) // ag * ag

    @property
    def max_block_bytes(self) -> int:
        """Largest master block: the first frame and MAX_BS _NEXT frames (ASAM: MAX_BS counts the _NEXT packets),
        255 elements at most; a single frame without master block mode."""
        frames = 1 + self.max_bs if self.master_block_mode else 1
        return min(255 * self.address_granularity, frames * self.max_data_per_frame)

    @property
    def programming(self) -> PgmParameters:
        """:attr:`pgm` with every communication parameter stated (those it leaves None are DOWNLOAD's)."""
        pgm = self.pgm
        block = self.master_block_mode if pgm.master_block_mode is None else pgm.master_block_mode
        return replace(pgm, max_cto=min(pgm.max_cto or self.max_cto, self.max_cto), master_block_mode=block,
                       max_bs=self.max_bs if pgm.max_bs is None else pgm.max_bs,
                       min_st_100us=self.min_st_100us if pgm.min_st_100us is None else pgm.min_st_100us)

    def transport_commands(self, transport: str) -> frozenset[Cmd]:
        """The commands the ``transport``'s port answers itself, beside the protocol layer's: XCP on CAN's
        TRANSPORT_LAYER_CMD (GET_SLAVE_ID, GET_DAQ_ID; SET_DAQ_ID with VARIABLE lists), unless :attr:`without` names it."""
        own = {"CAN": frozenset({Cmd.TRANSPORT_LAYER_CMD})}.get(transport, frozenset())
        return own - self.without

    @property
    def can_sub_commands(self) -> frozenset[CanCmd]:
        """XCP on CAN's TRANSPORT_LAYER_CMD sub-commands the CAN port answers (the A2L's OPTIONAL_TL_SUBCMD):
        GET_SLAVE_ID and GET_DAQ_ID, SET_DAQ_ID where a list is VARIABLE; none without TRANSPORT_LAYER_CMD."""
        if Cmd.TRANSPORT_LAYER_CMD not in self.transport_commands("CAN"):
            return frozenset()
        return frozenset({CanCmd.GET_SLAVE_ID, CanCmd.GET_DAQ_ID} | ({CanCmd.SET_DAQ_ID} if self.variable_daq_can_ids
                                                                   else set()))

    @property
    def pgm_data_per_frame(self) -> int:
        """Data bytes of a PROGRAM/PROGRAM_NEXT frame of MAX_CTO_PGM bytes."""
        return self._per_frame(self.programming.max_cto)

    @property
    def pgm_block_bytes(self) -> int:
        """Largest PROGRAM block: 1 + MAX_BS_PGM frames in the programming's master block mode, else one frame."""
        pgm = self.programming
        frames = 1 + pgm.max_bs if pgm.master_block_mode else 1
        return min(255 * self.address_granularity, frames * self.pgm_data_per_frame)
