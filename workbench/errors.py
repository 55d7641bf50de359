"""The workbench's exception tree.

Every error a user can cause or meet derives from :class:`WorkbenchError`; the CLI
prints its message on one line and exits with :attr:`WorkbenchError.exit_code`
(1: the operation failed, 2: the input was bad). Foreign exceptions (pyxcp,
pyelftools, cantools) are translated at the package boundary with ``raise ... from``.
"""

from __future__ import annotations

import time
from pathlib import Path

__all__ = ["A2lParseError", "Cancelled", "ConnectionLostError", "ConversionError", "DatasetParseError",
           "EcuSilentError", "EpkMismatchError", "InputError", "LimitsError", "LocatedInputError", "PageError",
           "PartialWriteError", "SeedKeyError", "UnknownSymbolError", "WorkbenchError", "XcpCommandError",
           "XcpTimeoutError", "epk_text", "placeholder_hint", "same_epk"]


class WorkbenchError(Exception):
    """Base of all workbench errors: an operation failed (exit code 1)."""

    exit_code = 1


class InputError(WorkbenchError):
    """The user's input (file, option, value) is wrong (exit code 2)."""

    exit_code = 2


class LocatedInputError(InputError):
    """An input file that cannot be read, located at ``path:line:column`` (1-based; 0: not known)."""

    def __init__(self, message: str, path: str | Path | None = None, line: int = 0, column: int = 0):
        self.reason = message
        self.path = str(path) if path is not None else "<string>"
        self.line = line
        self.column = column
        super().__init__(f"{self.location}: {message}")

    @property
    def location(self) -> str:
        return f"{self.path}:{self.line}:{self.column}"


class A2lParseError(LocatedInputError):
    """A malformed A2L file, located at ``path:line:column`` (1-based)."""


class DatasetParseError(LocatedInputError):
    """A calibration dataset file (DCM, CDFX) that cannot be read, located at ``path:line[:column]``."""

    @property
    def location(self) -> str:
        if not self.line:
            return self.path
        return f"{self.path}:{self.line}:{self.column}" if self.column else f"{self.path}:{self.line}"


class UnknownSymbolError(WorkbenchError, KeyError):
    """A name (A2L object, ELF symbol, DBC message/signal) that does not exist."""

    exit_code = 2

    def __init__(self, name: str, where: str = "", suggestions: tuple[str, ...] | list[str] = ()):
        self.name = name
        self.where = where
        self.suggestions = tuple(suggestions)  # the closest known names, best first
        super().__init__(name)

    def __str__(self) -> str:  # KeyError would quote the name
        text = f"unknown symbol {self.name!r}" + (f" in {self.where}" if self.where else "")
        if self.suggestions:
            text += "; did you mean " + ", ".join(repr(name) for name in self.suggestions) + "?"
        return text


class ConversionError(InputError):
    """A value that cannot be converted: a text a verbal table does not list, a physical value
    outside a conversion table, a COMPU_METHOD that cannot be inverted, a number the object's data
    type cannot hold, a value of the wrong shape."""


class LimitsError(InputError):
    """Calibration values that break their object's rules (limits, monotony, shape, READ_ONLY).

    ``violations`` lists every :class:`workbench.calib.limits.LimitViolation` found; the message
    shows the first few.
    """

    def __init__(self, violations):
        self.violations = list(violations)
        shown = "; ".join(str(violation) for violation in self.violations[:3])
        more = len(self.violations) - 3
        super().__init__(shown + (f" (and {more} more)" if more > 0 else ""))


class XcpCommandError(WorkbenchError):
    """The ECU answered an XCP command with a negative response.

    ``name`` defaults to the standard's name of ``code`` (``ERR_OUT_OF_RANGE`` for 0x22); ``payload`` holds the
    response's bytes after the code (BUILD_CHECKSUM's ERR_OUT_OF_RANGE tells the largest block there).
    """

    def __init__(self, command: str, code: int, name: str = "", context: str = "", payload: bytes = b""):
        self.command = command
        self.code = code
        self.payload = payload
        self.name = name or _error_name(code)
        self.context = context  # what the command was for, e.g. "reading xsPRV_KP (0x0..0x3)"
        super().__init__((f"{context}: " if context else "") + f"XCP {command} failed: {self.name} (0x{code:02X})")

    def about(self, context: str) -> "XcpCommandError":
        """The same refusal, saying what the command was for."""
        return XcpCommandError(self.command, self.code, self.name, context, self.payload)


def placeholder_hint(address: int) -> str:
    """Why an ECU refuses an address 0, said after it: an A2L whose addresses were never updated."""
    if address != 0:
        return ""
    return " (address 0: an A2L not yet updated from the build's ELF? workbench a2l update IN.a2l ELF -o OUT.a2l)"


def _error_name(code: int) -> str:
    from workbench.xcp_protocol import Err  # here: ``import workbench`` need not build the XCP enums

    try:
        return f"ERR_{Err(code).name}"
    except ValueError:
        return "unknown error"


class SeedKeyError(WorkbenchError):
    """A resource (``resource``: "CAL/PAG", "DAQ", "PGM") the ECU protects with seed & key could not be unlocked
    on the master's side: no key function is known, or it failed or gave no key (an ECU refusing the key answers
    UNLOCK with ERR_ACCESS_LOCKED: an :class:`XcpCommandError`)."""

    def __init__(self, message: str, resource: str):
        super().__init__(message)
        self.resource = resource


class XcpTimeoutError(WorkbenchError, TimeoutError):
    """The ECU did not answer an XCP command in time."""

    def __init__(self, command: str, timeout_s: float, hint: str = ""):
        self.command = command
        self.timeout_s = timeout_s
        super().__init__(f"XCP {command}: no response within {timeout_s * 1000:.0f} ms" + (f"; {hint}" if hint else ""))


class ConnectionLostError(WorkbenchError):
    """The ECU stopped answering during a session: a command with no response, DAQ with no DTO for too
    long, a closed TCP connection, a socket or bus error.

    ``what`` names the link ("XCP on UDP (127.0.0.1:5555)"), ``reason`` what was seen ("no DTO for
    300 ms"), ``when`` the wall-clock time it was noticed (seconds since the epoch, as ``time.time()``).
    Every command of the session raises it at once from then on, until a CONNECT (``Session.connect()``,
    or a new session) reaches the ECU again.
    """

    def __init__(self, what: str, reason: str, when: float | None = None):
        self.what = what
        self.reason = reason
        self.when = time.time() if when is None else when
        clock = time.strftime("%H:%M:%S", time.localtime(self.when)) + f".{int(self.when % 1 * 1000):03d}"
        WorkbenchError.__init__(self, f"connection to the ECU lost at {clock}: {what}: {reason}")  # not super():
        # in EcuSilentError the next class is XcpTimeoutError, whose arguments differ


class EcuSilentError(ConnectionLostError, XcpTimeoutError):
    """A command went unanswered and so did the SYNCH after it: the ECU stopped answering (also an
    :class:`XcpTimeoutError` of ``command``)."""

    def __init__(self, what: str, command: str, timeout_s: float, when: float | None = None):
        self.command = command
        self.timeout_s = timeout_s
        super().__init__(what, f"XCP {command}: no response within {timeout_s * 1000:.0f} ms, none to SYNCH either",
                         when)


class PartialWriteError(WorkbenchError):
    """A write that failed after some of its fields reached the ECU: ``written`` names them."""

    def __init__(self, name: str, written: list[str], failed: str, cause: Exception):
        self.written = written
        super().__init__(f"{cause}; {name} is half written: {', '.join(written)} reached the ECU, {failed} did not")


class PageError(WorkbenchError):
    """A write refused because XCP accesses a calibration page it may not write (the reference page)."""


class EpkMismatchError(WorkbenchError):
    """The EPK in the ECU differs from the one in the A2L/image."""

    def __init__(self, expected: str, actual: str, hint: str = ""):
        self.expected = expected
        self.actual = actual
        super().__init__(f"EPK mismatch: file has {epk_text(expected)}, ECU has {epk_text(actual)}"
                         + (f"; {hint}" if hint else ""))


def same_epk(one: str, other: str) -> bool:
    """Whether two EPKs (as read, or as an A2L states them) name one build: NULs and blanks pad an EPK differently
    in an A2L (blanks) and in a build (a C string's NULs)."""
    return one.replace("\0", "").strip() == other.replace("\0", "").strip()


def epk_text(epk: str) -> str:
    """An EPK (as read: one character a byte, latin-1) as messages and reports show it: ``'10300020250301'``,
    ``erased (14 bytes FF)`` where the flash holds no software, else its bytes in hex."""
    raw = epk.encode("latin-1", "replace")
    if raw and set(raw) <= {0xFF}:
        return f"erased ({len(raw)} bytes FF)"
    if raw and set(raw) <= {0}:
        return f"empty ({len(raw)} bytes 00)"
    text = epk.rstrip("\0 ")
    if text.isascii() and text.isprintable():
        return repr(text)
    return f"bytes {raw.hex(' ').upper()}"


class Cancelled(WorkbenchError):
    """A long job was cancelled through its progress object."""
