"""Helpers of the sync tests: fast XCP timeouts, the demo A2L edited, frame counts."""

from __future__ import annotations

from pathlib import Path

from workbench import demo
from workbench.xcp.master import Timeouts
from workbench.xcp_protocol import Cmd

FAST = Timeouts(t1=0.3, t2=0.6, t3=0.6, t4=2.0, t5=0.3, t6=0.3, t7=0.02)


def edited_a2l(tmp_path: Path, old: str, new: str) -> Path:
    """The demo A2L with ``old`` (which must occur) replaced by ``new``, written to ``tmp_path``."""
    text = Path(demo.a2l()).read_text(encoding="utf-8")
    assert old in text, old
    path = tmp_path / "edited.a2l"
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


def uploads(sim) -> int:
    """UPLOAD and SHORT_UPLOAD commands the simulated ECU has received."""
    faults = sim.ecu.faults
    return faults.commands_seen(Cmd.UPLOAD) + faults.commands_seen(Cmd.SHORT_UPLOAD)


def downloads(sim) -> int:
    return sim.ecu.faults.commands_seen(Cmd.DOWNLOAD)
