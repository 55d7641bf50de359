"""What a flash reports when it does not happen or does not finish (both exit code 1 in the CLI)."""

from __future__ import annotations

from workbench.errors import WorkbenchError

__all__ = ["FlashError", "FlashRefused"]


class FlashRefused(WorkbenchError):
    """The plan is unsafe (wrong EPK, data outside the region, BOOT ...): nothing on the ECU was touched.

    ``override``: the :class:`~workbench.flash.FlashOptions` field or planning keyword (``"allow_boot"``) that, set
    True, flashes anyway (the user's explicit choice, e.g. ``"erase_beyond_file"``); None: no option does.
    ``regions``: the regions to flash too for the flash to go ahead (the message names them).
    """

    def __init__(self, message: str, *, override: str | None = None, regions: tuple[str, ...] = ()):
        super().__init__(message)
        self.override = override
        self.regions = regions


class FlashError(WorkbenchError):
    """The flash started but did not finish, or its verification failed; the message says the ECU's state."""
