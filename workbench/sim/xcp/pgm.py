"""Flash programming: PROGRAM_START … PROGRAM_RESET with flash semantics and master block mode.

* PROGRAM_START halts the application (the flash driver runs) and is refused while DAQ runs; it
  answers the programming's own MAX_CTO_PGM, master block mode, MAX_BS_PGM and MIN_ST_PGM
  (:attr:`XcpParameters.programming <workbench.sim.xcp.parameters.XcpParameters.programming>`);
* PROGRAM_CLEAR erases whole sectors: in absolute mode from the MTA (a range that does not
  start and end on sector boundaries is ERR_OUT_OF_RANGE), in functional mode the sectors
  whose bit is in the range (0x01 calibration = CALIB, 0x02 code = APPLICATIVE, 0x04 NVRAM = SHARED);
  its answer leaves ``PgmParameters.erase_s`` late (the XCP port holds it back, and what follows);
* PROGRAM/PROGRAM_NEXT/PROGRAM_MAX write only erased bytes inside one sector
  (ERR_OUT_OF_RANGE outside flash, ERR_WRITE_PROTECTED in flash no sector covers (BOOT),
  ERR_ACCESS_DENIED onto written bytes); a block is checked whole at its first frame;
  PROGRAM with size 0 ends a memory segment. A driver that writes flash a page at a time
  (``PgmParameters.page_size``) holds a page's data in RAM until the page is full, data go to
  another page, or a PROGRAM with size 0 comes; what it holds is in no UPLOAD nor checksum, and is
  lost on PROGRAM_START, PROGRAM_CLEAR and resets;
* PROGRAM_RESET answers, then resets the ECU (boot checks the application-valid key), which then
  answers nothing, CONNECT included, for ``PgmParameters.boot_s``.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

from workbench.sim.memory import MemoryAccessError
from workbench.sim.xcp.responses import PowerLost, Writer, XcpNegative, memory_error, need
from workbench.xcp_protocol import Cmd, Err

if TYPE_CHECKING:
    from workbench.sim.xcp.slave import XcpSlave

__all__ = ["ProgrammingCommands"]

COMM_MODE_PGM_MASTER_BLOCK = 0x01
PGM_ABSOLUTE_MODE = 0x01
PGM_FUNCTIONAL_MODE = 0x02
PGM_NON_SEQUENTIAL_SUPPORTED = 0x40
CLEAR_ABSOLUTE = 0x00
CLEAR_FUNCTIONAL = 0x01


class ProgrammingCommands:
    def __init__(self, slave: XcpSlave):
        self.slave = slave
        self.active = False
        self._page: tuple[int, bytearray] | None = None  # a page-at-a-time driver's page in RAM: (start, bytes)

    def reset(self) -> None:
        """Out of programming (power-on, reset): what the driver held in RAM is lost."""
        self.active = False
        self._page = None

    def handlers(self):
        return {
            Cmd.PROGRAM_START: self._program_start,
            Cmd.PROGRAM_CLEAR: self._program_clear,
            Cmd.PROGRAM: self._program,
            Cmd.PROGRAM_NEXT: self._program_next,
            Cmd.PROGRAM_MAX: self._program_max,
            Cmd.PROGRAM_RESET: self._program_reset,
            Cmd.GET_PGM_PROCESSOR_INFO: self._get_pgm_processor_info,
            Cmd.GET_SECTOR_INFO: self._get_sector_info,
        }

    @property
    def _memory(self):
        return self.slave.target.memory

    def _require_active(self) -> None:
        if not self.active:
            raise XcpNegative(Err.SEQUENCE)

    def _frame_arrived(self) -> None:
        """Count a PROGRAM data frame; an injected power loss strikes before it is written."""
        if self.slave.faults.on_program_frame():
            self.slave.target.power_loss()
            raise PowerLost

    def _check(self, address: int, size: int) -> None:
        if self.slave.target.memory_map.protected(address, size):
            raise XcpNegative(Err.WRITE_PROTECTED)
        try:
            self._memory.check_program(address, size)
        except MemoryAccessError as exc:
            raise memory_error(exc) from None

    def _write(self, address: int, data: bytes) -> None:
        self._check(address, len(data))
        size = self.slave.params.pgm.page_size
        if not size:
            self._program_now(address, data)
            return
        while data:
            page = address - address % size
            if self._page is not None and self._page[0] != page:
                self._flush()
            if self._page is None:
                self._page = (page, bytearray(self._memory.read(page, size)))
            count = min(len(data), page + size - address)
            self._page[1][address - page:address - page + count] = data[:count]
            address, data = address + count, data[count:]
            if address == page + size:
                self._flush()

    def _flush(self) -> None:
        """Program the page the driver holds: the bytes that differ from flash."""
        if self._page is None:
            return
        page, held = self._page
        self._page = None
        flash = self._memory.read(page, len(held))
        changed = [i for i in range(len(held)) if held[i] != flash[i]]
        for first, last in _runs(changed):
            self._program_now(page + first, bytes(held[first:last + 1]))

    def _program_now(self, address: int, data: bytes) -> None:
        try:
            self._memory.program(address, data)
        except MemoryAccessError as exc:
            raise memory_error(exc) from None

    def _program_start(self, req: bytes) -> bytes:
        if self.slave.daq.running:
            raise XcpNegative(Err.DAQ_ACTIVE)
        self.active = True
        self._page = None
        self.slave.target.halt_application()
        pgm = self.slave.params.programming
        comm_mode = COMM_MODE_PGM_MASTER_BLOCK if pgm.master_block_mode else 0
        return bytes([0, comm_mode, pgm.max_cto, pgm.max_bs, pgm.min_st_100us, 0])

    def _program_clear(self, req: bytes) -> bytes:
        need(req, 8)
        self._require_active()
        mode, clear_range = req[1], self.slave.unpack_from("I", req, 4)[0]
        memory_map = self.slave.target.memory_map
        if mode == CLEAR_ABSOLUTE and self.slave.params.pgm.functional_only:
            raise XcpNegative(Err.MODE_NOT_VALID)
        if mode == CLEAR_ABSOLUTE:
            ranges = [(self.slave.mta, self.slave.elements(clear_range))]
        elif mode == CLEAR_FUNCTIONAL:
            chosen = [s for s in memory_map.sectors if s.functional_bit & clear_range]
            if not chosen or clear_range & ~sum(s.functional_bit for s in memory_map.sectors):
                raise XcpNegative(Err.OUT_OF_RANGE)
            ranges = [(s.range.start, s.range.size) for s in chosen]
        else:
            raise XcpNegative(Err.MODE_NOT_VALID)
        self._page = None
        for address, size in ranges:
            if memory_map.protected(address, size):
                raise XcpNegative(Err.WRITE_PROTECTED)
            try:
                self._memory.erase(address, size)
            except MemoryAccessError as exc:
                raise memory_error(exc) from None
        return b""

    def _program(self, req: bytes) -> bytes | None:
        need(req, 2)
        self._require_active()
        if req[1] == 0:  # the end of a memory segment
            self._flush()
            return b""
        self._frame_arrived()
        params = self.slave.params
        return self.slave.start_block(req, Cmd.PROGRAM_NEXT, Writer(self._check, self._write),
                                      params.pgm_data_per_frame, params.pgm_block_bytes)

    def _program_next(self, req: bytes) -> bytes | None:
        self._require_active()
        self._frame_arrived()
        return self.slave.continue_block(req, Cmd.PROGRAM_NEXT)

    def _program_max(self, req: bytes) -> bytes:
        self._require_active()
        data = self.slave.max_frame_data(req, self.slave.params.programming.max_cto)
        self._frame_arrived()
        self._write(self.slave.mta, data)
        self.slave.mta += len(data)
        return b""

    def _program_reset(self, req: bytes) -> bytes:
        self.slave.target.reset()
        self.slave.silent_until = time.monotonic() + self.slave.params.pgm.boot_s
        return b""

    def _get_pgm_processor_info(self, req: bytes) -> bytes:
        pgm = self.slave.params.pgm
        modes = PGM_FUNCTIONAL_MODE if pgm.functional_only else PGM_ABSOLUTE_MODE | PGM_FUNCTIONAL_MODE
        return bytes([modes | PGM_NON_SEQUENTIAL_SUPPORTED, len(self._sectors)])

    @property
    def _sectors(self):
        """The sectors GET_SECTOR_INFO tells (none from a slave that does not count them)."""
        return self.slave.target.memory_map.sectors if self.slave.params.pgm.counts_sectors else ()

    def _get_sector_info(self, req: bytes) -> bytes:
        need(req, 3)
        mode, number = req[1], req[2]
        sectors = self._sectors
        if number >= len(sectors):
            raise XcpNegative(Err.OUT_OF_RANGE)
        sector = sectors[number]
        if mode == 2:
            address, length = self.slave.info.index[f"sector:{number}"]
            self.slave.mta = address
            return bytes([length])
        if mode > 1:
            raise XcpNegative(Err.MODE_NOT_VALID)
        value = sector.range.start if mode == 0 else sector.range.size
        return self.slave.pack("BBBI", sector.clear_sequence, sector.program_sequence, 0, value)


def _runs(indices: list[int]) -> list[tuple[int, int]]:
    """Ascending ``indices`` as (first, last) of each run of consecutive ones."""
    runs: list[tuple[int, int]] = []
    for i in indices:
        if runs and runs[-1][1] == i - 1:
            runs[-1] = (runs[-1][0], i)
        else:
            runs.append((i, i))
    return runs
