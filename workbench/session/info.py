"""What ``workbench info`` shows: the ECU's identity and abilities beside what the A2L says."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING, Any

from workbench.errors import WorkbenchError, XcpCommandError, XcpTimeoutError
from workbench.xcp.detect import DaqCanIds, read_daq_can_ids
from workbench.xcp.info import DaqEventInfo, DaqProcessorInfo, DaqResolutionInfo
from workbench.xcp_protocol import IdType, Resource

if TYPE_CHECKING:
    from workbench.session.session import Session

__all__ = ["EcuInfo", "PageCopy", "PageState", "read_ecu_info"]


@dataclass(frozen=True)
class PageState:
    segment: int
    ecu_page: int  # the page the ECU's software uses
    xcp_page: int  # the page XCP reads and writes
    working: int
    reference: int

    def name(self, page: int) -> str:
        return {self.working: "working", self.reference: "reference"}.get(page, str(page))


@dataclass(frozen=True)
class PageCopy:
    """What copying the reference page onto the working page overwrites in one calibration segment."""

    segment: int
    memory_segment: str  # the A2L's MEMORY_SEGMENT ("": the ECU described the segment)
    address: int
    size: int  # bytes
    working: int  # the page overwritten
    reference: int  # the page copied
    calibrations: int  # the A2L's calibrations in the segment, whose changes since start-up the copy undoes

    def __str__(self) -> str:
        """``the working page 0 of segment 0 (CALRAM, 0x40000000-0x4001FFFF, 131072 bytes, 58 calibrations)``"""
        name = f"{self.memory_segment}, " if self.memory_segment else ""
        return (f"the working page {self.working} of segment {self.segment} ({name}0x{self.address:X}-"
                f"0x{self.address + self.size - 1:X}, {self.size} bytes, {self.calibrations} "
                f"calibration{'s' * (self.calibrations != 1)})")

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True)
class EcuInfo:
    link: str
    identification: str
    a2l_name: str
    epk_a2l: str | None
    epk_ecu: str | None
    epk_match: bool | None
    boot: bool
    resources: list[str]
    protected: list[str]
    max_cto: int
    max_dto: int
    byte_order: str
    address_granularity: int
    slave_block_mode: bool
    master_block_mode: bool
    max_bs: int | None
    protocol_version: int
    transport_version: int
    daq: DaqProcessorInfo | None = None
    daq_resolution: DaqResolutionInfo | None = None
    events: list[DaqEventInfo] = field(default_factory=list)
    pages: list[PageState] = field(default_factory=list)
    epk_parts: list[dict[str, Any]] = field(default_factory=list)  # EpkPart.to_dict() of each part with its own EPK
    daq_can_ids: list[DaqCanIds] = field(default_factory=list)  # XCP on CAN: GET_DAQ_ID of the first lists

    def to_dict(self) -> dict[str, Any]:
        return {**asdict(self), "daq_can_ids": [ids.to_dict() for ids in self.daq_can_ids]}


def _resources(flags: Resource) -> list[str]:
    return [r.name.replace("_", "/") for r in Resource if r & flags]


def _optional(read, default=None):
    """What ``read()`` returns, or ``default`` when the ECU refuses (or a resource cannot be unlocked here). A key
    the ECU refused is raised: the slave disconnects after it, and the next command went unanswered (a connect then
    failed as a lost connection, 'GET_ID: no response', the refusal unsaid)."""
    try:
        return read()
    except XcpTimeoutError:
        raise
    except XcpCommandError as exc:
        if exc.command == "UNLOCK":
            raise
        return default
    except WorkbenchError:
        return default


def read_ecu_info(session: Session) -> EcuInfo:
    master = session.master
    protected = master.get_status().protected  # before the DAQ queries below unlock DAQ
    connect, comm = master.connect_info, master.comm_mode
    daq = resolution = None
    events: list[DaqEventInfo] = []
    daq_can_ids: list[DaqCanIds] = []
    if connect.resources & Resource.DAQ and not session.in_boot:
        daq = _optional(session.daq_processor_info)
        resolution = _optional(session.daq_resolution_info)
        if daq is not None:
            count = daq.max_event_channels or (len(session.config.daq.events) if session.config.daq else 0)
            events = [e for e in (_optional(lambda n=n: session.event_info(n)) for n in range(count)) if e]
            if session.link.is_can:  # a slave without GET_DAQ_ID shows none
                daq_can_ids = list(read_daq_can_ids(master, []))
    pages = []
    if connect.resources & Resource.CAL_PAG and not session.in_boot:
        segments = _optional(session.calibration_segments, ())  # the A2L's, else the ECU's
        pages = [p for p in (_optional(lambda s=s.number: session.page(s)) for s in segments) if p]
    return EcuInfo(
        link=session.link.settings.describe(),
        identification=_optional(lambda: master.get_id(IdType.ASCII).decode("latin-1"), ""),
        a2l_name=_optional(lambda: master.get_id(IdType.ASAM_MC2_NAME).decode("latin-1"), ""),
        epk_a2l=session.epk.a2l, epk_ecu=session.epk.ecu, epk_match=session.epk.matches,
        boot=session.in_boot,
        resources=_resources(connect.resources), protected=_resources(protected),
        max_cto=connect.max_cto, max_dto=connect.max_dto,
        byte_order="MSB_FIRST (big endian)" if connect.byte_order == ">" else "MSB_LAST (little endian)",
        address_granularity=connect.address_granularity, slave_block_mode=connect.slave_block_mode,
        master_block_mode=bool(comm and comm.master_block_mode), max_bs=comm.max_bs if comm else None,
        protocol_version=connect.protocol_version, transport_version=connect.transport_version,
        daq=daq, daq_resolution=resolution, events=events, pages=pages, daq_can_ids=daq_can_ids,
        epk_parts=[part.to_dict() for part in session.epks()],
    )
