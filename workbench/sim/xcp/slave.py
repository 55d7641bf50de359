"""The XCP slave: session, dispatch, resource protection and the standard commands.

:meth:`XcpSlave.handle` takes one CTO (the payload of a CAN frame to CAN_ID_MASTER) and
returns the packets to send back: one response, several (an UPLOAD in slave block mode),
or none — the documented silences:

* every command but CONNECT while not connected (XCP: a disconnected slave stays silent);
* an empty frame;
* a DOWNLOAD/PROGRAM(_NEXT) frame inside a master block that is not the block's last;
* while the ECU has no power (also right after an injected power loss).

Everything else gets a positive (``FF …``) or negative (``FE code …``) response; a
handler never raises anything but :class:`XcpNegative`. Multi-byte parameters are
Intel (little-endian), as BYTE_ORDER_MSB_LAST in the A2L says.
"""

from __future__ import annotations

import logging
import random
import struct
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

from workbench.image import ChecksumType, checksum
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

log = logging.getLogger(__name__)

PROTOCOL_LAYER_VERSION = 1
TRANSPORT_LAYER_VERSION = 1
COMM_MODE_OPTIONAL = 0x80
COMM_MODE_SLAVE_BLOCK = 0x40
COMM_MODE_MASTER_BLOCK = 0x01
MAX_UPLOAD = 255  # elements of one UPLOAD in slave block mode
SESSION_DAQ_RUNNING = 0x40


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


# Commands by the resource that protects them; a resource the current mode lacks answers CMD_UNKNOWN.
CAL_PAG_COMMANDS = frozenset({
    Cmd.DOWNLOAD, Cmd.DOWNLOAD_NEXT, Cmd.DOWNLOAD_MAX, Cmd.SHORT_DOWNLOAD, Cmd.SET_CAL_PAGE,
    Cmd.GET_CAL_PAGE, Cmd.GET_PAG_PROCESSOR_INFO, Cmd.GET_SEGMENT_INFO, Cmd.COPY_CAL_PAGE,
})
DAQ_COMMANDS = frozenset({
    Cmd.SET_DAQ_PTR, Cmd.WRITE_DAQ, Cmd.SET_DAQ_LIST_MODE, Cmd.START_STOP_DAQ_LIST, Cmd.START_STOP_SYNCH,
    Cmd.GET_DAQ_CLOCK, Cmd.GET_DAQ_PROCESSOR_INFO, Cmd.GET_DAQ_RESOLUTION_INFO, Cmd.GET_DAQ_EVENT_INFO,
    Cmd.FREE_DAQ, Cmd.ALLOC_DAQ, Cmd.ALLOC_ODT, Cmd.ALLOC_ODT_ENTRY, Cmd.GET_DAQ_LIST_INFO, Cmd.CLEAR_DAQ_LIST,
})
PGM_COMMANDS = frozenset({
    Cmd.PROGRAM_START, Cmd.PROGRAM_CLEAR, Cmd.PROGRAM, Cmd.PROGRAM_RESET, Cmd.GET_PGM_PROCESSOR_INFO,
    Cmd.GET_SECTOR_INFO, Cmd.PROGRAM_NEXT, Cmd.PROGRAM_MAX,
})


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
        self.info = info
        self.faults = faults or FaultPlan()
        self._rng = rng or random.Random()
        self.calpage = CalPageCommands(self)
        self.daq = DaqProcessor(self)
        self.pgm = ProgrammingCommands(self)
        self._handlers: dict[int, Callable[[bytes], bytes | None]] = {
            Cmd.CONNECT: self._connect,
            Cmd.DISCONNECT: self._disconnect,
            Cmd.GET_STATUS: self._get_status,
            Cmd.SYNCH: self._synch,
            Cmd.GET_COMM_MODE_INFO: self._get_comm_mode_info,
            Cmd.GET_ID: self._get_id,
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
        self.reset()

    # --- session -------------------------------------------------------------------------

    def reset(self) -> None:
        """Back to the state after power-on: disconnected, everything locked, no DAQ, no block."""
        self.connected = False
        self.mta = 0
        self.locked = self.params.protected
        self._block: _Block | None = None
        self._seed: tuple[Resource, bytes] | None = None
        self.daq.free()
        self.pgm.active = False

    @property
    def available(self) -> Resource:
        """Resources the current mode offers: boot has only programming, the application all of them."""
        if self.target.application_running or self.pgm.active:
            return Resource.CAL_PAG | Resource.DAQ | Resource.PGM
        return Resource.PGM

    def handle(self, cto: bytes) -> list[bytes]:
        """Process one command; returns the packets to transmit (possibly none, see module doc)."""
        if not cto or (not self.connected and cto[0] != Cmd.CONNECT):
            return []
        command = cto[0]
        block = self._block
        if block is not None and command != block.next_command:
            self._block = None  # any other command ends an unfinished block
        try:
            rejected = self.faults.on_command(command)
            if rejected is not None:
                raise XcpNegative(rejected)
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
        if isinstance(response, list):
            return response
        return [bytes([PID_RES]) + response]

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
        try:
            return self.target.memory.read(self.target.pages.translate(address, size, self.target.pages.xcp_page), size)
        except MemoryAccessError as exc:
            raise memory_error(exc) from None

    def check_writable(self, address: int, size: int) -> None:
        """Refuse writes outside RAM and the application's ``.cal_ram`` (and any write to page 1)."""
        target = self.target
        try:
            target.memory.area_at(address, size)
            physical = target.pages.translate(address, size, target.pages.xcp_page)
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

    def start_block(self, req: bytes, next_command: Cmd, writer: Writer) -> bytes | None:
        need(req, 2)
        count = req[1]
        per_frame = self.params.max_data_per_frame
        if count == 0 or count > self.params.max_block_bytes:
            raise XcpNegative(Err.OUT_OF_RANGE)
        first = min(count, per_frame)
        need(req, 2 + first)
        self.require_mta_in(count)
        writer.check(self.mta, count)
        self._write_chunk(writer, req[2 : 2 + first])
        if count > first:
            self._block = _Block(next_command, count - first, writer)
            return None
        return b""

    def continue_block(self, req: bytes, next_command: Cmd) -> bytes | None:
        need(req, 2)
        block = self._block
        if block is None or block.next_command != next_command:
            raise XcpNegative(Err.SEQUENCE)
        if req[1] != block.remaining:
            self._block = None
            raise XcpNegative(Err.SEQUENCE, bytes([block.remaining]))
        chunk = min(block.remaining, self.params.max_data_per_frame)
        need(req, 2 + chunk)
        self._write_chunk(block.writer, req[2 : 2 + chunk])
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
        comm_mode = COMM_MODE_OPTIONAL | COMM_MODE_SLAVE_BLOCK  # byte order Intel, granularity BYTE
        return struct.pack(
            "<BBBHBB", int(self.available), comm_mode, self.params.max_cto, self.params.max_dto,
            PROTOCOL_LAYER_VERSION, TRANSPORT_LAYER_VERSION,
        )

    def disconnect(self) -> None:
        """End the session as DISCONNECT does (also when the transport loses the master): DAQ stops and is freed."""
        self.daq.free()
        self.connected = False
        self._seed = None

    def _disconnect(self, req: bytes) -> bytes:
        self.disconnect()
        return b""

    def _get_status(self, req: bytes) -> bytes:
        session = SESSION_DAQ_RUNNING if self.daq.running else 0
        return struct.pack("<BBBH", session, int(self.locked & self.available), 0, 0)

    def _synch(self, req: bytes) -> bytes:
        self._block = None
        raise XcpNegative(Err.CMD_SYNCH)

    def _get_comm_mode_info(self, req: bytes) -> bytes:
        return struct.pack(
            "<BBBBBBB", 0, COMM_MODE_MASTER_BLOCK, 0, self.params.max_bs, self.params.min_st_100us, 0,
            TRANSPORT_LAYER_VERSION,
        )

    def _get_id(self, req: bytes) -> bytes:
        need(req, 2)
        if req[1] == IdType.EPK:
            address, length = self.params.epk_address, self.params.epk_length
        elif f"id:{req[1]}" in self.info.index:
            address, length = self.info.index[f"id:{req[1]}"]
        else:
            raise XcpNegative(Err.OUT_OF_RANGE)
        self.mta = address
        return struct.pack("<BBBI", 0, 0, 0, length)  # mode 0: upload the text from the MTA

    def _get_seed(self, req: bytes) -> bytes:
        need(req, 3)
        mode, resource = req[1], req[2]
        if mode == 1:  # remaining part: the whole seed always fits the first response
            if self._seed is None:
                raise XcpNegative(Err.SEQUENCE)
            return bytes([0])
        if mode != 0 or resource not in (Resource.CAL_PAG, Resource.DAQ, Resource.PGM):
            raise XcpNegative(Err.OUT_OF_RANGE)
        if not resource & self.available:
            raise XcpNegative(Err.OUT_OF_RANGE)
        if not resource & self.locked:
            self._seed = None
            return bytes([0])  # already unlocked: seed length 0
        seed = bytes(self._rng.getrandbits(8) for _ in range(seedkey.SEED_LENGTH))
        self._seed = (Resource(resource), seed)
        return bytes([len(seed)]) + seed

    def _unlock(self, req: bytes) -> bytes:
        need(req, 2)
        if self._seed is None:
            raise XcpNegative(Err.SEQUENCE)
        resource, seed = self._seed
        self._seed = None
        length = req[1]
        need(req, 2 + length)
        if req[2 : 2 + length] != seedkey.compute_key(seed, resource):
            self.daq.free()
            self.connected = False  # a wrong key ends the session (ASAM XCP: ERR_ACCESS_LOCKED, disconnect)
            raise XcpNegative(Err.ACCESS_LOCKED)
        self.locked &= ~resource
        return bytes([int(self.locked & self.available)])

    def _set_mta(self, req: bytes) -> bytes:
        need(req, 8)
        if req[3] != 0:
            raise XcpNegative(Err.OUT_OF_RANGE)
        self.mta = struct.unpack_from("<I", req, 4)[0]
        return b""

    def _upload(self, req: bytes) -> list[bytes]:
        need(req, 2)
        count = req[1]
        if count == 0:
            raise XcpNegative(Err.OUT_OF_RANGE)
        self.require_mta_in(count)
        data = self.read(self.mta, count)
        self.mta += count
        per_frame = self.params.max_cto - 1
        return [bytes([PID_RES]) + data[i : i + per_frame] for i in range(0, count, per_frame)]

    def _short_upload(self, req: bytes) -> bytes:
        need(req, 8)
        count = req[1]
        if count == 0 or count > self.params.max_cto - 1 or req[3] != 0:
            raise XcpNegative(Err.OUT_OF_RANGE)
        address = struct.unpack_from("<I", req, 4)[0]
        data = self.read(address, count)
        self.mta = address + count
        return data

    def _build_checksum(self, req: bytes) -> bytes:
        need(req, 8)
        size = struct.unpack_from("<I", req, 4)[0]
        kind: ChecksumType = self.params.checksum_type
        if size == 0 or size % kind.element_size:
            raise XcpNegative(Err.OUT_OF_RANGE)
        if size > self.params.max_checksum_block:
            raise XcpNegative(Err.OUT_OF_RANGE, struct.pack("<BBI", 0, 0, self.params.max_checksum_block))
        self.require_mta_in(size)
        value = checksum(self.read(self.mta, size), kind)
        self.mta += size
        return struct.pack("<BBBI", int(kind), 0, 0, value)

    def _download_writer(self) -> Writer:
        return Writer(self.check_writable, self.write)

    def _download(self, req: bytes) -> bytes | None:
        return self.start_block(req, Cmd.DOWNLOAD_NEXT, self._download_writer())

    def _download_next(self, req: bytes) -> bytes | None:
        return self.continue_block(req, Cmd.DOWNLOAD_NEXT)

    def _download_max(self, req: bytes) -> bytes:
        count = self.params.max_cto - 1
        need(req, 1 + count)
        self.require_mta_in(count)
        self.write(self.mta, req[1 : 1 + count])
        self.mta += count
        return b""

    def _short_download(self, req: bytes) -> bytes:
        need(req, 8)
        count = req[1]
        if req[3] != 0 or 8 + count > self.params.max_cto:  # on classic CAN no data byte fits
            raise XcpNegative(Err.OUT_OF_RANGE)
        address = struct.unpack_from("<I", req, 4)[0]
        self.write(address, req[8 : 8 + count])
        self.mta = address + count
        return b""

