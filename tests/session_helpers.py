"""What the session tests share beside their fixtures: short timeouts and the demo A2L edited for a case
(tests import it by name, never from conftest)."""

from __future__ import annotations

from pathlib import Path

import pytest

from workbench import PageError, demo
from workbench.xcp.master import Timeouts

__all__ = ["FAST", "WRITE", "demo_a2l_text", "edited_a2l", "extended_limits_a2l", "refused_on_the_reference_page"]

FAST = Timeouts(t1=0.3, t2=0.6, t3=0.6, t4=2.0, t5=0.3, t6=0.3, t7=0.02)
WRITE = ["SET_MTA", "DOWNLOAD", "SHORT_UPLOAD"]  # a value written and read back


def demo_a2l_text() -> str:
    return Path(demo.a2l()).read_text(encoding="utf-8")


def edited_a2l(tmp_path: Path, old: str, new: str, count: int = 1) -> Path:
    """The demo A2L with ``old`` replaced by ``new`` (it must occur), written to ``tmp_path``."""
    text = demo_a2l_text()
    assert old in text, old
    path = tmp_path / "edited.a2l"
    path.write_text(text.replace(old, new, count), encoding="utf-8")
    return path


def extended_limits_a2l(tmp_path: Path) -> Path:
    """The demo A2L with EXTENDED_LIMITS 0 1000 on xsSWITCH_TANK_THR (its limits 0 800), written to ``tmp_path``."""
    end = ("/* Upper Limit            */ 800\n    /end CHARACTERISTIC\n\n    /begin MEASUREMENT\n"
           "      /* Name                   */ xsTankCtrlState")  # the block before xsTankCtrlState's
    return edited_a2l(tmp_path, end, end.replace("\n", "\n      EXTENDED_LIMITS 0 1000\n", 1))


def refused_on_the_reference_page(ecu, log, segment: int) -> None:
    """With the reference page active a value and a map cell of the demo (in ``segment``) are refused with
    nothing sent, the message saying how to switch; on the working page the value is one write. ``log``: the
    bus's :class:`xcp_commands.CommandLog`."""
    option = f" --segment {segment}" if segment else ""
    ecu.set_page("reference")
    log.take()
    with pytest.raises(PageError, match=rf"xsSWITCH_TANK_THR is not written: the reference page of segment {segment} "
                                        rf"is active .*`workbench cal page working{option}`"):
        ecu.write("xsSWITCH_TANK_THR", 21.0)
    with pytest.raises(PageError, match=f"xvPRV_DC_FF is not written: the reference page of segment {segment}"):
        ecu.write_cells("xvPRV_DC_FF", {(0, 0): 1.0})
    assert log.take() == []
    ecu.set_page("working")
    log.take()
    assert ecu.write("xsSWITCH_TANK_THR", 21.0).value == 21.0
    assert log.take() == WRITE  # the switch told the session the page XCP is on
