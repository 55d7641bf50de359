"""Helpers of the sync tests: the session tests' fast XCP timeouts and edited demo A2L, frame counts."""

from __future__ import annotations

from session_helpers import FAST, edited_a2l

from workbench.xcp_protocol import Cmd

__all__ = ["FAST", "downloads", "edited_a2l", "uploads"]


def uploads(sim) -> int:
    """UPLOAD and SHORT_UPLOAD commands the simulated ECU has received."""
    faults = sim.ecu.faults
    return faults.commands_seen(Cmd.UPLOAD) + faults.commands_seen(Cmd.SHORT_UPLOAD)


def downloads(sim) -> int:
    return sim.ecu.faults.commands_seen(Cmd.DOWNLOAD)
