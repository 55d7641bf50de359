"""The XCP slave: session, dispatch, resource protection and the standard commands.

:meth:`XcpSlave.handle` takes one CTO (the payload of a CAN frame to CAN_ID_MASTER) and
returns the packets to send back: one response, several (an UPLOAD in slave block mode),
or none — the documented silences:

* every command but CONNECT while not connected (XCP: a disconnected slave stays silent);
* an empty frame;
* a DOWNLOAD/PROGRAM(_NEXT) frame inside a master block that is not the block's last;
* while the ECU has no power (also right after an injected power loss).

Everything else gets a positive (``FF …``) or negative (``FE code …``) response; a
handler never raises anything but :class:`XcpNegative`. Multi-byte parameters are in the
byte order of :attr:`XcpParameters.byte_order` (the demo: Intel, BYTE_ORDER_MSB_LAST).

With an address granularity above BYTE (WORD, DWORD) addresses stay byte addresses, and every
transfer moves whole elements from an address aligned to one: UPLOAD, DOWNLOAD, PROGRAM and their
variants count elements and carry the spec's alignment bytes; a misaligned MTA is ERR_OUT_OF_RANGE.
With :attr:`XcpParameters.service_packets` an EV_USER or a SERV_TEXT packet goes before every
response, as a slave reporting its own business does.
"""

from __future__ import annotations

import random
import struct
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

from workbench.image import ChecksumType, checksum
from workbench.logs import logger
from workbench.sim import seedkey
from workbench.sim.faults import FaultPlan
from workbench.sim.layout import ApplicationLayout
from workbench.sim.memory import EcuMemory, MemoryAccessError
from workbench.sim.memory_map import MemoryMap
from workbench.sim.paging import CalPageSwitch
from workbench.sim.xcp.calpage import CalPageCommands
from workbench.sim.xcp.daq import DaqProcessor
from workbench.sim.xcp.info_rom import InfoRom
from workbench.sim.xcp.parameters import XcpParameters
from workbench.sim.xcp.pgm import ProgrammingCommands
from workbench.sim.xcp.responses import PowerLost, Writer, XcpNegative, memory_error, need
from workbench.xcp_protocol import PID_RES, Cmd, Err, IdType, Resource

__all__ = ["SlaveTarget", "XcpSlave"]

log = logger(__name__)

PROTOCOL_LAYER_VERSION = 1
TRANSPORT_LAYER_VERSION = 1
COMM_MODE_OPTIONAL = 0x80
COMM_MODE_SLAVE_BLOCK = 0x40
COMM_MODE_MASTER_BLOCK = 0x01
MAX_UPLOAD = 255  # elements of one UPLOAD in slave block mode
SESSION_DAQ_RUNNING = 0x40
PID_EV, PID_SERV = 0xFD, 0xFC
EV_USER, SERV_TEXT = 0xFE, 0x01
_GRANULARITY_CODES = {1: 0, 2: 1, 4: 2}  # COMM_MODE_BASIC bits 1..2


class SlaveTarget(Protocol):
    """What the slave needs from the ECU it runs in."""

    memory: EcuMemory
    memory_map: MemoryMap
    pages: CalPageSwitch
    layout: ApplicationLayout

    @property
    def application_running(self) -> bool: ...

    def timestamp_ticks(self) -> int: ...

    def halt_application(self) -> None: ...

    def reset(self) -> None: ...

    def power_loss(self) -> None: ...


@dataclass
class _Block:
    next_command: Cmd
    remaining: int
    writer: Writer
    per_frame: int  # data bytes of a _NEXT frame


# Commands by the resource that protects them; a resource the current mode lacks answers CMD_UNKNOWN.
CAL_PAG_COMMANDS = frozenset({
    Cmd.DOWNLOAD, Cmd.DOWNLOAD_NEXT, Cmd.DOWNLOAD_MAX, Cmd.SHORT_DOWNLOAD, Cmd.SET_CAL_PAGE,
    Cmd.GET_CAL_PAGE, Cmd.GET_PAG_PROCESSOR_INFO, Cmd.GET_SEGMENT_INFO, Cmd.COPY_CAL_PAGE,
})
DAQ_COMMANDS = frozenset({
    Cmd.SET_DAQ_PTR, Cmd.WRITE_DAQ, Cmd.SET_DAQ_LIST_MODE, Cmd.GET_DAQ_LIST_MODE, Cmd.START_STOP_DAQ_LIST,
    Cmd.START_STOP_SYNCH,
    Cmd.GET_DAQ_CLOCK, Cmd.GET_DAQ_PROCESSOR_INFO, Cmd.GET_DAQ_RESOLUTION_INFO, Cmd.GET_DAQ_EVENT_INFO,
    Cmd.FREE_DAQ, Cmd.ALLOC_DAQ, Cmd.ALLOC_ODT, Cmd.ALLOC_ODT_ENTRY, Cmd.GET_DAQ_LIST_INFO, Cmd.CLEAR_DAQ_LIST,
})
PGM_COMMANDS = frozenset({
    Cmd.PROGRAM_START, Cmd.PROGRAM_CLEAR, Cmd.PROGRAM, Cmd.PROGRAM_RESET, Cmd.GET_PGM_PROCESSOR_INFO,
    Cmd.GET_SECTOR_INFO, Cmd.PROGRAM_NEXT, Cmd.PROGRAM_MAX,
})


FILE_SPACE = 0xF0000000  # where a GET_ID file (the A2L of GET_ID 4) is uploaded from: no memory of the ECU's


class XcpSlave:
    def __init__(
        self,
        target: SlaveTarget,
        params: XcpParameters,
        info: InfoRom,
        faults: FaultPlan | None = None,
        rng: random.Random | None = None,
    ):
        self.target = target
        self.params = params
        self.order = params.byte_order
        self.granularity = params.address_granularity
        self.info = info
        self.faults = faults or FaultPlan()
        self._rng = rng or random.Random()
        self.files: dict[int, bytes] = {}  # GET_ID type -> a file the master uploads from FILE_SPACE (4: the A2L)
        self._file = b""  # the file GET_ID pointed the MTA at
        self.calpage = CalPageCommands(self)
        self.daq = DaqProcessor(self)
        self.pgm = ProgrammingCommands(self)
        self._handlers: dict[int, Callable[[bytes], bytes | None]] = {
            Cmd.CONNECT: self._connect,
            Cmd.DISCONNECT: self._disconnect,
            Cmd.GET_STATUS: self._get_status,
            Cmd.SYNCH: self._synch,
            Cmd.GET_COMM_MODE_INFO: self._get_comm_mode_info,
            **({Cmd.GET_ID: self._get_id} if params.get_id else {}),
            Cmd.GET_SEED: self._get_seed,
            Cmd.UNLOCK: self._unlock,
            Cmd.SET_MTA: self._set_mta,
            Cmd.UPLOAD: self._upload,
            Cmd.SHORT_UPLOAD: self._short_upload,
            Cmd.BUILD_CHECKSUM: self._build_checksum,
            Cmd.DOWNLOAD: self._download,
            Cmd.DOWNLOAD_NEXT: self._download_next,
            Cmd.DOWNLOAD_MAX: self._download_max,
            Cmd.SHORT_DOWNLOAD: self._short_download,
            **self.calpage.handlers(),
            **self.daq.handlers(),
            **self.pgm.handlers(),
        }
        for command in params.without:
            self._handlers.pop(command, None)
        self.reset()

    @property
    def commands(self) -> frozenset[Cmd]:
        """Every command this slave implements (the A2L's OPTIONAL_CMDs are those beyond the four mandatory ones)."""
        return frozenset(Cmd(code) for code in self._handlers)

    # --- session -------------------------------------------------------------------------

    def reset(self) -> None:
        """Back to the state after power-on: disconnected, everything locked, no DAQ, no block."""
        self.connected = False
        self.mta = 0
        self.locked = self.params.protected
        self._block: _Block | None = None
        self._seed: tuple[Resource, bytes] | None = None
        self._seed_sent = 0  # seed bytes GET_SEED has sent so far
        self._key = b""  # key bytes UNLOCK has brought so far
        self._key_length = 0  # ... of how many
        self._chatter = 0
        self._commands = 0  # commands received since power-on (a busy slave refuses every n-th)
        self.silent_until = 0.0  # time.monotonic() before which the ECU boots and answers nothing
        self.daq.free()
        self.pgm.reset()

    @property
    def available(self) -> Resource:
        """Resources the current mode offers: boot has only programming, the application all of them."""
        if self.target.application_running or self.pgm.active:
            return Resource.CAL_PAG | Resource.DAQ | Resource.PGM
        return Resource.PGM

    def handle(self, cto: bytes) -> list[bytes]:
        """Process one command; returns the packets to transmit (possibly none, see module doc)."""
        if not cto or (not self.connected and cto[0] != Cmd.CONNECT) or time.monotonic() < self.silent_until:
            return []
        command = cto[0]
        block = self._block
        if block is not None and command != block.next_command:
            self._block = None  # any other command ends an unfinished block
        try:
            rejected = self.faults.on_command(command)
            if rejected is not None:
                raise XcpNegative(rejected)
            if self._busy_now(command, cto):
                raise XcpNegative(Err.CMD_BUSY)
            handler = self._handlers.get(command)
            if handler is None:
                raise XcpNegative(Err.CMD_UNKNOWN)
            self._check_resource(command)
            response = handler(bytes(cto))
        except XcpNegative as refusal:
            if command in (Cmd.DOWNLOAD_NEXT, Cmd.PROGRAM_NEXT):
                self._block = None
            return [refusal.packet()]
        except PowerLost:
            return []
        except Exception:  # a slave bug must not kill the bus thread; tests watch this log
            log.exception("XCP slave failed on %s", cto.hex(" "))
            return [XcpNegative(Err.GENERIC).packet()]
        if response is None:
            return []
        packets = response if isinstance(response, list) else [bytes([PID_RES]) + response]
        return self._service_packets() + packets

    def _busy_now(self, command: int, cto: bytes) -> bool:
        """A busy slave (:attr:`XcpParameters.busy_every`) refuses every n-th command with ERR_CMD_BUSY before it runs
        it (the first frame of a master block too: its other frames then find no block, ERR_SEQUENCE): the master
        waits T7 and sends it again. CONNECT, SYNCH and the _NEXT frames are always served."""
        every = self.params.busy_every
        if not every or command in (Cmd.CONNECT, Cmd.SYNCH, Cmd.DOWNLOAD_NEXT, Cmd.PROGRAM_NEXT):
            return False
        self._commands += 1
        return self._commands % every == 0

    def _service_packets(self) -> list[bytes]:
        """What a chatty slave sends before a response: an EV_USER or a SERV_TEXT, in turns."""
        if not self.params.service_packets:
            return []
        self._chatter += 1
        if self._chatter % 2:
            return [bytes([PID_EV, EV_USER, self._chatter & 0xFF])]
        return [bytes([PID_SERV, SERV_TEXT]) + f"n{self._chatter}".encode()[: self.params.max_cto - 3] + b"\0"]

    # --- packing in the slave's byte order -------------------------------------------------------

    def pack(self, fmt: str, *values) -> bytes:
        return struct.pack(self.order + fmt, *values)

    def unpack_from(self, fmt: str, buffer: bytes, offset: int = 0) -> tuple:
        return struct.unpack_from(self.order + fmt, buffer, offset)

    def elements(self, count: int) -> int:
        """Bytes in ``count`` elements of the address granularity."""
        return count * self.granularity

    def require_aligned(self, address: int) -> None:
        """Transfers start on an element: a misaligned address (or MTA) is ERR_OUT_OF_RANGE."""
        if address % self.granularity:
            raise XcpNegative(Err.OUT_OF_RANGE)

    def _check_resource(self, command: int) -> None:
        resource = (
            Resource.CAL_PAG if command in CAL_PAG_COMMANDS
            else Resource.DAQ if command in DAQ_COMMANDS
            else Resource.PGM if command in PGM_COMMANDS
            else None
        )
        if resource is None:
            return
        if not resource & self.available:
            raise XcpNegative(Err.CMD_UNKNOWN)
        if self.pgm.active and resource != Resource.PGM:
            raise XcpNegative(Err.PGM_ACTIVE)
        if resource & self.locked:
            raise XcpNegative(Err.ACCESS_LOCKED)

    # --- memory seen by XCP (page switching, write rules) ----------------------------------

    def read(self, address: int, size: int) -> bytes:
        if address >= FILE_SPACE:  # the file GET_ID named; its last element filled with NULs
            offset = address - FILE_SPACE
            if offset >= len(self._file):
                raise XcpNegative(Err.OUT_OF_RANGE)
            return self._file[offset:offset + size].ljust(size, b"\0")
        try:
            pages = self.target.pages
            return self.target.memory.read(pages.translate(address, size, pages.xcp_pages), size)
        except MemoryAccessError as exc:
            raise memory_error(exc) from None

    def check_writable(self, address: int, size: int) -> None:
        """Refuse writes outside RAM and the application's ``.cal_ram`` (and any write to page 1)."""
        target = self.target
        try:
            target.memory.area_at(address, size)
            physical = target.pages.translate(address, size, target.pages.xcp_pages)
        except MemoryAccessError as exc:
            raise memory_error(exc) from None
        if target.pages.in_window(address):
            if physical != address or not target.layout.xcp_writable_cal(address, size):
                raise XcpNegative(Err.WRITE_PROTECTED)
        elif not (target.memory_map.ram.start <= address and address + size <= target.memory_map.ram.end):
            raise XcpNegative(Err.WRITE_PROTECTED)

    def write(self, address: int, data: bytes) -> None:
        self.check_writable(address, len(data))
        self.target.memory.write(address, data)

    def require_mta_in(self, size: int) -> None:
        if self.mta + size > 0xFFFFFFFF + 1:
            raise XcpNegative(Err.OUT_OF_RANGE)

    # --- block transfers (DOWNLOAD/PROGRAM and their _NEXT) ---------------------------------

    def start_block(self, req: bytes, next_command: Cmd, writer: Writer, per_frame: int, max_block: int
                    ) -> bytes | None:
        """The first frame of a DOWNLOAD/PROGRAM: ``req[1]`` elements in all, the frame's share (``per_frame`` bytes
        at most) from :attr:`XcpParameters.data_offset`; more than one frame holds only in master block mode, and
        ``max_block`` bytes at most."""
        need(req, 2)
        size = self.elements(req[1])
        offset = self.params.data_offset
        if size == 0 or size > max_block:
            raise XcpNegative(Err.OUT_OF_RANGE)
        self.require_aligned(self.mta)
        first = min(size, per_frame)
        need(req, offset + first)
        self.require_mta_in(size)
        writer.check(self.mta, size)
        self._write_chunk(writer, req[offset : offset + first])
        if size > first:
            self._block = _Block(next_command, size - first, writer, per_frame)
            return None
        return b""

    def continue_block(self, req: bytes, next_command: Cmd) -> bytes | None:
        need(req, 2)
        block = self._block
        if block is None or block.next_command != next_command:
            raise XcpNegative(Err.SEQUENCE)
        remaining = block.remaining // self.granularity
        if req[1] != remaining:
            self._block = None
            raise XcpNegative(Err.SEQUENCE, bytes([remaining]))
        chunk, offset = min(block.remaining, block.per_frame), self.params.data_offset
        need(req, offset + chunk)
        self._write_chunk(block.writer, req[offset : offset + chunk])
        block.remaining -= chunk
        if block.remaining:
            return None
        self._block = None
        return b""

    def _write_chunk(self, writer: Writer, data: bytes) -> None:
        writer.write(self.mta, data)
        self.mta += len(data)

    # --- standard commands -----------------------------------------------------------------

    def _connect(self, req: bytes) -> bytes:
        if not self.connected:
            self.daq.free()
            self.locked = self.params.protected
        self.connected = True
        optional = COMM_MODE_OPTIONAL if Cmd.GET_COMM_MODE_INFO in self._handlers else 0
        comm_mode = (optional | (COMM_MODE_SLAVE_BLOCK if self.params.slave_block_mode else 0)
                     | _GRANULARITY_CODES[self.granularity] << 1 | (self.order == ">"))
        return self.pack("BBBHBB", int(self.available), comm_mode, self.params.max_cto, self.params.max_dto,
                         PROTOCOL_LAYER_VERSION, TRANSPORT_LAYER_VERSION)

    def disconnect(self) -> None:
        """End the session as DISCONNECT does (also when the transport loses the master): DAQ stops and is freed."""
        self.daq.free()
        self.connected = False
        self._seed, self._key = None, b""

    def _disconnect(self, req: bytes) -> bytes:
        self.disconnect()
        return b""

    def _get_status(self, req: bytes) -> bytes:
        session = SESSION_DAQ_RUNNING if self.daq.running else 0
        return self.pack("BBBH", session, int(self.locked & self.available), 0, 0)

    def _synch(self, req: bytes) -> bytes:
        self._block = None
        raise XcpNegative(Err.CMD_SYNCH)

    def _get_comm_mode_info(self, req: bytes) -> bytes:
        optional = COMM_MODE_MASTER_BLOCK if self.params.master_block_mode else 0
        return bytes([0, optional, 0, self.params.max_bs, self.params.min_st_100us, 0, TRANSPORT_LAYER_VERSION])

    def _get_id(self, req: bytes) -> bytes:
        need(req, 2)
        if req[1] == IdType.EPK:
            address, length = self.params.epk_address, self.params.epk_length
        elif req[1] in self.files:
            self._file = self.files[req[1]]
            address, length = FILE_SPACE, len(self._file)
        elif f"id:{req[1]}" in self.info.index:
            address, length = self.info.index[f"id:{req[1]}"]
        else:
            raise XcpNegative(Err.OUT_OF_RANGE)
        self.mta = address
        return self.pack("BBBI", 0, 0, 0, length)  # mode 0: upload the text (length in bytes) from the MTA

    def _get_seed(self, req: bytes) -> bytes:
        """Mode 0 starts a seed, mode 1 asks for the part that did not fit: each response carries the length
        still to come and as much of it as fits (MAX_CTO - 2 bytes)."""
        need(req, 3)
        mode, resource = req[1], req[2]
        if mode == 1:
            if self._seed is None or self._seed_sent == 0:
                raise XcpNegative(Err.SEQUENCE)
        elif mode != 0 or resource not in (Resource.CAL_PAG, Resource.DAQ, Resource.PGM):
            raise XcpNegative(Err.OUT_OF_RANGE)
        elif not resource & self.available:
            raise XcpNegative(Err.OUT_OF_RANGE)
        elif not resource & self.locked:
            self._seed = None
            return bytes([0])  # already unlocked: seed length 0
        else:
            seed = bytes(self._rng.getrandbits(8) for _ in range(self.params.seed_length))
            self._seed, self._seed_sent, self._key = (Resource(resource), seed), 0, b""
        seed = self._seed[1]
        part = seed[self._seed_sent : self._seed_sent + self.params.max_cto - 2]
        remaining = len(seed) - self._seed_sent
        self._seed_sent += len(part)
        return bytes([remaining]) + part

    def _unlock(self, req: bytes) -> bytes:
        """The key in one or more UNLOCKs, each naming the key bytes still to come (its own included)."""
        need(req, 2)
        if self._seed is None or self._seed_sent < len(self._seed[1]):
            raise XcpNegative(Err.SEQUENCE)
        resource, seed = self._seed
        remaining = req[1]
        part = req[2 : 2 + min(remaining, self.params.max_cto - 2)]
        if remaining == 0 or len(part) < min(remaining, self.params.max_cto - 2) or (
                self._key and remaining != self._key_length - len(self._key)):
            self._seed, self._key = None, b""
            raise XcpNegative(Err.SEQUENCE if remaining else Err.CMD_SYNTAX)
        if not self._key:
            self._key_length = remaining
        self._key += part
        if len(self._key) < self._key_length:
            return bytes([int(self.locked & self.available)])  # more parts to come
        key, self._seed, self._key = self._key, None, b""
        if key != seedkey.compute_key(seed, resource):
            self.daq.free()
            self.connected = False  # a wrong key ends the session (ASAM XCP: ERR_ACCESS_LOCKED, disconnect)
            raise XcpNegative(Err.ACCESS_LOCKED)
        self.locked &= ~resource
        return bytes([int(self.locked & self.available)])

    def _set_mta(self, req: bytes) -> bytes:
        need(req, 8)
        if req[3] != 0:
            raise XcpNegative(Err.OUT_OF_RANGE)
        self.mta = self.unpack_from("I", req, 4)[0]
        return b""

    def _responses(self, data: bytes) -> list[bytes]:
        """``data`` in UPLOAD responses: the PID, alignment bytes up to an element, then whole elements."""
        per_response, pad = self.params.max_data_per_response, bytes([PID_RES]) + bytes(self.granularity - 1)
        return [pad + data[i : i + per_response] for i in range(0, len(data), per_response)]

    def _upload(self, req: bytes) -> list[bytes]:
        need(req, 2)
        size = self.elements(req[1])
        limit = self.elements(MAX_UPLOAD) if self.params.slave_block_mode else self.params.max_data_per_response
        if size == 0 or size > limit:
            raise XcpNegative(Err.OUT_OF_RANGE)
        self.require_aligned(self.mta)
        self.require_mta_in(size)
        data = self.read(self.mta, size)
        self.mta += size
        return self._responses(data)

    def _short_upload(self, req: bytes) -> list[bytes]:
        need(req, 8)
        size = self.elements(req[1])
        address = self.unpack_from("I", req, 4)[0]
        if size == 0 or size > self.params.max_data_per_response or req[3] != 0:
            raise XcpNegative(Err.OUT_OF_RANGE)
        self.require_aligned(address)
        data = self.read(address, size)
        self.mta = address + size
        return self._responses(data)

    def _build_checksum(self, req: bytes) -> bytes:
        need(req, 8)
        size = self.elements(self.unpack_from("I", req, 4)[0])
        kind: ChecksumType = self.params.checksum_type
        if size == 0 or size % kind.element_size:
            raise XcpNegative(Err.OUT_OF_RANGE)
        if size > self.params.max_checksum_block:
            limit = self.params.max_checksum_block // self.granularity
            raise XcpNegative(Err.OUT_OF_RANGE, self.pack("BBI", 0, 0, limit))
        self.require_aligned(self.mta)
        self.require_mta_in(size)
        value = checksum(self.read(self.mta, size), kind, self.order == "<")  # words as its CPU (BYTE_ORDER) reads them
        self.mta += size
        return self.pack("BBBI", int(kind), 0, 0, value)

    def _download_writer(self) -> Writer:
        return Writer(self.check_writable, self.write)

    def _download(self, req: bytes) -> bytes | None:
        return self.start_block(req, Cmd.DOWNLOAD_NEXT, self._download_writer(), self.params.max_data_per_frame,
                                self.params.max_block_bytes)

    def _download_next(self, req: bytes) -> bytes | None:
        return self.continue_block(req, Cmd.DOWNLOAD_NEXT)

    def max_frame_data(self, req: bytes, max_cto: int) -> bytes:
        """The data of a DOWNLOAD_MAX/PROGRAM_MAX (a frame of ``max_cto`` bytes): whole elements after the command and
        its alignment bytes, at the (aligned) MTA."""
        ag = self.granularity
        size = (max_cto - ag) // ag * ag  # the same layout as an UPLOAD response
        need(req, self.granularity + size)
        self.require_aligned(self.mta)
        self.require_mta_in(size)
        return req[self.granularity : self.granularity + size]

    def _download_max(self, req: bytes) -> bytes:
        data = self.max_frame_data(req, self.params.max_cto)
        self.write(self.mta, data)
        self.mta += len(data)
        return b""

    def _short_download(self, req: bytes) -> bytes:
        need(req, 8)
        size = self.elements(req[1])
        if req[3] != 0 or 8 + size > self.params.max_cto:  # on classic CAN no data byte fits
            raise XcpNegative(Err.OUT_OF_RANGE)
        address = self.unpack_from("I", req, 4)[0]
        self.require_aligned(address)
        need(req, 8 + size)
        self.write(address, req[8 : 8 + size])
        self.mta = address + size
        return b""

