"""PROGRAM of byte ranges into erased flash, repaired after transmission errors without ever writing twice.

Flash takes a byte once between erasures (the simulated ECU answers ERR_ACCESS_DENIED to a
second write), so a block that failed cannot simply be sent again: part of it may be in
flash. After a failure (a timeout, ERR_SEQUENCE from a lost or doubled frame, ERR_ACCESS_DENIED
from bytes a doubled frame wrote too far) the writer resynchronises, reads back the failed
block and one block beyond it, and

* continues after the last byte found written, when everything up to it is what the image
  says and nothing stands beyond it (beyond the range being written, what the image says may
  stand: a part's EPK is programmed last, into a gap before programmed bytes): a lost frame,
  a lost response;
* else raises :class:`WrongBytes`: a doubled first frame shifts a block (its bytes land
  behind where they belong), so the sector must be erased and written again. So does an ECU
  that refuses to go on where the read-back says (a real flash programs a page once: going on
  inside a half-written page may be refused).

Bytes a failure put where the read-back does not look are found by the verification of the
whole sector that follows programming.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

from workbench.errors import WorkbenchError, XcpCommandError, XcpTimeoutError
from workbench.flash.layout import Sector
from workbench.image import ERASED, MemoryImage
from workbench.logs import logger
from workbench.xcp.info import ProgramStartInfo
from workbench.xcp.master import XcpMaster
from workbench.xcp_protocol import Err

log = logger(__name__)
T = TypeVar("T")

__all__ = ["RangeWriter", "TooManyErrors", "WrongBytes", "is_transient"]

# Answers a lost, doubled or late frame provokes; anything else (OUT_OF_RANGE, WRITE_PROTECTED ...) is final.
_TRANSIENT = frozenset({Err.SEQUENCE, Err.ACCESS_DENIED, Err.CMD_SYNTAX, Err.CMD_SYNCH, Err.CMD_BUSY})


class WrongBytes(WorkbenchError):
    """Flash holds bytes the image does not say at ``address``: erase the sector and program it again."""

    def __init__(self, address: int, reason: str = "holds bytes the image does not"):
        self.address = address
        super().__init__(f"flash at {address:X}h {reason}")


class TooManyErrors(WorkbenchError):
    """More transmission errors than the flash repairs; the last one is the cause."""


def is_transient(error: Exception) -> bool:
    """A timeout, or a negative response that a lost, doubled or late frame explains."""
    return isinstance(error, XcpTimeoutError) or (isinstance(error, XcpCommandError) and error.code in _TRANSIENT)


class RangeWriter:
    """Programs ranges with one master; ``expected`` is what flash must hold when done (erased elsewhere)."""

    def __init__(self, master: XcpMaster, start: ProgramStartInfo, expected: MemoryImage, *, use_max: bool = False,
                 max_recoveries: int = 8, on_block: Callable[[int, int], None] | None = None):
        self.master = master
        self.start = start
        self.expected = expected
        self.use_max = use_max
        self.max_recoveries = max_recoveries
        self.on_block = on_block or (lambda address, size: None)
        self.block_size = master.program_block_size(start, use_max=use_max)
        self.recoveries = 0
        self.bytes_sent = 0

    def write(self, sector: Sector, address: int, data: bytes) -> None:
        """Program ``data`` at ``address`` (inside ``sector``, erased), calling ``on_block`` after every block, and end
        the memory segment (PROGRAM with size 0: a driver that holds a flash page in RAM writes it now).

        :raises WrongBytes: the sector holds bytes it must not: erase it and write it again.
        :raises TooManyErrors: more transmission errors than ``max_recoveries``.
        :raises XcpCommandError: the ECU refuses for a reason no repetition cures.
        :raises XcpTimeoutError: the ECU stopped answering (SYNCH too).
        """
        position = 0
        resumed_at = None  # where the last repair went on: failing there again, the ECU refuses to resume
        self.master.set_mta(address)
        while position < len(data):
            chunk = data[position:position + self.block_size]
            try:
                self.master.program(chunk, self.start, use_max=self.use_max)
            except (XcpCommandError, XcpTimeoutError) as error:
                self.bytes_sent += len(chunk)
                self._count(error, address + position)
                if position == resumed_at and isinstance(error, XcpCommandError):
                    raise WrongBytes(address + position, "cannot be programmed where the last one ended") from error
                resumed = self._resume_at(sector, address, position, len(chunk), address + len(data)) - address
                if resumed > position:
                    self.on_block(address + position, resumed - position)
                position = resumed_at = resumed
                self.master.set_mta(address + position)
                continue
            self.bytes_sent += len(chunk)
            position += len(chunk)
            self.on_block(address + position - len(chunk), len(chunk))
        try:
            self.master.program_end()
        except (XcpCommandError, XcpTimeoutError) as error:
            self.repair(error, address + len(data), self.master.program_end)

    def repair(self, error: Exception, address: int, action: Callable[[], T]) -> T:
        """Count ``error`` as a transmission error at ``address``, resynchronise and return ``action()`` run
        again (an idempotent step: SET_MTA + PROGRAM_CLEAR, a checksum, a read ...)."""
        while True:
            self._count(error, address)
            self.master.resynchronize()
            try:
                return action()
            except (XcpCommandError, XcpTimeoutError) as again:
                error = again

    def _count(self, error: Exception, address: int) -> None:
        if not is_transient(error):
            raise error
        self.recoveries += 1
        log.info("flash at %Xh: %s; repairing (%d)", address, error, self.recoveries)
        if self.recoveries > self.max_recoveries:
            raise TooManyErrors(f"more than {self.max_recoveries} transmission errors; the last at {address:X}h: "
                                f"{error}") from error

    def _resume_at(self, sector: Sector, address: int, position: int, sent: int, range_end: int) -> int:
        """Where to go on after a failed block at ``address + position`` of the range ending at ``range_end``: after
        what is found written."""
        self.master.resynchronize()
        start = address + position
        end = min(sector.range.end, start + sent + self.block_size)
        actual = self.master.read(start, end - start)
        expected = self.expected.read(start, end - start, ERASED)
        inside = range_end - start
        written = len(actual[:inside].rstrip(bytes((ERASED,))))
        written += -written % self.master.granularity  # an element is programmed whole, erased-looking bytes too
        beyond = next((i for i in range(inside, len(actual)) if actual[i] not in (ERASED, expected[i])), None)
        if actual[:written] != expected[:written] or beyond is not None:
            first = next((i for i in range(written) if actual[i] != expected[i]), beyond)
            raise WrongBytes(start + first)
        log.info("flash at %Xh: %d bytes of the failed block are in flash; going on from %Xh", start, written,
                 start + written)
        return start + written
