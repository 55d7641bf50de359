"""The A2L of a slave profile: the demo's A2L with IF_DATA XCP (and the calibration segments) as that slave is.

Everything a master reads from the A2L to talk to the slave is derived from the slave's own
parameters, never written by hand: PROTOCOL_LAYER (byte order, granularity, MAX_CTO/MAX_DTO per
transport, the commands the slave implements, its block modes, T1), DAQ (configuration type, MIN_DAQ,
identification field, granularity, timestamps), PAG and the MEMORY_SEGMENTs of the calibration
segments, PGM and XCP on CAN FD. The rest of the file stays as it is, byte for byte.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path

from workbench.a2l import A2lDocument, XcpConfig, load_a2l_string, read_xcp_config
from workbench.a2l.edits import Edit, Edits
from workbench.a2l.xcp import (
    XcpAddressMapping,
    XcpCommunicationMode,
    XcpDaq,
    XcpDaqListCanId,
    XcpEvent,
    XcpProtocolLayer,
    XcpSector,
    XcpSegment,
    XcpTimestamp,
)
from workbench.a2l.xcp_write import format_if_data_xcp, format_memory_segment
from workbench.errors import InputError
from workbench.sim.memory_map import MemoryMap
from workbench.sim.xcp.parameters import XcpParameters
from workbench.sim.xcp.slave import XcpSlave
from workbench.xcp_protocol import TIME_UNIT_S, Cmd

__all__ = ["profile_document"]

_MANDATORY = {Cmd.CONNECT, Cmd.DISCONNECT, Cmd.GET_STATUS, Cmd.SYNCH}
CAN_FD_DATA_BAUDRATE = 2_000_000


def profile_document(doc: A2lDocument, params: Mapping[str, XcpParameters], memory_map: MemoryMap,
                     name: str, timeouts_s: Mapping[str, float] | None = None) -> A2lDocument:
    """``doc`` with its XCP description replaced by that of the slave whose parameters per transport
    ("CAN", "UDP", "TCP": those ``doc`` describes) are ``params``; named ``<doc stem>-<name>.a2l``.

    :raises InputError: ``doc`` has no calibration segment (MEMORY_SEGMENT with an XCP SEGMENT) to redraw.
    """
    config = read_xcp_config(doc)
    described = _describe(config, params, memory_map, timeouts_s or {})
    memory = [m for m in doc.memory_segments() if any(s.memory_segment == m.name for s in config.segments)]
    if not memory:
        raise InputError(f"{doc.path or 'the A2L'}: no MEMORY_SEGMENT with an IF_DATA XCP SEGMENT to describe the "
                         "slave's calibration pages in")
    module = doc.module()
    if_data = next(b for b in module.children_named("IF_DATA") if b.name in ("XCP", "XCPplus"))
    segments = _memory_segments(memory[0], described.segments)
    edits = Edits([Edit(*if_data.span, _in_place(doc, if_data.span[0], format_if_data_xcp(described))),
                   Edit(*memory[0].block.span, _in_place(doc, memory[0].block.span[0], segments))])
    edits.extend(Edit(*m.block.span, b"") for m in memory[1:])
    data = edits.apply(doc.data)
    path = doc.path.with_name(f"{doc.path.stem}-{name}.a2l") if doc.path else Path(f"FLCU-{name}.a2l")
    return load_a2l_string(data.decode(doc.encoding), path)


def _in_place(doc: A2lDocument, offset: int, text: str) -> bytes:
    """``text`` indented as the line at ``offset`` is (its first line goes where the old block began)."""
    line_start = doc.data.rfind(b"\n", 0, offset) + 1
    indent = doc.data[line_start:offset].decode(doc.encoding)
    indent = indent if not indent.strip() else ""
    newline = doc.source.newline
    lines = [line if i == 0 else indent + line for i, line in enumerate(text.splitlines())]
    return newline.join(lines).encode(doc.encoding)


def _memory_segments(base, segments: tuple[XcpSegment, ...]) -> str:
    return "\n".join(format_memory_segment(s.memory_segment, f"{base.long_identifier} (XCP segment {s.number})"
                                           if len(segments) > 1 else base.long_identifier,
                                           base.prg_type, base.memory_type, base.attribute, s.address, s.size, s)
                     for s in segments)


def _describe(config: XcpConfig, params: Mapping[str, XcpParameters], memory_map: MemoryMap,
              timeouts_s: Mapping[str, float]) -> XcpConfig:
    common_transport = "CAN" if "CAN" in params else next(iter(params))
    common = params[common_transport]
    layer = _protocol_layer(config, common, common_transport, timeouts_s)
    described = replace(config, **vars(layer), daq=_daq(config, common),
                        max_segments=len(_segments(common, memory_map)),
                        segments=_xcp_segments(config, common, memory_map), pgm=_pgm(config, common, memory_map))
    if config.can is not None and "CAN" in params:
        can = params["CAN"]
        described = replace(described, can=replace(
            config.can, max_dlc_required=can.max_dlc_required, max_dlc=64 if can.can_fd else None,
            fd_data_baudrate=CAN_FD_DATA_BAUDRATE if can.can_fd else None, protocol_layer=None, daq=None, pgm=None,
            daq_list_can_ids=_daq_list_can_ids(can),
            optional_tl_subcommands=tuple(sub.name for sub in sorted(can.can_sub_commands, reverse=True))))
    for transport in ("UDP", "TCP"):
        block = getattr(config, transport.lower())
        if block is None or transport not in params:
            continue
        own = params[transport]
        block = replace(block, protocol_layer=replace(layer, max_cto=own.max_cto, max_dto=own.max_dto,
                                                      optional_commands=_commands(own, transport)),
                        daq=None, pgm=_pgm(config, own, memory_map))
        described = replace(described, **{transport.lower(): block})
    return described


def _daq_list_can_ids(can: XcpParameters) -> tuple[XcpDaqListCanId, ...]:
    """DAQ_LIST_CAN_ID per list with an id of its own: FIXED with it, or VARIABLE (the id it starts on is the
    slave's business: a master that does not SET_DAQ_ID it hears nothing)."""
    stated = {number: can_id for number, can_id in can.daq_can_ids} | {number: None for number, _ in
                                                                         can.variable_daq_can_ids}
    return tuple(XcpDaqListCanId(number, can_id) for number, can_id in sorted(stated.items()))


def _commands(params: XcpParameters, transport: str) -> frozenset[str]:
    """OPTIONAL_CMD on ``transport``: what the slave (without an ECU: it only lists them) and the port answer."""
    commands = XcpSlave(None, params, None).commands | params.transport_commands(transport)
    return frozenset(command.name for command in commands - _MANDATORY)


def _protocol_layer(config: XcpConfig, params: XcpParameters, transport: str,
                    timeouts_s: Mapping[str, float]) -> XcpProtocolLayer:
    return XcpProtocolLayer(
        protocol_version=config.protocol_version,
        timeouts=replace(config.timeouts, **timeouts_s),
        max_cto=params.max_cto, max_dto=params.max_dto,
        byte_order="MSB_FIRST" if params.byte_order == ">" else "MSB_LAST",
        address_granularity=params.address_granularity,
        optional_commands=_commands(params, transport),
        communication_mode=XcpCommunicationMode(
            slave_block_mode=params.slave_block_mode, master_block_mode=params.master_block_mode,
            max_bs=params.max_bs if params.master_block_mode else None,
            min_st_s=params.min_st_100us * 100e-6 if params.master_block_mode else None),
        seed_and_key_function=config.seed_and_key_function,
    )


def _daq(config: XcpConfig, params: XcpParameters) -> XcpDaq:
    daq = params.daq
    stamp = (XcpTimestamp(daq.timestamp_size, TIME_UNIT_S[daq.timestamp_unit], daq.timestamp_ticks,
                          daq.timestamp_fixed) if daq.timestamp_size else None)
    events = tuple(XcpEvent(e.number, e.name, _short_name(config, e.number, e.name), "DAQ", 0xFF,
                            (e.period_s or None) if params.events_cyclic else None,
                            e.priority) for e in params.events)
    return XcpDaq(
        config_type="STATIC" if daq.static else "DYNAMIC",
        max_daq=len(daq.static_lists) if daq.static else daq.max_daq,
        max_event_channels=len(events), min_daq=daq.min_daq,
        optimisation_type="OPTIMISATION_TYPE_DEFAULT", address_extension="ADDRESS_EXTENSION_FREE",
        identification_field=daq.identification_field, granularity=daq.granularity,
        max_odt_entry_size=daq.max_odt_entry_size, overload_indication="NO_OVERLOAD_INDICATION",
        timestamp=stamp, events=events,
    )


def _short_name(config: XcpConfig, number: int, name: str) -> str:
    known = [e for e in (config.daq.events if config.daq else ()) if e.number == number]
    return known[0].short_name if known else name


def _segments(params: XcpParameters, memory_map: MemoryMap):
    return params.segments or (memory_map.cal_ram,)


def _xcp_segments(config: XcpConfig, params: XcpParameters, memory_map: MemoryMap) -> tuple[XcpSegment, ...]:
    base = config.segments[0]
    ranges = _segments(params, memory_map)
    return tuple(replace(base, memory_segment=base.memory_segment if len(ranges) == 1 else f"{base.memory_segment}_{n}",
                         address=r.start, size=r.size, number=n, checksum_type=f"XCP_{params.checksum_type.name}",
                         checksum_max_block_size=params.max_checksum_block,
                         address_mappings=(XcpAddressMapping(r.start, memory_map.rom_address(r.start), r.size),))
                 for n, r in enumerate(ranges))


def _pgm(config: XcpConfig, params: XcpParameters, memory_map: MemoryMap):
    if config.pgm is None:
        return None
    pgm = params.programming
    mode = (XcpCommunicationMode(master_block_mode=True, max_bs=pgm.max_bs, min_st_s=pgm.min_st_100us * 100e-6)
            if pgm.master_block_mode else None)
    sectors = tuple(XcpSector(s.name, n, s.range.start, s.range.size, s.clear_sequence, s.program_sequence, 0)
                    for n, s in enumerate(memory_map.sectors))
    return replace(config.pgm, max_sectors=len(sectors), max_cto_pgm=pgm.max_cto, sectors=sectors,
                   communication_mode=mode)
