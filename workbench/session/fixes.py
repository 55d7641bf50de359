"""Fix calibrations through the session: override a signal with its ``_EN``/``_VALUE`` pair, release it.

The pairs come from the A2L (:func:`workbench.calib.fixes.fix_pairs_of`: its COMPARISON_QUANTITY links, else
its names) or a mapping the caller gives. A CAN signal no measurement of the A2L shows is read from CAN2 as it
is sent when the caller names the DBC (as the window shows it); otherwise the state says why it has no value.
An override writes ``_VALUE`` first and then ``_EN`` = 1, so the ECU never switches to a stale
value; a release writes ``_EN`` = 0 and leaves ``_VALUE`` for the next time.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from workbench.a2l.xcp import read_daq_events
from workbench.calib.fixes import FixPair, dbc_signal_of, fix_pairs_of, live_as_override, resolve_fix
from workbench.can.naming import dbc_signal_name
from workbench.errors import WorkbenchError

if TYPE_CHECKING:
    import can

    from workbench.bus_defaults import BusSpec
    from workbench.can import DbcFile
    from workbench.session.session import Session

__all__ = ["FixAccess", "FixState"]

_SETTLE_S = 0.5  # the longest an override or release waits for the ECU to show the switched signal
_UNKNOWN_PERIOD_S = 0.01  # the raster assumed for a signal on no cyclic event
_CAN2_WAIT_S = 0.5  # how long a CAN2 frame is awaited whose message has no cycle time in the DBC


@dataclass(frozen=True)
class FixState:
    pair: FixPair
    live: Any  # the signal's value now as the _VALUE reads it (FuelLevelLow's Low, not xsLEDEn's ON; None: neither
    # the A2L nor CAN2 showed it, ``no_live`` says why)
    override: Any  # the _VALUE, physical
    active: bool  # _EN is 1
    live_from: str | None = None  # where ``live`` was read: a measurement, or "CAN2 Message.Signal"
    no_live: str | None = None  # why there is no live value
    measured: Any = None  # the live measurement's own reading (xsLEDEn: ON; ``live`` is Low)

    @property
    def signal(self) -> str:
        return self.pair.signal


class FixAccess:
    """Mixed into :class:`Session`: every fixable signal, override and release."""

    fix_mapping: Mapping[str, tuple[str, str]] | None = None  # signal -> (enable, value) beyond the naming rule

    def fix_pairs(self: Session) -> list[FixPair]:
        """Every ``_EN``/``_VALUE`` pair of the A2L (and of :attr:`fix_mapping`)."""
        return fix_pairs_of(self.model, self.fix_mapping)

    def fix(self: Session, signal: str) -> FixPair:
        """The pair ``signal`` names (stem, _EN/_VALUE, signal or measurement name; two candidates are refused)."""
        return resolve_fix(self.fix_pairs(), signal)

    def fixes(self: Session, can2: DbcFile | str | Path | None = None, *,
              can2_bus: BusSpec | can.BusABC | None = None) -> list[FixState]:
        """Every fixable signal: live value, override value, whether the override is on (one batch read).

        ``can2``: the CAN2 DBC. A CAN signal that no measurement of the A2L shows (a third-party A2L without
        COMPARISON_QUANTITY, no measurement of the signal's name) is then found in it by the fix's name and read
        as sent on ``can2_bus`` (default: the XCP bus), waiting up to two cycles of its message.
        """
        pairs = self.fix_pairs()
        names = [n for pair in pairs for n in (pair.enable, pair.value, pair.live) if n is not None]
        values = self.read_many(names)
        states = [self._state(pair, values) for pair in pairs]
        unseen = [state for state in states if state.live_from is None and state.pair.kind == "CAN signal"]
        if not unseen:
            return states
        if can2 is None:
            found = {state.pair: replace(state, no_live=state.no_live + "; name the CAN2 DBC to read it as sent "
                                                                   "(--can2 DBC, fixes(can2=...))")
                     for state in unseen}
        else:
            found = self._from_can2(unseen, can2, can2_bus)
        return [found.get(state.pair, state) for state in states]

    def _from_can2(self: Session, states: list[FixState], can2: DbcFile | str | Path,
                   bus: BusSpec | can.BusABC | None) -> dict[FixPair, FixState]:
        """``states`` with the values their signals have on CAN2 as the DBC finds them (else why not)."""
        from workbench.can import load_dbc

        database = (load_dbc(can2) if isinstance(can2, (str, Path)) else can2).database
        signals = {state.pair: dbc_signal_of(state.pair, [database]) for state in states}
        wanted = {(message.frame_id, message.is_extended_frame): message
                  for message, _ in filter(None, signals.values())}
        frames: dict[tuple[int, bool], bytes] = {}
        complete = threading.Event()

        def heard(frame) -> None:
            key = (frame.arbitration_id, frame.is_extended_id)
            if key in wanted and not frame.is_error_frame and key not in frames:
                frames[key] = bytes(frame.data)
                if len(frames) == len(wanted):
                    complete.set()

        wait_s = max((2 * message.cycle_time / 1000 if message.cycle_time else _CAN2_WAIT_S)
                     for message in wanted.values()) if wanted else 0.0
        where, failed = "", None
        if wanted:
            try:
                with self.listen_can(heard, bus) as listening:
                    where = listening.describe()
                    complete.wait(wait_s)
            except WorkbenchError as exc:  # no CAN2 bus to listen to (XCP on Ethernet, none named)
                failed = str(exc)
        found = {}
        for state in states:
            named = signals[state.pair]
            if named is None:
                found[state.pair] = replace(state, no_live=f"{state.no_live}, and no signal of the CAN2 DBC has the "
                                                           f"name of {state.pair.stem}")
                continue
            message, signal = named
            qualified = dbc_signal_name(message.name, signal.name)
            data = frames.get((message.frame_id, message.is_extended_frame))
            if data is None:
                why = failed or f"{message.name} did not come on CAN2 ({where}) within {wait_s * 1000:.0f} ms"
                found[state.pair] = replace(state, no_live=f"{state.no_live}; CAN2 {qualified}: {why}")
                continue
            value = message.decode(data, decode_choices=True, allow_truncated=True).get(signal.name)
            found[state.pair] = replace(state, live=value if isinstance(value, (int, float)) else str(value),
                                        live_from=f"CAN2 {qualified}", no_live=None)
        return found

    def fix_state(self: Session, signal: str) -> FixState:
        pair = self.fix(signal)
        names = [n for n in (pair.enable, pair.value, pair.live) if n is not None]
        return self._state(pair, self.read_many(names))

    def _state(self: Session, pair: FixPair, values: Mapping[str, Any]) -> FixState:
        """A pair's state from the values read: the live measurement's in the _VALUE's terms."""
        if pair.live is None:
            return FixState(pair, None, values[pair.value], self._is_on(pair.enable, values[pair.enable]), None,
                            f"no measurement of the A2L shows {pair.signal} (no COMPARISON_QUANTITY links one, "
                            "none has its name)")
        measured = values.get(pair.live)
        live = live_as_override(self.model, pair, measured)
        return FixState(pair, live, values[pair.value], self._is_on(pair.enable, values[pair.enable]), pair.live,
                        measured=measured)

    def override(self: Session, signal: str, value: Any) -> FixState:
        """Replace ``signal`` by ``value`` (physical, in the _VALUE's units): _VALUE first, then _EN = 1.
        The state returned is read once the ECU has computed the signal with the switch (see :meth:`release`)."""
        pair = self.fix(signal)
        with self.lock:
            before = self.fix_state(pair.stem).live
            self.write(pair.value, value)
            self.write(pair.enable, 1)
        return self._settled(pair, before)

    def release(self: Session, signal: str) -> FixState:
        """Give ``signal`` back to the ECU: _EN = 0. The state returned is read once the ECU has computed the
        signal again: after two periods of its DAQ event, and while it still shows the value it had before the
        switch, every period up to half a second (a value that equals the override stays so)."""
        pair = self.fix(signal)
        with self.lock:
            before = self.fix_state(pair.stem).live
            self.write(pair.enable, 0)
        return self._settled(pair, before)

    def _settled(self: Session, pair: FixPair, before: Any) -> FixState:
        if pair.live is None:
            return self.fix_state(pair.stem)
        period = self._period_s(pair.live)
        deadline = time.monotonic() + max(_SETTLE_S, 10 * period)
        time.sleep(2 * period)
        state = self.fix_state(pair.stem)
        while _same(state.live, before) and time.monotonic() < deadline:
            time.sleep(period)
            state = self.fix_state(pair.stem)
        return state

    def _period_s(self: Session, measurement: str) -> float:
        """The period of the DAQ event the A2L names for ``measurement`` (else the fastest event)."""
        preferred = read_daq_events(self.model.block(measurement)).preferred
        number = preferred if preferred is not None else self.fastest_event()
        daq = self.config.daq
        periods = [event.period_s for event in (daq.events if daq else ()) if event.number == number and event.period_s]
        return periods[0] if periods else _UNKNOWN_PERIOD_S

    def _is_on(self: Session, enable: str, value: Any) -> bool:
        if isinstance(value, str):  # a verbal conversion (OFF/ON): its raw value decides
            value = self.model.conversion(self.model.object(enable)).to_raw(value)
        return value == 1


def _same(a: Any, b: Any) -> bool:
    try:
        return bool(np.all(np.asarray(a) == np.asarray(b)))
    except (TypeError, ValueError):
        return a == b
