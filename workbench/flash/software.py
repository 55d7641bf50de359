"""Whether a flash that replaces part of the software fits the part it leaves (thesis 5.3: CALIB is flashed
"when the application software is the same but change only calibration parameters").

The demo ECU, as the thesis's HDS9, keeps its EPK at ADDR_EPK in front of the calibrations in CALIB
(FC0000h); the application's header repeats it (840008h). GET_ID type 5 reads ADDR_EPK, so after a
CALIB flash it reports the EPK of the data just written, whatever code runs: comparing it with the A2L
afterwards proves nothing. What is compared, before anything is erased, is the EPK of what the flash
writes (the image's at ADDR_EPK, else the A2L's) with the ECU's as it reported it before the flash, the
EPK of the part that stays. A flash of code and the EPK's region together replaces the whole software
and is not compared.

With one ADDR_EPK, once a mismatch was accepted (``--accept-epk-mismatch``) and the flash wrote ADDR_EPK, the
ECU reports the flashed EPK although the application that stays is another build's: no later flash or session
can see it, and the flash says so when it happens (:meth:`EpkPairing.describe`). An A2L that names an EPK address
in each part (MOD_PAR ADDR_EPK more than once: CALIB's FC0000h and the application header's 840008h) lets the
flash read the EPK of the part that stays where that part keeps it: the mismatch stays visible to the session
and to every later flash of part of the software, until the parts are one build again.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from workbench.errors import epk_text, same_epk
from workbench.flash.plan import FlashPlan

__all__ = ["EpkPairing", "epk_pairing"]


@dataclass(frozen=True)
class EpkPairing:
    flashed: str  # the EPK of what the flash writes
    kept: str | None  # the ECU's EPK before the flash (None: it could not be read)
    source: str  # how the ECU's was read: "GET_ID" or "ADDR_EPK"
    stays: str  # what the flash leaves on the ECU: "the application", "the calibration data"
    echoed: bool = False  # the flash writes ADDR_EPK: from then on the ECU reports ``flashed``
    part: bool = False  # ``kept`` was read at the ADDR_EPK of the part that stays, where later checks read it too

    @property
    def kept_erased(self) -> bool:
        return self.kept is not None and set(self.kept.rstrip("\0")) <= {"\xff"}

    @property
    def matches(self) -> bool:
        return self.kept is not None and same_epk(self.kept, self.flashed)

    def refusal(self, source: str, regions: str) -> str:
        """One line: why the flash of ``regions`` from ``source`` is refused (the ECU untouched)."""
        if self.kept is None or self.kept_erased:
            why = "could not be read" if self.kept is None else "reads erased (a flash that did not finish?)"
            return (f"{source}: the ECU's EPK {why}, so which software {self.stays} on it belongs to is unknown: "
                    f"flash the whole software (code and calibration regions together), or pass "
                    f"--accept-epk-mismatch if {self.stays} is the software of EPK {epk_text(self.flashed)} "
                    f"(nothing was erased)")
        return (f"{source}: {regions} only, with EPK {epk_text(self.flashed)}, but the ECU reports EPK "
                f"{epk_text(self.kept)} ({self.source}) for {self.stays} that stays on it: they belong to different "
                f"software; flash the whole software, or pass --accept-epk-mismatch to flash it anyway "
                f"(nothing was erased)")

    def describe(self) -> str:
        kept = epk_text(self.kept) if self.kept is not None else "unknown"
        verdict = "the same" if self.matches else "MISMATCH accepted (--accept-epk-mismatch)"
        if not self.matches and self.part:
            verdict += f"; {self.stays} keeps its EPK there, so the session and later flashes see the mismatch"
        elif not self.matches and self.echoed:
            verdict += (f"; after it the ECU reports EPK {epk_text(self.flashed)} (the flash writes ADDR_EPK), so no "
                        f"later check sees that {self.stays} is another build's: flash it too to make them one")
        return f"{self.stays} kept: EPK {kept} before the flash ({self.source or 'not read'}), {verdict}"


def epk_pairing(plan: FlashPlan, ecu_epk: str | None, source: str,
                ecu_parts: Mapping[int, str | None] | None = None) -> EpkPairing | None:
    """The comparison a flash of ``plan`` needs with the ECU's EPK read before it (``source``: how); None when
    the A2L states no EPK or the flash replaces the whole software (its code and every ADDR_EPK).

    :param ecu_parts: the ECU's EPK at each ADDR_EPK (None where it could not be read), used where the A2L
        names one in more than one region (:attr:`FlashLayout.epk_parts`): the part that stays is compared by its own.
    """
    layout = plan.layout
    if layout.epk is None:
        return None
    chosen = {r.region for r in plan.regions}
    flashed = plan.image_epk or layout.epk
    parts = layout.epk_parts
    if parts:
        kept = [(address, region) for address, region in parts if region not in chosen]
        if not kept:
            return None
        ecu = ecu_parts or {}
        pairings = [EpkPairing(flashed, ecu.get(address), f"{region.name} at {address:X}h",
                               "the application" if region.holds_code else "the calibration data", part=True)
                    for address, region in kept]
        return next((p for p in pairings if not p.matches), pairings[0])
    code_flashed = any(region in chosen for region in layout.application_regions())
    epk_region = layout.region_at(layout.addr_epk) if layout.addr_epk is not None else None
    epk_flashed = plan.image_epk is not None and (epk_region is None or epk_region in chosen)
    if code_flashed and epk_flashed:
        return None
    stays = "the calibration data" if code_flashed else "the application"
    return EpkPairing(flashed, ecu_epk, source, stays, echoed=epk_flashed)

