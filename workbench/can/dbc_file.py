"""Loading a DBC file as cantools reads it: what CANdb++ reads loads, with a located warning per problem.

cantools' reading is the reference; this module adds what the workbench needs around it:

* the file is decoded as UTF-8 (with or without BOM), as UTF-16 when it starts with a
  UTF-16 BOM, and, failing that, as Windows-1252 (CANdb++'s encoding), so umlauts in
  comments never stop a load; an empty file or one with NUL bytes (a binary, not a DBC)
  is refused before cantools sees it;
* what CANdb++ reads but cantools refuses (a standard id above 0x7FF, names that start
  with a digit, comments without text, value descriptions of signals that do not exist,
  CANdb++'s ``VECTOR__INDEPENDENT_SIG_MSG`` placeholder ...) is repaired in the text by
  :mod:`workbench.can.dbc_repair` first; each problem becomes one warning in
  :attr:`DbcFile.warnings`, located ``file:line``, and the values read are those the file gives;
* signals keep their DBC file order (cantools sorts them by start bit by default);
* loading is not strict: overlapping signals or signals beyond the DLC are left to
  :mod:`workbench.can.validation`, which reports them all with names and lines;
* what cantools still refuses becomes a one-line :class:`InputError` naming the file and,
  where the position is known, the line (a syntax error quotes a few characters around the
  spot, not the whole line); its "Overwriting message" warnings about duplicate names/ids
  are dropped because the validation reports those itself;
* the line of every ``BO_`` and ``SG_`` is indexed, so findings can point into the file;
* what the commands need (:attr:`DbcFile.content`: nodes, messages, signals, the period and
  timeout attributes) is read from the statements the repair cut, by :mod:`workbench.can.dbc_read`
  with cantools' rules, without building cantools' database; where that reader is not sure to read
  as cantools does, cantools loads the file then and there. cantools' database, with its codecs for
  encoding and decoding, is :attr:`DbcFile.database`, built on first use.

Every command (``workbench dbc table|check|fixcal|callbacks``, the simulated ECU) loads
through :func:`load_dbc`, so they agree on what a file holds.
"""

from __future__ import annotations

import codecs
import logging
import re
import warnings
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

from workbench.can.dbc_read import Unreadable, read_content
from workbench.can.dbc_repair import EXTENDED_ID_FLAG, Repaired, repair
from workbench.can.dbc_text import DbcText
from workbench.can.model import DbcContent
from workbench.errors import InputError
from workbench.fileio import read_input
from workbench.findings import Finding, Severity
from workbench.logs import logger

log = logger(__name__)

__all__ = ["EXTENDED_ID_FLAG", "DbcFile", "load_dbc"]

_MESSAGE_IN_ERROR = re.compile(r"in message '?(\w+)'?")
_POSITION_IN_ERROR = re.compile(r" at line \d+, column \d+")
_OVERWRITE_WARNING = "Overwriting message"
_SYNTAX_EXCERPT = re.compile(r'"(.*)>>!<<(.*)"$')
_EXCERPT_CHARS = 30
_UTF16_BOMS = (codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)

if TYPE_CHECKING:
    from cantools.database.can import Database


@dataclass(frozen=True, eq=False)
class DbcFile:
    """A loaded DBC: its content, where each message and signal is in the file, and cantools' database."""

    path: Path
    content: DbcContent
    """Nodes, messages and signals as cantools reads them (what the commands use)."""
    repaired: Repaired = field(repr=False)
    """The text cantools reads, and where each message and signal is in the file."""
    warnings: tuple[Finding, ...] = ()
    """What the load repaired or ignored, one warning per problem, located ``file:line``."""

    @property
    def message_lines(self) -> dict[str, tuple[int, ...]]:
        """Message name → 1-based lines of its ``BO_`` s (more than one when the name is doubled)."""
        return self.repaired.message_lines

    @property
    def signal_lines(self) -> dict[tuple[int, str], int]:
        """(line of the message's ``BO_``, signal name) → 1-based line of the signal's ``SG_``."""
        return self.repaired.signal_lines

    @cached_property
    def database(self) -> Database:
        """cantools' database of the file, with the codecs to encode and decode its messages; built on first use.

        :raises InputError: cantools refuses the file (``path:line: reason``).
        """
        database, problems = _parse(self.path, self.repaired)
        for problem in problems:
            log.warning("%s", problem)
        return database

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


def load_dbc(path: str | Path) -> DbcFile:
    """Load one DBC file as CANdb++ would: problems it reads past are :attr:`DbcFile.warnings`.

    :raises InputError: the file cannot be read or cantools rejects it (``path:line: reason``).
    """
    path = Path(path)
    text = DbcText(_decode(path, read_input(path, "a DBC file")))
    repaired = repair(text, str(path))
    try:
        content = read_content(text if repaired.text == text.text else DbcText(repaired.text), repaired.original_name)
    except Unreadable as exc:
        log.debug("%s: read by cantools (%s)", path, exc)
    else:
        return DbcFile(path, content, repaired, repaired.warnings)
    from workbench.can.dbc_database import content_of_database  # here: it loads cantools

    database, cantools_warnings = _parse(path, repaired)
    content = content_of_database(database, repaired.message_lines)
    dbc = DbcFile(path, content, repaired, repaired.warnings + cantools_warnings)
    vars(dbc)["database"] = database  # cached_property's cache: parsed already
    return dbc


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


class _WarningCollector(logging.Handler):
    """Keeps the messages of the cantools warnings logged during one load."""

    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(record.getMessage())


def _parse(path: Path, repaired: Repaired) -> tuple[Database, tuple[Finding, ...]]:
    """cantools' database of the repaired text and its log warnings (but those about duplicates) as findings.

    :raises InputError: cantools refuses the text.
    """
    import cantools.database  # here: cantools loads only when a file needs its database

    cantools_log = logging.getLogger("cantools")
    collector = _WarningCollector()
    cantools_log.addHandler(collector)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            database = cantools.database.load_string(repaired.text, database_format="dbc", strict=False,
                                                     sort_signals=None)
    except (cantools.database.Error, ValueError) as exc:
        cause = getattr(exc, "e_dbc", None) or exc
        raise InputError(_located(path, cause, repaired.message_lines).replace(repaired.name_prefix, "")) from exc
    finally:
        cantools_log.removeHandler(collector)
    problems = []
    for message in collector.messages:
        if message.startswith(_OVERWRITE_WARNING):
            log.debug("%s: cantools: %s", path, message)  # a duplicate the validation reports
        else:
            problems.append(message)
    problems += [str(w.message) for w in caught]
    if not isinstance(database, cantools.database.can.Database):
        raise InputError(f"{path}: not a CAN database")
    _restore_names(database, repaired)
    return database, tuple(Finding("cantools", path.name, f"cantools: {_one_line(problem)}", str(path),
                                   severity=Severity.WARNING) for problem in problems)


def _restore_names(database: Database, repaired: Repaired) -> None:
    """Give back the names the repair prefixed (those that start with a digit) as the file writes them."""
    if repaired.name_prefix not in repaired.text:
        return
    name = repaired.original_name
    for node in database.nodes:
        node.name = name(node.name)
    for message in database.messages:
        message.name = name(message.name)
        message.senders[:] = [name(sender) for sender in message.senders]
        for signal in message.signals:
            signal.name = name(signal.name)
            signal.receivers[:] = [name(receiver) for receiver in signal.receivers]
            if signal.multiplexer_signal is not None:
                signal.multiplexer_signal = name(signal.multiplexer_signal)
        for group in message.signal_groups or ():
            group.name = name(group.name)
            group.signal_names = [name(signal) for signal in group.signal_names]
    if database.dbc is not None and database.dbc.value_tables:
        tables = database.dbc.value_tables
        renamed = {name(key): table for key, table in tables.items()}
        tables.clear()
        tables.update(renamed)
    database.refresh()


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
