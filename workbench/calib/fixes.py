"""Fix calibrations (thesis chapter 6): an ``_EN``/``_VALUE`` pair that overrides a signal.

While ``<stem>_EN`` is 1 the ECU uses ``<stem>_VALUE`` instead of the signal it computes or
receives. The thesis names them

* ``cf<SIGNAL>_EN/_VALUE`` for a CAN signal (``cf<MESSAGE>_<SIGNAL>_...`` where signal names
  repeat across messages), the value raw with the signal's factor/offset as its conversion;
* ``zf<SENSOR>_EN/_VALUE`` for a sensor (``zfRAILPRESSURE`` fixes ``zsRailPressure``);
* any other ``<stem>_EN/_VALUE`` pair follows the same rule.

:func:`find_fix_pairs` finds every pair among an A2L's CHARACTERISTICs and the MEASUREMENT that shows
its signal's live value. The A2L says it where it links them: the ``COMPARISON_QUANTITY`` of the
``_VALUE`` (or ``_EN``) names that measurement (``workbench dbc fixcal --measurements`` writes it; the
demo's ``cfFUELLEVELLOW_VALUE`` names ``xsLEDEn``, the variable FuelLevelLow is sent from). An A2L
without the link (third-party files) is read by the names alone (case-blind): ``cs<Message>_<Signal>``
for a received signal, ``zs<Sensor>`` for a sensor, a measurement of the signal's name, else one whose
words abbreviate the signal's (``xsRailPSDiagStatus`` for ``RailPSDiagnosticStatus``). Where none is
found the window shows the value as sent on CAN2, when it knows the DBC. :func:`fix_pairs_of` reads an
A2L model so, for the session, ``cal fix`` and the window alike; :func:`live_as_override` gives them the live
value in the override's terms (its verbal table). :func:`resolve_fix` finds the pair a user means by any of its names, and refuses to guess between two (``RailPressure`` has a CAN fix and a
sensor fix).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from workbench.can.naming import fix_stem
from workbench.errors import InputError, UnknownSymbolError, WorkbenchError

if TYPE_CHECKING:
    from workbench.a2l.model import A2lModel

__all__ = ["ENABLE", "VALUE", "FixPair", "dbc_signal_of", "find_fix_pairs", "fix_pairs_of", "live_as_override",
           "resolve_fix"]

ENABLE, VALUE = "_EN", "_VALUE"
KINDS = {"cf": "CAN signal", "zf": "sensor"}


@dataclass(frozen=True)
class FixPair:
    stem: str  # cfRAILPRESSURE
    enable: str  # cfRAILPRESSURE_EN
    value: str  # cfRAILPRESSURE_VALUE
    kind: str  # "CAN signal", "sensor" or "fix"
    measurement: str | None  # the signal it overrides, when the A2L has it (zsRailPressure, csPCM_TO_FLCU_001_EnableFLCU)
    source: str | None = None  # else the measurement the signal is computed from (cfFUELLEVELLOW: xsLEDEn)

    @property
    def signal(self) -> str:
        """The overridden signal's name: its MEASUREMENT, else the stem without its prefix."""
        return self.measurement or self.stem[2:]

    @property
    def live(self) -> str | None:
        """The measurement that shows the signal's value now."""
        return self.measurement or self.source

    def names(self) -> set[str]:
        """Every name a user may call it by, upper-cased."""
        return {name.upper() for name in self.spellings()}

    def spellings(self) -> set[str]:
        """Every name a user may call it by, as the A2L writes it."""
        names = {self.stem, self.enable, self.value, self.stem[2:]}
        if self.measurement:
            names |= {self.measurement, _bare(self.measurement)}
        return names


def _bare(measurement: str) -> str:
    """A measurement's name without its module prefix and message: csPCM_TO_FLCU_001_EnableFLCU -> EnableFLCU."""
    if measurement.startswith("cs") and "_" in measurement:
        return measurement.rsplit("_", 1)[1]
    return measurement[2:]


def find_fix_pairs(characteristics: Iterable[str], measurements: Iterable[str],
                   explicit: Mapping[str, tuple[str, str]] | None = None,
                   links: Mapping[str, str] | None = None) -> list[FixPair]:
    """Every ``_EN``/``_VALUE`` pair of ``characteristics``, with the measurement that shows its signal.

    ``explicit``: signal name -> (enable, value) for pairs the naming rule does not find.
    ``links``: characteristic -> the MEASUREMENT its COMPARISON_QUANTITY names; a pair's link (its
    ``_VALUE``'s, else its ``_EN``'s) is its live measurement whatever the names say (one that is not
    among ``measurements`` is ignored).
    """
    names = set(characteristics)
    measurements = list(measurements)
    known = set(measurements)
    by_upper: dict[str, list[str]] = {}
    for measurement in measurements:
        by_upper.setdefault(measurement.upper(), []).append(measurement)
        by_upper.setdefault(_bare(measurement).upper(), []).append(measurement)
    links = links or {}
    pairs = []
    for enable in sorted(names):
        if not enable.endswith(ENABLE):
            continue
        stem = enable[: -len(ENABLE)]
        if stem + VALUE not in names:
            continue
        measurement, source = _overridden(stem, by_upper)
        link = next((links[n] for n in (stem + VALUE, enable) if links.get(n) in known), None)
        if link is not None and link != measurement:  # the A2L's link, not a name, says where the value is
            measurement, source = None, link
        elif measurement is None and source is None:
            source = _abbreviated(stem[2:], by_upper)
        pairs.append(FixPair(stem, enable, stem + VALUE, KINDS.get(stem[:2], "fix"), measurement, source))
    for signal, (enable, value) in (explicit or {}).items():
        stem = enable[: -len(ENABLE)] if enable.endswith(ENABLE) else enable
        found = by_upper.get(signal.upper(), [])
        pairs.append(FixPair(stem, enable, value, "fix", found[0] if len(found) == 1 else signal))
    return pairs


def fix_pairs_of(model: "A2lModel", explicit: Mapping[str, tuple[str, str]] | None = None) -> list[FixPair]:
    """:func:`find_fix_pairs` of an A2L: its CHARACTERISTICs and MEASUREMENTs, the COMPARISON_QUANTITY of
    every ``_EN``/``_VALUE`` characteristic as its link."""
    characteristics = model.names("CHARACTERISTIC")
    links = {}
    for name in characteristics:
        if name.endswith((ENABLE, VALUE)):
            link = model.characteristic(name).comparison_quantity
            if link:
                links[name] = link
    return find_fix_pairs(characteristics, model.names("MEASUREMENT"), explicit, links)


def live_as_override(model: "A2lModel", pair: FixPair, measured: Any) -> Any:
    """The live value ``measured`` (the physical value of ``pair.live``) in the terms of the pair's ``_VALUE``,
    so that it reads as the override does: where the ``_VALUE`` is verbal, the measurement's number by the
    ``_VALUE``'s table (xsLEDEn ``ON`` is 1, which cfFUELLEVELLOW_VALUE calls ``Low``); a number the table
    does not list, a numeric ``_VALUE`` (the same quantity: the signal's factor and offset) or None as it is."""
    if measured is None or pair.live is None:
        return measured
    target = model.conversion(model.object(pair.value))
    if not target.verbal:
        return measured
    number = measured
    if isinstance(measured, str):
        try:
            number = model.conversion(model.object(pair.live)).to_raw(measured)
        except WorkbenchError:  # a text the measurement's table lacks
            return measured
    shown = target.to_physical(number)
    return shown if isinstance(shown, str) and shown != target.default else measured


def _overridden(stem: str, by_upper: dict[str, list[str]]) -> tuple[str | None, str | None]:
    """(the measurement ``stem`` overrides, else one of the same name), matched case-blind."""
    key = stem[2:].upper()
    candidates = by_upper.get(key, [])
    if stem.startswith("cf"):  # a received signal is published as cs<Message>_<Signal>
        received = [m for m in candidates if m.startswith("cs")] or by_upper.get("CS" + key, [])
        if len(received) == 1:
            return received[0], None
    elif stem.startswith("zf"):  # zfRAILPRESSURE fixes zsRailPressure
        sensors = [m for m in candidates if m.startswith("zs")]
        if len(sensors) == 1:
            return sensors[0], None
    plain = [m for m in candidates if not m.startswith("cs")]
    return None, plain[0] if len(plain) == 1 else None


_WORDS = re.compile(r"[A-Z]+(?=[A-Z][a-z])|[A-Z]?[a-z]+|[A-Z]+|\d+")


def _abbreviated(signal: str, by_upper: dict[str, list[str]]) -> str | None:
    """The one measurement (prefix and message left off) whose inner words each begin the signal name's words
    in order, its first and last word whole: ``RailPSDiagStatus`` for ``RAILPSDIAGNOSTICSTATUS`` (not
    ``FuelLevel`` for ``FUELLEVELLOW``); None when none or several do."""
    found = set()
    for upper, measurements in by_upper.items():
        for measurement in measurements:
            bare = _bare(measurement)
            if bare.upper() != upper:
                continue
            words = _WORDS.findall(bare)
            pattern = "[A-Z0-9]*?".join(re.escape(word.upper()) for word in words)
            if len(words) > 2 and re.fullmatch(pattern, signal.upper()):
                found.add(measurement)
    return found.pop() if len(found) == 1 else None


def resolve_fix(pairs: list[FixPair], signal: str) -> FixPair:
    """The pair ``signal`` names (stem, _EN/_VALUE name, signal or measurement, or a CAN signal as
    ``Message.Signal``; case-blind).

    :raises UnknownSymbolError: no pair has that name (the closest are suggested).
    :raises InputError: two pairs answer to it (both are named: choose one).
    """
    key = signal.upper()
    exact = [pair for pair in pairs if key in {pair.stem.upper(), pair.enable.upper(), pair.value.upper()}]
    found = exact or [pair for pair in pairs if key in pair.names()] or _can_signal_fix(pairs, key)
    if len(found) == 1:
        return found[0]
    if found:
        choices = ", ".join(f"{pair.stem} ({pair.kind})" for pair in found)
        raise InputError(f"{signal!r} has {len(found)} fix calibrations: {choices}; name the one you mean")
    import difflib

    spelled = {name.upper(): name for pair in pairs for name in sorted(pair.spellings())}
    close = [spelled[name] for name in difflib.get_close_matches(key, sorted(spelled), n=3, cutoff=0.6)]
    where = "the A2L's fix calibrations" + (f" (did you mean {', '.join(close)}?)" if close else "")
    raise UnknownSymbolError(signal, where)


def dbc_signal_of(pair: FixPair, databases: Iterable) -> tuple | None:
    """``(message, signal)`` (cantools) of ``databases`` that a CAN fix overrides, by the fix's name alone
    (``cf<SIGNAL>``, or ``cf<MESSAGE>_<SIGNAL>``, case-blind), as the window finds a CAN2 value; None when the
    pair is no CAN fix or no signal (or several) answers to its name."""
    if pair.kind != KINDS["cf"]:
        return None
    stem = pair.stem.upper()
    found = [(message, signal) for database in databases for message in database.messages for signal in message.signals
             if stem in (fix_stem(signal.name, message.name).upper(), fix_stem(signal.name).upper())]
    return found[0] if len(found) == 1 else None


def _can_signal_fix(pairs: list[FixPair], key: str) -> list[FixPair]:
    """The CAN fix of a DBC signal named as the window names it, ``Message.Signal`` (upper-cased ``key``):
    ``cf<SIGNAL>``, or ``cf<MESSAGE>_<SIGNAL>`` where the signal's name repeats across messages."""
    message, dot, name = key.partition(".")
    if not dot:
        return []
    for stem in (fix_stem(name, message).upper(), fix_stem(name).upper()):
        found = [pair for pair in pairs if pair.stem.upper() == stem]
        if found:
            return found
    return []
