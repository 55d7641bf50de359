"""ASAM XCP 1.x names the slave needs: command codes, error codes, resources, packet ids."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from enum import IntEnum, IntFlag

from workbench.sim.memory import AccessFault, MemoryAccessError

PID_RES = 0xFF  # positive response
PID_ERR = 0xFE  # negative response
MAX_DAQ_PID = 0xFB  # DTO packet ids run from 0x00 to 0xFB


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


class XcpNegative(Exception):
    """A command handler's refusal: becomes the negative response ``FE code *extra``."""

    def __init__(self, code: Err, extra: bytes = b""):
        super().__init__(f"{Err(code).name}")
        self.code = Err(code)
        self.extra = extra

    def packet(self) -> bytes:
        return bytes([PID_ERR, self.code]) + self.extra


def need(req: bytes, length: int) -> None:
    """Refuse a command shorter than ``length`` bytes (command byte included) with ERR_CMD_SYNTAX."""
    if len(req) < length:
        raise XcpNegative(Err.CMD_SYNTAX)


def memory_error(exc: MemoryAccessError) -> XcpNegative:
    """The negative response for a refused memory access."""
    code = {
        AccessFault.READ_ONLY: Err.WRITE_PROTECTED,
        AccessFault.NOT_ERASED: Err.ACCESS_DENIED,
    }.get(exc.fault, Err.OUT_OF_RANGE)
    return XcpNegative(code)


class PowerLost(Exception):
    """Raised inside a handler when an injected power loss strikes: the frame gets no answer."""


@dataclass
class Writer:
    """How a block transfer checks its whole destination, then writes each frame's bytes."""

    check: Callable[[int, int], None]
    write: Callable[[int, bytes], None]
