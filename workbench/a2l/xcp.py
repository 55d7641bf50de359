"""The XCP settings of an A2L (MODULE ``IF_DATA XCP`` and MEMORY_SEGMENT ``SEGMENT``\\ s).

Read through the generic IF_DATA tree (:mod:`workbench.a2l.ifdata`): fields are found
by their tag or enum prefix, and leading numbers by their order in the XCP spec's
A2ML, never by a byte offset of one particular file. Times are seconds, sizes bytes.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import TYPE_CHECKING

from workbench.a2l.ifdata import IfDataNode, Word, read_if_data
from workbench.errors import A2lParseError
from workbench.xcp_protocol import TIME_UNIT_S, CanId

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument, Block

__all__ = [
    "XcpAddressMapping", "XcpCommunicationMode", "XcpConfig", "XcpDaq", "XcpDaqEvents", "XcpDaqList", "XcpDaqListCanId",
    "XcpEvent",
    "XcpOnCan", "XcpOnIp", "XcpPage", "XcpPgm", "XcpProtocolLayer", "XcpSector", "XcpSegment", "XcpTimeouts",
    "XcpTimestamp", "read_daq_events", "read_xcp_config",
]

# TIMESTAMP_SUPPORTED UNIT_x -> the time unit code (seconds: TIME_UNIT_S)
_UNIT_NAMES = {
    "UNIT_1NS": 0, "UNIT_10NS": 1, "UNIT_100NS": 2, "UNIT_1US": 3, "UNIT_10US": 4, "UNIT_100US": 5,
    "UNIT_1MS": 6, "UNIT_10MS": 7, "UNIT_100MS": 8, "UNIT_1S": 9, "UNIT_1PS": 10, "UNIT_10PS": 11,
    "UNIT_100PS": 12,
}
TRANSPORT_BLOCKS = {"CAN": "XCP_ON_CAN", "UDP": "XCP_ON_UDP_IP", "TCP": "XCP_ON_TCP_IP"}
_TIMESTAMP_SIZES = {"NO_TIME_STAMP": 0, "SIZE_BYTE": 1, "SIZE_WORD": 2, "SIZE_DWORD": 4}
_GRANULARITY_SIZES = {"BYTE": 1, "WORD": 2, "DWORD": 4, "DLONG": 8}


@dataclass(frozen=True)
class XcpTimeouts:
    """T1-T7 in seconds (the A2L gives milliseconds)."""

    t1: float
    t2: float
    t3: float
    t4: float
    t5: float
    t6: float
    t7: float


@dataclass(frozen=True)
class XcpCommunicationMode:
    """COMMUNICATION_MODE_SUPPORTED: block transfer in either direction, interleaved mode."""

    slave_block_mode: bool = False
    master_block_mode: bool = False
    max_bs: int | None = None  # frames per master block (DOWNLOAD_NEXT / PROGRAM_NEXT)
    min_st_s: float | None = None  # minimum separation time between master block frames
    interleaved_queue_size: int | None = None


@dataclass(frozen=True)
class XcpProtocolLayer:
    """A PROTOCOL_LAYER block: the common one, or a transport's own (XCP_ON_UDP_IP ... PROTOCOL_LAYER)."""

    protocol_version: int
    timeouts: XcpTimeouts
    max_cto: int
    max_dto: int
    byte_order: str  # MSB_LAST (little endian) or MSB_FIRST
    address_granularity: int  # bytes per address unit
    optional_commands: frozenset[str]
    communication_mode: XcpCommunicationMode | None
    seed_and_key_function: str | None


@dataclass(frozen=True)
class XcpEvent:
    number: int
    name: str
    short_name: str
    direction: str  # DAQ, STIM or DAQ_STIM
    max_daq_lists: int
    period_s: float | None  # None for an event that is not cyclic (TIME_CYCLE 0)
    priority: int


@dataclass(frozen=True)
class XcpTimestamp:
    size: int  # bytes: 0 (none), 1, 2 or 4
    unit_s: float  # seconds per timestamp unit (UNIT_10US -> 1e-5)
    ticks: int  # units per timestamp tick
    fixed: bool  # TIMESTAMP_FIXED: timestamps cannot be switched off

    @property
    def resolution_s(self) -> float:
        """Seconds per timestamp count."""
        return self.unit_s * self.ticks


@dataclass(frozen=True)
class XcpDaqList:
    """A DAQ block's DAQ_LIST: a static or predefined list as the A2L states it (what GET_DAQ_LIST_INFO says)."""

    number: int
    direction: str  # DAQ_LIST_TYPE: DAQ, STIM or DAQ_STIM
    max_odt: int
    max_odt_entries: int
    fixed_event: int | None = None  # EVENT_FIXED
    predefined: bool = False  # a PREDEFINED block: the slave configured it


@dataclass(frozen=True)
class XcpDaq:
    config_type: str  # STATIC or DYNAMIC
    max_daq: int
    max_event_channels: int
    min_daq: int
    optimisation_type: str
    address_extension: str
    identification_field: str  # ABSOLUTE, RELATIVE_BYTE, RELATIVE_WORD, RELATIVE_WORD_ALIGNED
    granularity: int  # bytes: GRANULARITY_ODT_ENTRY_SIZE_DAQ
    max_odt_entry_size: int  # bytes: MAX_ODT_ENTRY_SIZE_DAQ (one ODT entry, not the ODT)
    overload_indication: str
    timestamp: XcpTimestamp | None
    events: tuple[XcpEvent, ...]
    prescaler_supported: bool = False
    resume_supported: bool = False
    lists: tuple[XcpDaqList, ...] = ()  # DAQ_LIST blocks (a static configuration's lists, predefined ones)

    @property
    def pid_size(self) -> int:
        """Bytes of the identification field in front of every DTO."""
        return {"ABSOLUTE": 1, "RELATIVE_BYTE": 2, "RELATIVE_WORD": 3, "RELATIVE_WORD_ALIGNED": 4}.get(
            self.identification_field, 1)

    def event(self, name_or_number: str | int) -> XcpEvent:
        for event in self.events:
            if event.number == name_or_number or event.name == name_or_number or event.short_name == name_or_number:
                return event
        raise KeyError(name_or_number)


@dataclass(frozen=True)
class XcpPage:
    number: int
    ecu_access: str  # ECU_ACCESS_...
    xcp_read_access: str
    xcp_write_access: str
    init_segment: int | None = None


@dataclass(frozen=True)
class XcpAddressMapping:
    source: int
    destination: int
    length: int


@dataclass(frozen=True)
class XcpSegment:
    """A MEMORY_SEGMENT with an XCP SEGMENT (calibration pages)."""

    memory_segment: str
    address: int
    size: int
    number: int
    page_count: int
    address_extension: int
    compression_method: int
    encryption_method: int
    pages: tuple[XcpPage, ...]
    address_mappings: tuple[XcpAddressMapping, ...]
    checksum_type: str | None = None
    checksum_max_block_size: int | None = None  # bytes one BUILD_CHECKSUM may cover (CHECKSUM MAX_BLOCK_SIZE)


@dataclass(frozen=True)
class XcpSector:
    name: str
    number: int
    address: int
    length: int
    clear_sequence: int
    program_sequence: int
    program_method: int


@dataclass(frozen=True)
class XcpPgm:
    mode: str  # PGM_MODE_ABSOLUTE, PGM_MODE_FUNCTIONAL, PGM_MODE_ABSOLUTE_AND_FUNCTIONAL
    max_sectors: int
    max_cto_pgm: int
    sectors: tuple[XcpSector, ...]
    communication_mode: XcpCommunicationMode | None = None


@dataclass(frozen=True)
class XcpDaqListCanId:
    daq_list: int
    can_id: CanId | None  # None: VARIABLE (set by the master at run time)


@dataclass(frozen=True)
class XcpOnCan:
    version: int
    can_id_master: CanId  # master -> ECU (commands)
    can_id_slave: CanId  # ECU -> master (responses, DTOs)
    baudrate: int | None
    sample_point: int | None  # percent
    max_dlc_required: bool
    can_id_broadcast: CanId | None = None
    daq_list_can_ids: tuple[XcpDaqListCanId, ...] = ()
    optional_tl_subcommands: tuple[str, ...] = ()  # OPTIONAL_TL_SUBCMD: GET_SLAVE_ID, GET_DAQ_ID, SET_DAQ_ID ...
    max_dlc: int | None = None  # CAN FD
    fd_data_baudrate: int | None = None  # CAN FD data phase
    protocol_layer: XcpProtocolLayer | None = None  # this transport's own PROTOCOL_LAYER (overrules the common one)
    daq: XcpDaq | None = None  # ... its own DAQ
    pgm: XcpPgm | None = None  # ... its own PGM


@dataclass(frozen=True)
class XcpOnIp:
    """XCP_ON_UDP_IP or XCP_ON_TCP_IP: where the ECU listens, and the blocks this transport overrules."""

    protocol: str  # "UDP" or "TCP"
    version: int
    port: int
    host: str | None  # HOST_NAME or ADDRESS
    protocol_layer: XcpProtocolLayer | None = None  # e.g. MAX_CTO/MAX_DTO larger than on CAN
    daq: XcpDaq | None = None
    pgm: XcpPgm | None = None


@dataclass(frozen=True)
class XcpConfig(XcpProtocolLayer):
    """Everything a master (or the simulated ECU) needs from the A2L to talk XCP: the common
    PROTOCOL_LAYER's fields, the other common blocks and the transport blocks."""

    daq: XcpDaq | None
    max_segments: int | None  # PAG
    freeze_supported: bool
    segments: tuple[XcpSegment, ...]
    pgm: XcpPgm | None
    can: XcpOnCan | None
    udp: XcpOnIp | None
    tcp: XcpOnIp | None

    def for_transport(self, transport: str) -> XcpConfig:
        """The settings a master on ``transport`` ("CAN", "UDP" or "TCP") works with: that transport
        block's own PROTOCOL_LAYER, DAQ and PGM in place of the common ones (ASAM: they overrule them).

        :raises KeyError: an unknown transport, or the A2L has no block for it (the key names the block).
        """
        block_name = TRANSPORT_BLOCKS[transport.upper()]
        block = getattr(self, transport.lower())
        if block is None:
            raise KeyError(block_name)
        config = self
        if block.protocol_layer is not None:
            config = replace(config, **{f.name: getattr(block.protocol_layer, f.name) for f in fields(XcpProtocolLayer)})
        if block.daq is not None:
            config = replace(config, daq=block.daq)
        if block.pgm is not None:
            config = replace(config, pgm=block.pgm)
        return config


@dataclass(frozen=True)
class XcpDaqEvents:
    """A MEASUREMENT's IF_DATA XCP DAQ_EVENT: the events it may (or must) be sampled on."""

    fixed: tuple[int, ...] = ()  # FIXED_EVENT_LIST: only these
    default: tuple[int, ...] = ()  # VARIABLE DEFAULT_EVENT_LIST: the preselection
    available: tuple[int, ...] = ()  # VARIABLE AVAILABLE_EVENT_LIST (empty: any)

    @property
    def preferred(self) -> int | None:
        """The event to sample on when the user names none."""
        for events in (self.fixed, self.default, self.available):
            if events:
                return events[0]
        return None


def read_daq_events(block: "Block") -> XcpDaqEvents:
    """The DAQ_EVENT of an object's ``IF_DATA XCP`` (an empty one when it has none)."""
    for if_data in block.children_named("IF_DATA"):
        if if_data.name not in ("XCP", "XCPplus"):
            continue
        node = read_if_data(if_data).block("DAQ_EVENT")
        if node is None:
            continue

        def events(owner: IfDataNode | None) -> tuple[int, ...]:
            return tuple(int(v[0]) for v in owner.all_after("EVENT") if v and not isinstance(v[0], str)) if owner else ()

        if node.has("FIXED_EVENT_LIST"):
            return XcpDaqEvents(fixed=events(node))
        return XcpDaqEvents(default=events(node.block("DEFAULT_EVENT_LIST")),
                            available=events(node.block("AVAILABLE_EVENT_LIST")))
    return XcpDaqEvents()


def read_xcp_config(doc: "A2lDocument", module: str | None = None) -> XcpConfig:
    """The XCP configuration of ``module`` (default: the only MODULE).

    Raises :class:`A2lParseError` when the MODULE has no ``IF_DATA XCP`` (or ``XCPplus``)
    or its PROTOCOL_LAYER lacks mandatory fields.
    """
    module_block = doc.module(module)
    root = None
    for block in module_block.children_named("IF_DATA"):
        if block.name in ("XCP", "XCPplus"):
            root = read_if_data(block)
            break
    if root is None:
        raise A2lParseError("the MODULE has no IF_DATA XCP block", *module_block.position)
    protocol = root.block("PROTOCOL_LAYER")
    if protocol is None:
        raise A2lParseError("IF_DATA XCP has no PROTOCOL_LAYER", *root.location)
    pag = root.block("PAG")
    return XcpConfig(
        **vars(_protocol_layer(protocol)),
        daq=_daq(root.block("DAQ")),
        max_segments=int(pag.leading_numbers()[0]) if pag is not None and pag.leading_numbers() else None,
        freeze_supported=bool(pag is not None and pag.has("FREEZE_SUPPORTED")),
        segments=tuple(_segments(doc, module)),
        pgm=_pgm(root.block("PGM")),
        can=_can(root.block("XCP_ON_CAN")),
        udp=_ip(root.block("XCP_ON_UDP_IP"), "UDP"),
        tcp=_ip(root.block("XCP_ON_TCP_IP"), "TCP"),
    )


def _protocol_layer(node: IfDataNode) -> XcpProtocolLayer:
    numbers = node.leading_numbers()
    if len(numbers) < 10:
        raise A2lParseError("PROTOCOL_LAYER needs version, T1-T7, MAX_CTO and MAX_DTO", *node.location)
    byte_order = node.word_with_prefix("BYTE_ORDER_")
    granularity = node.word_with_prefix("ADDRESS_GRANULARITY_")
    seed_key = node.after("SEED_AND_KEY_EXTERNAL_FUNCTION")
    return XcpProtocolLayer(
        protocol_version=int(numbers[0]),
        timeouts=XcpTimeouts(*(value / 1000.0 for value in numbers[1:8])),
        max_cto=int(numbers[8]),
        max_dto=int(numbers[9]),
        byte_order=byte_order[len("BYTE_ORDER_"):] if byte_order else "MSB_LAST",
        address_granularity=_GRANULARITY_SIZES.get(granularity[len("ADDRESS_GRANULARITY_"):], 1) if granularity else 1,
        optional_commands=frozenset(str(v[0]) for v in node.all_after("OPTIONAL_CMD") if v),
        communication_mode=_communication_mode(node),
        seed_and_key_function=str(seed_key[0]) if seed_key else None,
    )


def _overrides(node: IfDataNode) -> dict:
    """The common blocks a transport block repeats with its own values (PROTOCOL_LAYER, DAQ, PGM)."""
    protocol = node.block("PROTOCOL_LAYER")
    return {
        "protocol_layer": _protocol_layer(protocol) if protocol is not None else None,
        "daq": _daq(node.block("DAQ")),
        "pgm": _pgm(node.block("PGM")),
    }


def _communication_mode(node: IfDataNode) -> XcpCommunicationMode | None:
    if not node.has("COMMUNICATION_MODE_SUPPORTED"):
        return None
    master = node.numbers_after("MASTER")
    interleaved = node.numbers_after("INTERLEAVED")
    return XcpCommunicationMode(
        slave_block_mode=node.has("SLAVE"),
        master_block_mode=node.has("MASTER"),
        max_bs=int(master[0]) if len(master) > 0 else None,
        min_st_s=master[1] * 100e-6 if len(master) > 1 else None,  # MIN_ST counts 100 us
        interleaved_queue_size=int(interleaved[0]) if interleaved else None,
    )


def _daq(node: IfDataNode | None) -> XcpDaq | None:
    if node is None:
        return None
    config_type = node.word_among(("STATIC", "DYNAMIC"))
    numbers = node.numbers_after(config_type) if config_type else node.leading_numbers()
    if len(numbers) < 3:
        raise A2lParseError("DAQ needs MAX_DAQ, MAX_EVENT_CHANNEL and MIN_DAQ", *node.location)
    granularity = node.word_with_prefix("GRANULARITY_ODT_ENTRY_SIZE_DAQ_")
    identification = node.word_with_prefix("IDENTIFICATION_FIELD_TYPE_")
    max_entry = _number_after_word(node, granularity) if granularity else None
    timestamp = node.block("TIMESTAMP_SUPPORTED")
    return XcpDaq(
        config_type=str(config_type or "STATIC"),
        max_daq=int(numbers[0]),
        max_event_channels=int(numbers[1]),
        min_daq=int(numbers[2]),
        optimisation_type=str(node.word_with_prefix("OPTIMISATION_TYPE_") or "OPTIMISATION_TYPE_DEFAULT"),
        address_extension=str(node.word_with_prefix("ADDRESS_EXTENSION_") or "ADDRESS_EXTENSION_FREE"),
        identification_field=identification[len("IDENTIFICATION_FIELD_TYPE_"):] if identification else "ABSOLUTE",
        granularity=_GRANULARITY_SIZES.get(granularity[len("GRANULARITY_ODT_ENTRY_SIZE_DAQ_"):], 1) if granularity else 1,
        max_odt_entry_size=int(max_entry) if max_entry is not None else 0xFF,
        overload_indication=str(node.word_among(("NO_OVERLOAD_INDICATION", "OVERLOAD_INDICATION_PID",
                                                 "OVERLOAD_INDICATION_EVENT")) or "NO_OVERLOAD_INDICATION"),
        timestamp=_timestamp(timestamp) if timestamp is not None else None,
        events=tuple(_event(event) for event in node.blocks("EVENT")),
        prescaler_supported=node.has("PRESCALER_SUPPORTED"),
        resume_supported=node.has("RESUME_SUPPORTED"),
        lists=tuple(_daq_list(daq_list) for daq_list in node.blocks("DAQ_LIST")),
    )


def _daq_list(node: IfDataNode) -> XcpDaqList:
    numbers = node.leading_numbers()
    if not numbers:
        raise A2lParseError("DAQ_LIST needs its DAQ_LIST_NUMBER", *node.location)
    fixed = node.number_after("EVENT_FIXED")
    direction = node.after("DAQ_LIST_TYPE")
    return XcpDaqList(int(numbers[0]), str(direction[0]) if direction else "DAQ",
                      int(node.number_after("MAX_ODT") or 0), int(node.number_after("MAX_ODT_ENTRIES") or 0),
                      int(fixed) if fixed is not None else None, node.block("PREDEFINED") is not None)


def _number_after_word(node: IfDataNode, word: str) -> int | float | None:
    found = node.after(word)
    return found[0] if found and not isinstance(found[0], str) else None


def _timestamp(node: IfDataNode) -> XcpTimestamp:
    numbers = node.leading_numbers()
    size = node.word_among(_TIMESTAMP_SIZES)
    unit = node.word_with_prefix("UNIT_")
    return XcpTimestamp(
        size=_TIMESTAMP_SIZES[size] if size else 0,
        unit_s=TIME_UNIT_S[_UNIT_NAMES[unit]] if unit in _UNIT_NAMES else 1e-6,
        ticks=int(numbers[0]) if numbers else 1,
        fixed=node.has("TIMESTAMP_FIXED"),
    )


def _event(node: IfDataNode) -> XcpEvent:
    strings = [v for v in node.values if isinstance(v, str) and not isinstance(v, Word)]
    direction = node.word_among(("DAQ", "STIM", "DAQ_STIM"))
    fields = [v for v in node.values if not isinstance(v, str)]
    if len(strings) < 1 or len(fields) < 5:
        raise A2lParseError("EVENT needs name, short name, channel, MAX_DAQ_LIST, TIME_CYCLE, TIME_UNIT, PRIORITY",
                            *node.location)
    number, max_daq_lists, cycle, unit, priority = (int(v) for v in fields[:5])
    unit_s = TIME_UNIT_S.get(unit)
    if unit_s is None:
        raise A2lParseError(f"EVENT {strings[0]!r}: unknown TIME_UNIT {unit}", *node.location)
    return XcpEvent(
        number=number,
        name=strings[0],
        short_name=strings[1] if len(strings) > 1 else strings[0],
        direction=str(direction or "DAQ"),
        max_daq_lists=max_daq_lists,
        period_s=cycle * unit_s if cycle else None,
        priority=priority,
    )


def _segments(doc: "A2lDocument", module: str | None) -> list[XcpSegment]:
    segments = []
    for memory in doc.memory_segments(module):
        for if_data in memory.block.children_named("IF_DATA"):
            if if_data.name not in ("XCP", "XCPplus"):
                continue
            for node in read_if_data(if_data).blocks("SEGMENT"):
                numbers = node.leading_numbers()
                if len(numbers) < 5:
                    raise A2lParseError("SEGMENT needs number, pages, address extension, compression, encryption",
                                        *node.location)
                checksum = node.block("CHECKSUM")
                segments.append(XcpSegment(
                    memory_segment=memory.name,
                    address=memory.address,
                    size=memory.size,
                    number=int(numbers[0]),
                    page_count=int(numbers[1]),
                    address_extension=int(numbers[2]),
                    compression_method=int(numbers[3]),
                    encryption_method=int(numbers[4]),
                    pages=tuple(_page(page) for page in node.blocks("PAGE")),
                    address_mappings=tuple(_mapping(m) for m in node.blocks("ADDRESS_MAPPING")),
                    checksum_type=str(checksum.values[0]) if checksum is not None and checksum.values else None,
                    checksum_max_block_size=_int_or_none(checksum.number_after("MAX_BLOCK_SIZE"))
                    if checksum is not None else None,
                ))
    return segments


def _page(node: IfDataNode) -> XcpPage:
    numbers = node.leading_numbers()
    init = node.number_after("INIT_SEGMENT")
    return XcpPage(
        number=int(numbers[0]) if numbers else 0,
        ecu_access=str(node.word_with_prefix("ECU_ACCESS_") or "ECU_ACCESS_DONT_CARE"),
        xcp_read_access=str(node.word_with_prefix("XCP_READ_ACCESS_") or "XCP_READ_ACCESS_DONT_CARE"),
        xcp_write_access=str(node.word_with_prefix("XCP_WRITE_ACCESS_") or "XCP_WRITE_ACCESS_DONT_CARE"),
        init_segment=int(init) if init is not None else None,
    )


def _mapping(node: IfDataNode) -> XcpAddressMapping:
    numbers = node.leading_numbers()
    if len(numbers) < 3:
        raise A2lParseError("ADDRESS_MAPPING needs source, destination and length", *node.location)
    return XcpAddressMapping(*(int(v) for v in numbers[:3]))


def _pgm(node: IfDataNode | None) -> XcpPgm | None:
    if node is None:
        return None
    numbers = [v for v in node.values if not isinstance(v, str)]
    sectors = []
    for sector in node.blocks("SECTOR"):
        name = next((v for v in sector.values if isinstance(v, str) and not isinstance(v, Word)), "")
        fields = [int(v) for v in sector.values if not isinstance(v, str)]
        if len(fields) < 6:
            raise A2lParseError("SECTOR needs number, address, length, clear/program sequence, method",
                                *sector.location)
        sectors.append(XcpSector(name, *fields[:6]))
    return XcpPgm(
        mode=str(node.word_with_prefix("PGM_MODE_") or "PGM_MODE_ABSOLUTE"),
        max_sectors=int(numbers[0]) if numbers else len(sectors),
        max_cto_pgm=int(numbers[1]) if len(numbers) > 1 else 0,
        sectors=tuple(sectors),
        communication_mode=_communication_mode(node),
    )


def _can(node: IfDataNode | None) -> XcpOnCan | None:
    if node is None:
        return None
    master = _can_id(node, "CAN_ID_MASTER")
    slave = _can_id(node, "CAN_ID_SLAVE")
    if master is None or slave is None:
        raise A2lParseError("XCP_ON_CAN needs CAN_ID_MASTER and CAN_ID_SLAVE", *node.location)
    baudrate = node.number_after("BAUDRATE")
    sample_point = node.number_after("SAMPLE_POINT")
    fd = node.block("CAN_FD")
    numbers = node.leading_numbers()
    return XcpOnCan(
        version=int(numbers[0]) if numbers else 0x0100,
        can_id_master=master,
        can_id_slave=slave,
        baudrate=int(baudrate) if baudrate is not None else None,
        sample_point=int(sample_point) if sample_point is not None else None,
        max_dlc_required=node.has("MAX_DLC_REQUIRED"),
        can_id_broadcast=_can_id(node, "CAN_ID_BROADCAST"),
        daq_list_can_ids=tuple(_daq_list_can_id(item) for item in node.blocks("DAQ_LIST_CAN_ID")),
        optional_tl_subcommands=tuple(str(v[0]) for v in node.all_after("OPTIONAL_TL_SUBCMD") if v),
        max_dlc=_int_or_none(fd.number_after("MAX_DLC")) if fd is not None else None,
        fd_data_baudrate=_int_or_none(fd.number_after("CAN_FD_DATA_TRANSFER_BAUDRATE")) if fd is not None else None,
        **_overrides(node),
    )


def _daq_list_can_id(node: IfDataNode) -> XcpDaqListCanId:
    numbers = node.leading_numbers()
    return XcpDaqListCanId(daq_list=int(numbers[0]) if numbers else 0, can_id=_can_id(node, "FIXED"))


def _can_id(node: IfDataNode, keyword: str) -> CanId | None:
    """The CAN id after ``keyword`` (bit 31: extended), None when it is not there."""
    number = node.number_after(keyword)
    if number is None:
        return None
    try:
        return CanId.from_a2l(int(number))
    except ValueError as exc:
        raise A2lParseError(f"{node.name} {keyword}: {exc}", *node.location) from None


def _ip(node: IfDataNode | None, protocol: str) -> XcpOnIp | None:
    if node is None:
        return None
    numbers = node.leading_numbers()
    if len(numbers) < 2:
        raise A2lParseError(f"XCP_ON_{protocol}_IP needs version and port", *node.location)
    host = node.after("HOST_NAME") or node.after("ADDRESS")
    return XcpOnIp(protocol, int(numbers[0]), int(numbers[1]), str(host[0]) if host else None, **_overrides(node))


def _int_or_none(value) -> int | None:
    return int(value) if value is not None else None
