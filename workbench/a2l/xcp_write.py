"""XCP settings back into A2L text: the MODULE's ``IF_DATA XCP`` and a MEMORY_SEGMENT's ``SEGMENT``.

The inverse of :func:`~workbench.a2l.xcp.read_xcp_config`: ``read_xcp_config`` of what
:func:`format_if_data_xcp` writes gives the same :class:`~workbench.a2l.xcp.XcpConfig` (fields the
reader does not keep, such as XCP_ON_CAN's BTL_CYCLES, are not written). The simulated ECU uses it
to publish the A2L of a slave profile (:mod:`workbench.sim.profiles`); the output follows the A2ML of
ASAM XCP 1.x (``XCP.aml``), two spaces a level.
"""

from __future__ import annotations

from collections.abc import Iterable

from workbench.a2l.xcp import (
    XcpCommunicationMode,
    XcpConfig,
    XcpDaq,
    XcpDaqList,
    XcpEvent,
    XcpOnCan,
    XcpOnIp,
    XcpPgm,
    XcpProtocolLayer,
    XcpSegment,
)
from workbench.xcp_protocol import TIME_UNIT_S, CanId, Cmd

__all__ = ["format_if_data_xcp", "format_memory_segment", "format_segment"]

_GRANULARITY_NAMES = {1: "BYTE", 2: "WORD", 4: "DWORD", 8: "DLONG"}
_TIMESTAMP_SIZE_NAMES = {0: "NO_TIME_STAMP", 1: "SIZE_BYTE", 2: "SIZE_WORD", 4: "SIZE_DWORD"}
_UNIT_NAMES = {0: "UNIT_1NS", 1: "UNIT_10NS", 2: "UNIT_100NS", 3: "UNIT_1US", 4: "UNIT_10US", 5: "UNIT_100US",
               6: "UNIT_1MS", 7: "UNIT_10MS", 8: "UNIT_100MS", 9: "UNIT_1S", 10: "UNIT_1PS", 11: "UNIT_10PS",
               12: "UNIT_100PS"}
_MS_UNIT = 6


def format_if_data_xcp(config: XcpConfig) -> str:
    """``/begin IF_DATA XCP ... /end IF_DATA``: PROTOCOL_LAYER, DAQ, PAG, PGM and the transport blocks."""
    lines = ["/begin IF_DATA XCP", *_indent(_protocol_layer(config))]
    if config.daq is not None:
        lines += _indent(_daq(config.daq))
    if config.max_segments is not None:
        lines += _indent([_line("PAG", [str(config.max_segments)] + (["FREEZE_SUPPORTED"] if config.freeze_supported
                                                                       else []))])
    if config.pgm is not None:
        lines += _indent(_pgm(config.pgm))
    if config.can is not None:
        lines += _indent(_can(config.can))
    for block in (config.udp, config.tcp):
        if block is not None:
            lines += _indent(_ip(block))
    return "\n".join(lines + ["/end IF_DATA"])


def format_segment(segment: XcpSegment) -> str:
    """``/begin IF_DATA XCP /begin SEGMENT ... /end SEGMENT /end IF_DATA`` of a MEMORY_SEGMENT."""
    body = [f"{segment.number} {segment.page_count} {segment.address_extension} {segment.compression_method} "
            f"{segment.encryption_method}  /* number, pages, address extension, compression, encryption */"]
    if segment.checksum_type:
        body.append(_line("CHECKSUM", [segment.checksum_type] + (
            [f"MAX_BLOCK_SIZE 0x{segment.checksum_max_block_size:X}"] if segment.checksum_max_block_size else [])))
    for page in segment.pages:
        body.append(_line("PAGE", [str(page.number), page.ecu_access, page.xcp_read_access, page.xcp_write_access]
                          + ([f"INIT_SEGMENT {page.init_segment}"] if page.init_segment is not None else [])))
    for mapping in segment.address_mappings:
        body.append(_line("ADDRESS_MAPPING", [f"0x{mapping.source:X}", f"0x{mapping.destination:X}",
                                              f"0x{mapping.length:X}"]))
    return "\n".join(["/begin IF_DATA XCP", *_indent(_block("SEGMENT", body)), "/end IF_DATA"])


def format_memory_segment(name: str, description: str, prg_type: str, memory_type: str, attribute: str, address: int,
                          size: int, segment: XcpSegment | None = None) -> str:
    """A MOD_PAR ``MEMORY_SEGMENT`` (no offsets), with the XCP ``SEGMENT`` of its calibration pages if given."""
    head = f'{name} "{description}"'
    body = [f"{prg_type} {memory_type} {attribute} 0x{address:X} 0x{size:X} -1 -1 -1 -1 -1"]
    if segment is not None:
        body += format_segment(segment).splitlines()
    return "\n".join([f"/begin MEMORY_SEGMENT {head}", *_indent(body), "/end MEMORY_SEGMENT"])


def _indent(lines: Iterable[str]) -> list[str]:
    return ["  " + line for line in lines]


def _block(name: str, body: Iterable[str]) -> list[str]:
    return [f"/begin {name}", *_indent(body), f"/end {name}"]


def _line(name: str, values: Iterable[str]) -> str:
    """A small block on one line: ``/begin NAME v1 v2 ... /end NAME``."""
    return " ".join([f"/begin {name}", *values, f"/end {name}"])


def _protocol_layer(layer: XcpProtocolLayer) -> list[str]:
    t = layer.timeouts
    body = [f"0x{layer.protocol_version:04X}",
            " ".join(str(round(v * 1000)) for v in (t.t1, t.t2, t.t3, t.t4, t.t5, t.t6, t.t7)) + "  /* T1-T7 [ms] */",
            f"{layer.max_cto} {layer.max_dto}  /* MAX_CTO MAX_DTO */", f"BYTE_ORDER_{layer.byte_order}",
            f"ADDRESS_GRANULARITY_{_GRANULARITY_NAMES[layer.address_granularity]}"]
    body += [f"OPTIONAL_CMD {command}" for command in sorted(layer.optional_commands, key=_command_order)]
    body += _communication_mode(layer.communication_mode)
    if layer.seed_and_key_function:
        body.append(f'SEED_AND_KEY_EXTERNAL_FUNCTION "{layer.seed_and_key_function}"')
    return _block("PROTOCOL_LAYER", body)


def _command_order(name: str) -> tuple[int, str]:
    """The spec's order: by command code, highest first (names the protocol does not know last)."""
    return (-Cmd[name].value if name in Cmd.__members__ else 0, name)


def _communication_mode(mode: XcpCommunicationMode | None) -> list[str]:
    if mode is None:
        return []
    lines = ["COMMUNICATION_MODE_SUPPORTED BLOCK"]
    if mode.slave_block_mode:
        lines.append("  SLAVE")
    if mode.master_block_mode:
        lines.append(f"  MASTER {mode.max_bs or 0} {round((mode.min_st_s or 0.0) / 100e-6)}")
    if mode.interleaved_queue_size is not None:
        lines.append(f"INTERLEAVED {mode.interleaved_queue_size}")
    return lines


def _daq(daq: XcpDaq) -> list[str]:
    body = [daq.config_type,
            f"{daq.max_daq} {daq.max_event_channels} {daq.min_daq}  /* MAX_DAQ MAX_EVENT_CHANNEL MIN_DAQ */",
            daq.optimisation_type, daq.address_extension, f"IDENTIFICATION_FIELD_TYPE_{daq.identification_field}",
            f"GRANULARITY_ODT_ENTRY_SIZE_DAQ_{_GRANULARITY_NAMES[daq.granularity]}", str(daq.max_odt_entry_size),
            daq.overload_indication]
    body += [word for word, present in (("PRESCALER_SUPPORTED", daq.prescaler_supported),
                                        ("RESUME_SUPPORTED", daq.resume_supported)) if present]
    stamp = daq.timestamp
    if stamp is not None:
        body.append(_line("TIMESTAMP_SUPPORTED", [str(stamp.ticks), _TIMESTAMP_SIZE_NAMES[stamp.size],
                                                  _UNIT_NAMES[_unit_code(stamp.unit_s)]]
                          + (["TIMESTAMP_FIXED"] if stamp.fixed else [])))
    body += [_daq_list(daq_list) for daq_list in daq.lists if not daq_list.predefined]  # PREDEFINED's ODTs: not kept
    body += [_event(event) for event in daq.events]
    return _block("DAQ", body)


def _daq_list(daq_list: XcpDaqList) -> str:
    fixed = [] if daq_list.fixed_event is None else ["EVENT_FIXED", str(daq_list.fixed_event)]
    return _line("DAQ_LIST", [str(daq_list.number), "DAQ_LIST_TYPE", daq_list.direction, "MAX_ODT",
                              str(daq_list.max_odt), "MAX_ODT_ENTRIES", str(daq_list.max_odt_entries), *fixed])


def _unit_code(seconds: float) -> int:
    return min(TIME_UNIT_S, key=lambda code: abs(TIME_UNIT_S[code] - seconds) / TIME_UNIT_S[code])


def _event(event: XcpEvent) -> str:
    cycle, unit = _cycle(event.period_s)
    return _line("EVENT", [f'"{event.name}"', f'"{event.short_name}"', str(event.number), event.direction,
                           f"0x{event.max_daq_lists:X}", str(cycle), str(unit), str(event.priority)])


def _cycle(period_s: float | None) -> tuple[int, int]:
    """TIME_CYCLE and TIME_UNIT of a period: milliseconds when they count it, else the finest unit that does."""
    if not period_s:
        return 0, _MS_UNIT
    for unit in (_MS_UNIT, *range(10)):
        count = period_s / TIME_UNIT_S[unit]
        if abs(count - round(count)) < 1e-6 and 0 < round(count) <= 0xFF:
            return round(count), unit
    raise ValueError(f"an EVENT period of {period_s} s fits no TIME_CYCLE byte")


def _pgm(pgm: XcpPgm) -> list[str]:
    body = [pgm.mode, f"{pgm.max_sectors} {pgm.max_cto_pgm}  /* MAX_SECTORS MAX_CTO_PGM */"]
    body += [_line("SECTOR", [f'"{sector.name}"', str(sector.number), f"0x{sector.address:X}", f"0x{sector.length:X}",
                              str(sector.clear_sequence), str(sector.program_sequence), str(sector.program_method)])
             for sector in pgm.sectors]
    return _block("PGM", body + _communication_mode(pgm.communication_mode))


def _overrides(block: XcpOnCan | XcpOnIp) -> list[str]:
    lines = _protocol_layer(block.protocol_layer) if block.protocol_layer is not None else []
    lines += _daq(block.daq) if block.daq is not None else []
    return lines + (_pgm(block.pgm) if block.pgm is not None else [])


def _can_id(can_id: CanId) -> str:
    return f"0x{can_id.a2l:X}"


def _can(can: XcpOnCan) -> list[str]:
    body = [f"0x{can.version:04X}"]
    if can.can_id_broadcast is not None:
        body.append(f"CAN_ID_BROADCAST {_can_id(can.can_id_broadcast)}")
    body += [f"CAN_ID_MASTER {_can_id(can.can_id_master)}", f"CAN_ID_SLAVE {_can_id(can.can_id_slave)}"]
    if can.baudrate is not None:
        body.append(f"BAUDRATE {can.baudrate}")
    if can.sample_point is not None:
        body.append(f"SAMPLE_POINT {can.sample_point}")
    if can.max_dlc_required:
        body.append("MAX_DLC_REQUIRED")
    body += [f"OPTIONAL_TL_SUBCMD {name}" for name in can.optional_tl_subcommands]
    for item in can.daq_list_can_ids:
        where = "VARIABLE" if item.can_id is None else f"FIXED {_can_id(item.can_id)}"
        body.append(_line("DAQ_LIST_CAN_ID", [str(item.daq_list), where]))
    if can.max_dlc is not None:
        body.append(_line("CAN_FD", [f"MAX_DLC {can.max_dlc}"] + (
            [f"CAN_FD_DATA_TRANSFER_BAUDRATE {can.fd_data_baudrate}"] if can.fd_data_baudrate else [])))
    return _block("XCP_ON_CAN", body + _overrides(can))


def _ip(block: XcpOnIp) -> list[str]:
    body = [f"0x{block.version:04X}", str(block.port)]
    if block.host:
        body.append(f'ADDRESS "{block.host}"')
    return _block(f"XCP_ON_{block.protocol}_IP", body + _overrides(block))
