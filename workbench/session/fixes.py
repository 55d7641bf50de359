"""Fix calibrations through the session: override a signal with its ``_EN``/``_VALUE`` pair, release it.

The pairs come from the A2L's names (:mod:`workbench.calib.fixes`) or a mapping the caller gives.
An override writes ``_VALUE`` first and then ``_EN`` = 1, so the ECU never switches to a stale
value; a release writes ``_EN`` = 0 and leaves ``_VALUE`` for the next time.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from workbench.calib.fixes import FixPair, find_fix_pairs, resolve_fix

if TYPE_CHECKING:
    from workbench.session.session import Session

__all__ = ["FixAccess", "FixState"]


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
        model = self.model
        return find_fix_pairs(model.names("CHARACTERISTIC"), model.names("MEASUREMENT"), self.fix_mapping)

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
        """Replace ``signal`` by ``value`` (physical, in the _VALUE's units): _VALUE first, then _EN = 1."""
        pair = self.fix(signal)
        with self.lock:
            self.write(pair.value, value)
            self.write(pair.enable, 1)
        return self.fix_state(pair.stem)

    def release(self: Session, signal: str) -> FixState:
        """Give ``signal`` back to the ECU: _EN = 0."""
        pair = self.fix(signal)
        self.write(pair.enable, 0)
        return self.fix_state(pair.stem)

    def _is_on(self: Session, enable: str, value: Any) -> bool:
        if isinstance(value, str):  # a verbal conversion (OFF/ON): its raw value decides
            value = self.model.conversion(self.model.object(enable)).to_raw(value)
        return value == 1
