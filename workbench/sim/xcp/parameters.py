"""The XCP slave's published parameters: what the A2L's IF_DATA XCP must state.

These are the simulator's truth (docs/demo-ecu.md); a test checks the demo A2L against them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from workbench.image import ChecksumType
from workbench.sim.xcp.protocol import MAX_DAQ_PID, Resource

# GET_DAQ_RESOLUTION_INFO timestamp units (TIMESTAMP_MODE bits 4..7)
TIMESTAMP_UNIT_10US = 0x4
# GET_DAQ_EVENT_INFO time units
EVENT_TIME_UNIT_1MS = 6


@dataclass(frozen=True)
class EventChannel:
    """A DAQ event channel: raised after the task with the same period ran."""

    number: int
    name: str
    period_s: float
    priority: int = 0

    @property
    def cycle_ms(self) -> int:
        return round(self.period_s * 1000)


@dataclass(frozen=True)
class DaqParameters:
    max_daq: int = 16  # dynamic DAQ lists that can be allocated (MIN_DAQ = 0)
    max_odt_total: int = MAX_DAQ_PID + 1  # one absolute PID (0x00..0xFB) per ODT of all lists
    max_odt_entry_size: int = 4  # MAX_ODT_ENTRY_SIZE_DAQ, bytes: smaller than a DTO's payload on purpose
    granularity: int = 1  # GRANULARITY_ODT_ENTRY_SIZE_DAQ
    timestamp_size: int = 4  # DWORD, in the first ODT of each list whose mode asks for timestamps
    timestamp_unit: int = TIMESTAMP_UNIT_10US
    timestamp_ticks: int = 1
    timestamp_tick_s: float = 10e-6


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
        EventChannel(0, "Task4ms", 0.004, 2),
        EventChannel(1, "Task50ms", 0.050, 1),
        EventChannel(2, "Task100ms", 0.100, 0),
    )

    @property
    def max_data_per_frame(self) -> int:
        """Data bytes of a DOWNLOAD/PROGRAM/…_NEXT frame (command and count byte excluded)."""
        return self.max_cto - 2

    @property
    def max_block_bytes(self) -> int:
        """Largest master block: the first frame and MAX_BS _NEXT frames (ASAM: MAX_BS counts the _NEXT packets)."""
        return min(255, (1 + self.max_bs) * self.max_data_per_frame)
