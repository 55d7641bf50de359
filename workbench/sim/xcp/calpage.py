"""Calibration page commands: one segment (CAL RAM), page 0 working (RAM), page 1 reference (ROM).

GET_SEGMENT_INFO mode 2 reports the A2L's ADDRESS_MAPPING: source = the CAL RAM address,
destination = the CAL ROM address, length = the segment size.
"""

from __future__ import annotations

import struct
from typing import TYPE_CHECKING

from workbench.sim.paging import PAGES, REFERENCE_PAGE
from workbench.sim.xcp.responses import XcpNegative, need
from workbench.xcp_protocol import Cmd, Err

if TYPE_CHECKING:
    from workbench.sim.xcp.slave import XcpSlave

MODE_ECU = 0x01
MODE_XCP = 0x02
MODE_ALL = 0x80
MAX_SEGMENTS = 1
MAX_MAPPING = 1


class CalPageCommands:
    def __init__(self, slave: XcpSlave):
        self.slave = slave

    def handlers(self):
        return {
            Cmd.GET_PAG_PROCESSOR_INFO: self._get_pag_processor_info,
            Cmd.GET_SEGMENT_INFO: self._get_segment_info,
            Cmd.GET_CAL_PAGE: self._get_cal_page,
            Cmd.SET_CAL_PAGE: self._set_cal_page,
            Cmd.COPY_CAL_PAGE: self._copy_cal_page,
        }

    @property
    def _pages(self):
        return self.slave.target.pages

    def _get_pag_processor_info(self, req: bytes) -> bytes:
        return bytes([MAX_SEGMENTS, 0])  # no FREEZE support

    def _get_segment_info(self, req: bytes) -> bytes:
        need(req, 4)
        mode, segment, info = req[1], req[2], req[3]
        mapping_index = req[4] if len(req) > 4 else 0
        if segment >= MAX_SEGMENTS:
            raise XcpNegative(Err.OUT_OF_RANGE)
        memory_map = self.slave.target.memory_map
        if mode == 0:
            values = {0: memory_map.cal_ram.start, 1: memory_map.cal_ram.size}
        elif mode == 1:
            return bytes([len(PAGES), 0, MAX_MAPPING, 0, 0])
        elif mode == 2:
            if mapping_index >= MAX_MAPPING:
                raise XcpNegative(Err.OUT_OF_RANGE)
            values = {0: memory_map.cal_ram.start, 1: memory_map.cal_rom_start, 2: memory_map.cal_ram.size}
        else:
            raise XcpNegative(Err.MODE_NOT_VALID)
        if info not in values:
            raise XcpNegative(Err.OUT_OF_RANGE)
        return struct.pack("<BBBI", 0, 0, 0, values[info])

    def _get_cal_page(self, req: bytes) -> bytes:
        need(req, 3)
        mode, segment = req[1], req[2]
        if segment >= MAX_SEGMENTS:
            raise XcpNegative(Err.SEGMENT_NOT_VALID)
        if mode == MODE_ECU:
            page = self._pages.ecu_page
        elif mode == MODE_XCP:
            page = self._pages.xcp_page
        else:
            raise XcpNegative(Err.MODE_NOT_VALID)
        return bytes([0, 0, page])

    def _set_cal_page(self, req: bytes) -> bytes:
        need(req, 4)
        mode, segment, page = req[1], req[2], req[3]
        if not mode & (MODE_ECU | MODE_XCP) or mode & ~(MODE_ECU | MODE_XCP | MODE_ALL):
            raise XcpNegative(Err.MODE_NOT_VALID)
        if not mode & MODE_ALL and segment >= MAX_SEGMENTS:
            raise XcpNegative(Err.SEGMENT_NOT_VALID)
        if page not in PAGES:
            raise XcpNegative(Err.PAGE_NOT_VALID)
        if mode & MODE_ECU:
            self._pages.ecu_page = page
        if mode & MODE_XCP:
            self._pages.xcp_page = page
        return b""

    def _copy_cal_page(self, req: bytes) -> bytes:
        need(req, 5)
        src_segment, src_page, dst_segment, dst_page = req[1:5]
        if src_segment >= MAX_SEGMENTS or dst_segment >= MAX_SEGMENTS:
            raise XcpNegative(Err.SEGMENT_NOT_VALID)
        if src_page not in PAGES or dst_page not in PAGES:
            raise XcpNegative(Err.PAGE_NOT_VALID)
        if src_page == dst_page:
            return b""
        if dst_page == REFERENCE_PAGE:
            raise XcpNegative(Err.WRITE_PROTECTED)  # the reference page is flash
        target = self.slave.target  # reference -> working: CAL ROM over CAL RAM
        memory_map = target.memory_map
        rom = target.memory.read(memory_map.cal_rom_start, memory_map.cal_ram.size)
        target.memory.write(memory_map.cal_ram.start, rom)
        return b""
