"""The XCP slave's published parameters: what the A2L's IF_DATA XCP must state.

These are the simulator's truth (docs/demo-ecu.md); a test checks the demo A2L against them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from workbench.image import ChecksumType
from workbench.xcp_protocol import MAX_DAQ_PID, TIME_UNIT_S, Resource

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
    max_daq: int = 16  # dynamic DAQ lists that can be allocated (MIN_DAQ = 0); static lists: their number
    max_odt_total: int = MAX_DAQ_PID + 1  # one absolute PID (0x00..0xFB) per ODT of all lists
    max_odt_entry_size: int = 4  # MAX_ODT_ENTRY_SIZE_DAQ, bytes: smaller than a DTO's payload on purpose
    granularity: int = 1  # GRANULARITY_ODT_ENTRY_SIZE_DAQ
    timestamp_size: int = 4  # DWORD, in the first ODT of each list whose mode asks for timestamps
    timestamp_unit: int = TIMESTAMP_UNIT_10US
    timestamp_ticks: int = 1
    static_lists: tuple[StaticDaqList, ...] = ()  # given: static DAQ configuration (no ALLOC_*), these lists only

    def __post_init__(self) -> None:
        if sum(daq.odts for daq in self.static_lists) > self.max_odt_total:
            raise ValueError(f"static DAQ lists with more than {self.max_odt_total} ODTs: absolute PIDs run out")
        if any(not (1 <= daq.odts <= 0xFF and 1 <= daq.entries <= 0xFF) for daq in self.static_lists):
            raise ValueError("a static DAQ list has 1..255 ODTs of 1..255 entries")

    @property
    def static(self) -> bool:
        """DAQ_CONFIG_TYPE static: the lists, ODTs and entries are fixed, ALLOC_* do not exist."""
        return bool(self.static_lists)

    @property
    def timestamp_tick_s(self) -> float:
        """Seconds per timestamp count."""
        return TIME_UNIT_S[self.timestamp_unit] * self.timestamp_ticks


@dataclass(frozen=True)
class XcpParameters:
    can_id_master: int = 0x7F0  # master -> slave (bit 31 set: extended id)
    can_id_slave: int = 0x7F1  # slave -> master, responses and DTOs
    baudrate: int = 1_000_000
    max_dlc_required: bool = True  # XCP_ON_CAN MAX_DLC_REQUIRED: frames both ways have DLC 8 (shorter ones are ignored)
    max_cto: int = 8
    max_dto: int = 8
    max_bs: int = 42  # _NEXT frames of a master block after its DOWNLOAD/PROGRAM: (1 + 42) * 6 >= 255 bytes
    min_st_100us: int = 0
    protected: Resource = Resource.CAL_PAG | Resource.DAQ | Resource.PGM  # locked at CONNECT until UNLOCK
    checksum_type: ChecksumType = ChecksumType.CRC_32
    max_checksum_block: int = 0x20000  # BUILD_CHECKSUM limit: the SEGMENT CHECKSUM MAX_BLOCK_SIZE of the A2L
    epk_address: int = 0xFC0000
    epk_length: int = 14
    asam_mc2_name: str = "FLCU"
    ecu_text: str = "FLCU demo ECU (workbench simulated HDS9)"
    daq: DaqParameters = field(default_factory=DaqParameters)
    events: tuple[EventChannel, ...] = (
        EventChannel(0, "Task4ms", 0.004),
        EventChannel(1, "Task50ms", 0.050),
        EventChannel(2, "Task100ms", 0.100),
    )

    @property
    def max_data_per_frame(self) -> int:
        """Data bytes of a DOWNLOAD/PROGRAM/…_NEXT frame (command and count byte excluded)."""
        return self.max_cto - 2

    @property
    def max_block_bytes(self) -> int:
        """Largest master block: the first frame and MAX_BS _NEXT frames (ASAM: MAX_BS counts the _NEXT packets)."""
        return min(255, (1 + self.max_bs) * self.max_data_per_frame)
