"""Finding XCP on CAN slaves on a bus, as CANape's "detect devices" does (ASAM XCP Part 3, XCP on CAN).

:func:`detect_can_slaves` sends TRANSPORT_LAYER_CMD GET_SLAVE_ID (``F2 FF 'X' 'C' 'P' mode``) on the broadcast
identifier, twice: "identify by echo" (mode 0), then "confirm by inverse echo" (mode 1). Every slave answers on
its own response identifier (CAN_ID_SLAVE) with ``FF 'X' 'C' 'P'`` (inverted: ``FF A7 BC AF``) and the identifier
it takes commands on (CAN_ID_MASTER, a DWORD in the slave's byte order, bit 31 set for an extended id). Nothing
else is sent on the bus: no CONNECT, no sweep over identifiers. :func:`identify_slave` then talks to one slave
found on the identifiers it named: CONNECT, GET_ID (text, EPK), GET_DAQ_ID per DAQ list, DISCONNECT.

Before CONNECT the master cannot know the slave's byte order: the caller says it (the A2L's PROTOCOL_LAYER
BYTE_ORDER, Intel by default); a DWORD that is no CAN identifier in that order but is one in the other is read
the other way.
"""

from __future__ import annotations

import struct
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from workbench.errors import WorkbenchError, XcpCommandError, XcpTimeoutError
from workbench.logs import logger
from workbench.xcp.link import Link, LinkSettings
from workbench.xcp.master import Timeouts, XcpMaster
from workbench.xcp_protocol import (
    PID_RES,
    SLAVE_ID_ECHO,
    CanCmd,
    CanId,
    Cmd,
    Err,
    IdType,
    SlaveIdMode,
)

if TYPE_CHECKING:
    import can

log = logger(__name__)

__all__ = ["DEFAULT_WAIT_S", "MAX_DAQ_ID_LISTS", "DaqCanIds", "DetectedSlave", "SlaveDetection", "SlaveIdentity",
           "detect_can_slaves", "get_slave_id_request", "identify_slave", "parse_slave_id_answer", "read_daq_can_ids"]

DEFAULT_WAIT_S = 0.2  # how long each GET_SLAVE_ID collects answers (a slave answers within T1, mostly at once)
MAX_DAQ_ID_LISTS = 16  # GET_DAQ_ID is asked for the first lists only (a dynamic slave may have hundreds)
_ANSWER_LENGTH = 8  # PID, the 3 pattern bytes, the DWORD identifier


def get_slave_id_request(mode: SlaveIdMode) -> bytes:
    """GET_SLAVE_ID with ``mode``, padded to 8 bytes (a slave with MAX_DLC_REQUIRED ignores a shorter frame)."""
    return bytes((Cmd.TRANSPORT_LAYER_CMD, CanCmd.GET_SLAVE_ID)) + SLAVE_ID_ECHO + bytes((mode, 0, 0))


def parse_slave_id_answer(data: bytes, mode: SlaveIdMode, byte_order: str = "<") -> CanId | str | None:
    """The command identifier a GET_SLAVE_ID answer names; a string says why a packet shaped as an answer is none
    (a wrong pattern, no CAN identifier); None: the packet is no answer (not a positive response of 8 bytes)."""
    if len(data) < _ANSWER_LENGTH or data[0] != PID_RES:
        return None
    expected = SlaveIdMode(mode).pattern
    if data[1:4] != expected:
        return f"pattern {data[1:4].hex(' ').upper()}, not {expected.hex(' ').upper()}"
    for order in (byte_order, ">" if byte_order == "<" else "<"):
        try:
            return CanId.from_a2l(struct.unpack_from(order + "I", data, 4)[0])
        except ValueError:
            continue
    return f"identifier bytes {data[4:8].hex(' ').upper()} are no CAN identifier"


@dataclass(frozen=True)
class DetectedSlave:
    """One slave that answered: it takes commands on ``command_id`` (CAN_ID_MASTER) and answers on ``response_id``
    (CAN_ID_SLAVE); ``confirmed``: it answered the inverse echo too."""

    command_id: CanId
    response_id: CanId
    confirmed: bool

    def to_dict(self) -> dict:
        return {"can_id_master": self.command_id.a2l, "can_id_slave": self.response_id.a2l,
                "command_id": str(self.command_id), "response_id": str(self.response_id), "confirmed": self.confirmed}


@dataclass(frozen=True)
class SlaveDetection:
    """What a detection sent where, the slaves that answered and the answers refused (id, why)."""

    broadcast_id: CanId
    bus: str
    wait_s: float
    slaves: tuple[DetectedSlave, ...]
    refused: tuple[tuple[CanId, str], ...] = ()

    def sent(self) -> str:
        """What was sent, for people: 'GET_SLAVE_ID (echo and inverse echo) on 0x6F0 (virtual workbench)'."""
        return f"GET_SLAVE_ID (echo and inverse echo) on {self.broadcast_id} ({self.bus})"

    def to_dict(self) -> dict:
        return {"broadcast_id": self.broadcast_id.a2l, "bus": self.bus, "wait_s": self.wait_s,
                "slaves": [slave.to_dict() for slave in self.slaves],
                "refused": [{"can_id": can_id.a2l, "reason": reason} for can_id, reason in self.refused]}


def detect_can_slaves(bus: can.BusABC, broadcast_id: CanId, *, wait_s: float = DEFAULT_WAIT_S,
                      byte_order: str = "<", fd: bool = False, describe: str | None = None) -> SlaveDetection:
    """The XCP slaves on ``bus`` that answer GET_SLAVE_ID on ``broadcast_id``, each step waiting ``wait_s``.

    ``bus`` is the caller's and stays open; no receiver (python-can Notifier) may read it meanwhile. ``fd``: the
    requests go as CAN FD frames. A slave that answers the echo but not the inverse echo is listed unconfirmed;
    an answer with a wrong pattern is listed in :attr:`SlaveDetection.refused`.

    :raises WorkbenchError: the bus refuses the frame or fails.
    """
    import can

    where = describe or str(bus.channel_info)
    _drain(bus)
    echoes, refused = _ask(can, bus, broadcast_id, SlaveIdMode.ECHO, wait_s, byte_order, fd, where)
    inverse, refused_inverse = _ask(can, bus, broadcast_id, SlaveIdMode.INVERSE_ECHO, wait_s, byte_order, fd, where)
    slaves = tuple(DetectedSlave(command, response, inverse.get(response) == command)
                   for response, command in sorted(echoes.items()))
    slaves += tuple(DetectedSlave(command, response, True) for response, command in sorted(inverse.items())
                    if response not in echoes)  # it missed the first request: the inverse echo says it all the same
    for slave in slaves:
        log.info("XCP slave: commands on %s, answers on %s%s", slave.command_id, slave.response_id,
                 "" if slave.confirmed else " (no inverse echo)")
    return SlaveDetection(broadcast_id, where, wait_s, slaves, tuple(refused + refused_inverse))


def _drain(bus: can.BusABC) -> None:
    """Frames queued before the request are not its answers."""
    import can

    try:
        while bus.recv(0) is not None:
            pass
    except (can.CanError, OSError) as exc:
        raise WorkbenchError(f"cannot read the CAN bus ({exc})") from None


def _ask(can, bus: can.BusABC, broadcast_id: CanId, mode: SlaveIdMode, wait_s: float, byte_order: str, fd: bool,
         where: str) -> tuple[dict[CanId, CanId], list[tuple[CanId, str]]]:
    """Send one GET_SLAVE_ID; the answers within ``wait_s``: response id -> command id, and those refused."""
    request = can.Message(arbitration_id=broadcast_id.id, is_extended_id=broadcast_id.extended, is_fd=fd,
                          data=get_slave_id_request(mode))
    answers: dict[CanId, CanId] = {}
    refused: list[tuple[CanId, str]] = []
    try:
        bus.send(request)
        deadline = time.monotonic() + wait_s
        while (left := deadline - time.monotonic()) > 0:
            message = bus.recv(left)
            if message is None:
                break
            if message.is_error_frame or message.is_remote_frame:
                continue
            sender = CanId(message.arbitration_id, message.is_extended_id)
            if sender == broadcast_id:
                continue  # another master's request (or our own, echoed by the interface)
            answer = parse_slave_id_answer(bytes(message.data), mode, byte_order)
            if isinstance(answer, CanId):
                answers[sender] = answer
            elif answer is not None:
                log.info("a GET_SLAVE_ID answer on %s refused: %s", sender, answer)
                refused.append((sender, answer))
    except (can.CanError, OSError, ValueError) as exc:
        raise WorkbenchError(f"cannot send GET_SLAVE_ID on {broadcast_id} ({where}): {exc}") from None
    return answers, refused


@dataclass(frozen=True)
class DaqCanIds:
    """GET_DAQ_ID's answer for the DAQ lists ``first``..``last``: their DTOs go on ``can_id`` (``fixed``: the
    slave does not let SET_DAQ_ID move them)."""

    first: int
    last: int
    can_id: CanId
    fixed: bool

    def to_dict(self) -> dict:
        return {"first_list": self.first, "last_list": self.last, "can_id": self.can_id.a2l, "fixed": self.fixed}

    def __str__(self) -> str:
        lists = f"list {self.first}" if self.first == self.last else f"lists {self.first}-{self.last}"
        return f"{lists} on {self.can_id} ({'fixed' if self.fixed else 'configurable'})"


@dataclass(frozen=True)
class SlaveIdentity:
    """What one slave said of itself in a short session: its text (GET_ID 0), EPK (GET_ID 5), the DAQ lists' ids
    (GET_DAQ_ID; empty when it has none or no such command), or why the session failed (``error``)."""

    slave: DetectedSlave
    text: str | None = None
    epk: str | None = None
    daq_ids: tuple[DaqCanIds, ...] = ()
    error: str | None = None
    notes: tuple[str, ...] = field(default=())

    def to_dict(self) -> dict:
        return {**self.slave.to_dict(), "identification": self.text, "epk": self.epk,
                "daq_ids": [item.to_dict() for item in self.daq_ids], "error": self.error, "notes": list(self.notes)}


def identify_slave(bus: can.BusABC, slave: DetectedSlave, *, fd: bool = False, timeouts: Timeouts | None = None
                   ) -> SlaveIdentity:
    """CONNECT to ``slave`` on the identifiers it named, GET_ID (text and EPK), GET_DAQ_ID for the first
    :data:`MAX_DAQ_ID_LISTS` lists, DISCONNECT. A refusal or silence is kept in the result, never raised."""
    # classic CAN: frames padded to 8 bytes, as a slave with MAX_DLC_REQUIRED wants them (and any other takes them)
    settings = LinkSettings("CAN", None, slave.command_id, slave.response_id, max_dlc_required=not fd, fd=fd,
                            max_dlc=64 if fd else 8)
    notes: list[str] = []
    with Link(settings, bus=bus) as link:
        master = XcpMaster(link, timeouts=timeouts or Timeouts())
        try:
            master.connect()
        except WorkbenchError as exc:
            return SlaveIdentity(slave, error=f"CONNECT: {exc}")
        try:
            text = _identification(master, IdType.ASCII, notes)
            epk = _identification(master, IdType.EPK, notes)
            daq_ids = read_daq_can_ids(master, notes)
        except WorkbenchError as exc:
            return SlaveIdentity(slave, error=str(exc), notes=tuple(notes))
        finally:
            try:
                master.disconnect()
            except WorkbenchError:
                log.debug("DISCONNECT after identifying %s failed", slave.command_id, exc_info=True)
    return SlaveIdentity(slave, text, epk, daq_ids, notes=tuple(notes))


def _identification(master: XcpMaster, kind: IdType, notes: list[str]) -> str | None:
    try:
        value = master.get_id(kind)
    except XcpCommandError as exc:
        notes.append(f"GET_ID {kind.name}: {exc}")
        return None
    return value.rstrip(b"\0").decode("latin-1") or None


def read_daq_can_ids(master: XcpMaster, notes: list[str]) -> tuple[DaqCanIds, ...]:
    """GET_DAQ_ID for the first :data:`MAX_DAQ_ID_LISTS` lists, until the slave refuses one; consecutive lists on one
    id are one entry. A refusal (other than the end of the lists) or silence goes to ``notes``, never raised."""
    found: list[DaqCanIds] = []
    for number in range(MAX_DAQ_ID_LISTS):
        try:
            can_id, fixed = master.get_daq_id(number)
        except (XcpCommandError, XcpTimeoutError) as exc:
            if number == 0 or getattr(exc, "code", None) != Err.OUT_OF_RANGE:
                notes.append(f"GET_DAQ_ID of list {number}: {exc}")
            break
        except WorkbenchError as exc:  # an answer that names no CAN id
            notes.append(str(exc))
            break
        last = found[-1] if found else None
        if last is not None and (last.can_id, last.fixed, last.last) == (can_id, fixed, number - 1):
            found[-1] = DaqCanIds(last.first, number, can_id, fixed)
        else:
            found.append(DaqCanIds(number, number, can_id, fixed))
    return tuple(found)
