"""What the session tests share beside their fixtures: short timeouts and the demo A2L edited for a case
(tests import it by name, never from conftest)."""

from __future__ import annotations

from pathlib import Path

from workbench import demo
from workbench.xcp.master import Timeouts

__all__ = ["FAST", "demo_a2l_text", "edited_a2l"]

FAST = Timeouts(t1=0.3, t2=0.6, t3=0.6, t4=2.0, t5=0.3, t6=0.3, t7=0.02)


def demo_a2l_text() -> str:
    return Path(demo.a2l()).read_text(encoding="utf-8")


def edited_a2l(tmp_path: Path, old: str, new: str, count: int = 1) -> Path:
    """The demo A2L with ``old`` replaced by ``new`` (it must occur), written to ``tmp_path``."""
    text = demo_a2l_text()
    assert old in text, old
    path = tmp_path / "edited.a2l"
    path.write_text(text.replace(old, new, count), encoding="utf-8")
    return path
