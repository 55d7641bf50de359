"""Loading a DBC file with cantools, with every problem turned into an :class:`InputError`.

cantools parses; this module adds what the workbench needs around it:

* the file is decoded as UTF-8 (with or without BOM), as UTF-16 when it starts with a
  UTF-16 BOM, and, failing that, as Windows-1252 (CANdb++'s encoding), so umlauts in
  comments never stop a load; an empty file or one with NUL bytes (a binary, not a DBC)
  is refused before cantools sees it;
* signals keep their DBC file order (cantools sorts them by start bit by default);
* loading is not strict: overlapping signals or signals beyond the DLC are left to
  :mod:`workbench.can.validation`, which reports them all with names and lines;
* cantools' exceptions and log warnings become one-line :class:`InputError` s naming the
  file and, where the position is known, the line (a syntax error quotes a few characters
  around the spot, not the whole line); its "Overwriting message" warnings
  about duplicate names/ids are dropped because the validation reports those itself;
* the line of every ``BO_`` and ``SG_`` is indexed, so findings can point into the file.

A standard id above 0x7FF (no bit 31 in the ``BO_`` id) makes cantools refuse the whole
file. :func:`load_dbc` reports it as an error at that line; with ``tolerant=True`` (for
``workbench dbc check``) the message is loaded as extended instead and listed in
:attr:`DbcFile.oversized_standard_ids`, so the check can go on and report everything.
"""

from __future__ import annotations

import codecs
import logging
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import cantools.database
from cantools.database.can import Database

from workbench.errors import InputError
from workbench.fileio import read_input

log = logging.getLogger(__name__)

EXTENDED_ID_FLAG = 0x80000000  # bit 31 of a BO_ id: the message has a 29-bit (extended) id
_STANDARD_ID_MAX = 0x7FF
_MESSAGE_LINE = re.compile(r"^[ \t]*BO_[ \t]+(\d+)[ \t]+(\w+)[ \t]*:", re.MULTILINE)
_SIGNAL_LINE = re.compile(r"^[ \t]*SG_[ \t]+(\w+)\s")
# Keywords after which the DBC grammar puts a message id (BA_/CM_ ... BO_ <id>, VAL_ <id> ...).
_ID_REFERENCE = r"\b(BO_|SG_|VAL_|SIG_VALTYPE_|BO_TX_BU_|SG_MUL_VAL_|SIG_GROUP_)(\s+){id}\b"
_MESSAGE_IN_ERROR = re.compile(r"in message '?(\w+)'?")
_POSITION_IN_ERROR = re.compile(r" at line \d+, column \d+")
_OVERWRITE_WARNING = "Overwriting message"
_SYNTAX_EXCERPT = re.compile(r'"(.*)>>!<<(.*)"$')
_EXCERPT_CHARS = 30
_UTF16_BOMS = (codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)


@dataclass(frozen=True)
class DbcFile:
    """A loaded DBC: the cantools database plus where each message and signal is in the file."""

    path: Path
    database: Database
    message_lines: dict[str, tuple[int, ...]] = field(default_factory=dict)
    """Message name → 1-based lines of its ``BO_`` s (more than one when the name is doubled)."""
    signal_lines: dict[tuple[int, str], int] = field(default_factory=dict)
    """(line of the message's ``BO_``, signal name) → 1-based line of the signal's ``SG_``."""
    oversized_standard_ids: tuple[str, ...] = ()
    """Messages whose ``BO_`` id is above 0x7FF without the extended flag (tolerant loads only)."""

    def message_line(self, name: str, occurrence: int = 0) -> int:
        """The line of the ``occurrence``-th ``BO_`` named ``name`` (0 when unknown)."""
        lines = self.message_lines.get(name, ())
        return lines[occurrence] if occurrence < len(lines) else 0

    def signal_line(self, message_line: int, signal: str) -> int:
        """The line of a signal's ``SG_`` in the message at ``message_line`` (that line when unknown)."""
        return self.signal_lines.get((message_line, signal), message_line)

    def where(self, line: int) -> str:
        """``path:line`` for error messages (just the path when the line is unknown)."""
        return f"{self.path}:{line}" if line else str(self.path)


def load_dbc(path: str | Path, *, tolerant: bool = False) -> DbcFile:
    """Load one DBC file.

    :param tolerant: load a standard id above 0x7FF as extended instead of failing
        (the check reports it).
    :raises InputError: the file cannot be read or cantools rejects it (``path:line: reason``).
    """
    path = Path(path)
    text = _decode(path, read_input(path, "a DBC file"))
    message_lines, signal_lines = _index_lines(text)
    oversized = _oversized_standard_ids(text)
    if oversized and not tolerant:
        name, frame_id, line = oversized[0]
        raise InputError(
            f"{path}:{line}: message {name}: standard id 0x{frame_id:X} does not fit in 11 bits "
            f"(an extended id needs bit 31 set in the BO_ id: {frame_id | EXTENDED_ID_FLAG})"
        )
    for _name, frame_id, _line in oversized:
        text = re.sub(_ID_REFERENCE.format(id=frame_id), rf"\g<1>\g<2>{frame_id | EXTENDED_ID_FLAG}", text)
    database = _parse(path, text, message_lines)
    return DbcFile(path, database, message_lines, signal_lines, tuple(name for name, _, _ in oversized))


def _decode(path: Path, raw: bytes) -> str:
    """The text of a DBC file.

    :raises InputError: the file is empty or binary.
    """
    if raw.startswith(_UTF16_BOMS):
        text = raw.decode("utf-16", errors="replace")
    elif b"\0" in raw:
        raise InputError(f"{path}: not a DBC: binary content (a NUL byte at offset {raw.index(0)})")
    else:
        try:
            text = raw.decode("utf-8-sig")
        except UnicodeDecodeError:
            text = raw.decode("cp1252", errors="replace")
    if not text.strip():
        raise InputError(f"{path}: not a DBC: the file is empty")
    return text


def _index_lines(text: str) -> tuple[dict[str, int], dict[tuple[str, str], int]]:
    message_lines: dict[str, tuple[int, ...]] = {}
    signal_lines: dict[tuple[int, str], int] = {}
    current = 0
    for number, line in enumerate(text.splitlines(), start=1):
        message = _MESSAGE_LINE.match(line)
        if message:
            current = number
            message_lines[message.group(2)] = message_lines.get(message.group(2), ()) + (number,)
            continue
        signal = _SIGNAL_LINE.match(line)
        if signal and current:
            signal_lines.setdefault((current, signal.group(1)), number)
        elif line.strip():
            current = 0
    return message_lines, signal_lines


def _oversized_standard_ids(text: str) -> list[tuple[str, int, int]]:
    found = []
    for match in _MESSAGE_LINE.finditer(text):
        frame_id = int(match.group(1))
        if _STANDARD_ID_MAX < frame_id < EXTENDED_ID_FLAG:
            found.append((match.group(2), frame_id, text.count("\n", 0, match.start()) + 1))
    return found


class _WarningCollector(logging.Handler):
    """Keeps the messages of the cantools warnings logged during one load."""

    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(record.getMessage())


def _parse(path: Path, text: str, message_lines: dict[str, tuple[int, ...]]) -> Database:
    cantools_log = logging.getLogger("cantools")
    collector = _WarningCollector()
    cantools_log.addHandler(collector)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            database = cantools.database.load_string(text, database_format="dbc", strict=False, sort_signals=None)
    except (cantools.database.Error, ValueError) as exc:
        cause = getattr(exc, "e_dbc", None) or exc
        raise InputError(_located(path, cause, message_lines)) from exc
    finally:
        cantools_log.removeHandler(collector)
    problems = []
    for message in collector.messages:
        if message.startswith(_OVERWRITE_WARNING):
            log.debug("%s: cantools: %s", path, message)  # a duplicate the validation reports
        else:
            problems.append(message)
    problems += [str(w.message) for w in caught]
    if problems:
        raise InputError(f"{path}: {_one_line(problems[0])}")
    if not isinstance(database, Database):
        raise InputError(f"{path}: not a CAN database")
    return database


def _located(path: Path, error: BaseException, message_lines: dict[str, tuple[int, ...]]) -> str:
    reason = _one_line(str(error))
    line = getattr(error, "line", None)
    if line:
        return f"{path}:{line}:{getattr(error, 'column', 0)}: {_short_excerpt(_POSITION_IN_ERROR.sub('', reason))}"
    mentioned = _MESSAGE_IN_ERROR.search(reason)
    if mentioned and mentioned.group(1) in message_lines:
        return f"{path}:{message_lines[mentioned.group(1)][0]}: {reason}"
    return f"{path}: {reason}"


def _short_excerpt(reason: str) -> str:
    """A syntax error's quoted line cut to a few characters either side of cantools' ``>>!<<``."""
    match = _SYNTAX_EXCERPT.search(reason)
    if match is None:
        return reason
    before, after = match.group(1), match.group(2)
    if len(before) > _EXCERPT_CHARS:
        before = "…" + before[-_EXCERPT_CHARS:]
    if len(after) > _EXCERPT_CHARS:
        after = after[:_EXCERPT_CHARS] + "…"
    return f'{reason[:match.start()]}"{before}>>!<<{after}"'


def _one_line(text: str) -> str:
    """``text`` on one line, without control characters (a stray byte must not garble the terminal)."""
    printable = "".join(char if char.isprintable() or char.isspace() else "?" for char in text)
    return " ".join(printable.split())
