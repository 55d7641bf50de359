"""Calibration page commands: the CAL RAM segments (one on the demo), page 0 working (RAM), page 1 reference (ROM).

GET_SEGMENT_INFO mode 2 reports the A2L's ADDRESS_MAPPING of a segment: source = its CAL RAM address,
destination = the CAL ROM address that mirrors it, length = its size. SET_CAL_PAGE's mode bit 0x80
switches every segment at once, unless the slave lacks it (:attr:`XcpParameters.all_segments_mode`
false: ERR_MODE_NOT_VALID, the master switches segment by segment).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.sim.paging import PAGES, REFERENCE_PAGE
from workbench.sim.xcp.responses import XcpNegative, need
from workbench.xcp_protocol import Cmd, Err

if TYPE_CHECKING:
    from workbench.sim.xcp.slave import XcpSlave

__all__ = ["CalPageCommands"]

MODE_ECU = 0x01
MODE_XCP = 0x02
MODE_ALL = 0x80
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

    def _segment(self, number: int, error: Err = Err.SEGMENT_NOT_VALID):
        segments = self._pages.segments
        if number >= len(segments):
            raise XcpNegative(error)
        return segments[number]

    def _get_pag_processor_info(self, req: bytes) -> bytes:
        return bytes([len(self._pages.segments), 0])  # no FREEZE support

    def _get_segment_info(self, req: bytes) -> bytes:
        need(req, 4)
        mode, number, info = req[1], req[2], req[3]
        mapping_index = req[4] if len(req) > 4 else 0
        segment = self._segment(number, Err.OUT_OF_RANGE)
        if mode == 0:
            values = {0: segment.start, 1: segment.size}
        elif mode == 1:
            return bytes([len(PAGES), 0, MAX_MAPPING, 0, 0])
        elif mode == 2:
            if mapping_index >= MAX_MAPPING:
                raise XcpNegative(Err.OUT_OF_RANGE)
            values = {0: segment.start, 1: self.slave.target.memory_map.rom_address(segment.start), 2: segment.size}
        else:
            raise XcpNegative(Err.MODE_NOT_VALID)
        if info not in values:
            raise XcpNegative(Err.OUT_OF_RANGE)
        return self.slave.pack("BBBI", 0, 0, 0, values[info])

    def _get_cal_page(self, req: bytes) -> bytes:
        need(req, 3)
        mode, number = req[1], req[2]
        self._segment(number)
        if mode == MODE_ECU:
            page = self._pages.ecu_pages[number]
        elif mode == MODE_XCP:
            page = self._pages.xcp_pages[number]
        else:
            raise XcpNegative(Err.MODE_NOT_VALID)
        return bytes([0, 0, page])

    def _set_cal_page(self, req: bytes) -> bytes:
        need(req, 4)
        mode, number, page = req[1], req[2], req[3]
        if not mode & (MODE_ECU | MODE_XCP) or mode & ~(MODE_ECU | MODE_XCP | MODE_ALL):
            raise XcpNegative(Err.MODE_NOT_VALID)
        if mode & MODE_ALL and not self.slave.params.all_segments_mode:
            raise XcpNegative(Err.MODE_NOT_VALID)
        if not mode & MODE_ALL:
            self._segment(number)
        if page not in PAGES:
            raise XcpNegative(Err.PAGE_NOT_VALID)
        numbers = range(len(self._pages.segments)) if mode & MODE_ALL else (number,)
        for n in numbers:
            if mode & MODE_ECU:
                self._pages.ecu_pages[n] = page
            if mode & MODE_XCP:
                self._pages.xcp_pages[n] = page
        return b""

    def _copy_cal_page(self, req: bytes) -> bytes:
        need(req, 5)
        src_segment, src_page, dst_segment, dst_page = req[1:5]
        source, destination = self._segment(src_segment), self._segment(dst_segment)
        if src_page not in PAGES or dst_page not in PAGES:
            raise XcpNegative(Err.PAGE_NOT_VALID)
        if src_segment != dst_segment:
            raise XcpNegative(Err.SEGMENT_NOT_VALID)  # pages of one segment only: segments differ in size
        if src_page == dst_page:
            return b""
        if dst_page == REFERENCE_PAGE:
            raise XcpNegative(Err.WRITE_PROTECTED)  # the reference page is flash
        target = self.slave.target  # reference -> working: the segment's CAL ROM over its CAL RAM
        rom = target.memory.read(target.memory_map.rom_address(source.start), source.size)
        target.memory.write(destination.start, rom)
        return b""
