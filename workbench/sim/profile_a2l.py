"""The A2L of a slave profile: the demo's A2L with IF_DATA XCP (and the calibration segments) as that slave is.

Everything a master reads from the A2L to talk to the slave is derived from the slave's own
parameters, never written by hand: PROTOCOL_LAYER (byte order, granularity, MAX_CTO/MAX_DTO per
transport, the commands the slave implements, its block modes, T1), DAQ (configuration type, MIN_DAQ,
identification field, granularity, timestamps), PAG and the MEMORY_SEGMENTs of the calibration
segments, PGM and XCP on CAN's MAX_DLC_REQUIRED, OPTIONAL_TL_SUBCMD, DAQ_LIST_CAN_ID and CAN FD (MAX_DLC and
data bit rate). Those items are written anew where they differ (:data:`_REWRITTEN`); the rest of the file stays as
it is, byte for byte, the rest of IF_DATA XCP too (XCP_ON_CAN's SAMPLE_RATE, BTL_CYCLES, SJW, SYNC_EDGE,
MAX_BUS_LOAD, the rest of CAN_FD, what an XCP_ON_UDP_IP adds, blocks of other transports, comments).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path

from workbench.a2l import A2lDocument, XcpConfig, load_a2l_string, read_xcp_config
from workbench.a2l.document import Block
from workbench.a2l.edits import Edit, Edits, cut_spans, indentation_of
from workbench.a2l.xcp import (
    XcpAddressMapping,
    XcpCommunicationMode,
    XcpDaq,
    XcpDaqList,
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
# What a profile writes anew in IF_DATA XCP, per block: its tags (with the number of values after each) and its
# child blocks; blocks named in _MERGED are edited item by item like this, the other child blocks replaced whole
_REWRITTEN: dict[str, tuple[dict[str, int], tuple[str, ...]]] = {
    "XCP": ({}, ("PROTOCOL_LAYER", "DAQ", "PAG", "PGM", "XCP_ON_CAN", "XCP_ON_UDP_IP", "XCP_ON_TCP_IP")),
    "XCP_ON_CAN": ({"MAX_DLC_REQUIRED": 0, "OPTIONAL_TL_SUBCMD": 1},
                   ("DAQ_LIST_CAN_ID", "CAN_FD", "PROTOCOL_LAYER", "DAQ", "PGM")),
    "CAN_FD": ({"MAX_DLC": 1, "CAN_FD_DATA_TRANSFER_BAUDRATE": 1}, ()),
    "XCP_ON_UDP_IP": ({}, ("PROTOCOL_LAYER", "DAQ", "PGM")),
    "XCP_ON_TCP_IP": ({}, ("PROTOCOL_LAYER", "DAQ", "PGM")),
}
_MERGED = frozenset({"XCP_ON_CAN", "XCP_ON_UDP_IP", "XCP_ON_TCP_IP", "CAN_FD"})


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
    edits = Edits(_merge(doc, if_data, _if_data_block(format_if_data_xcp(described)), "XCP"))
    drawn = _module_document(f'/begin MOD_PAR ""\n{segments}\n/end MOD_PAR').memory_segments()
    if [_words(m.block) for m in memory] != [_words(m.block) for m in drawn]:  # else kept as written (comments)
        edits.append(Edit(*memory[0].block.span, _in_place(doc, memory[0].block.span[0], segments)))
        edits.extend(Edit(*m.block.span, b"") for m in memory[1:])
    data = edits.apply(doc.data)
    path = doc.path.with_name(f"{doc.path.stem}-{name}.a2l") if doc.path else Path(f"FLCU-{name}.a2l")
    return load_a2l_string(data.decode(doc.encoding), path)


def _module_document(text: str) -> A2lDocument:
    """``text`` (blocks of a MODULE) as a document of its own, to read its blocks' items and spans."""
    return load_a2l_string(f'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n/begin MODULE M ""\n{text}\n/end MODULE\n'
                           "/end PROJECT\n")


def _if_data_block(text: str) -> Block:
    """``/begin IF_DATA XCP ... /end IF_DATA`` as a block of a document of its own (its items and spans)."""
    return next(b for b in _module_document(text).module().children_named("IF_DATA") if b.name == "XCP")


def _merge(doc: A2lDocument, source: Block, written: Block, rules: str) -> list[Edit]:
    """Edits that make ``source`` say what ``written`` (the writer's block of the profile) says in the items
    :data:`_REWRITTEN` names for ``rules``, keeping every other item of ``source`` as it is."""
    tags, blocks = _REWRITTEN[rules]
    edits: list[Edit] = []
    for tag, count in tags.items():
        edits += _replace_items(doc, source, _tagged(source, tag, count),
                                [(words, words) for words, _ in _tagged(written, tag, count)])
    order = [child.keyword for child in written.children]
    for keyword in blocks:
        old, new = source.children_named(keyword), written.children_named(keyword)
        if keyword in _MERGED and len(old) == len(new) == 1:
            edits += _merge(doc, old[0], new[0], keyword)
        elif len(old) == len(new) == 1:
            if _words(old[0]) != _words(new[0]):  # the same said stays as written (comments, layout)
                edits.append(Edit(*old[0].span, _in_place(doc, old[0].span[0], _reindented(new[0]))))
        else:  # added, removed, or repeated (DAQ_LIST_CAN_ID): block by block
            later = order[order.index(keyword) + 1:] if keyword in order else []
            before = next((child for child in source.children if child.keyword in later), None)
            edits += _replace_items(doc, source, [(_words(b), b.span) for b in old],
                                    [(_words(b), _reindented(b)) for b in new], before)
    return edits


def _tagged(block: Block, tag: str, count: int) -> list[tuple[str, tuple[int, int]]]:
    """``tag`` with the ``count`` values after it, each time ``block`` has it: (their words, their byte span)."""
    doc, own = block.doc, block.own_tokens
    return [(" ".join(doc.text(t) for t in own[at:at + count + 1]),
             (doc.tokens.span(token)[0], doc.tokens.span(own[at + count])[1]))
            for at, token in enumerate(own) if doc.text(token) == tag and at + count < len(own)]


def _replace_items(doc: A2lDocument, block: Block, old: list[tuple[str, tuple[int, int]]],
                   new: list[tuple[str, str]], before: Block | None = None) -> list[Edit]:
    """Cut the items of ``old`` (words, span) whose words ``new`` (words, text) lacks, add the texts of those of
    ``new`` that ``old`` lacks: on the lines after the last of ``old``, else before ``before`` (a child block of
    ``block``), else before ``block``'s ``/end``."""
    old_words, new_words = {words for words, _ in old}, {words for words, _ in new}
    edits = cut_spans(doc, [span for words, span in old if words not in new_words])
    added = [text for words, text in new if words not in old_words]
    if added:
        data, newline, encoding = doc.data, doc.source.newline, doc.encoding
        if old:
            line_end = data.find(b"\n", old[-1][1][1])
            at = len(data) if line_end < 0 else line_end + 1
        else:
            anchor = before.span[0] if before is not None else doc.tokens.span(block.end_token)[0]
            at = data.rfind(b"\n", 0, anchor) + 1
        indent = (indentation_of(data, old[0][1][0]) if old else _item_indent(block)).decode(encoding)
        text = "".join(indent + item.replace("\n", newline + indent) + newline for item in added)
        edits.append(Edit(at, at, text.encode(encoding)))
    return edits


def _item_indent(block: Block) -> bytes:
    """How the items of ``block`` are indented: as its second item (the first may share the ``/begin`` line), else
    two spaces more than the block."""
    doc = block.doc
    starts = sorted([doc.tokens.span(token)[0] for token in block.own_tokens] + [c.span[0] for c in block.children])
    on_own_line = [start for start in starts if doc.data.rfind(b"\n", 0, start) > block.span[0]]
    if on_own_line:
        return indentation_of(doc.data, on_own_line[0])
    return indentation_of(doc.data, block.span[0]) + b"  "


def _words(block: Block) -> str:
    """A block's tokens, one space apart: two blocks with the same words say the same, however laid out."""
    doc = block.doc
    return " ".join(doc.text(token) for token in range(block.begin_token, block.end_token + 2))


def _reindented(block: Block) -> str:
    """The text of ``block`` with its lines indented relative to its first."""
    doc = block.doc
    start, end = block.span
    indent = indentation_of(doc.data, start).decode(doc.encoding)
    lines = doc.data[start:end].decode(doc.encoding).split("\n")
    return "\n".join([lines[0], *(line[len(indent):] if line.startswith(indent) else line for line in lines[1:])])


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
        lists=tuple(XcpDaqList(number, "DAQ", shape.odts, shape.entries, shape.fixed_event)
                    for number, shape in enumerate(daq.static_lists)),
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
