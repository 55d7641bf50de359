"""The master session: one ECU, one A2L, measured and calibrated by name.

::

    from workbench import Session
    with Session.open("out/FLCU.a2l", interface="udp_multicast", channel="239.74.163.2") as ecu:
        print(ecu.read("zsRailPressure"))      # physical value
        ecu.write("xsSWITCH_TANK_THR", 25.0)    # limits checked, written, read back

:meth:`Session.open` reads the A2L, opens the link its IF_DATA describes (or the one the caller
names), connects, and checks the EPK. Every public method takes the session's lock, so a GUI
may poll from one thread while a DAQ measurement runs in another; closing stops what runs and
frees the bus, also after an error.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from workbench import demo
from workbench.a2l import A2lDocument, read_xcp_config
from workbench.a2l.includes import load_a2l_to_work
from workbench.a2l.xcp import XcpConfig, XcpPage, XcpSegment
from workbench.bus_defaults import BusSpec
from workbench.errors import (
    ConnectionLostError,
    EpkMismatchError,
    InputError,
    WorkbenchError,
    XcpCommandError,
    XcpTimeoutError,
)
from workbench.logs import logger
from workbench.session.can_listeners import CanListeners, Listening
from workbench.session.connection import (
    Connection,
    daq_can_ids_of,
    link_settings,
    timeouts_of,
)
from workbench.session.epk import EpkCheck, EpkPart, check_epk
from workbench.session.fixes import FixAccess
from workbench.session.info import EcuInfo, PageCopy, PageState, read_ecu_info
from workbench.session.measure import DaqMeasurement, EventAccess
from workbench.session.memory import KnownMemory
from workbench.session.values import ValueAccess
from workbench.xcp.link import Link
from workbench.xcp.master import KeyFunction, Timeouts, XcpMaster
from workbench.xcp.seedkey import load_key_function
from workbench.xcp_protocol import PID_SERV, CanId, Err, IdType, Resource

if TYPE_CHECKING:
    import can

log = logger(__name__)

__all__ = ["LISTEN_BEFORE_CONNECT_S", "Session", "other_master"]

# Before CONNECT on CAN the master listens this long on the ECU's ids: a DAQ another master (CANape beside us)
# runs on a 10 ms event or faster shows, and a connect costs no time a person notices (a session opens in ~17 ms
# instead of ~7).
LISTEN_BEFORE_CONNECT_S = 0.01
_XCP_ONLY, _ECU_AND_XCP, _ALL_SEGMENTS = 0x02, 0x03, 0x80
# what a slave without SET_CAL_PAGE's "all segments" mode answers it
_NO_ALL_SEGMENTS = {Err.MODE_NOT_VALID, Err.CMD_SYNTAX, Err.OUT_OF_RANGE, Err.SEGMENT_NOT_VALID, Err.PAGE_NOT_VALID}


class Session(ValueAccess, EventAccess, FixAccess):
    """A connected ECU with its A2L. Build it with :meth:`open`; use it as a context manager.

    By name (mixed in): :meth:`read`, :meth:`read_value`, :meth:`read_many`, :meth:`write`
    (:mod:`~workbench.session.values`); :meth:`measure` with DAQ (:mod:`~workbench.session.measure`);
    :meth:`fixes`, :meth:`override`, :meth:`release` (:mod:`~workbench.session.fixes`).
    """

    def __init__(self, doc: A2lDocument, config: XcpConfig, link: Link, master: XcpMaster, *,
                 accept_epk_mismatch: bool = False, module: str | None = None):
        self.doc = doc
        self.config = config
        self.link = link
        self.master = master
        self.module = module
        self.accept_epk_mismatch = accept_epk_mismatch
        self.lock = threading.RLock()
        self.epk: EpkCheck = EpkCheck(None, None, "")
        self.other_master = ""  # what was heard on the ECU's CAN ids before CONNECT: another master's traffic
        self.closed = False
        self._closers: list = []  # things to stop on close (a recorder ...)
        self._can_listeners = CanListeners(link)
        self._daq: DaqMeasurement | None = None  # the DAQ measurement running (one at a time)
        self._event_info: dict = {}  # GET_DAQ_EVENT_INFO by event number
        self._known_memory = KnownMemory()  # calibration bytes as last read or written (session.values)
        self._layouts: dict = {}  # name -> ObjectLayout, ResolvedLayout (when static), MeasurementCodec
        self._resolved: dict = {}
        self._codecs: dict = {}
        self._readers: dict = {}  # name -> (span, decode) of a polled read (values.py)
        self._model = None
        self._all_segments: bool | None = None  # SET_CAL_PAGE's "all segments" mode works (None: not tried yet)
        self._slave_segments: tuple[XcpSegment, ...] | None = None  # what GET_SEGMENT_INFO says, when asked

    # --- opening and closing ------------------------------------------------------------------

    @classmethod
    def open(cls, a2l: str | Path | A2lDocument | None = None, *, interface: str | None = None,
             channel: str | int | None = None, bitrate: int | None = None, bus_kwargs: dict[str, Any] | None = None,
             bus=None, host: str | None = None, port: int | None = None, protocol: str | None = None,
             key_function: KeyFunction | str | None = None, accept_epk_mismatch: bool = False,
             timeouts: Timeouts | None = None, module: str | None = None,
             daq_can_ids: Mapping[int, int | CanId] | None = None) -> Session:
        """Connect to the ECU the A2L describes.

        :param a2l: the A2L (path or loaded document); default: the built-in demo ECU's.
        :param interface, channel, bitrate, bus_kwargs: python-can's bus options (XCP on CAN); or ``bus``:
            the bus whole, a :class:`~workbench.bus_defaults.BusSpec`, or an open python-can bus to use
            instead (it stays the caller's).
        :param host, port, protocol: XCP on Ethernet ("udp"/"tcp").
        :param key_function: seed & key: a function ``f(seed, resource) -> key`` or its name
            (``module:function``, ``file.py:function``, an entry point, a key library ``.dll``/``.so``);
            default: the A2L's SEED_AND_KEY_EXTERNAL_FUNCTION.
        :param accept_epk_mismatch: allow writes although the ECU's EPK differs from the A2L's.
        :param timeouts: T1-T7 instead of the A2L's.
        :param daq_can_ids: XCP on CAN: DAQ list number -> the CAN id its DTOs go on (a :class:`CanId` or the
            number as the A2L writes it, bit 31 for extended), set with SET_DAQ_ID before the list starts; for the
            lists the A2L's DAQ_LIST_CAN_ID calls VARIABLE (those not given: CAN_ID_SLAVE) or does not mention.
        :raises InputError: bad A2L or options; :raises WorkbenchError: the bus or ECU cannot be reached.
        """
        doc = a2l if isinstance(a2l, A2lDocument) else load_a2l_to_work(a2l or demo.a2l())
        spec = _bus_spec(bus, {"interface": interface, "channel": channel, "bitrate": bitrate, **(bus_kwargs or {})})
        opened = bus if bus is not None and not isinstance(bus, BusSpec) else None
        connection = Connection(spec, host, port, protocol, open_bus=opened is not None,
                                daq_can_ids=daq_can_ids_of(daq_can_ids or {}))
        settings, config = link_settings(read_xcp_config(doc, module), connection)
        function, name = _key_function(key_function, config, doc)
        link = Link(settings, bus=opened)
        try:
            master = XcpMaster(link, timeouts=timeouts or timeouts_of(config), key_function=function,
                               key_function_name=name)
            session = cls(doc, config, link, master, accept_epk_mismatch=accept_epk_mismatch, module=module)
            session.connect()
        except BaseException:
            link.close()
            raise
        return session

    def connect(self) -> None:
        """CONNECT and check the EPK (again, e.g. after the ECU was reset or flashed). On CAN, listens
        :data:`LISTEN_BEFORE_CONNECT_S` first: what it hears on the ECU's ids is :attr:`other_master`."""
        with self.lock:
            self.other_master = other_master(self.link.heard(LISTEN_BEFORE_CONNECT_S), LISTEN_BEFORE_CONNECT_S)
            if self.other_master:
                log.warning("%s", self.other_master)
            try:
                self.master.connect()
            except XcpTimeoutError as exc:
                raise XcpTimeoutError("CONNECT", exc.timeout_s,
                                      f"no ECU answers on {self.link.settings.describe()}: {self._unanswered()}") from None
            except ConnectionLostError as exc:  # e.g. nothing listens at the address: it was never there
                raise WorkbenchError(f"cannot reach the ECU: {exc.what}: {exc.reason}") from None
            parts = [(epk.address, epk.part) for epk in self.doc.epk_parts(self.module)]
            self.epk = check_epk(self.master, self.doc.epk(self.module), self.doc.addr_epk(self.module), parts)
            if self.epk.matches is False:
                log.warning("%s%s", self.epk.describe(),
                            "" if self.accept_epk_mismatch else "; the session is read-only")

    def _unanswered(self) -> str:
        """What to check when CONNECT goes unanswered, in the transport's terms."""
        settings = self.link.settings
        if self.link.is_can:
            return "is it powered, on this bus, with these ids?"
        if settings.transport == "TCP":  # the connection was taken: something is there, but serves us nothing
            return ("it took the TCP connection but answers no CONNECT: another master (a second workbench, CANape) "
                    "may hold it, an XCP server serves one at a time (XCPlite lets the next wait); or it speaks no XCP")
        return (f"is it powered, at {settings.host}:{settings.port}, serving XCP on UDP (--protocol tcp for TCP)?")

    def close(self) -> None:
        """Stop running measurements, DISCONNECT, close the link; safe to call twice, also after errors."""
        if self.closed:
            return
        self.closed = True
        with self.lock:
            if self._daq is not None:
                try:
                    self._daq.stop()
                except WorkbenchError as exc:
                    log.warning("stopping DAQ: %s", exc)
            for closer in reversed(self._closers):
                try:
                    closer()
                except WorkbenchError as exc:  # a lost ECU was said where it was found
                    log.log(logging.INFO if isinstance(exc, ConnectionLostError) else logging.WARNING, "closing: %s", exc)
            self._closers.clear()
            self._can_listeners.close()
            try:
                if self.master.connected and not self.master.silent and self.link.lost is None:
                    self.master.disconnect()  # not to an ECU found gone: it would only wait out T1 twice
            except WorkbenchError as exc:
                log.debug("DISCONNECT: %s", exc)
            finally:
                self.link.close()

    def listen_can(self, listener, bus: BusSpec | can.BusABC | None = None) -> Listening:
        """Hand every CAN frame of ``bus`` (default: the session's XCP on CAN bus, which the demo ECU's CAN2
        messages share) to ``listener`` (a python-can Listener or a callable) until the returned
        :class:`~workbench.session.can_listeners.Listening` closes or the session does. One bus object and one
        receive thread a bus, whoever listens (see :mod:`workbench.session.can_listeners`).

        :raises InputError: no ``bus`` on a session whose XCP runs on Ethernet, or options ``bus`` would ignore or
            refuses (named as ``CAN2``'s). :raises WorkbenchError: the bus cannot be opened.
        """
        return self._can_listeners.add(listener, bus)

    def on_close(self, closer) -> None:
        """Call ``closer()`` when the session closes (before DISCONNECT)."""
        self._closers.append(closer)

    def __enter__(self) -> Session:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"<Session {self.link.settings.describe()} {self.epk.describe()}>"

    # --- state --------------------------------------------------------------------------------

    @property
    def in_boot(self) -> bool:
        """The ECU answers in its boot loader: programming only (no calibration, no DAQ)."""
        info = self.master.connect_info
        return info is not None and not info.resources & (Resource.CAL_PAG | Resource.DAQ)

    @property
    def bus_spec(self) -> BusSpec | None:
        """The CAN bus XCP runs on, as the A2L completed it (its bit rate, CAN FD); None on Ethernet or on a
        bus the caller opened."""
        return self.link.settings.bus

    @property
    def read_only(self) -> bool:
        return self.epk.matches is False and not self.accept_epk_mismatch

    def epks(self) -> tuple[EpkPart, ...]:
        """The EPK of each part of the software, ECU beside A2L, as read at CONNECT, when the A2L names ADDR_EPK
        in more than one MEMORY_SEGMENT (empty otherwise: :attr:`epk` is then the whole check)."""
        return self.epk.parts

    def require_application(self) -> None:
        """:raises WorkbenchError: the ECU answers in its boot loader, where no calibration or measurement
        lives (a read there gives whatever the memory holds, the simulator's zeros; writes, pages and DAQ are
        unknown commands); nothing is sent. Raw memory (:meth:`read_memory`) and flashing stay open."""
        if self.in_boot:
            raise WorkbenchError("the ECU is in its boot loader (programming only: no application runs, so there "
                                 "are no calibrations or measurements to read); flash its software first: "
                                 "`workbench flash FILE -r APPLICATIVE -r CALIB` (workbench.flash; every region a "
                                 "flash that did not finish was writing)")

    def require_writable(self) -> None:
        """:raises EpkMismatchError: the EPKs differ and the caller did not accept it (writes, page switches
        and page copies are refused then, before anything is sent).
        :raises WorkbenchError: the ECU is in its boot loader (:meth:`require_application`)."""
        self.require_application()
        if self.read_only:
            part = next(iter(self.epk.mismatched_parts), None)  # GET_ID may report the other part's
            raise EpkMismatchError(self.epk.a2l or "", (part.ecu if part is not None else self.epk.ecu) or "",
                                   (f"in {part.segment} ({part.address:X}h); " if part is not None else "") +
                                   "the session is read-only (no writes, no page switches); flash the matching "
                                   "software or open the session with accept_epk_mismatch=True "
                                   "(--accept-epk-mismatch) to write anyway")

    def info(self) -> EcuInfo:
        """What the ECU says about itself, beside what the A2L says."""
        with self.lock:
            return read_ecu_info(self)

    def ecu_a2l(self) -> bytes:
        """The A2L the ECU holds itself (GET_ID 4, "ASAM-MC2 file to upload"): XCPlite writes its own at run time
        and offers it so. Its /include files (XCPlite's XCP_104.aml) are not in it.

        :raises WorkbenchError: the ECU offers none (GET_ID refused, or a length of 0).
        """
        with self.lock:
            try:
                data = self.master.get_id(IdType.ASAM_MC2_FILE)
            except XcpCommandError as error:
                raise WorkbenchError(f"the ECU offers no A2L to upload (GET_ID 4: {error.name})") from None
        if not data:
            raise WorkbenchError("the ECU offers no A2L to upload (GET_ID 4 says 0 bytes)")
        return data

    # --- raw memory ---------------------------------------------------------------------------

    def read_memory(self, address: int, size: int, extension: int = 0) -> bytes:
        with self.lock:
            return self.master.read(address, size, extension)

    def write_memory(self, address: int, data: bytes, extension: int = 0) -> None:
        with self.lock:
            self.require_writable()
            self.master.write(address, data, extension)

    # --- calibration pages --------------------------------------------------------------------

    def segment(self, number: int = 0) -> XcpSegment:
        for segment in self.calibration_segments():
            if segment.number == number:
                return segment
        raise InputError(f"the ECU has no calibration segment {number} (it has "
                         f"{', '.join(str(s.number) for s in self.calibration_segments()) or 'none'})")

    def calibration_segments(self) -> tuple[XcpSegment, ...]:
        """The calibration segments: the A2L's (XCP SEGMENTs of its MEMORY_SEGMENTs), else what the slave says
        (GET_PAG_PROCESSOR_INFO, GET_SEGMENT_INFO; working page 0, reference page 1); asked once a session.

        :raises InputError: neither describes one: there are no pages to switch.
        """
        if self.config.segments:
            return self.config.segments
        if self._slave_segments is None:
            with self.lock:
                try:
                    count = self.master.get_pag_processor_info().max_segments
                    ranges = [self.master.get_segment_range(number) for number in range(count)]
                except XcpCommandError as error:
                    if error.code == Err.CMD_UNKNOWN:  # it has no PAG commands: asked no more (a write checks pages)
                        self._slave_segments = ()
                    raise InputError(f"the A2L describes no calibration segments (XCP SEGMENT) and the ECU says none "
                                     f"either ({error})") from None
                self._slave_segments = tuple(_segment_of_slave(n, *r) for n, r in enumerate(ranges))
        if not self._slave_segments:
            raise InputError("neither the A2L (XCP SEGMENT) nor the ECU (GET_PAG_PROCESSOR_INFO) has calibration pages")
        return self._slave_segments

    def segment_numbers(self) -> list[int]:
        """The calibration segments' numbers (:meth:`calibration_segments`).

        :raises InputError: there are none: no pages to switch.
        """
        return sorted({segment.number for segment in self.calibration_segments()})

    def segments_of(self, names: Iterable[str]) -> list[int]:
        """The calibration segments that hold the objects ``names`` (by their addresses); objects outside
        every segment (measurements in RAM) need none."""
        found = set()
        segments = self.calibration_segments()
        for name in names:
            address = self.model.object(name).address
            found.update(s.number for s in segments if s.address <= address < s.address + s.size)
        return sorted(found)

    def page_numbers(self, segment: int = 0) -> tuple[int, int]:
        """(working page, reference page) of a segment: the page XCP may write, and one it may not."""
        pages = self.segment(segment).pages
        writable = [p.number for p in pages if p.xcp_write_access != "XCP_WRITE_ACCESS_NOT_ALLOWED"]
        locked = [p.number for p in pages if p.xcp_write_access == "XCP_WRITE_ACCESS_NOT_ALLOWED"]
        return (writable[0] if writable else 0), (locked[0] if locked else 1)

    def page(self, segment: int = 0) -> PageState:
        """The pages the ECU and XCP access now in ``segment``.

        :raises WorkbenchError: the ECU is in its boot loader, which has no pages (:meth:`require_application`)."""
        with self.lock:
            self.require_application()
            working, reference = self.page_numbers(segment)
            try:
                return PageState(segment, self.master.get_cal_page(segment, 0x01),
                                 self.master.get_cal_page(segment, 0x02), working, reference)
            except XcpCommandError as error:
                if error.code != Err.CMD_UNKNOWN:
                    raise
                raise error.about(f"the ECU does not tell the pages of segment {segment} (no GET_CAL_PAGE): switching "
                                  "them (cal page working, or reference) puts them on a known page") from None

    def pages(self) -> list[PageState]:
        """The pages of every calibration segment."""
        with self.lock:
            return [self.page(number) for number in self.segment_numbers()]

    def set_page(self, page: str | int, segment: int | None = None) -> None:
        """Switch ECU and XCP to ``"working"``, ``"reference"`` or a page number: in ``segment``, or (None) in
        every calibration segment, at once with SET_CAL_PAGE's "all segments" mode where the slave has it.

        :raises EpkMismatchError: the session is read-only (nothing is sent)."""
        with self.lock:
            self.require_writable()
            numbers = self.segment_numbers() if segment is None else [segment]
            chosen = {number: self._page_number(page, number) for number in numbers}
            if segment is None and len(set(chosen.values())) == 1 and self._all_segments is not False:
                try:
                    self.master.set_cal_page(0, chosen[numbers[0]], _ECU_AND_XCP | _ALL_SEGMENTS)
                    self._all_segments = True
                    self.master.xcp_pages.update(chosen)
                    self.master.ecu_pages.update(chosen)
                    return
                except XcpCommandError as error:
                    if error.code not in _NO_ALL_SEGMENTS:
                        raise
                    log.debug("SET_CAL_PAGE for all segments: %s; switching them one by one", error)
                    self._all_segments = False
            for number, page_number in chosen.items():
                self.master.set_cal_page(number, page_number, _ECU_AND_XCP)

    def page_copies(self, segment: int | None = None) -> list[PageCopy]:
        """What :meth:`copy_reference_to_working` overwrites in ``segment`` (None: every calibration segment),
        to show before it does (nothing is written)."""
        addresses = [obj.address for obj in self.model.find("*", kind=("CHARACTERISTIC", "AXIS_PTS"))]
        copies = []
        for number in self.segment_numbers() if segment is None else [segment]:
            found, (working, reference) = self.segment(number), self.page_numbers(number)
            inside = sum(found.address <= address < found.address + found.size for address in addresses)
            copies.append(PageCopy(number, found.memory_segment, found.address, found.size, working, reference, inside))
        return copies

    def copy_reference_to_working(self, segment: int | None = None) -> None:
        """COPY_CAL_PAGE reference -> working in ``segment`` (None: every calibration segment): the working
        page starts over from the flashed values (:meth:`page_copies` says what that overwrites). A slave without
        COPY_CAL_PAGE (it is optional) gets the copy by UPLOAD and DOWNLOAD: the segment read on both pages, the bytes
        that differ written on the working page."""
        with self.lock:
            self.require_writable()
            for number in self.segment_numbers() if segment is None else [segment]:
                working, reference = self.page_numbers(number)
                try:
                    self.master.copy_cal_page(number, reference, number, working)
                except XcpCommandError as error:
                    if error.code != Err.CMD_UNKNOWN:
                        raise
                    log.info("COPY_CAL_PAGE: ERR_CMD_UNKNOWN; segment %d copied by UPLOAD and DOWNLOAD", number)
                    self._copy_by_transfer(number, reference, working)

    def _copy_by_transfer(self, number: int, reference: int, working: int) -> None:
        found = self.segment(number)
        with self.on_page(reference, number):
            wanted = self.master.read(found.address, found.size)
        with self.on_page(working, number):
            now = self.master.read(found.address, found.size)
            for start, end in _differing_runs(wanted, now):
                self.master.write(found.address + start, wanted[start:end])

    def _page_number(self, page: str | int, segment: int) -> int:
        if isinstance(page, int):
            return page
        working, reference = self.page_numbers(segment)
        choices = {"working": working, "reference": reference, "ram": working, "rom": reference}
        if page.lower() not in choices:
            raise InputError(f"page must be 'working', 'reference' or a number, not {page!r}")
        return choices[page.lower()]

    def on_page(self, page: str | int | None, segment: int | Iterable[int] | None = None):
        """A context in which XCP (not the ECU) accesses ``page`` of ``segment`` (a number, several, or None:
        every calibration segment); ``page`` None: leave the pages as they are.

        :raises WorkbenchError: the ECU is in its boot loader, which has no pages (:meth:`require_application`)."""
        if page is None:
            return _XcpPages(self, {})
        self.require_application()
        numbers = self.segment_numbers() if segment is None else [segment] if isinstance(segment, int) else segment
        return _XcpPages(self, {number: self._page_number(page, number) for number in numbers})


class _XcpPages:
    """XCP on the given page of each segment inside the context; each segment back on its page after."""

    def __init__(self, session: Session, pages: dict[int, int]):
        self.session, self.pages = session, pages
        self.previous: dict[int, int] = {}

    def __enter__(self):
        master = self.session.master
        for segment, page in self.pages.items():
            try:
                previous = master.get_cal_page(segment, _XCP_ONLY)
            except XcpCommandError as error:  # GET_CAL_PAGE is optional: XCP goes back to the working page after
                if error.code != Err.CMD_UNKNOWN:
                    raise
                previous = None
            if previous != page:
                master.set_cal_page(segment, page, _XCP_ONLY)
                self.previous[segment] = self.session.page_numbers(segment)[0] if previous is None else previous
        return self

    def __exit__(self, *exc_info):
        for segment, previous in self.previous.items():
            self.session.master.set_cal_page(segment, previous, _XCP_ONLY)


def _differing_runs(wanted: bytes, now: bytes, gap: int = 8) -> list[tuple[int, int]]:
    """[start, end) runs where ``now`` differs from ``wanted``, runs fewer than ``gap`` bytes apart joined (one DOWNLOAD
    for close changes)."""
    differs = np.flatnonzero(np.frombuffer(wanted, np.uint8) != np.frombuffer(now, np.uint8))
    if not len(differs):
        return []
    breaks = np.flatnonzero(np.diff(differs) > gap)
    starts = np.concatenate(([differs[0]], differs[breaks + 1]))
    ends = np.concatenate((differs[breaks], [differs[-1]])) + 1
    return list(zip(starts.tolist(), ends.tolist()))


def _segment_of_slave(number: int, address: int, size: int) -> XcpSegment:
    """A segment the slave reports and the A2L does not describe: page 0 the working page, page 1 the reference."""
    pages = (XcpPage(0, "ECU_ACCESS_DONT_CARE", "XCP_READ_ACCESS_DONT_CARE", "XCP_WRITE_ACCESS_DONT_CARE"),
             XcpPage(1, "ECU_ACCESS_DONT_CARE", "XCP_READ_ACCESS_DONT_CARE", "XCP_WRITE_ACCESS_NOT_ALLOWED"))
    return XcpSegment("", address, size, number, len(pages), 0, 0, 0, pages, ())


def _bus_spec(bus: Any, given: dict[str, Any]) -> BusSpec | None:
    """The bus the options name: ``bus`` when it is a BusSpec, else the python-can keywords (None: none given).

    :raises InputError: a BusSpec and keywords both.
    """
    given = {key: value for key, value in given.items() if value is not None}
    if isinstance(bus, BusSpec):
        if given:
            raise InputError(f"give the bus as a BusSpec or as python-can options ({', '.join(given)}), not both")
        return bus
    return BusSpec.from_kwargs(given) if given else None


def _key_function(given: KeyFunction | str | None, config: XcpConfig, doc: A2lDocument
                  ) -> tuple[KeyFunction | None, str | None]:
    if callable(given):
        return given, getattr(given, "__name__", "key function")
    name = given or config.seed_and_key_function
    if not name:
        return None, None
    base = doc.path.parent if doc.path is not None else None
    try:
        return load_key_function(name, base), name
    except InputError as exc:
        if given:
            raise
        log.warning("%s (from the A2L); connecting without seed & key", exc)  # a key library that cannot load here must not stop reads
        return None, name


def other_master(heard: list[tuple[CanId, bytes]], seconds: float) -> str:
    """One line on the packets heard on the ECU's ids before this master's CONNECT ("" for none): another master
    talks to the ECU, or a DAQ that a master started (and was killed before stopping) still runs. A warning, not a
    refusal: the two cannot be told apart by listening, and the CONNECT that follows is how a stale DAQ is
    cleaned up; but two masters on one ECU break each other's DAQ, which is said before it happens."""
    if not heard:
        return ""
    ids = list(dict.fromkeys(str(can_id) for can_id, _ in heard))
    responses = sum(packet[0] >= PID_SERV for _, packet in heard)  # answers, events, service requests: to a master
    kinds = ", ".join(part for part in (f"{len(heard) - responses} DTO(s)" if len(heard) > responses else "",
                                        f"{responses} response(s)" if responses else "") if part)
    return (f"before CONNECT, the ECU's id{'s' if len(ids) > 1 else ''} {', '.join(ids)} carried {kinds} within "
            f"{seconds * 1000:g} ms: another master "
            "(CANape, a second workbench) is talking to this ECU, or a DAQ nobody stopped still runs; two masters "
            "break each other's DAQ (XCP serves one at a time)")

