"""Fix calibrations through the session: override a signal with its ``_EN``/``_VALUE`` pair, release it.

The pairs come from the A2L (:func:`workbench.calib.fixes.fix_pairs_of`: its COMPARISON_QUANTITY links, else
its names) or a mapping the caller gives.
An override writes ``_VALUE`` first and then ``_EN`` = 1, so the ECU never switches to a stale
value; a release writes ``_EN`` = 0 and leaves ``_VALUE`` for the next time.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from workbench.a2l.xcp import read_daq_events
from workbench.calib.fixes import FixPair, fix_pairs_of, resolve_fix

if TYPE_CHECKING:
    from workbench.session.session import Session

__all__ = ["FixAccess", "FixState"]

_SETTLE_S = 0.5  # the longest an override or release waits for the ECU to show the switched signal
_UNKNOWN_PERIOD_S = 0.01  # the raster assumed for a signal on no cyclic event


@dataclass(frozen=True)
class FixState:
    pair: FixPair
    live: Any  # the signal's value now (None: the A2L has no measurement for it)
    override: Any  # the _VALUE, physical
    active: bool  # _EN is 1

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

    def fixes(self: Session) -> list[FixState]:
        """Every fixable signal: live value, override value, whether the override is on (one batch read)."""
        pairs = self.fix_pairs()
        names = [n for pair in pairs for n in (pair.enable, pair.value, pair.live) if n is not None]
        values = self.read_many(names)
        return [FixState(pair, values.get(pair.live) if pair.live else None, values[pair.value],
                         self._is_on(pair.enable, values[pair.enable])) for pair in pairs]

    def fix_state(self: Session, signal: str) -> FixState:
        pair = self.fix(signal)
        names = [n for n in (pair.enable, pair.value, pair.live) if n is not None]
        values = self.read_many(names)
        return FixState(pair, values.get(pair.live) if pair.live else None, values[pair.value],
                        self._is_on(pair.enable, values[pair.enable]))

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
