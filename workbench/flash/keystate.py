"""What the ECU's flash says about an unfinished flash: the application-valid key (thesis 5.3).

A flash clears the key first and sets it last, so a key that reads cleared means a flash started
and did not finish: the boot will not start the application at the next reset (after PROGRAM_START
the application is stopped already). Which part the broken flash was writing its EPK tells: a part's
EPK is programmed last, so the one that broke off reads erased there (:mod:`workbench.flash.parts`,
read before the key is set). A flash that finds the key cleared also compares the other regions its
file holds with the ECU (:func:`unfinished_regions`), so it does not set the key over a region that
differs from the file (with one ADDR_EPK, in CALIB, an APPLICATIVE that broke off shows only so).
"""

from __future__ import annotations

from enum import Enum

from workbench.errors import WorkbenchError
from workbench.flash.checksums import ChecksumVerifier
from workbench.flash.layout import AppKey
from workbench.flash.plan import FlashPlan
from workbench.session import Session

__all__ = ["KeyState", "app_key_state", "unfinished_regions"]


class KeyState(Enum):
    SET = "set"  # the boot starts the application
    CLEARED = "cleared"  # a flash did not finish: the boot stays in the boot loader at the next reset
    UNKNOWN = "unknown"  # the ECU refused to read it

    def describe(self, key: AppKey) -> str:
        if self is KeyState.SET:
            return f"application key {key}: set"
        if self is KeyState.CLEARED:
            return (f"application key at {key.address:X}h cleared: a flash did not finish (the application does not "
                    f"start at the next reset); flash again what was flashed")
        return f"application key at {key.address:X}h: could not be read"


def app_key_state(session: Session, key: AppKey) -> KeyState:
    """Whether ``key`` is in the ECU's flash (one UPLOAD; works in the boot loader too)."""
    try:
        held = session.read_memory(key.address, len(key.value))
    except WorkbenchError:
        return KeyState.UNKNOWN
    return KeyState.SET if held == key.value else KeyState.CLEARED


def unfinished_regions(session: Session, plan: FlashPlan) -> list[str]:
    """The regions the plan's file fills but does not flash whose ECU content differs from the file (BUILD_CHECKSUM):
    with the key cleared, the likely victims of the flash that did not finish."""
    verifier = ChecksumVerifier(session.master)
    return [name for name, image in plan.unchosen
            if any(verifier.differing(address, data) for address, data in image.segments)]
