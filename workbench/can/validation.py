"""DBC problems a user would hit, reported with file, line, message and signal.

The report starts with what the load repaired or ignored (:attr:`DbcFile.warnings
<workbench.can.dbc_file.DbcFile.warnings>`: ``id-format``, ``name-syntax``,
``unknown-reference`` ..., see :mod:`workbench.can.dbc_repair`), then these checks, each a
:class:`~workbench.findings.Finding` of one ``kind`` named ``MESSAGE`` or
``MESSAGE.SIGNAL`` (block ``BO_`` or ``SG_``), an error unless said otherwise:

* ``overlap`` — two signals of a message share a bit (multiplexed signals only when they
  can be present together);
* ``beyond-dlc`` — a signal has bits outside the message's DLC; ``signal-type`` — a signal
  whose raw value fits no C type (over 64 bits, or a float of other than 32/64 bits);
* ``duplicate-id`` — two messages of one network have the same id and frame format
  (across all DBCs given for that network); ``duplicate-name`` — the same for names, and
  a signal name used twice in one message;
* ``missing-period`` — a message without (or with a zero) ``GenMsgCycleTime``, so neither
  its period nor its default timeout is known: one warning per message, or one for the
  file when it defines no ``GenMsgCycleTime`` at all; ``missing-timeout`` — a message with
  a period but no ``GenMsgTimeoutTime`` (the table uses 3 × period, as the thesis does): a
  warning per message, or one note (info) for a file that defines no ``GenMsgTimeoutTime``;
* ``id-format`` — a message's explicit ``VFrameFormat`` that disagrees with its id (only
  the attribute set on the message counts: a ``BA_DEF_DEF_`` default says nothing about
  one message);
* ``fixcal-collision`` — one hint (info) when signals would define the same
  ``cf<SIGNAL>_EN``/``_VALUE`` calibration: a matter for ``workbench dbc fixcal``, which
  refuses them (among the node's messages when a node is given; with ``qualified`` the
  message-qualified ``cf<MESSAGE>_<SIGNAL>_…`` names are checked).
"""

from __future__ import annotations

from collections import Counter, defaultdict
from collections.abc import Sequence
from itertools import combinations

from workbench.can.dbc_file import DbcFile
from workbench.can.fixcal import collision_remedy, describe_owners, fixcal_collisions
from workbench.can.naming import FIX_ENABLE_SUFFIX, FIX_VALUE_SUFFIX, raw_c_type
from workbench.can.model import (
    FRAME_FORMAT_ATTRIBUTE,
    PERIOD_ATTRIBUTE,
    TIMEOUT_ATTRIBUTE,
    Message,
    SignalOfMsg,
    check_node,
    messages_of,
)
from workbench.findings import Finding, Report, Severity

__all__ = ["bit_positions", "check_dbcs"]

_HINT_NAMES = 3  # collisions named in the fix-calibration hint
_EXTENDED_FORMATS = ("ExtendedCAN", "ExtendedCAN_FD", "J1939PG")
_STANDARD_FORMATS = ("StandardCAN", "StandardCAN_FD")


def bit_positions(signal: SignalOfMsg) -> list[int]:
    """The payload bits a signal occupies, as byte · 8 + bit (bit 0 = LSB of the byte)."""
    if signal.byte_order == "Intel":
        return list(range(signal.bit_start, signal.bit_start + signal.length))
    positions, position = [], signal.bit_start
    for _ in range(signal.length):  # Motorola: from the MSB down, then into the next byte's bit 7
        positions.append(position)
        position = position + 15 if position % 8 == 0 else position - 1
    return positions


def check_dbcs(dbcs: Sequence[tuple[DbcFile, str | None]], node: str | None = None, *,
          qualified: bool = False) -> Report:
    """Every finding in ``dbcs`` ((DBC, network) pairs), in file and line order.

    The report fails (:attr:`Report.ok <workbench.findings.Report.ok>` False) on a warning or an
    error; hints (info) leave it ok.

    Duplicate ids and names are looked for among the DBCs of one network; a DBC without a
    network is compared with itself only.

    :param qualified: look for collisions of the message-qualified fix-calibration names.

    :raises InputError: ``node`` is given but is not a node of one of the DBCs.
    """
    if node is not None:
        for dbc, _network in dbcs:
            check_node(dbc, node)
    per_dbc = [(dbc, messages_of(dbc, network, None)) for dbc, network in dbcs]
    everything = [message for _, messages in per_dbc for message in messages]
    findings: list[Finding] = []
    for dbc, messages in per_dbc:
        findings += dbc.warnings
        findings += _timing_findings(dbc, messages)
        for message in messages:
            findings += _layout_findings(message)
            findings += _format_findings(dbc, message)
    findings += _duplicate_findings(everything)
    in_scope = [m for dbc, network in dbcs for m in messages_of(dbc, network, node) if node is None or m.role]
    findings += _collision_hint(in_scope, qualified)
    return Report("check", sorted(findings, key=lambda f: (f.file, f.line, f.kind)), fails_on=Severity.WARNING)


def _finding(kind: str, message: Message, signal: str | None, text: str,
             severity: Severity = Severity.ERROR) -> Finding:
    dbc = message.source
    line = (dbc.signal_line(message.line, signal) if signal else message.line) if dbc else 0
    name = f"{message.name}.{signal}" if signal else message.name
    return Finding(kind, name, f"{name}: {text}", str(dbc.path) if dbc else "", line, 0, "SG_" if signal else "BO_",
                   severity)


def _layout_findings(message: Message) -> list[Finding]:
    findings = []
    size = message.dlc * 8
    bits = [set(bit_positions(signal)) for signal in message.signals]
    for signal, occupied in zip(message.signals, bits):
        problem = _c_type_problem(signal)
        if problem:
            findings.append(_finding("signal-type", message, signal.name, problem))
        outside = [b for b in occupied if not 0 <= b < size]
        if outside:
            findings.append(_finding(
                "beyond-dlc", message, signal.name,
                f"bits {min(outside)}..{max(outside)} lie beyond the DLC of {message.dlc} bytes",
            ))
    for name, count in Counter(signal.name for signal in message.signals).items():
        if count > 1:
            findings.append(_finding("duplicate-name", message, None, f"signal {name} is defined {count} times"))
    for (first, first_bits), (second, second_bits) in combinations(zip(message.signals, bits), 2):
        if not _can_coexist(first, second):
            continue
        shared = first_bits & second_bits
        if shared:
            findings.append(_finding(
                "overlap", message, second.name,
                f"overlaps {first.name} in bit{'s' if len(shared) > 1 else ''} {_bit_list(shared)}",
            ))
    return findings


def _c_type_problem(signal: SignalOfMsg) -> str | None:
    try:
        raw_c_type(signal.length, signal.is_signed, signal.is_float)
    except ValueError as exc:
        return str(exc)
    return None


def _can_coexist(first: SignalOfMsg, second: SignalOfMsg) -> bool:
    if first.multiplexer_ids is None or second.multiplexer_ids is None:
        return True
    return bool(set(first.multiplexer_ids) & set(second.multiplexer_ids))


def _bit_list(bits: set[int]) -> str:
    ordered = sorted(bits)
    return f"{ordered[0]}..{ordered[-1]}" if len(ordered) > 1 else str(ordered[0])


def _timing_findings(dbc: DbcFile, messages: list[Message]) -> list[Finding]:
    """One finding per message whose period or timeout is missing; one per file for an attribute it never defines."""
    findings = []
    without_period = [m for m in messages if m.period_ms is None]
    defaulted = [m for m in messages if m.period_ms is not None and m.timeout_is_default]
    if without_period and not _defines(dbc, PERIOD_ATTRIBUTE):
        findings.append(_file_finding(
            "missing-period", dbc, f"the DBC defines no {PERIOD_ATTRIBUTE}: the periods (and so the default "
            f"timeouts) of its {len(without_period)} message{'s' if len(without_period) > 1 else ''} are unknown",
            Severity.WARNING))
        without_period = []
    for message in without_period:
        text = (f"no {PERIOD_ATTRIBUTE} (or 0) and no {TIMEOUT_ATTRIBUTE}: period and timeout are unknown"
                if message.timeout_is_default else f"no {PERIOD_ATTRIBUTE} (or 0): the period is unknown")
        findings.append(_finding("missing-period", message, None, text, Severity.WARNING))
    if defaulted and not _defines(dbc, TIMEOUT_ATTRIBUTE):
        findings.append(_file_finding(
            "missing-timeout", dbc, f"the DBC defines no {TIMEOUT_ATTRIBUTE}: the timeout of each of its "
            f"{len(defaulted)} message{'s' if len(defaulted) > 1 else ''} with a period is 3 × period, as the "
            "thesis's import does", Severity.INFO))
        defaulted = []
    for message in defaulted:
        findings.append(_finding("missing-timeout", message, None,
                                 f"no {TIMEOUT_ATTRIBUTE}: using 3 × period = {message.timeout_ms} ms",
                                 Severity.WARNING))
    return findings


def _defines(dbc: DbcFile, attribute: str) -> bool:
    return attribute in dbc.content.attributes


def _file_finding(kind: str, dbc: DbcFile, text: str, severity: Severity) -> Finding:
    return Finding(kind, dbc.path.name, f"{dbc.path.name}: {text}", str(dbc.path), 0, 0, "BA_DEF_", severity)


def _format_findings(dbc: DbcFile, message: Message) -> list[Finding]:
    frame_format = dbc.content.frame_formats.get(message.name)
    if frame_format in _EXTENDED_FORMATS and not message.extended:
        kind = "standard"
    elif frame_format in _STANDARD_FORMATS and message.extended:
        kind = "extended"
    else:
        return []
    return [_finding("id-format", message, None, f"{FRAME_FORMAT_ATTRIBUTE} is {frame_format} but the id is {kind}")]


def _duplicate_findings(messages: list[Message]) -> list[Finding]:
    findings = []
    by_id: dict[tuple, list[Message]] = defaultdict(list)
    by_name: dict[tuple, list[Message]] = defaultdict(list)
    for message in messages:
        bus = message.network or str(message.source.path if message.source else "")
        by_id[(bus, message.frame_id, message.extended)].append(message)
        by_name[(bus, message.name)].append(message)
    for (bus, frame_id, extended), owners in by_id.items():
        for message in owners[1:]:
            findings.append(_finding(
                "duplicate-id", message, None,
                f"{'extended' if extended else 'standard'} id 0x{frame_id:X} is also used by "
                + ", ".join(f"{other.name} ({other.where()})" for other in owners if other is not message),
            ))
    for (_bus, _name), owners in by_name.items():
        for message in owners[1:]:
            findings.append(_finding(
                "duplicate-name", message, None,
                "message name also used at " + ", ".join(o.where() for o in owners if o is not message),
            ))
    return findings


def _collision_hint(messages: list[Message], qualified: bool) -> list[Finding]:
    """One hint for all fix-calibration names that signals would share (``workbench dbc fixcal`` refuses them)."""
    collisions = fixcal_collisions(messages, qualified=qualified)
    if not collisions:
        return []
    names = list(collisions)
    first_message, first_signal = collisions[names[0]][0]
    listed = "; ".join(f"{name.removesuffix(FIX_VALUE_SUFFIX)}{FIX_ENABLE_SUFFIX}/{FIX_VALUE_SUFFIX} by "
                       f"{describe_owners(collisions[name])}" for name in names[:_HINT_NAMES])
    more = f" and {len(names) - _HINT_NAMES} more" if len(names) > _HINT_NAMES else ""
    remedy = collision_remedy(messages, qualified)
    return [_finding(
        "fixcal-collision", first_message, first_signal.name,
        f"workbench dbc fixcal would define {len(names)} fix calibration name{'s' if len(names) > 1 else ''} more "
        f"than once ({listed}{more}){'; ' + remedy if remedy else ''}",
        Severity.INFO,
    )]
