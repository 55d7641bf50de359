"""Fault injection for tests: disturb the n-th frame, command or PROGRAM frame from now on.

``n`` counts from 1 (``drop_frame(1)`` drops the next frame) and starts when the fault is
armed. Frames are the XCP frames on CAN1 in one direction: ``"tx"`` (slave → master:
responses and DTOs) or ``"rx"`` (master → slave). Every fault fires once; :attr:`fired`
lists what happened, so a test can check that its fault was really hit.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from enum import Enum

from workbench.xcp_protocol import Cmd, Err

__all__ = ["FaultPlan", "FrameAction", "FrameFault"]


class FrameAction(Enum):
    DROP = "drop"
    DELAY = "delay"
    DUPLICATE = "duplicate"


@dataclass(frozen=True)
class FrameFault:
    action: FrameAction
    delay_s: float = 0.0


@dataclass
class _Armed:
    at: int  # counter value that triggers
    what: object
    command: int | None = None  # for command faults: only this command counts


class FaultPlan:
    """Armed faults and the counters they trigger on; safe to arm from another thread."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._frames = {"tx": 0, "rx": 0}
        self._commands: dict[int | None, int] = {}
        self._program_frames = 0
        self._frame_faults: dict[str, list[_Armed]] = {"tx": [], "rx": []}
        self._command_faults: list[_Armed] = []
        self._late_answers: list[_Armed] = []
        self._answers: dict[int, int] = {}
        self._power_losses: list[int] = []
        self.fired: list[str] = []

    # --- arming -----------------------------------------------------------------------------

    def drop_frame(self, n: int = 1, direction: str = "tx") -> None:
        self._arm_frame(n, direction, FrameFault(FrameAction.DROP))

    def delay_frame(self, n: int, seconds: float, direction: str = "tx") -> None:
        self._arm_frame(n, direction, FrameFault(FrameAction.DELAY, seconds))

    def duplicate_frame(self, n: int = 1, direction: str = "tx") -> None:
        self._arm_frame(n, direction, FrameFault(FrameAction.DUPLICATE))

    def reject_command(self, n: int = 1, code: Err = Err.GENERIC, command: Cmd | None = None) -> None:
        """Answer the n-th command (the n-th ``command`` if given) with the negative response ``code``."""
        _check_n(n)
        key = None if command is None else int(command)
        with self._lock:
            self._command_faults.append(_Armed(self._commands.get(key, 0) + n, Err(code), key))

    def delay_answer(self, command: Cmd, seconds: float, n: int = 1) -> None:
        """Answer the n-th ``command`` from now ``seconds`` late, as a busy slave would: the answers to the
        commands after it (a SYNCH ...) wait their turn behind it."""
        _check_n(n)
        with self._lock:
            self._late_answers.append(_Armed(self._answers.get(int(command), 0) + n, seconds, int(command)))

    def power_loss_at_program(self, n: int = 1) -> None:
        """Cut the power when the n-th PROGRAM/PROGRAM_NEXT/PROGRAM_MAX frame arrives (before it is written)."""
        _check_n(n)
        with self._lock:
            self._power_losses.append(self._program_frames + n)

    def clear(self) -> None:
        with self._lock:
            for faults in self._frame_faults.values():
                faults.clear()
            self._command_faults.clear()
            self._late_answers.clear()
            self._power_losses.clear()

    def _arm_frame(self, n: int, direction: str, fault: FrameFault) -> None:
        _check_n(n)
        if direction not in self._frames:
            raise ValueError(f"direction must be 'tx' or 'rx', got {direction!r}")
        with self._lock:
            self._frame_faults[direction].append(_Armed(self._frames[direction] + n, fault))

    # --- counters (what a test measures traffic with) ------------------------------------------

    def frames_seen(self, direction: str = "rx") -> int:
        """XCP frames seen so far in ``direction`` ("rx": master -> slave, "tx": slave -> master)."""
        with self._lock:
            return self._frames[direction]

    def commands_seen(self, command: Cmd | None = None) -> int:
        """Commands received so far: all of them, or those of one kind (a block's _NEXT frames count apart)."""
        with self._lock:
            return self._commands.get(None if command is None else int(command), 0)

    # --- consulted by the transport and the slave ----------------------------------------------

    def on_frame(self, direction: str) -> FrameFault | None:
        with self._lock:
            self._frames[direction] += 1
            fault = self._take(self._frame_faults[direction], self._frames[direction])
            if fault is not None:
                self.fired.append(f"{fault.action.value} {direction} frame {self._frames[direction]}")
            return fault

    def on_command(self, command: int) -> Err | None:
        with self._lock:
            self._commands[None] = self._commands.get(None, 0) + 1
            self._commands[command] = self._commands.get(command, 0) + 1
            for armed in list(self._command_faults):
                if armed.command in (None, command) and armed.at == self._commands[armed.command]:
                    self._command_faults.remove(armed)
                    self.fired.append(f"reject command 0x{command:02X} with {armed.what.name}")
                    return armed.what
            return None

    def on_answer(self, command: int) -> float:
        """Seconds the answer to ``command`` leaves late (0: at once). Answers are counted only while a late one
        is armed (``n`` counts from the arming)."""
        if not self._late_answers:
            return 0.0
        with self._lock:
            self._answers[command] = self._answers.get(command, 0) + 1
            for armed in list(self._late_answers):
                if armed.command == command and armed.at == self._answers[command]:
                    self._late_answers.remove(armed)
                    self.fired.append(f"answer command 0x{command:02X} {armed.what} s late")
                    return armed.what
            return 0.0

    def on_program_frame(self) -> bool:
        with self._lock:
            self._program_frames += 1
            if self._program_frames in self._power_losses:
                self._power_losses.remove(self._program_frames)
                self.fired.append(f"power loss at PROGRAM frame {self._program_frames}")
                return True
            return False

    @staticmethod
    def _take(armed: list[_Armed], count: int):
        for item in armed:
            if item.at == count:
                armed.remove(item)
                return item.what
        return None


def _check_n(n: int) -> None:
    if n < 1:
        raise ValueError(f"n counts from 1, got {n}")
