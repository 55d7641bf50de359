"""The message table as text (aligned columns, signals under their message) and as CSV."""

from __future__ import annotations

import csv
import io
from collections.abc import Sequence

from workbench.can.fixcal import format_number
from workbench.can.model import Message, SignalOfMsg
from workbench.can.table import CanTable

__all__ = ["MESSAGE_COLUMNS", "SIGNAL_COLUMNS", "message_cells", "signal_cells", "table_csv", "table_text"]

MESSAGE_COLUMNS = ("MboxId", "Role", "Name", "ID", "NetworkType", "Type", "DLC", "Period", "Timeout",
                   "Enable", "UniqueID")
SIGNAL_COLUMNS = ("Signal", "BitStart", "Length", "ByteOrder", "ValueType", "Factor", "Offset", "Min", "Max",
                  "Unit", "Comment")
_DEFAULT_TIMEOUT_MARK = "*"


def message_cells(message: Message) -> list[str]:
    timeout = "" if message.timeout_ms is None else str(message.timeout_ms)
    if message.timeout_is_default and timeout:
        timeout += _DEFAULT_TIMEOUT_MARK
    return [
        message.mailbox or "-", message.role.value if message.role else "-", message.name,
        f"0x{message.frame_id:X}", message.network or "-", message.type, str(message.dlc),
        "" if message.period_ms is None else str(message.period_ms), timeout,
        "yes" if message.enable else "no", "yes" if message.unique_id else "no",
    ]


def signal_cells(signal: SignalOfMsg) -> list[str]:
    def number(value: float | None) -> str:
        return "" if value is None else format_number(value)

    return [
        signal.name, str(signal.bit_start), str(signal.length), signal.byte_order, signal.value_type,
        number(signal.factor), number(signal.offset), number(signal.minimum), number(signal.maximum),
        signal.unit, signal.comment,
    ]


def table_text(table: CanTable) -> str:
    """Messages as aligned rows, each followed by its signals (indented), then notes."""
    message_rows = [list(MESSAGE_COLUMNS)] + [message_cells(m) for m in table.messages]
    signal_rows = [list(SIGNAL_COLUMNS)] + [_one_line_cells(s) for m in table.messages for s in m.signals]
    message_widths, signal_widths = _widths(message_rows), _widths(signal_rows)
    lines = [_row(message_rows[0], message_widths), "    " + _row(signal_rows[0], signal_widths)]
    for message in table.messages:
        lines.append(_row(message_cells(message), message_widths))
        lines += ["    " + _row(_one_line_cells(s), signal_widths) for s in message.signals]
    if any(m.timeout_is_default and m.timeout_ms is not None for m in table.messages):
        lines.append(f"{_DEFAULT_TIMEOUT_MARK} no GenMsgTimeoutTime in the DBC: 3 x period")
    if table.node is None:
        lines.append("no --node given: roles (RX/TX) and mailboxes are relative to a node")
    elif table.others:
        lines.append(f"not in {table.node}'s table (neither sent nor received by it): "
                     + ", ".join(m.name for m in table.others))
    return "\n".join(lines) + "\n"


def table_csv(table: CanTable) -> str:
    """One row per signal (message columns repeated); a message without signals has one row."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(MESSAGE_COLUMNS + SIGNAL_COLUMNS)
    for message in table.messages:
        cells = message_cells(message)
        cells[MESSAGE_COLUMNS.index("Timeout")] = "" if message.timeout_ms is None else str(message.timeout_ms)
        for signal in message.signals or (None,):
            writer.writerow(cells + (signal_cells(signal) if signal else [""] * len(SIGNAL_COLUMNS)))
    return out.getvalue()


def _widths(rows: Sequence[Sequence[str]]) -> list[int]:
    return [max(len(row[i]) for row in rows) for i in range(len(rows[0]))]


def _row(cells: Sequence[str], widths: Sequence[int]) -> str:
    return "  ".join(cell.ljust(width) for cell, width in zip(cells, widths)).rstrip()


def _one_line_cells(signal: SignalOfMsg) -> list[str]:
    """The signal's cells for the text table: a DBC comment may span several lines, a row may not."""
    return [" ".join(cell.split()) if "\n" in cell or "\r" in cell else cell for cell in signal_cells(signal)]
