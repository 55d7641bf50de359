"""A residual-bus PCM: the node that tells the FLCU to run and which rail pressure to hold.

It sends PCM_TO_FLCU_001 (EnableFLCU) and PCM_TO_FLCU_002 (TargetRailPressure) every
100 ms (their DBC cycle time), encoded from the DBC, so the simulated ECU alone shows
the rail pressure rising to the target.

Faults for tests (:mod:`workbench.sim.inject`): a message can stop (the FLCU sees its RX
timeout) or go out with another DLC than the DBC's (the FLCU's driver flags a DLC error).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import can

from workbench.can.dbc_file import DbcFile

__all__ = ["ENABLE_MESSAGE", "TARGET_MESSAGE", "PcmNode"]

ENABLE_MESSAGE = "PCM_TO_FLCU_001"
TARGET_MESSAGE = "PCM_TO_FLCU_002"
MESSAGES = (ENABLE_MESSAGE, TARGET_MESSAGE)


@dataclass
class PcmNode:
    dbc: DbcFile
    enable: bool = True
    target_bar: float = 25.0
    stopped: set[str] = field(default_factory=set)  # messages not sent (an RX timeout on the FLCU)
    wrong_dlc: dict[str, int] = field(default_factory=dict)  # message -> the DLC it goes out with

    @property
    def period_s(self) -> float:
        message = self.dbc.database.get_message_by_name(ENABLE_MESSAGE)
        return (message.cycle_time or 100) / 1000

    def frames(self) -> list[can.Message]:
        """The frames of one cycle, with the current enable and target (and the faults set).

        :raises ValueError: the target is outside the signal's DBC range.
        """
        database = self.dbc.database
        frames = []
        for name, signals in (
            (ENABLE_MESSAGE, {"EnableFLCU": int(self.enable)}),
            (TARGET_MESSAGE, {"TargetRailPressure": self.target_bar}),
        ):
            message = database.get_message_by_name(name)
            try:
                data = message.encode(signals)
            except Exception as exc:  # cantools raises EncodeError/ValueError variants
                raise ValueError(f"{name}: {exc}") from exc
            if name in self.stopped:
                continue
            if name in self.wrong_dlc:
                data = bytes(data).ljust(8, b"\0")[:self.wrong_dlc[name]]
            frames.append(can.Message(arbitration_id=message.frame_id, is_extended_id=message.is_extended_frame, data=data))
        return frames
