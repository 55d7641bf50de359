"""The XCP master: commands as methods, with the spec's timeouts, SYNCH-and-repeat and errors as ours.

:class:`XcpMaster` sends every command itself over a :class:`~workbench.xcp.link.Link` and
reads the response, so it controls what pyxcp's request path does not:

* every command waits for its own timeout (T1 for most, T2 BUILD_CHECKSUM, T3 PROGRAM_START,
  T4 PROGRAM_CLEAR, T5 PROGRAM*, T6 CONNECT after a reset, T7 the pause after ERR_CMD_BUSY),
  from the A2L or the caller;
* on a timeout it sends SYNCH and repeats the command twice (commands that move the MTA are
  repeated from their SET_MTA by the memory functions); an ECU that answers neither is
  reported as gone after about two timeouts, never waited for forever;
* a negative response raises :class:`~workbench.errors.XcpCommandError` naming the command and
  the error; a locked resource is unlocked with the seed & key function, once, and the command
  repeated;
* UPLOAD uses the slave's block mode and DOWNLOAD the master block mode when offered;
* with an address granularity above BYTE every transfer counts elements, carries the spec's alignment
  bytes and starts on an element: :meth:`XcpMaster.read` and :meth:`XcpMaster.write` widen any byte range
  to whole elements (a write reads the bytes it does not change first).
"""

from __future__ import annotations

import struct
import time
from collections.abc import Callable
from dataclasses import dataclass

from workbench.errors import EcuSilentError, SeedKeyError, WorkbenchError, XcpCommandError, XcpTimeoutError
from workbench.logs import logger
from workbench.xcp.info import (
    CommModeInfo,
    ConnectInfo,
    DaqEventInfo,
    DaqListInfo,
    DaqProcessorInfo,
    DaqResolutionInfo,
    PagProcessorInfo,
    PgmProcessorInfo,
    ProgramStartInfo,
    SectorInfo,
    Status,
    data_per_frame,
)
from workbench.xcp.info import program_block_size as block_size  # the method of the same name uses it
from workbench.xcp.link import Link
from workbench.xcp_protocol import PID_ERR, PID_RES, CanCmd, CanId, Cmd, Err, IdType, Resource

log = logger(__name__)

__all__ = ["KeyFunction", "Timeouts", "XcpMaster"]

KeyFunction = Callable[[bytes, int], bytes]  # (seed, resource bit) -> key
_BUSY_REPEATS = 20  # ERR_CMD_BUSY / ERR_PGM_ACTIVE: T7 apart (ASAM: without end; a master that waits for people: ~4 s)
# the error matrix's "wait T7, repeat" (and for a resource temporarily not accessible "display the error, repeat": it
# is logged as a warning, and said if it stays)
_WAIT_AND_REPEAT = (Err.CMD_BUSY, Err.PGM_ACTIVE, Err.RESOURCE_TEMPORARY_NOT_ACCESSIBLE)


@dataclass(frozen=True)
class Timeouts:
    """T1-T7 in seconds (XCP protocol layer: T1 standard, T2 checksum, T3 PROGRAM_START, T4 PROGRAM_CLEAR,
    T5 PROGRAM, T6 CONNECT after reset, T7 busy-wait period)."""

    t1: float = 1.0
    t2: float = 2.0
    t3: float = 2.0
    t4: float = 10.0
    t5: float = 1.0
    t6: float = 1.0
    t7: float = 0.2


_TIMEOUT_OF = {Cmd.BUILD_CHECKSUM: "t2", Cmd.PROGRAM_START: "t3", Cmd.PROGRAM_CLEAR: "t4", Cmd.PROGRAM: "t5",
               Cmd.PROGRAM_NEXT: "t5", Cmd.PROGRAM_MAX: "t5", Cmd.PROGRAM_FORMAT: "t5", Cmd.PROGRAM_VERIFY: "t5"}

# The resource a command needs unlocked (XCP: CAL/PAG, DAQ, STIM, PGM).
_CAL_PAG_COMMANDS = {Cmd.DOWNLOAD, Cmd.DOWNLOAD_NEXT, Cmd.DOWNLOAD_MAX, Cmd.SHORT_DOWNLOAD, Cmd.MODIFY_BITS,
                     Cmd.SET_CAL_PAGE, Cmd.GET_CAL_PAGE, Cmd.GET_PAG_PROCESSOR_INFO, Cmd.GET_SEGMENT_INFO,
                     Cmd.GET_PAGE_INFO, Cmd.SET_SEGMENT_MODE, Cmd.GET_SEGMENT_MODE, Cmd.COPY_CAL_PAGE}


def resource_of(command: Cmd) -> Resource | None:
    if command in _CAL_PAG_COMMANDS:
        return Resource.CAL_PAG
    if Cmd.ALLOC_ODT_ENTRY <= command <= Cmd.CLEAR_DAQ_LIST:
        return Resource.DAQ
    if Cmd.PROGRAM_VERIFY <= command <= Cmd.PROGRAM_START:
        return Resource.PGM
    return None


_RESOURCE_OF = {command: resource_of(command) for command in Cmd}  # looked up for every command
_LATE_SYNCH = bytes((PID_ERR, Err.CMD_SYNCH))
_BLOCK_COMMANDS = (Cmd.DOWNLOAD.name, Cmd.DOWNLOAD_NEXT.name)  # a master block's ERR_SEQUENCE names one of them


class XcpMaster:
    """XCP commands on one link. Not thread-safe: one caller at a time (the session serialises)."""

    def __init__(self, link: Link, *, timeouts: Timeouts | None = None, key_function: KeyFunction | None = None,
                 key_function_name: str | None = None):
        self.link = link
        self.timeouts = timeouts or Timeouts()
        self.key_function = key_function
        self.key_function_name = key_function_name
        self.connect_info: ConnectInfo | None = None
        self.comm_mode: CommModeInfo | None = None
        self.protected: Resource = Resource(0)
        self.silent = False  # the last command went unanswered, and so did the SYNCH after it
        self._unlocking = False
        # What a caller may remember about the slave's memory holds while this count stays the same: it
        # grows with every CONNECT, DOWNLOAD/PROGRAM, page switch and page copy, whoever sends them.
        self.memory_changes = 0
        self.xcp_pages: dict[int, int] = {}  # segment -> page XCP accesses, as last set or read (CONNECT clears)
        self.ecu_pages: dict[int, int] = {}  # segment -> page the ECU accesses, as last set (CONNECT clears)
        self.has_short_upload = True  # False after SHORT_UPLOAD's ERR_CMD_UNKNOWN: SET_MTA + UPLOAD instead

    # --- the slave's parameters ---------------------------------------------------------------

    @property
    def connected(self) -> bool:
        return self.connect_info is not None

    @property
    def order(self) -> str:
        return self.connect_info.byte_order if self.connect_info else "<"

    @property
    def max_cto(self) -> int:
        return self.connect_info.max_cto if self.connect_info else 8

    @property
    def max_dto(self) -> int:
        return self.connect_info.max_dto if self.connect_info else 8

    @property
    def granularity(self) -> int:
        return self.connect_info.address_granularity if self.connect_info else 1

    @property
    def per_response(self) -> int:
        """Data bytes of one UPLOAD response: whole elements after the PID and its alignment bytes."""
        return self._whole(self.max_cto - self.granularity)

    def _whole(self, size: int) -> int:
        """``size`` rounded down to whole elements."""
        return size - size % self.granularity

    def _elements(self, size: int) -> int:
        """Elements that hold ``size`` bytes (rounded up)."""
        return -(-size // self.granularity)

    # --- one command --------------------------------------------------------------------------

    def command(self, command: Cmd, payload: bytes = b"", *, timeout: str | None = None, repeat: bool = True,
                check: Callable[[bytes], str | None] | None = None) -> bytes:
        """Send ``command`` with ``payload``; return the positive response's bytes after the PID.

        :param timeout: "t1".."t7" (default: the command's own, mostly T1).
        :param repeat: SYNCH and repeat on a timeout (not for commands that move the MTA: their
            callers repeat from SET_MTA).
        :param check: what makes a positive response no answer to this command (None: it is one); such a
            packet (a stale one: a late answer of an earlier session) is dropped and the next one awaited.
        :raises XcpCommandError: a negative response.
        :raises XcpTimeoutError: no response, and none to SYNCH either (or none after the repeats).
        :raises WorkbenchError: only packets that ``check`` refused came (it says what was wrong).
        """
        self._unlock_for(command)
        try:
            return self._command(command, payload, timeout, repeat, check)
        except XcpCommandError as error:
            resource = _RESOURCE_OF[command]
            if error.code != Err.ACCESS_LOCKED or resource is None or self._unlocking:
                raise
            self.protected |= resource  # the slave locked it (again): unlock and try once more
            self._unlock_for(command)
            return self._command(command, payload, timeout, repeat, check)

    def _command(self, command: Cmd, payload: bytes, timeout: str | None, repeat: bool,
                 check: Callable[[bytes], str | None] | None = None) -> bytes:
        timeout_s = getattr(self.timeouts, timeout or _TIMEOUT_OF.get(command, "t1"))
        if self.silent and command not in (Cmd.CONNECT, Cmd.SYNCH):
            self._settle(command)
        packet = bytes((command,)) + payload
        attempts, busy = 0, 0
        refused: tuple[str, bytes] | None = None  # the last packet ``check`` refused, and why
        while True:
            response = self._skip_late_synch(command, self.link.exchange(packet, timeout_s), timeout_s)
            if check is not None:
                response, refused = self._checked(command, response, timeout_s, check, refused)
            if refused is not None and response is None and (attempts >= 2 or not repeat):
                problem, stale = refused
                raise WorkbenchError(f"XCP {command.name}: the answer {stale[:8].hex(' ')} is no {command.name} "
                                     f"response: {problem}; another master on the bus, or a packet of an "
                                     f"earlier session?")
            if response is not None:
                self.silent = False
            else:
                attempts += 1
                if command in (Cmd.CONNECT, Cmd.SYNCH):
                    if attempts < 3:
                        continue
                    raise XcpTimeoutError(command.name, timeout_s)
                self.synch_after_timeout(command, timeout_s)
                if not repeat or attempts >= 3:
                    raise XcpTimeoutError(command.name, timeout_s)
                log.info("XCP %s: no response within %.0f ms; repeating after SYNCH", command.name, timeout_s * 1e3)
                continue
            if response[0] == PID_RES:
                if attempts and command == Cmd.CONNECT:
                    self.resynchronize()  # the answer to the CONNECT that timed out may still be on its way
                return response[1:]
            if response[0] == PID_ERR and len(response) > 1:
                code = response[1]
                if code in _WAIT_AND_REPEAT and busy < _BUSY_REPEATS:
                    busy += 1
                    if code == Err.RESOURCE_TEMPORARY_NOT_ACCESSIBLE:
                        log.warning("XCP %s: the ECU says the resource is temporarily not accessible; trying again",
                                    command.name)
                    time.sleep(self.timeouts.t7)
                    continue
                if command == Cmd.SYNCH and code == Err.CMD_SYNCH:
                    return response[1:]
                raise XcpCommandError(command.name, code, payload=response[2:])
            raise WorkbenchError(f"XCP {command.name}: unexpected packet {response.hex(' ')}")

    def _checked(self, command: Cmd, response: bytes | None, timeout_s: float, check: Callable[[bytes], str | None],
                 refused: tuple[str, bytes] | None) -> tuple[bytes | None, tuple[str, bytes] | None]:
        """``response``, or the next packet within ``timeout_s`` when ``check`` refuses it (and the next ...);
        with the last refused packet and why."""
        deadline = time.monotonic() + timeout_s
        while response is not None and response[0] == PID_RES:
            problem = check(response)
            if problem is None:
                break
            refused = (problem, response)
            log.info("XCP %s: %s dropped, no %s response: %s", command.name, response[:8].hex(" "), command.name,
                     problem)
            response = self.link.receive(max(deadline - time.monotonic(), 0.0))
        return response, refused

    def _skip_late_synch(self, command: Cmd, response: bytes | None, timeout_s: float) -> bytes | None:
        """ERR_CMD_SYNCH only ever answers SYNCH: arriving for another command, it is the answer to a SYNCH
        that came after its timeout (a slow or busy ECU). On CAN nothing else tells responses apart, so
        it is dropped and the command's own response awaited."""
        if response is None or response[:2] != _LATE_SYNCH or command == Cmd.SYNCH:
            return response  # (tested first: this runs for every command)
        deadline = time.monotonic() + timeout_s
        while response is not None and response[:2] == _LATE_SYNCH:
            log.debug("XCP %s: a late answer to SYNCH dropped", command.name)
            response = self.link.receive(max(deadline - time.monotonic(), 0.0))
        return response

    def synch_after_timeout(self, command: Cmd, timeout_s: float) -> None:
        """After ``command`` went unanswered: SYNCH, so the next command starts clean. A slow slave's late
        answer to ``command`` comes before SYNCH's ERR_CMD_SYNCH and is dropped with it (on CAN nothing else
        tells responses apart: taken for the next command's, it would shift every answer by one).

        :raises EcuSilentError: the ECU does not answer SYNCH either: it is gone (an XcpTimeoutError and a
            ConnectionLostError).
        """
        response = self.link.exchange(bytes((Cmd.SYNCH,)), self.timeouts.t1)
        if response is None:
            self.silent = True
            raise EcuSilentError(self.link.describe(), command.name, timeout_s)
        while response is not None and response[:2] != bytes((PID_ERR, Err.CMD_SYNCH)):
            log.debug("XCP %s: a late answer dropped after SYNCH", command.name)
            response = self.link.receive(self.timeouts.t1)

    def _settle(self, command: Cmd) -> None:
        """Before ``command``, on an ECU found silent (a command and its SYNCH unanswered): the answers to both may
        still come, and on CAN nothing tells them from the next command's (a late SHORT_UPLOAD taken for
        GET_DAQ_PROCESSOR_INFO's answer). SYNCH once more and drop everything before its ERR_CMD_SYNCH.

        :raises EcuSilentError: nothing answers that SYNCH (``command`` is not sent: one T1, not two).
        """
        response = self.link.exchange(bytes((Cmd.SYNCH,)), self.timeouts.t1)
        if response is None:
            raise EcuSilentError(self.link.describe(), command.name, self.timeouts.t1)
        while response is not None and response[:2] != _LATE_SYNCH:  # (an ERR_CMD_SYNCH later than T1 is skipped)
            log.debug("XCP %s: a late answer dropped after the SYNCH before it", command.name)
            response = self.link.receive(self.timeouts.t1)
        self.silent = False

    # --- session ------------------------------------------------------------------------------

    def connect(self, mode: int = 0, *, timeout: str = "t1") -> ConnectInfo:
        """CONNECT (mode 0 normal, 1 user defined), then GET_STATUS and GET_COMM_MODE_INFO when offered."""
        self.memory_changes += 1
        self.xcp_pages.clear()
        self.ecu_pages.clear()
        self.connect_info = ConnectInfo.parse(self.command(Cmd.CONNECT, bytes((mode,)), timeout=timeout,
                                                           check=self._connect_problem))
        self.comm_mode = None
        self.has_short_upload = True
        if self.connect_info.optional_comm_mode:
            try:
                self.comm_mode = CommModeInfo.parse(self.command(Cmd.GET_COMM_MODE_INFO))
            except XcpCommandError as error:  # CONNECT offered it all the same: no master block mode then
                if error.code != Err.CMD_UNKNOWN:
                    raise
                log.info("XCP GET_COMM_MODE_INFO: ERR_CMD_UNKNOWN although CONNECT offers it; no master block mode")
        self.protected = self.get_status().protected
        return self.connect_info

    def _connect_problem(self, response: bytes) -> str | None:
        return ConnectInfo.problem(response, self.link.max_packet)

    def disconnect(self) -> None:
        try:
            self.command(Cmd.DISCONNECT, repeat=False)
        finally:
            self.connect_info = None

    def get_status(self) -> Status:
        status = Status.parse(self.command(Cmd.GET_STATUS), self.order)
        self.protected = status.protected
        return status

    def synch(self) -> None:
        self.command(Cmd.SYNCH)

    def get_id(self, kind: int = IdType.ASCII) -> bytes:
        """GET_ID: the identification of ``kind`` (0 ASCII, 1 A2L name, 5 EPK ...), read back with UPLOAD
        unless the response carries it; b"" when the slave has none."""
        payload = self.command(Cmd.GET_ID, bytes((kind,)))
        mode, length = struct.unpack_from(f"{self.order}B2xI", payload)
        if length == 0:
            return b""
        if mode & 0x01:
            return bytes(payload[7:7 + length])
        return self.upload(length)

    # --- seed & key ---------------------------------------------------------------------------

    def _unlock_for(self, command: Cmd) -> None:
        resource = _RESOURCE_OF[command]
        if resource is not None and resource & self.protected and not self._unlocking:
            self.unlock(resource)

    def unlock(self, resource: Resource) -> None:
        """GET_SEED and UNLOCK ``resource`` with the key function.

        :raises SeedKeyError: there is no key function, or it fails.
        :raises XcpCommandError: the slave rejects the key (ERR_ACCESS_LOCKED).
        """
        name = Resource(resource).name.replace("_", "/")
        if self.key_function is None:
            raise SeedKeyError(f"the ECU protects {name} with seed & key and no key function is known: the A2L names "
                               f"no SEED_AND_KEY_EXTERNAL_FUNCTION; give one as 'module:function'", name)
        self._unlocking = True
        try:
            for attempt in range(2):  # GET_SEED and UNLOCK are no commands to repeat: after a timeout start over
                try:
                    self._seed_and_key(resource, name)
                    break
                except XcpTimeoutError as error:
                    if attempt or isinstance(error, EcuSilentError):
                        raise
                    log.info("XCP seed & key for %s: a command timed out; starting over with GET_SEED", name)
                except XcpCommandError as error:  # ERR_SEQUENCE (the error matrix: GET_SEED + UNLOCK again)
                    if attempt or error.code != Err.SEQUENCE:
                        raise
                    log.info("XCP seed & key for %s: %s ERR_SEQUENCE; starting over with GET_SEED", name,
                             error.command)
        finally:
            self._unlocking = False
        if resource & self.protected:
            raise WorkbenchError(f"UNLOCK of {name} was accepted but the resource is still protected")

    def _seed_and_key(self, resource: Resource, name: str) -> None:
        """One GET_SEED ... UNLOCK exchange (the seed and the key in as many packets as they need)."""
        seed = self._seed(resource)
        if not seed:  # length 0: already unlocked (an UNLOCK whose answer was lost may have done it)
            self.protected &= ~resource
            return
        try:
            key = bytes(self.key_function(seed, int(resource)))
        except Exception as exc:  # the plugin is the user's code: report it, don't crash
            raise SeedKeyError(f"the seed & key function {self.key_function_name or ''} failed for {name}: "
                               f"{type(exc).__name__}: {exc}".replace("  ", " "), name) from exc
        if not key:
            raise SeedKeyError(f"the seed & key function {self.key_function_name or ''} returned no key for {name}",
                               name)
        chunk = self.max_cto - 2
        for start in range(0, len(key), chunk):
            remaining = len(key) - start
            try:
                payload = self.command(Cmd.UNLOCK, bytes((remaining,)) + key[start:start + chunk], repeat=False)
            except XcpCommandError as exc:  # ERR_ACCESS_LOCKED: the key is wrong (and the slave disconnected)
                raise exc.about(f"the ECU refused the key of {self.key_function_name or 'the seed & key function'} "
                                f"for {name}") from exc
        self.protected = Resource(payload[0] & 0x1D)

    def _seed(self, resource: Resource) -> bytes:
        payload = self.command(Cmd.GET_SEED, bytes((0, resource)), repeat=False)
        total, seed = payload[0], bytes(payload[1:1 + min(payload[0], self.max_cto - 2)])
        while len(seed) < total:
            payload = self.command(Cmd.GET_SEED, bytes((1, resource)), repeat=False)
            seed += bytes(payload[1:1 + min(payload[0], self.max_cto - 2)])
        return seed[:total]

    # --- memory -------------------------------------------------------------------------------

    def set_mta(self, address: int, extension: int = 0) -> None:
        self.command(Cmd.SET_MTA, struct.pack(f"{self.order}2xBI", extension, address))

    def short_upload(self, address: int, size: int, extension: int = 0) -> bytes:
        """SHORT_UPLOAD of ``size`` bytes (whole elements, at most :attr:`per_response`) at an aligned ``address``."""
        elements = self._elements(size)
        payload = self.command(Cmd.SHORT_UPLOAD, struct.pack(f"{self.order}BxBI", elements, extension, address))
        return self._data(payload[self.granularity - 1:], size, Cmd.SHORT_UPLOAD)

    def upload(self, size: int) -> bytes:
        """UPLOAD ``size`` bytes from the MTA (which advances by whole elements), in as few commands as the slave
        allows; the data follow each response's PID and alignment bytes."""
        data = bytearray()
        per_frame, skip = self.per_response, self.granularity - 1
        block = self.connect_info is not None and self.connect_info.slave_block_mode
        per_command = 255 * self.granularity if block else per_frame
        while len(data) < size:
            count = min(per_command, size - len(data))
            elements = self._elements(count)
            payload = self.command(Cmd.UPLOAD, bytes((elements,)), repeat=False)
            wanted = elements * self.granularity
            chunk = bytearray(payload[skip:skip + min(wanted, per_frame)])
            while len(chunk) < wanted:  # slave block mode: the rest follows in further responses
                more = self.link.receive(self.timeouts.t1)
                if more is None:
                    self.synch_after_timeout(Cmd.UPLOAD, self.timeouts.t1)
                    raise XcpTimeoutError("UPLOAD", self.timeouts.t1)
                if more[0] != PID_RES:
                    raise XcpCommandError("UPLOAD", more[1] if len(more) > 1 else 0)
                chunk += more[1 + skip:1 + skip + min(wanted - len(chunk), per_frame)]
            data += chunk[:count]
        return bytes(data)

    def read(self, address: int, size: int, extension: int = 0) -> bytes:
        """``size`` bytes at ``address``: SHORT_UPLOAD when it fits one response, else SET_MTA + UPLOAD;
        a timeout is repeated from SET_MTA (twice) after SYNCH. Read as whole elements of the granularity."""
        start, end = self._aligned(address, size)
        if (start, end) != (address, address + size):
            return self.read(start, end - start, extension)[address - start:address - start + size]
        if size <= self.per_response and self.has_short_upload:
            try:
                return self.short_upload(address, size, extension)
            except XcpCommandError as error:  # optional: the error matrix's alternative is SET_MTA + UPLOAD
                if error.code != Err.CMD_UNKNOWN:
                    raise
                self.has_short_upload = False
        return self._repeat_from_mta(lambda: self._set_mta_and(address, extension, lambda: self.upload(size)))

    def write(self, address: int, data: bytes, extension: int = 0) -> None:
        """DOWNLOAD ``data`` to ``address`` (master block mode when the slave offers it); a timeout is
        repeated from SET_MTA (twice) after SYNCH. Bytes that share an element with ``data`` (address
        granularity WORD or DWORD) are read first and written back as they were."""
        if not data:
            return
        start, end = self._aligned(address, len(data))
        if (start, end) != (address, address + len(data)):
            whole = bytearray(self.read(start, end - start, extension))
            whole[address - start:address - start + len(data)] = data
            address, data = start, bytes(whole)
        self._repeat_from_mta(lambda: self._set_mta_and(address, extension, lambda: self.download(data)))

    def _aligned(self, address: int, size: int) -> tuple[int, int]:
        """``[address, address + size)`` widened to whole elements: (start, end)."""
        ag = self.granularity
        return address - address % ag, -(-(address + size) // ag) * ag

    def _set_mta_and(self, address: int, extension: int, action: Callable[[], bytes | None]):
        self.set_mta(address, extension)
        return action()

    def _repeat_from_mta(self, action: Callable[[], bytes | None]):
        """``action`` (SET_MTA and a transfer), repeated from SET_MTA as ASAM's error matrix says: twice after a
        timeout (SYNCH sent) or a master block the slave refused with ERR_SEQUENCE (a frame of it lost), T7 later
        (as a single command would be) after a block refused busy; the answers to the block's other frames are
        drained by SYNCH first."""
        repeats = busy = 0
        while True:
            try:
                return action()
            except XcpTimeoutError as error:
                if repeats == 2 or isinstance(error, EcuSilentError):  # SYNCH unanswered too: nothing to repeat to
                    raise
                log.info("XCP memory transfer timed out; repeating from SET_MTA")
                repeats += 1
            except XcpCommandError as error:
                if error.command not in _BLOCK_COMMANDS:
                    raise
                if error.code in _WAIT_AND_REPEAT and busy < _BUSY_REPEATS:
                    busy += 1
                    self.resynchronize()
                    time.sleep(self.timeouts.t7)
                elif error.code == Err.SEQUENCE and repeats < 2:
                    repeats += 1
                    self.resynchronize()
                else:
                    raise
                log.info("XCP %s: %s; repeating the block from SET_MTA", error.command, error.name)

    def download(self, data: bytes, *, command: Cmd = Cmd.DOWNLOAD, next_command: Cmd = Cmd.DOWNLOAD_NEXT,
                 timeout: str | None = None, max_bs: int | None = None, min_st_s: float | None = None) -> None:
        """DOWNLOAD (or PROGRAM) ``data`` (whole elements) at the MTA: blocks of a first frame and _NEXT frames when
        the slave offers master block mode (``max_bs`` frames a block, ``min_st_s`` apart), else one command a frame."""
        self.memory_changes += 1
        per_frame = self._per_frame(self.max_cto)
        block_mode = max_bs is not None or (self.comm_mode is not None and self.comm_mode.master_block_mode)
        frames = max(1, max_bs if max_bs is not None else (self.comm_mode.max_bs if block_mode else 1))
        separation = min_st_s if min_st_s is not None else (self.comm_mode.min_st_s if block_mode and self.comm_mode else 0.0)
        per_block = min(255 * self.granularity, per_frame * frames) if block_mode else per_frame
        for start in range(0, len(data), per_block):
            self._download_block(data[start:start + per_block], command, next_command, timeout, separation)

    def _per_frame(self, max_cto: int) -> int:
        """Data bytes of a DOWNLOAD/PROGRAM/_NEXT frame: whole elements after command, count and alignment."""
        return data_per_frame(max_cto, self.granularity)

    def _download_block(self, block: bytes, command: Cmd, next_command: Cmd, timeout: str | None,
                        separation_s: float, per_frame: int | None = None) -> None:
        per_frame = per_frame or self._per_frame(self.max_cto)
        first, rest = block[:per_frame], block[per_frame:]
        elements = len(block) // self.granularity
        align = bytes(max(2, self.granularity) - 2)  # AG DWORD: two alignment bytes before the data
        if not rest:
            self.command(command, bytes((elements,)) + align + first, timeout=timeout, repeat=False)
            return
        self._unlock_for(command)
        self.link.send(bytes((command, elements)) + align + first)
        sent = len(first)
        while sent < len(block):
            chunk = block[sent:sent + per_frame]
            remaining = (len(block) - sent) // self.granularity
            if separation_s:
                time.sleep(separation_s)
            early = self.link.receive(0)  # a slave that rejects a block answers before its end
            if early is not None and early[0] == PID_ERR:
                raise XcpCommandError(command.name, early[1] if len(early) > 1 else 0)
            packet = bytes((next_command, remaining)) + align + chunk
            sent += len(chunk)
            if sent < len(block):
                self.link.send(packet)
            else:
                self._last_of_block(next_command, packet, timeout)

    def _last_of_block(self, command: Cmd, packet: bytes, timeout: str | None) -> None:
        timeout_s = getattr(self.timeouts, timeout or _TIMEOUT_OF.get(command, "t1"))
        response = self.link.exchange(packet, timeout_s, drop_queued=False)
        if response is None:
            self.synch_after_timeout(command, timeout_s)
            raise XcpTimeoutError(command.name, timeout_s)
        if response[0] != PID_RES:
            raise XcpCommandError(command.name, response[1] if len(response) > 1 else 0)

    def build_checksum(self, address: int, size: int, extension: int = 0) -> tuple[int, int]:
        """BUILD_CHECKSUM over ``size`` bytes at ``address``: (checksum type code, value)."""
        def checksum():
            payload = self.command(Cmd.BUILD_CHECKSUM, struct.pack(f"{self.order}3xI", size // self.granularity),
                                   repeat=False)
            kind, value = struct.unpack_from(f"{self.order}B2xI", payload)
            return kind, value

        return self._repeat_from_mta(lambda: self._set_mta_and(address, extension, checksum))

    def _data(self, payload: bytes, size: int, command: Cmd) -> bytes:
        if len(payload) < size:
            raise WorkbenchError(f"XCP {command.name}: {len(payload)} data bytes in the response, expected {size}")
        return bytes(payload[:size])

    # --- calibration pages --------------------------------------------------------------------

    def get_cal_page(self, segment: int, mode: int = 0x02) -> int:
        """The page of ``segment`` the ECU (mode 0x01) or XCP (0x02) accesses; from a slave without GET_CAL_PAGE
        (ERR_CMD_UNKNOWN: it is optional) the page as this master last set it.

        :raises XcpCommandError: refused, or not implemented and not set since CONNECT.
        """
        try:
            page = self.command(Cmd.GET_CAL_PAGE, bytes((mode, segment)))[2]
        except XcpCommandError as error:
            known = (self.ecu_pages if mode == 0x01 else self.xcp_pages).get(segment)
            if error.code != Err.CMD_UNKNOWN or known is None:
                raise
            return known
        if mode == 0x02:
            self.xcp_pages[segment] = page
        return page

    def set_cal_page(self, segment: int, page: int, mode: int = 0x03) -> None:
        """Switch ``segment`` to ``page`` for the ECU (0x01), XCP (0x02) or both (0x03); 0x80: all segments."""
        self.memory_changes += 1
        for pages, bit in ((self.ecu_pages, 0x01), (self.xcp_pages, 0x02)):
            if mode & bit:
                pages.pop(segment, None)
                if mode & 0x80:  # the caller knows which segments "all" are
                    pages.clear()
        self.command(Cmd.SET_CAL_PAGE, bytes((mode, segment, page)))
        if not mode & 0x80:
            for pages, bit in ((self.ecu_pages, 0x01), (self.xcp_pages, 0x02)):
                if mode & bit:
                    pages[segment] = page

    def copy_cal_page(self, source_segment: int, source_page: int, target_segment: int, target_page: int) -> None:
        self.memory_changes += 1
        self.command(Cmd.COPY_CAL_PAGE, bytes((source_segment, source_page, target_segment, target_page)))

    def get_pag_processor_info(self) -> PagProcessorInfo:
        return PagProcessorInfo.parse(self.command(Cmd.GET_PAG_PROCESSOR_INFO))

    def get_segment_range(self, segment: int) -> tuple[int, int]:
        """GET_SEGMENT_INFO mode 0 (basic): ``segment``'s address and length."""
        address, length = (struct.unpack_from(f"{self.order}3xI", self.command(Cmd.GET_SEGMENT_INFO,
                                                                              bytes((0, segment, info, 0))))[0]
                           for info in (0, 1))
        return address, length

    # --- flash programming --------------------------------------------------------------------

    def get_pgm_processor_info(self) -> PgmProcessorInfo:
        return PgmProcessorInfo.parse(self.command(Cmd.GET_PGM_PROCESSOR_INFO))

    def get_sector_info(self, number: int) -> SectorInfo:
        """Start, length and clear/program order of sector ``number`` (GET_SECTOR_INFO modes 0 and 1)."""
        start = self.command(Cmd.GET_SECTOR_INFO, bytes((0, number)))
        length = self.command(Cmd.GET_SECTOR_INFO, bytes((1, number)))
        return SectorInfo.parse(number, start, length, self.order)

    def program_start(self) -> ProgramStartInfo:
        """PROGRAM_START: the slave prepares for programming and says how (MAX_CTO_PGM, MAX_BS_PGM, MIN_ST_PGM,
        QUEUE_SIZE_PGM)."""
        return ProgramStartInfo.parse(self.command(Cmd.PROGRAM_START))

    def program_clear(self, size: int) -> None:
        """PROGRAM_CLEAR in absolute mode: erase ``size`` bytes (whole sectors) from the MTA."""
        self.command(Cmd.PROGRAM_CLEAR, struct.pack(f"{self.order}B2xI", 0, size // self.granularity))

    def program_block_size(self, start: ProgramStartInfo, *, use_max: bool = False) -> int:
        """Bytes :meth:`program` sends per response: a master block of whole frames (at most 1 + MAX_BS_PGM
        of them and 255 elements), else one PROGRAM_MAX (``use_max``) or PROGRAM frame
        (:func:`~workbench.xcp.info.program_block_size`)."""
        return block_size(start.max_cto_pgm, self.granularity, use_max=use_max,
                          max_bs=start.max_bs_pgm if start.master_block_mode else None)

    def program(self, data: bytes, start: ProgramStartInfo, *, use_max: bool = False) -> None:
        """PROGRAM ``data`` at the MTA (which advances), as :meth:`program_start` allowed: master blocks of
        PROGRAM + PROGRAM_NEXT frames (MIN_ST_PGM apart, one response a block), else one frame a command
        (PROGRAM_MAX when ``use_max``, one byte more a frame). Never more than one command is outstanding,
        so any QUEUE_SIZE_PGM is honoured. Not repeated on a timeout: the caller knows what may be written.

        :raises XcpCommandError: the slave refuses a block (the early response of a block is caught).
        :raises XcpTimeoutError: the last frame of a block went unanswered.
        """
        per_frame = self._per_frame(start.max_cto_pgm)
        if start.master_block_mode:
            size = self.program_block_size(start)
            for offset in range(0, len(data), size):
                self._download_block(data[offset:offset + size], Cmd.PROGRAM, Cmd.PROGRAM_NEXT, "t5",
                                     start.min_st_pgm_s, per_frame)
            return
        offset = 0
        if use_max:
            per_max = self.program_block_size(start, use_max=True)
            while len(data) - offset >= per_max:  # PROGRAM_MAX: alignment bytes after the command, like an UPLOAD
                self.command(Cmd.PROGRAM_MAX, bytes(self.granularity - 1) + data[offset:offset + per_max],
                             repeat=False)
                offset += per_max
        align = bytes(max(2, self.granularity) - 2)
        for offset in range(offset, len(data), per_frame):
            chunk = data[offset:offset + per_frame]
            self.command(Cmd.PROGRAM, bytes((len(chunk) // self.granularity,)) + align + chunk, repeat=False)

    def program_end(self) -> None:
        """PROGRAM with size 0: the end of a memory segment (ASAM), after each range programmed. A driver that writes
        flash a page at a time writes the page it holds now, before anything reads it back; one that writes every
        frame at once has nothing to do. Repeated after a timeout: ending a segment twice does no harm."""
        self.command(Cmd.PROGRAM, bytes(max(2, self.granularity) - 1), timeout="t5")

    def program_reset(self) -> None:
        """PROGRAM_RESET: the slave resets (answering first or not at all); the session ends either way.

        Without an answer a SYNCH tells the two apart: a slave that reset is disconnected and silent, one
        that still answers never got the command, which is then sent again (twice at most).

        :raises XcpCommandError: the slave refuses the reset.
        :raises XcpTimeoutError: the slave answers SYNCH but no PROGRAM_RESET: it does not reset.
        """
        self._unlock_for(Cmd.PROGRAM_RESET)
        try:
            unanswered = busy = 0
            while unanswered < 3:
                response = self.link.exchange(bytes((Cmd.PROGRAM_RESET,)), self.timeouts.t1)
                if response is not None:
                    code = response[1] if len(response) > 1 else 0
                    if response[0] == PID_ERR and code in _WAIT_AND_REPEAT and busy < _BUSY_REPEATS:
                        busy += 1
                        time.sleep(self.timeouts.t7)
                        continue
                    if response[0] == PID_ERR:
                        raise XcpCommandError(Cmd.PROGRAM_RESET.name, code)
                    return
                if self.link.exchange(bytes((Cmd.SYNCH,)), self.timeouts.t1) is None:
                    return
                unanswered += 1
                log.info("XCP PROGRAM_RESET: no response, but the slave answers SYNCH; repeating")
            raise XcpTimeoutError(Cmd.PROGRAM_RESET.name, self.timeouts.t1)
        finally:
            self.connect_info = None

    def resynchronize(self, attempts: int = 3) -> None:
        """SYNCH until its ERR_CMD_SYNCH arrives, dropping the late responses before it (after a broken block,
        the slave may still be answering the frames the master sent on).

        :raises XcpTimeoutError: the slave answers none of ``attempts`` SYNCHs: it is gone.
        """
        for _ in range(attempts):
            response = self.link.exchange(bytes((Cmd.SYNCH,)), self.timeouts.t1)
            while response is not None:
                if response[0] == PID_ERR and len(response) > 1 and response[1] == Err.CMD_SYNCH:
                    return
                response = self.link.receive(self.timeouts.t1)
        raise XcpTimeoutError(Cmd.SYNCH.name, self.timeouts.t1)

    # --- DAQ ----------------------------------------------------------------------------------

    def get_daq_processor_info(self) -> DaqProcessorInfo:
        return DaqProcessorInfo.parse(self.command(Cmd.GET_DAQ_PROCESSOR_INFO), self.order)

    def get_daq_resolution_info(self) -> DaqResolutionInfo:
        return DaqResolutionInfo.parse(self.command(Cmd.GET_DAQ_RESOLUTION_INFO), self.order)

    def get_daq_list_info(self, daq_list: int) -> DaqListInfo:
        """GET_DAQ_LIST_INFO: a static or predefined list's ODTs, entries per ODT and fixed event."""
        return DaqListInfo.parse(daq_list, self.command(Cmd.GET_DAQ_LIST_INFO, struct.pack(f"{self.order}xH", daq_list)),
                                 self.order)

    def get_daq_event_info(self, event: int) -> DaqEventInfo:
        payload = self.command(Cmd.GET_DAQ_EVENT_INFO, struct.pack(f"{self.order}xH", event))
        length = DaqEventInfo.name_length(payload)
        name = self.upload(length).decode("latin-1") if length else ""
        return DaqEventInfo.parse(event, payload, name)

    def get_daq_clock(self) -> int:
        """The slave's free-running DAQ clock (its timestamp counter)."""
        payload = self.command(Cmd.GET_DAQ_CLOCK)
        return struct.unpack_from(f"{self.order}3xI", payload)[0]

    def free_daq(self) -> None:
        self.command(Cmd.FREE_DAQ)

    # ALLOC_* and WRITE_DAQ are not repeated after a timeout: done twice they fail (ERR_SEQUENCE) or write the
    # next entry (the DAQ pointer moves on); the caller starts the configuration over instead.

    def alloc_daq(self, count: int) -> None:
        self.command(Cmd.ALLOC_DAQ, struct.pack(f"{self.order}xH", count), repeat=False)

    def alloc_odt(self, daq_list: int, count: int) -> None:
        self.command(Cmd.ALLOC_ODT, struct.pack(f"{self.order}xHB", daq_list, count), repeat=False)

    def alloc_odt_entry(self, daq_list: int, odt: int, count: int) -> None:
        self.command(Cmd.ALLOC_ODT_ENTRY, struct.pack(f"{self.order}xHBB", daq_list, odt, count), repeat=False)

    def set_daq_ptr(self, daq_list: int, odt: int, entry: int) -> None:
        self.command(Cmd.SET_DAQ_PTR, struct.pack(f"{self.order}xHBB", daq_list, odt, entry))

    def write_daq(self, size: int, address: int, extension: int = 0, bit_offset: int = 0xFF) -> None:
        self.command(Cmd.WRITE_DAQ, struct.pack(f"{self.order}BBBI", bit_offset, size // self.granularity,
                                                extension, address), repeat=False)

    def clear_daq_list(self, daq_list: int) -> None:
        """CLEAR_DAQ_LIST: empty a (static) list's ODT entries and reset its mode; the list must be stopped."""
        self.command(Cmd.CLEAR_DAQ_LIST, struct.pack(f"{self.order}xH", daq_list))

    def set_daq_list_mode(self, daq_list: int, event: int, *, timestamp: bool, prescaler: int = 1,
                          priority: int = 0) -> None:
        mode = 0x10 if timestamp else 0x00
        self.command(Cmd.SET_DAQ_LIST_MODE, struct.pack(f"{self.order}BHHBB", mode, daq_list, event, prescaler, priority))

    def get_daq_list_mode(self, daq_list: int) -> tuple[int, int]:
        """GET_DAQ_LIST_MODE: the list's CURRENT_MODE bits (0x01 SELECTED, 0x10 TIMESTAMP, 0x40 RUNNING), its event."""
        payload = self.command(Cmd.GET_DAQ_LIST_MODE, struct.pack(f"{self.order}xH", daq_list))
        if len(payload) < 5:
            raise WorkbenchError(f"XCP GET_DAQ_LIST_MODE: the response has {len(payload) + 1} bytes, expected 8")
        mode, event = struct.unpack_from(f"{self.order}BxxH", payload)
        return mode, event

    def start_stop_daq_list(self, daq_list: int, mode: int) -> int:
        """Mode 0 stop, 1 start, 2 select; returns the list's FIRST_PID."""
        return self.command(Cmd.START_STOP_DAQ_LIST, struct.pack(f"{self.order}BH", mode, daq_list))[0]

    def start_stop_synch(self, mode: int) -> None:
        """Mode 0 stop all, 1 start selected, 2 stop selected."""
        self.command(Cmd.START_STOP_SYNCH, bytes((mode,)))

    # --- XCP on CAN's DAQ list identifiers (TRANSPORT_LAYER_CMD) ------------------------------

    def get_daq_id(self, daq_list: int) -> tuple[CanId, bool]:
        """GET_DAQ_ID: the CAN id a DAQ list's DTOs go on, and whether it is fixed (SET_DAQ_ID cannot move it).

        :raises XcpCommandError: the slave refuses (named ``TRANSPORT_LAYER_CMD GET_DAQ_ID``).
        :raises WorkbenchError: the answer names no CAN id.
        """
        answer = self._can_command(CanCmd.GET_DAQ_ID, struct.pack(f"{self.order}H", daq_list))
        try:
            return CanId.from_a2l(struct.unpack_from(f"{self.order}I", answer, 3)[0]), answer[0] == 1
        except (struct.error, ValueError):
            raise WorkbenchError(f"XCP GET_DAQ_ID of DAQ list {daq_list}: the response {answer.hex(' ').upper()} "
                                 "names no CAN id") from None

    def set_daq_id(self, daq_list: int, can_id: CanId) -> None:
        """SET_DAQ_ID: the DAQ list's DTOs go on ``can_id`` from now (a list DAQ_LIST_CAN_ID calls VARIABLE).

        :raises XcpCommandError: the slave refuses (named ``TRANSPORT_LAYER_CMD SET_DAQ_ID``; a fixed list or an
            id it cannot send on: ERR_OUT_OF_RANGE).
        """
        self._can_command(CanCmd.SET_DAQ_ID, struct.pack(f"{self.order}HI", daq_list, can_id.a2l))

    def _can_command(self, sub_command: CanCmd, payload: bytes) -> bytes:
        try:
            return self.command(Cmd.TRANSPORT_LAYER_CMD, bytes((sub_command,)) + payload, repeat=False)
        except XcpCommandError as error:  # named by the sub-command: TRANSPORT_LAYER_CMD alone says too little
            raise XcpCommandError(f"{error.command} {sub_command.name}", error.code, error.name,
                                  payload=error.payload) from None
