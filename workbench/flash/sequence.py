"""The flash sequence, command by command on the session's master (:func:`flash_ecu`).

1. the ECU's own sectors (GET_PGM_PROCESSOR_INFO, GET_SECTOR_INFO) replace the A2L's when it
   offers them, and the plan is checked again with them; nothing is written before;
2. PROGRAM_START (PGM unlocked with seed & key on the way), which says MAX_CTO_PGM, MAX_BS_PGM,
   MIN_ST_PGM and QUEUE_SIZE_PGM;
3. the application-valid key is cleared: its sector erased (what else the sector holds is
   written back), so from here an interruption leaves the ECU in boot, reachable;
4. PROGRAM_CLEAR of the sectors the ranges lie in, then PROGRAM of the ranges in master block
   mode (:class:`~workbench.flash.writer.RangeWriter`), in the sectors' program order, each range
   ended by a PROGRAM with size 0 (a driver that buffers a flash page writes it then); the bytes at
   each part's ADDR_EPK are held back (:mod:`workbench.flash.parts`);
5. every erased sector is compared with the image by BUILD_CHECKSUM (the gaps, and the EPKs held
   back, must read erased); a sector that differs is erased and written again;
6. the EPKs held back are programmed: a part that broke off before keeps its EPK erased;
7. every part the application needs, flashed or not, is read at its ADDR_EPK: the key is not set
   over one whose EPK is erased or another build's (the ECU stays in boot);
8. the key is programmed and read back, PROGRAM_RESET, CONNECT again (T6), the EPK checked.

Any failure or a cancel after PROGRAM_START ends with a PROGRAM_RESET when the ECU still
answers: with the key cleared the ECU restarts in boot, and a new flash finishes the job.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from enum import Enum
from typing import Any, TypeVar

from workbench.errors import Cancelled, WorkbenchError, XcpCommandError, XcpTimeoutError
from workbench.flash.checksums import ChecksumVerifier
from workbench.flash.errors import FlashError, FlashRefused
from workbench.flash.keystate import KeyState, app_key_state, unfinished_regions
from workbench.flash.layout import Sector
from workbench.flash.parts import epk_ranges, read_part_epks
from workbench.flash.plan import FlashPlan, with_sectors
from workbench.flash.software import EpkPairing, epk_pairing
from workbench.flash.unlisted import unlisted_data
from workbench.flash.writer import RangeWriter, WrongBytes
from workbench.image import ERASED, AddressRange, MemoryImage
from workbench.logs import logger
from workbench.progress import Progress, report
from workbench.session import Session
from workbench.xcp.info import ProgramStartInfo
from workbench.xcp_protocol import Err, Resource

log = logger(__name__)

__all__ = ["FlashOptions", "FlashResult", "Verify", "check_flash", "flash_ecu"]

T = TypeVar("T")


class Verify(Enum):
    CHECKSUM = "checksum"  # BUILD_CHECKSUM of every erased sector
    READBACK = "readback"  # and UPLOAD of every programmed byte
    NONE = "none"  # the user's explicit choice: no verification at all


@dataclass(frozen=True)
class FlashOptions:
    verify: Verify = Verify.CHECKSUM
    ecu_sectors: bool = True  # ask the ECU for its sectors (GET_SECTOR_INFO) when it offers them
    use_program_max: bool = True  # PROGRAM_MAX frames when the ECU offers no master block mode
    max_recoveries: int = 8  # transmission errors repaired in one flash
    max_rewrites: int = 2  # times one sector is erased and written again after wrong bytes
    reconnect_s: float = 5.0  # how long to try CONNECT after PROGRAM_RESET
    erase_beyond_file: bool = False  # erase sectors although they hold data beyond the file's ranges (lost)
    accept_epk_mismatch: bool = False  # flash part of the software although the EPK of the part kept differs


@dataclass(frozen=True)
class FlashResult:
    plan: FlashPlan
    seconds: float  # the whole sequence
    program_seconds: float  # the PROGRAM commands only
    bytes_sent: int  # PROGRAM data bytes sent, repetitions included
    verified: str  # how, e.g. "CRC_32 of 1 sector"
    recoveries: int  # transmission errors repaired
    rewrites: int  # sectors erased and written again
    epk: str  # the EPK check after the reconnect
    application_running: bool
    notes: tuple[str, ...] = field(default=())

    @property
    def rate(self) -> float:
        """Bytes per second of the programming (the plan's bytes over the PROGRAM commands' time)."""
        return self.plan.size / self.program_seconds if self.program_seconds else 0.0

    def describe(self) -> str:
        state = "the application runs" if self.application_running else "the ECU is in boot"
        lines = [f"flashed {self.plan.size} bytes ({', '.join(r.region.name for r in self.plan.regions)}) in "
                 f"{self.seconds:.3g} s; programming {self.program_seconds:.3g} s = {self.rate / 1024:.1f} KiB/s",
                 f"verified: {self.verified}; {self.epk}; {state}"]
        if self.recoveries or self.rewrites:
            lines.append(f"repaired {self.recoveries} transmission error(s), rewrote {self.rewrites} sector(s)")
        lines.extend(self.notes)
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        return {"plan": self.plan.to_dict(), "seconds": self.seconds, "program_seconds": self.program_seconds,
                "bytes_per_second": self.rate, "bytes_sent": self.bytes_sent, "verified": self.verified,
                "recoveries": self.recoveries, "rewrites": self.rewrites, "epk": self.epk,
                "application_running": self.application_running, "notes": list(self.notes)}


def flash_ecu(session: Session, plan: FlashPlan, *, progress: Progress | None = None,
              options: FlashOptions = FlashOptions(), checked: Callable[[FlashPlan], None] | None = None
              ) -> FlashResult:
    """Flash ``plan`` into the ECU of ``session`` (connected); see the module for the sequence.

    :param progress: gets (bytes done, bytes total, "what: rate, time left"); cancelling it stops at the
        next block (:class:`~workbench.errors.Cancelled`, the ECU reset into a state a new flash finishes).
    :param checked: called with the plan that will run (the ECU's sectors in it) once every check passed and
        before anything is written, e.g. to show it: a refused flash shows no plan as if it were running.
    :raises FlashRefused: the ECU's sectors make the plan unsafe, or DAQ runs; nothing was touched.
    :raises FlashError: the flash failed or did not verify; the message says the ECU's state.
    :raises Cancelled: cancelled through ``progress``; the message says the ECU's state.
    """
    with session.lock:
        return _Flash(session, plan, progress, options, checked).run()


def check_flash(session: Session, plan: FlashPlan, options: FlashOptions = FlashOptions()
                ) -> tuple[FlashPlan, list[str]]:
    """The checks of :func:`flash_ecu` that write nothing, against the connected ECU: it offers programming, no DAQ
    runs, it programs by address, and its sectors (GET_SECTOR_INFO, when it answers) replace the A2L's in the plan.
    A dry run asks the same. Returns the plan to flash and notes (sectors that differ from the A2L's).

    :raises FlashRefused: the flash would be refused; nothing was touched.
    """
    master = session.master
    info = master.connect_info
    if info is None or not info.resources & Resource.PGM:
        raise FlashRefused("the ECU offers no programming (CONNECT: no PGM resource); nothing was touched")
    if master.get_status().daq_running:
        raise FlashRefused("a DAQ measurement runs on the ECU: stop it before flashing; nothing was touched")
    _unfinished_parts_before(session, plan)
    pairing = _pairing(session, plan, options)
    notes = [f"{pairing.describe()}"] if pairing is not None and not pairing.matches else []
    notes += _unfinished_before(session, plan)
    plan, sector_notes = _with_ecu_sectors(master, plan) if options.ecu_sectors else (plan, [])
    lost = unlisted_data(master, plan)
    if lost and not options.erase_beyond_file:
        raise FlashRefused(f"{plan.source}: erasing {', '.join(map(str, plan.sectors_holding(lost)))} would also erase "
                           f"{' '.join(map(str, lost))}, which hold data the file does not give back: put them in the "
                           f"file, or pass --erase-beyond-file to lose them (nothing was erased)",
                           override="erase_beyond_file")
    if lost:
        notes.append(f"erased and not written again (--erase-beyond-file): {' '.join(map(str, lost))}")
    return plan, notes + sector_notes


def _unfinished_before(session: Session, plan: FlashPlan) -> list[str]:
    """With the application key cleared before the flash (an earlier one did not finish; flash.keystate): refused
    when a region the file fills but the plan leaves differs from the file, else a note.

    :raises FlashRefused: the key would be set over a region that differs from the file.
    """
    if plan.app_key is None or app_key_state(session, plan.app_key) is not KeyState.CLEARED:
        return []
    chosen = [r.region.name for r in plan.regions]
    unfinished = unfinished_regions(session, plan)
    if unfinished:
        regions = " ".join(f"-r {name}" for name in chosen + unfinished)
        raise FlashRefused(f"{plan.source}: the application key is cleared (a flash did not finish) and "
                           f"{'/'.join(unfinished)} on the ECU differs from the file: flash it too ({regions}), so "
                           f"that the key is not set over an unfinished region (nothing was erased)",
                           regions=tuple(unfinished))
    if all(r.name in chosen for r in plan.layout.regions if r.selectable and not r.is_boot):
        return ["the application key was cleared before this flash: an earlier flash did not finish"]
    if len(read_part_epks(session.master, plan.layout)) > 1:  # a part that broke off has its EPK erased: refused
        return ["the application key was cleared before this flash: an earlier flash did not finish; the parts this "
                "one leaves hold their EPK (none of them broke off)"]
    return [f"the application key was cleared before this flash: an earlier flash did not finish, and the ECU does "
            f"not record which region; if it was not {'/'.join(chosen)}, flash that region again too"]


def _unfinished_parts_before(session: Session, plan: FlashPlan) -> None:
    """A part the flash leaves whose EPK is erased (it broke off: flash.parts): refused, so that the key is not set
    over it. Another build's EPK there is the pairing's to refuse (it may be accepted).

    :raises FlashRefused: nothing was erased.
    """
    if plan.app_key is None:
        return
    chosen = [r.region.name for r in plan.regions]
    for part in read_part_epks(session.master, plan.layout):
        if part.region.name not in chosen and not part.complete:
            state = "the ECU stays in its boot loader" if app_key_state(session, plan.app_key) is KeyState.CLEARED \
                else "the key stays as it is"
            raise FlashRefused(f"{plan.source}: {part.unfinished(chosen, state)} (nothing was erased)",
                               regions=(part.region.name,))


def _with_ecu_sectors(master, plan: FlashPlan) -> tuple[FlashPlan, list[str]]:
    """``plan`` with the ECU's sectors (GET_SECTOR_INFO) when it gives them, and a note when they differ.

    :raises FlashRefused: the ECU programs in functional mode only.
    """
    try:
        processor = master.get_pgm_processor_info()
    except XcpCommandError as exc:
        if exc.code not in (Err.CMD_UNKNOWN, Err.OUT_OF_RANGE):
            raise
        log.info("the ECU gives no programming information (%s): the A2L's sectors apply", exc)
        return plan, []
    if not processor.absolute_mode:
        raise FlashRefused("the ECU programs in functional mode only; the workbench clears and programs by "
                           "address (absolute mode); nothing was touched")
    try:
        sectors = [master.get_sector_info(n) for n in range(processor.max_sectors)]
    except XcpCommandError as exc:
        if exc.code not in (Err.CMD_UNKNOWN, Err.OUT_OF_RANGE):
            raise
        log.info("the ECU gives no sector information (%s): the A2L's sectors apply", exc)
        return plan, []
    if not sectors:  # MAX_SECTOR 0: no sectors told, not none there (all flash would be one erase unit)
        log.info("the ECU counts no sectors (MAX_SECTOR 0): the A2L's sectors apply")
        return plan, []
    ecu = tuple(Sector("", s.number, AddressRange(s.address, s.address + s.length), s.clear_sequence,
                       s.program_sequence) for s in sectors)
    layout = plan.layout
    notes = []
    if {s.range for s in ecu} != {s.range for s in layout.sectors}:
        notes.append(f"the ECU's sectors differ from the A2L's ({layout.sectors_from or 'none'}): used the ECU's")
    return with_sectors(plan, layout.with_sectors(ecu, "ECU")), notes


def _pairing(session: Session, plan: FlashPlan, options: FlashOptions) -> EpkPairing | None:
    """The flash's EPK against the ECU's before it, when the flash leaves part of the software (flash.software).

    :raises FlashRefused: they differ and neither the options nor the session accept an EPK mismatch.
    """
    pairing = _ecu_pairing(session, plan)
    accepted = options.accept_epk_mismatch or session.accept_epk_mismatch
    if pairing is not None and not pairing.matches and not accepted:
        raise FlashRefused(pairing.refusal(plan.source, "/".join(r.region.name for r in plan.regions)),
                           override="accept_epk_mismatch")
    return pairing


def _ecu_pairing(session: Session, plan: FlashPlan) -> EpkPairing | None:
    """:func:`epk_pairing` with the ECU's EPKs as the session read them at CONNECT."""
    check = session.epk
    return epk_pairing(plan, check.ecu, check.source, {part.address: part.ecu for part in check.parts})


class _Meter:
    """Bytes done and total, rate and time left, to a :class:`Progress` (which may cancel)."""

    def __init__(self, progress: Progress | None, total: int):
        self.progress = progress
        self.total = total
        self.done = 0
        self.since: float | None = None
        self.seconds = 0.0  # spent in PROGRAM

    def phase(self, label: str) -> None:
        report(self.progress, self.done, self.total, label)

    def programmed(self, where: str, size: int) -> None:
        self.done = min(self.total, self.done + size)
        elapsed = time.perf_counter() - self.since if self.since is not None else 0.0
        rate = self.done / elapsed if elapsed > 0 else 0.0
        left = (self.total - self.done) / rate if rate else 0.0
        report(self.progress, self.done, self.total, f"programming {where}: {rate / 1024:.1f} KiB/s, "
                                                     f"{int(left) // 60}:{int(left) % 60:02d} left")

    def undo(self, size: int) -> None:
        self.done = max(0, self.done - size)


class _Flash:
    def __init__(self, session: Session, plan: FlashPlan, progress: Progress | None, options: FlashOptions,
                 checked: Callable[[FlashPlan], None] | None = None):
        self.session = session
        self.checked = checked
        self.master = session.master
        self.plan = plan
        self.options = options
        self.meter = _Meter(progress, plan.size)
        self.started = self.key_cleared = self.erased = False
        self.verifier = ChecksumVerifier(self.master)
        self.writer: RangeWriter | None = None
        self.rewrites = 0
        self.notes: list[str] = []
        self.expected = plan.image  # what the programmed sectors hold when done; the key sector's bytes join it
        self.held_back = MemoryImage()  # the parts' EPKs: programmed after everything else (flash.parts)

    # --- the sequence -----------------------------------------------------------------------------

    def run(self) -> FlashResult:
        began = time.perf_counter()
        pairing = _ecu_pairing(self.session, self.plan)  # the ECU's before
        try:
            self.plan, notes = check_flash(self.session, self.plan, self.options)  # writes nothing
            self.notes += notes
            if self.checked is not None:
                self.checked(self.plan)
            start = self._program_start()
            use_max = self.options.use_program_max and "PROGRAM_MAX" in self.session.config.optional_commands
            self._hold_back_epks()
            self.writer = RangeWriter(self.master, start, self.expected, use_max=use_max,
                                      max_recoveries=self.options.max_recoveries, on_block=self._on_block)
            if self.plan.app_key is not None:
                self._clear_key()
            self._erase(self.plan.sectors)
            self.meter.since = time.perf_counter()
            for sector in self._program_order():
                self._program_sector(sector)
            self.meter.seconds = time.perf_counter() - self.meter.since
            verified = self._verify()
            self._program_epks()
            if self.plan.app_key is not None:
                self._check_parts()
                self._set_key()
            self.meter.phase("PROGRAM_RESET")
            self.master.program_reset()
        except Cancelled as exc:
            raise Cancelled(f"{exc}; {self._abandon()}") from None
        except KeyboardInterrupt:
            log.warning("interrupted: %s", self._abandon())
            raise
        except FlashRefused:
            raise
        except _PartUnfinished:
            self._abandon()  # PROGRAM_RESET: with the key cleared, into the boot loader
            raise
        except WorkbenchError as exc:
            raise FlashError(f"the flash failed: {exc}; {self._abandon()}") from exc
        try:
            running = self._reconnect()
        except FlashError:
            raise
        except WorkbenchError as exc:
            raise FlashError(f"the flash is complete and verified, but reconnecting after PROGRAM_RESET failed: "
                             f"{exc}") from exc
        epk = self.session.epk.describe() + (f"; {pairing.describe()}" if pairing is not None else "")
        notes = [n for n in self.notes if pairing is None or n != pairing.describe()]  # said in epk
        return FlashResult(self.plan, time.perf_counter() - began, self.meter.seconds, self.writer.bytes_sent,
                           verified, self.writer.recoveries, self.rewrites, epk, running, tuple(notes))

    def _program_start(self) -> ProgramStartInfo:
        self.meter.phase("PROGRAM_START")
        try:
            start = self.master.program_start()
        except XcpTimeoutError:
            self.started = True  # it may have arrived: the application may be halted
            raise
        self.started = True
        return replace(start, max_cto_pgm=start.max_cto_pgm or self.master.max_cto)

    def _program_order(self) -> list[Sector]:
        return sorted(self.plan.sectors, key=lambda s: (s.program_sequence, s.range.start))

    def _erase(self, sectors: list[Sector]) -> None:
        for sector in sectors:
            self.meter.phase(f"erasing {sector}")
            if sector == self.plan.key_sector:  # from the moment PROGRAM_CLEAR is sent, the sector may be erased
                self.key_cleared = True
            else:
                self.erased = True
            self._retrying(sector.range.start, lambda s=sector: self._clear(s))

    def _clear(self, sector: Sector) -> None:
        self.master.set_mta(sector.range.start)
        self.master.program_clear(sector.range.size)

    def _retrying(self, address: int, action: Callable[[], T]) -> T:
        """``action()``, repeated after a transmission error (it must be idempotent)."""
        try:
            return action()
        except (XcpCommandError, XcpTimeoutError) as error:
            return self.writer.repair(error, address, action)

    def _read(self, address: int, size: int) -> bytes:
        return self._retrying(address, lambda: self.master.read(address, size))

    # --- the parts' EPKs --------------------------------------------------------------------------

    def _hold_back_epks(self) -> None:
        ranges = epk_ranges(self.plan.layout, self.master.granularity)
        for held in ranges:
            for address, data in self.expected.crop(held.start, held.end).segments:
                self.held_back.add(address, data)
        self.expected = _without(self.expected, ranges)

    def _program_epks(self) -> None:
        """The EPKs held back, once every other byte of their parts is programmed (and verified)."""
        if not self.held_back.size:
            return
        self.expected = _merged(self.expected, self.held_back)
        self.writer.expected = self.expected
        for address, data in self.held_back.segments:
            self.meter.phase(f"programming the EPK at {address:X}h")
            self._write(next(s for s in self.plan.sectors if s.range.start <= address < s.range.end), address, data)

    def _check_parts(self) -> None:
        """Every part the application needs holds its EPK (read back now), before the key says it may start.

        :raises FlashError: a part's EPK is erased, or another build's (unless an EPK mismatch is accepted: the
            pairing's note says so).
        """
        chosen = [r.region.name for r in self.plan.regions]
        accepted = self.options.accept_epk_mismatch or self.session.accept_epk_mismatch
        state = "the ECU stays in its boot loader"
        for part in read_part_epks(self.master, self.plan.layout):
            if not part.complete:
                without = part.region.name in chosen and not self.held_back.crop(part.address, part.address + 1).size
                raise _PartUnfinished(f"{self.plan.source}: {part.unfinished(chosen, state, without)}")
            if not part.same and not accepted:
                raise _PartUnfinished(f"{self.plan.source}: {part.other_build(self.plan.layout.epk or '')}, so the "
                                      f"application key is not set and {state}: flash the whole software, or pass "
                                      f"--accept-epk-mismatch to set it anyway")

    # --- the key ------------------------------------------------------------------------------------

    def _clear_key(self) -> None:
        key, sector = self.plan.app_key, self.plan.key_sector
        keep = self._key_sector_rest(sector)
        self._erase([sector])
        if keep.size:
            self.expected = _merged(self.expected, keep)
            self.writer.expected = self.expected
            for address, data in keep.segments:
                self._write(sector, address, data)
        if self._read(key.address, len(key.value)) != bytes([ERASED]) * len(key.value):
            raise FlashError(f"the application key {key} still reads after erasing {sector}")

    def _key_sector_rest(self, sector: Sector) -> MemoryImage:
        """What the key's sector holds besides the key (kept across its erasure); empty when nothing."""
        key = self.plan.app_key
        only_key = MemoryImage.from_bytes(key.address, key.value).read(sector.range.start, sector.range.size, ERASED)
        erased = bytes([ERASED]) * sector.range.size
        if not self._differing_blocks(sector.range.start, only_key) or not self._differing_blocks(
                sector.range.start, erased):
            return MemoryImage()
        content = bytearray(self._read(sector.range.start, sector.range.size))
        offset = key.address - sector.range.start
        content[offset:offset + len(key.value)] = bytes([ERASED]) * len(key.value)
        self.notes.append(f"kept what {sector} holds besides the key")
        return MemoryImage.from_flash_content(sector.range.start, bytes(content))

    def _set_key(self) -> None:
        key, sector = self.plan.app_key, self.plan.key_sector
        self.meter.phase(f"setting the application key {key}")
        self.expected = _merged(self.expected, MemoryImage.from_bytes(key.address, key.value))
        self.writer.expected = self.expected
        self._write(sector, key.address, key.value)
        if self._read(key.address, len(key.value)) != key.value:
            raise FlashError(f"the application key {key} does not read back after programming")

    # --- programming and verification ----------------------------------------------------------

    def _program_sector(self, sector: Sector) -> None:
        pieces = _whole_elements(self.expected.crop(sector.range.start, sector.range.end), self.master.granularity)
        before = self.meter.done
        for attempt in range(self.options.max_rewrites + 1):
            try:
                for address, data in pieces:
                    self._write(sector, address, data)
                return
            except WrongBytes as exc:
                if attempt == self.options.max_rewrites:
                    raise FlashError(f"{sector}: {exc}, also after erasing it {attempt} more time(s)") from exc
                log.warning("%s: %s; erasing it again", sector, exc)
                self.rewrites += 1
                self.meter.undo(self.meter.done - before)
                self._erase([sector])

    def _write(self, sector: Sector, address: int, data: bytes) -> None:
        self.writer.write(sector, address, data)

    def _on_block(self, address: int, size: int) -> None:
        key_sector = self.plan.key_sector
        if key_sector is None or not key_sector.range.start <= address < key_sector.range.end:  # not the plan's bytes
            self.meter.programmed(f"{address:X}h", size)

    def _verify(self) -> str:
        if self.options.verify is Verify.NONE:
            self.notes.append("not verified (the user chose so)")
            return "not verified"
        sectors = self._program_order()
        for sector in sectors:
            for attempt in range(self.options.max_rewrites + 1):
                self.meter.phase(f"verifying {sector}")
                bad = self._differing(sector)
                if not bad:
                    break
                if attempt == self.options.max_rewrites:
                    raise FlashError(f"verification failed: {' '.join(map(str, bad))} differ from the image "
                                     f"(BUILD_CHECKSUM {self.verifier.kind.name if self.verifier.kind else ''})")
                log.warning("%s: %s differ after programming; erasing and writing it again", sector,
                            " ".join(map(str, bad)))
                self.rewrites += 1
                self.meter.undo(self.expected.crop(sector.range.start, sector.range.end).size)
                self._erase([sector])
                self._program_sector(sector)
        kind = self.verifier.kind.name if self.verifier.kind else "read-back"
        how = f"{kind} of {len(sectors)} sector{'s' if len(sectors) != 1 else ''}"
        if self.options.verify is Verify.READBACK:
            how += f", {self.plan.size} bytes read back"
        return how

    def _differing(self, sector: Sector) -> list[AddressRange]:
        bad = self._differing_blocks(sector.range.start, self.expected.read(sector.range.start, sector.range.size,
                                                                             ERASED))
        if not bad and self.options.verify is Verify.READBACK:
            for address, data in self.expected.crop(sector.range.start, sector.range.end).segments:
                if self._read(address, len(data)) != data:
                    bad.append(AddressRange(address, address + len(data)))
        return bad

    def _differing_blocks(self, address: int, expected: bytes) -> list[AddressRange]:
        return self._retrying(address, lambda: self.verifier.differing(address, expected))

    # --- the end -----------------------------------------------------------------------------------

    def _reconnect(self) -> bool:
        """CONNECT after the reset (T6 each try) and check the EPK; True when the application runs."""
        self.meter.phase("reconnecting")
        deadline = time.monotonic() + self.options.reconnect_s
        while True:
            try:
                self.master.connect(timeout="t6")
                break
            except XcpTimeoutError:
                if time.monotonic() > deadline:
                    raise FlashError("the flash is complete and verified, but the ECU does not answer CONNECT after "
                                     "PROGRAM_RESET") from None
                time.sleep(self.master.timeouts.t7)
        self.session.connect()
        running = not self.session.in_boot
        if self.plan.app_key is not None and not running:
            raise FlashError(f"the flash is complete and verified and the key {self.plan.app_key} is set, but the ECU "
                             f"stays in boot after the reset")
        if self._flashed_epk_differs():
            raise FlashError(f"the flash is complete and verified, but {self.session.epk.describe()}: flash the region "
                             f"that holds the EPK too")
        return running

    def _flashed_epk_differs(self) -> bool:
        """After the reconnect: the EPK the flash wrote is not the A2L's. With an EPK in each part, only the parts
        flashed are judged (one that stays may differ: the flash was refused unless that was accepted)."""
        check = self.session.epk
        if not check.parts:
            return check.matches is False
        flashed = {r.region.name for r in self.plan.regions}
        return any(p.matches is False for p in check.parts if p.segment in flashed)

    def _abandon(self) -> str:
        """After a failure or a cancel: reset the ECU when it still answers; say in what state it is left."""
        if not self.started:
            return "nothing was written to the ECU"
        try:
            self.master.resynchronize(attempts=1)
            self.master.program_reset()
            reset = True
        except WorkbenchError as exc:
            log.info("PROGRAM_RESET after the failure: %s", exc)
            reset = False
        if reset:
            try:
                self.master.connect(timeout="t6")
            except WorkbenchError as exc:
                log.info("CONNECT after the reset: %s", exc)
        if self.key_cleared:
            where = "the ECU was reset and stays in boot" if reset else \
                "the ECU does not answer; powered again, it starts in boot"
            return f"the application key is cleared: {where} (programming only); flash again to finish"
        if self.erased:
            return ("the ECU was reset" if reset else "the ECU does not answer") + \
                "; erased sectors are incomplete: flash again to finish"
        return "nothing was erased" + ("; the ECU was reset" if reset else "; the ECU does not answer")


class _PartUnfinished(FlashError):
    """The key is not set: a part's EPK is missing (its message says which and what to do)."""


def _without(image: MemoryImage, ranges: list[AddressRange]) -> MemoryImage:
    """``image`` without the bytes in ``ranges``."""
    if not ranges:
        return image
    rest = MemoryImage()
    for address, data in image.segments:
        for piece in AddressRange(address, address + len(data)).outside(ranges):
            rest.add(piece.start, data[piece.start - address:piece.end - address])
    return rest


def _merged(image: MemoryImage, more: MemoryImage) -> MemoryImage:
    merged = MemoryImage()
    for source in (image, more):
        for address, data in source.segments:
            merged.add(address, data, overwrite=True)
    return merged


def _whole_elements(image: MemoryImage, granularity: int) -> list[tuple[int, bytes]]:
    """The ranges of ``image`` to PROGRAM, widened to whole elements of the address granularity (the bytes
    added are the erased value, which programs nothing) and joined where they then touch."""
    if granularity == 1:
        return image.segments
    widened: list[list[int]] = []
    for address, data in image.segments:
        start, end = address - address % granularity, -(-(address + len(data)) // granularity) * granularity
        if widened and start <= widened[-1][1]:
            widened[-1][1] = max(widened[-1][1], end)
        else:
            widened.append([start, end])
    return [(start, image.read(start, end - start, ERASED)) for start, end in widened]
