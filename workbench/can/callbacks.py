"""The CAN driver configuration calls of api.c, generated between its ``// <initCbk>`` markers.

This is the thesis's "Generate callbacks" (chapter 6.3.2, Figure 55): every message of the
node's table gets, in mailbox order (TX first, then RX, network by network)::

    //callbacks automatically generated for FLCU_TO_PCM_003
    API_CAN_setPduInitValues(CAN2_MSG_TX_000, DataInitPduIntel);
    CanNetwork_SetTxPeriod(CAN2_MSG_TX_000, 100);
    CanNetwork_SetTxDlc(CAN2_MSG_TX_000, 8);
    CanNetwork_EnableDisableSendMessages(CAN2_MSG_TX_000, TRUE);

    //callbacks automatically generated for PCM_TO_FLCU_002
    CanNetwork_SetRxPeriod(CAN2_MSG_RX_000, 100);
    CanNetwork_SetRxTimeout(CAN2_MSG_RX_000, 300);
    CanNetwork_SetRxDlc(CAN2_MSG_RX_000, 4);
    CanNetwork_EnableDisableReceivedMessages(CAN2_MSG_RX_000, TRUE);

with a blank line before each group and one before the end marker. A TX message whose
signals are all Intel gets ``DataInitPduIntel``, one with a Motorola signal
``DataInitPduMotorola``. Periods and timeouts are milliseconds.

The markers are the lines ``// <initCbk>`` and ``// </initCbk>`` (any whitespace around
and inside them); there must be exactly one of each, start before end. Everything outside
them stays byte for byte as it was: the file is handled as bytes, the generated lines take
the start marker's indentation and line ending. Regenerating from the same DBCs writes
nothing; a new content is written atomically.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from workbench.can.model import Message, Role
from workbench.errors import InputError
from workbench.fileio import read_input, write_output

__all__ = ["END_MARKER", "START_MARKER", "callback_lines", "splice", "write_callbacks"]

START_MARKER = "// <initCbk>"
END_MARKER = "// </initCbk>"
_START = re.compile(rb"^[ \t]*//[ \t]*<initCbk>[ \t]*$")
_END = re.compile(rb"^[ \t]*//[ \t]*</initCbk>[ \t]*$")
_INDENT = re.compile(rb"^[ \t]*")


def callback_lines(messages: Iterable[Message]) -> list[str]:
    """The generated lines (without indentation or line endings) for the node's messages.

    :raises InputError: a message lacks the period the driver needs (a missing timeout is 3 × period).
    """
    lines: list[str] = []
    for message in messages:
        if message.role is None or message.mailbox is None:
            continue
        if message.period_ms is None:
            raise InputError(f"{message.where()}: message {message.name} has no period "
                             "(GenMsgCycleTime); the driver configuration needs one")
        mailbox, enable = message.mailbox, "TRUE" if message.enable else "FALSE"
        lines += ["", f"//callbacks automatically generated for {message.name}"]
        if message.role is Role.TX:
            init_data = "DataInitPduIntel" if message.is_intel else "DataInitPduMotorola"
            lines += [
                f"API_CAN_setPduInitValues({mailbox}, {init_data});",
                f"CanNetwork_SetTxPeriod({mailbox}, {message.period_ms});",
                f"CanNetwork_SetTxDlc({mailbox}, {message.dlc});",
                f"CanNetwork_EnableDisableSendMessages({mailbox}, {enable});",
            ]
        else:
            lines += [
                f"CanNetwork_SetRxPeriod({mailbox}, {message.period_ms});",
                f"CanNetwork_SetRxTimeout({mailbox}, {message.timeout_ms});",
                f"CanNetwork_SetRxDlc({mailbox}, {message.dlc});",
                f"CanNetwork_EnableDisableReceivedMessages({mailbox}, {enable});",
            ]
    return lines + [""]


@dataclass(frozen=True)
class _Markers:
    start: int
    """Index of the start marker line."""
    end: int
    indent: bytes
    newline: bytes


def _find_markers(path: Path, lines: Sequence[bytes]) -> _Markers:
    starts = [i for i, line in enumerate(lines) if _START.match(line.rstrip(b"\r\n"))]
    ends = [i for i, line in enumerate(lines) if _END.match(line.rstrip(b"\r\n"))]
    for found, marker in ((starts, START_MARKER), (ends, END_MARKER)):
        if not found:
            raise InputError(f"{path}: no '{marker}' marker line")
        if len(found) > 1:
            raise InputError(f"{path}:{found[1] + 1}: second '{marker}' marker (the first is at line {found[0] + 1})")
    start, end = starts[0], ends[0]
    if end < start:
        raise InputError(f"{path}:{end + 1}: '{END_MARKER}' comes before '{START_MARKER}' (line {start + 1})")
    marker_line = lines[start]
    newline = b"\r\n" if marker_line.endswith(b"\r\n") else b"\n"
    return _Markers(start, end, _INDENT.match(marker_line).group(0), newline)


def splice(path: str | Path, content: bytes, generated: Sequence[str]) -> bytes:
    """``content`` (an api.c) with ``generated`` lines between its markers.

    :raises InputError: a marker is missing, doubled or out of order (``path:line``).
    """
    lines = content.splitlines(keepends=True)
    markers = _find_markers(Path(path), lines)
    body = b"".join(
        (markers.indent + line.encode("utf-8") if line else b"") + markers.newline for line in generated
    )
    return b"".join(lines[: markers.start + 1]) + body + b"".join(lines[markers.end:])


def write_callbacks(api_path: str | Path, messages: Iterable[Message]) -> bool:
    """Regenerate the driver configuration in ``api_path``; returns whether the file changed.

    Nothing is written when the result equals the file, or when an error is raised.

    :raises InputError: the file cannot be read or written there, its markers are wrong, a message
        lacks a period, or no message has a mailbox (a node without messages would empty the block).
    :raises WorkbenchError: the write failed otherwise (:func:`~workbench.fileio.write_output`).
    """
    api_path = Path(api_path)
    messages = list(messages)
    if not any(message.role is not None and message.mailbox is not None for message in messages):
        raise InputError(f"{api_path}: the node sends and receives no message; its driver configuration "
                         "is left as it is")
    generated = callback_lines(messages)
    content = read_input(api_path, "a C file")
    updated = splice(api_path, content, generated)
    if updated == content:
        return False
    write_output(api_path, updated)
    return True
