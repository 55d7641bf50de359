"""What a flash reports when it does not happen or does not finish (both exit code 1 in the CLI)."""

from __future__ import annotations

from workbench.errors import WorkbenchError

__all__ = ["FlashError", "FlashRefused"]


class FlashRefused(WorkbenchError):
    """The plan is unsafe (wrong EPK, data outside the region, BOOT ...): nothing on the ECU was touched."""


class FlashError(WorkbenchError):
    """The flash started but did not finish, or its verification failed; the message says the ECU's state."""
