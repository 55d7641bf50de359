"""A residual-bus PCM: the node that tells the FLCU to run and which rail pressure to hold.

It sends PCM_TO_FLCU_001 (EnableFLCU) and PCM_TO_FLCU_002 (TargetRailPressure) every
100 ms (their DBC cycle time), encoded from the DBC, so the simulated ECU alone shows
the rail pressure rising to the target.
"""

from __future__ import annotations

from dataclasses import dataclass

import can

from workbench.can.dbc_file import DbcFile

ENABLE_MESSAGE = "PCM_TO_FLCU_001"
TARGET_MESSAGE = "PCM_TO_FLCU_002"


@dataclass
class PcmNode:
    dbc: DbcFile
    enable: bool = True
    target_bar: float = 25.0

    @property
    def period_s(self) -> float:
        message = self.dbc.database.get_message_by_name(ENABLE_MESSAGE)
        return (message.cycle_time or 100) / 1000

    def frames(self) -> list[can.Message]:
        """The two frames of one cycle, with the current enable and target.

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
            frames.append(can.Message(arbitration_id=message.frame_id, is_extended_id=message.is_extended_frame, data=data))
        return frames
