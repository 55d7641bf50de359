"""ASAM XCP 1.x names shared by the simulated slave and the master: command, error and packet
codes, resource bits, GET_ID types, time units, and the CAN identifier (:class:`CanId`, with the A2L's
extended flag in one place).

Neutral ground: it imports nothing, so :mod:`workbench.sim` and the master in
:mod:`workbench.xcp` can both use it without depending on each other (DESIGN: sim never
depends on xcp).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum, IntFlag

__all__ = ["CAN_ID_EXTENDED_FLAG", "EV_CMD_PENDING", "EV_DAQ_OVERLOAD", "EV_SESSION_TERMINATED", "MAX_DAQ_PID",
           "PID_ERR", "PID_EV", "PID_RES", "PID_SERV", "SLAVE_ID_ECHO", "SLAVE_ID_INVERSE", "TIME_UNIT_S", "CanCmd",
           "CanId", "Cmd", "Err", "IdType", "Resource", "SlaveIdMode"]

PID_RES = 0xFF  # positive response
PID_ERR = 0xFE  # negative response
PID_EV = 0xFD  # event packet (EV_...)
PID_SERV = 0xFC  # service request packet (SERV_RESET, SERV_TEXT)
EV_CMD_PENDING = 0x05  # event code: the slave needs longer for the command; the master restarts its timeout
EV_DAQ_OVERLOAD = 0x06  # event code: the slave could not send every DTO (OVERLOAD_INDICATION_EVENT)
EV_SESSION_TERMINATED = 0x07  # event code: the slave ended the session on its own (the master is disconnected)
MAX_DAQ_PID = 0xFB  # DTO packet ids run from 0x00 to 0xFB

CAN_ID_EXTENDED_FLAG = 0x80000000  # bit 31 of an XCP-on-CAN id (CAN_ID_MASTER/SLAVE, DAQ_LIST_CAN_ID): a 29-bit id
_STANDARD_MASK, _EXTENDED_MASK = 0x7FF, 0x1FFFFFFF


@dataclass(frozen=True, order=True)
class CanId:
    """A CAN identifier: ``id`` and whether it is a 29-bit (extended) one, as python-can's ``Message`` has it
    (``arbitration_id``, ``is_extended_id``). The A2L's XCP_ON_CAN writes the two as one number with bit 31
    (0x80000000) set for an extended id: :meth:`from_a2l` and :attr:`a2l`.

    :raises ValueError: an id the frame format cannot carry (above 0x7FF standard, 0x1FFFFFFF extended).
    """

    id: int
    extended: bool = False

    def __post_init__(self) -> None:
        if not 0 <= self.id <= self.mask:
            hint = f"; a 29-bit id has bit 31 set in the A2L (0x{self.id | CAN_ID_EXTENDED_FLAG:X})" if (
                not self.extended and self.id <= _EXTENDED_MASK) else ""
            raise ValueError(f"CAN id 0x{self.id:X} does not fit a{'n extended' if self.extended else ' standard'} "
                             f"frame{hint}")

    @classmethod
    def from_a2l(cls, number: int) -> CanId:
        """The id an A2L number means (bit 31: extended)."""
        return cls(number & ~CAN_ID_EXTENDED_FLAG, bool(number & CAN_ID_EXTENDED_FLAG))

    @property
    def a2l(self) -> int:
        """The number the A2L writes: the id, with bit 31 set when it is extended."""
        return self.id | (CAN_ID_EXTENDED_FLAG if self.extended else 0)

    @property
    def mask(self) -> int:
        """All the id's bits: 0x7FF or 0x1FFFFFFF (for a receive filter that takes this id only)."""
        return _EXTENDED_MASK if self.extended else _STANDARD_MASK

    def matches(self, message) -> bool:
        """Whether a python-can ``Message`` carries this id."""
        return message.arbitration_id == self.id and message.is_extended_id == self.extended

    def __str__(self) -> str:
        return f"0x{self.id:X}" + (" (extended)" if self.extended else "")

# Time unit codes of DAQ events and timestamps (A2L EVENT TIME_UNIT, GET_DAQ_EVENT_INFO,
# GET_DAQ_RESOLUTION_INFO TIMESTAMP_MODE bits 4..7) -> seconds: code n < 10 counts 10**(n - 9) s.
TIME_UNIT_S = {
    0: 1e-9, 1: 1e-8, 2: 1e-7, 3: 1e-6, 4: 1e-5, 5: 1e-4, 6: 1e-3, 7: 1e-2, 8: 1e-1, 9: 1.0,
    10: 1e-12, 11: 1e-11, 12: 1e-10,
}


class Cmd(IntEnum):
    CONNECT = 0xFF
    DISCONNECT = 0xFE
    GET_STATUS = 0xFD
    SYNCH = 0xFC
    GET_COMM_MODE_INFO = 0xFB
    GET_ID = 0xFA
    SET_REQUEST = 0xF9
    GET_SEED = 0xF8
    UNLOCK = 0xF7
    SET_MTA = 0xF6
    UPLOAD = 0xF5
    SHORT_UPLOAD = 0xF4
    BUILD_CHECKSUM = 0xF3
    TRANSPORT_LAYER_CMD = 0xF2
    USER_CMD = 0xF1
    DOWNLOAD = 0xF0
    DOWNLOAD_NEXT = 0xEF
    DOWNLOAD_MAX = 0xEE
    SHORT_DOWNLOAD = 0xED
    MODIFY_BITS = 0xEC
    SET_CAL_PAGE = 0xEB
    GET_CAL_PAGE = 0xEA
    GET_PAG_PROCESSOR_INFO = 0xE9
    GET_SEGMENT_INFO = 0xE8
    GET_PAGE_INFO = 0xE7
    SET_SEGMENT_MODE = 0xE6
    GET_SEGMENT_MODE = 0xE5
    COPY_CAL_PAGE = 0xE4
    CLEAR_DAQ_LIST = 0xE3
    SET_DAQ_PTR = 0xE2
    WRITE_DAQ = 0xE1
    SET_DAQ_LIST_MODE = 0xE0
    GET_DAQ_LIST_MODE = 0xDF
    START_STOP_DAQ_LIST = 0xDE
    START_STOP_SYNCH = 0xDD
    GET_DAQ_CLOCK = 0xDC
    READ_DAQ = 0xDB
    GET_DAQ_PROCESSOR_INFO = 0xDA
    GET_DAQ_RESOLUTION_INFO = 0xD9
    GET_DAQ_LIST_INFO = 0xD8
    GET_DAQ_EVENT_INFO = 0xD7
    FREE_DAQ = 0xD6
    ALLOC_DAQ = 0xD5
    ALLOC_ODT = 0xD4
    ALLOC_ODT_ENTRY = 0xD3
    PROGRAM_START = 0xD2
    PROGRAM_CLEAR = 0xD1
    PROGRAM = 0xD0
    PROGRAM_RESET = 0xCF
    GET_PGM_PROCESSOR_INFO = 0xCE
    GET_SECTOR_INFO = 0xCD
    PROGRAM_PREPARE = 0xCC
    PROGRAM_FORMAT = 0xCB
    PROGRAM_NEXT = 0xCA
    PROGRAM_MAX = 0xC9
    PROGRAM_VERIFY = 0xC8


class CanCmd(IntEnum):
    """XCP on CAN's sub-commands of TRANSPORT_LAYER_CMD (the byte after 0xF2)."""

    GET_SLAVE_ID = 0xFF  # 'X' 'C' 'P' mode: asked on CAN_ID_BROADCAST, every slave answers with its CAN_ID_MASTER
    GET_DAQ_ID = 0xFE  # DAQ list number (WORD): the CAN id its DTOs go on, and whether it is fixed
    SET_DAQ_ID = 0xFD  # DAQ list number (WORD), CAN id (DWORD)


class SlaveIdMode(IntEnum):
    """GET_SLAVE_ID's mode byte: the answer carries ``XCP`` (:data:`SLAVE_ID_ECHO`) or its bytes inverted."""

    ECHO = 0  # identify by echo
    INVERSE_ECHO = 1  # confirm by inverse echo

    @property
    def pattern(self) -> bytes:
        """The three bytes an answer to GET_SLAVE_ID in this mode carries after its PID."""
        return SLAVE_ID_INVERSE if self is SlaveIdMode.INVERSE_ECHO else SLAVE_ID_ECHO


SLAVE_ID_ECHO = b"XCP"
SLAVE_ID_INVERSE = bytes(0xFF - byte for byte in SLAVE_ID_ECHO)  # A7 BC AF


class Err(IntEnum):
    CMD_SYNCH = 0x00
    CMD_BUSY = 0x10
    DAQ_ACTIVE = 0x11
    PGM_ACTIVE = 0x12
    CMD_UNKNOWN = 0x20
    CMD_SYNTAX = 0x21
    OUT_OF_RANGE = 0x22
    WRITE_PROTECTED = 0x23
    ACCESS_DENIED = 0x24
    ACCESS_LOCKED = 0x25
    PAGE_NOT_VALID = 0x26
    MODE_NOT_VALID = 0x27
    SEGMENT_NOT_VALID = 0x28
    SEQUENCE = 0x29
    DAQ_CONFIG = 0x2A
    MEMORY_OVERFLOW = 0x30
    GENERIC = 0x31
    VERIFY = 0x32
    RESOURCE_TEMPORARY_NOT_ACCESSIBLE = 0x33
    SUBCMD_UNKNOWN = 0x34


class Resource(IntFlag):
    """Resource bits of CONNECT, GET_STATUS, GET_SEED and UNLOCK."""

    CAL_PAG = 0x01
    DAQ = 0x04
    STIM = 0x08
    PGM = 0x10


class IdType(IntEnum):
    """GET_ID request types."""

    ASCII = 0  # the ECU's text
    ASAM_MC2_NAME = 1  # the A2L's file name without path and extension
    ASAM_MC2_FILE = 4  # the A2L itself, to upload (XCPlite writes its own at run time)
    EPK = 5  # the EPROM identifier (the EPK at ADDR_EPK)
