"""Flashing CALIB and APPLICATIVE over XCP (thesis 5.3): plan, program, verify, with a safe key sequence.

::

    from workbench import Session
    from workbench.flash import FlashLayout, flash_ecu, plan_file

    with Session.open("assets/FLCU.a2l") as ecu:
        plan = plan_file("new.s19", FlashLayout.from_a2l(ecu.doc, ecu.config), ["CALIB"])
        print(plan.describe())                  # "CALIB FC0000h FDFFFFh 20000h Partial: ..."
        print(flash_ecu(ecu, plan).describe())  # programmed, verified, key set, reset, EPK checked

:func:`plan_flash` checks everything it can before the ECU is touched; :func:`flash_ecu`
drives the sequence command by command; :func:`plan_working_page` plans the "flash
calibrations" step (CAL RAM into CAL ROM); :func:`verify_ecu` only compares.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.lazy_exports import lazy_exports

_EXPORTS = {
    "workbench.flash.errors": ("FlashError", "FlashRefused"),
    "workbench.flash.layout": ("DEMO_APP_KEY", "AppKey", "FlashLayout", "FlashRegion", "Sector"),
    "workbench.flash.plan": ("FlashPlan", "RegionPlan", "plan_file", "plan_flash"),
    "workbench.flash.sequence": ("FlashOptions", "FlashResult", "Verify", "check_flash", "flash_ecu"),
    "workbench.flash.compare": ("RangeCheck", "verify_ecu"),
    "workbench.flash.working_page": ("plan_working_page",),
    "workbench.flash.software": ("EpkPairing", "epk_pairing"),
    "workbench.flash.keystate": ("KeyState", "app_key_state", "unfinished_regions"),
    "workbench.flash.parts": ("PartEpk", "read_part_epks"),
}
__all__, __getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

if TYPE_CHECKING:
    from workbench.flash.compare import RangeCheck, verify_ecu
    from workbench.flash.errors import FlashError, FlashRefused
    from workbench.flash.keystate import KeyState, app_key_state, unfinished_regions
    from workbench.flash.layout import DEMO_APP_KEY, AppKey, FlashLayout, FlashRegion, Sector
    from workbench.flash.parts import PartEpk, read_part_epks
    from workbench.flash.plan import FlashPlan, RegionPlan, plan_file, plan_flash
    from workbench.flash.sequence import FlashOptions, FlashResult, Verify, check_flash, flash_ecu
    from workbench.flash.software import EpkPairing, epk_pairing
    from workbench.flash.working_page import plan_working_page
