"""The EPK check: the software in the ECU must be the one the A2L describes before anything is written.

The ECU's EPK is read with GET_ID type 5 when the slave offers it, else from ADDR_EPK (the
A2L's address of the EPK string). On a mismatch the session stays read-only unless the caller
explicitly accepts the risk (thesis figure 37: flash the matching software, or work read-only).
"""

from __future__ import annotations

from dataclasses import dataclass

from workbench.errors import XcpCommandError, epk_text
from workbench.logs import logger
from workbench.xcp.master import XcpMaster
from workbench.xcp_protocol import IdType

log = logger(__name__)

__all__ = ["EpkCheck", "check_epk"]


@dataclass(frozen=True)
class EpkCheck:
    a2l: str | None  # MOD_PAR EPK (None: the A2L states none)
    ecu: str | None  # what the ECU reports (None: it could not be read)
    source: str  # "GET_ID", "ADDR_EPK" or "" (not read)

    @property
    def matches(self) -> bool | None:
        """True/False, or None when there is nothing to compare."""
        if self.a2l is None or self.ecu is None:
            return None
        return _clean(self.a2l) == _clean(self.ecu)

    def describe(self) -> str:
        if self.a2l is None:
            return "the A2L states no EPK: not checked"
        if self.ecu is None:
            return f"the ECU's EPK could not be read (A2L: {epk_text(self.a2l)})"
        verdict = "match" if self.matches else "MISMATCH"
        return f"EPK {verdict}: A2L {epk_text(self.a2l)}, ECU {epk_text(self.ecu)} ({self.source})"


def _clean(text: str) -> str:
    return text.replace("\0", "").strip()


def check_epk(master: XcpMaster, a2l_epk: str | None, addr_epk: int | None) -> EpkCheck:
    """Read the ECU's EPK (GET_ID 5, else ADDR_EPK) for comparison with ``a2l_epk``."""
    if a2l_epk is None:
        return EpkCheck(None, None, "")
    try:
        text = master.get_id(IdType.EPK)
        if text:
            return EpkCheck(a2l_epk, text.decode("latin-1"), "GET_ID")
    except XcpCommandError as exc:
        log.debug("GET_ID EPK: %s", exc)
    if addr_epk is None:
        return EpkCheck(a2l_epk, None, "")
    try:
        text = master.read(addr_epk, len(a2l_epk.encode("latin-1")))
    except XcpCommandError as exc:
        log.debug("EPK at ADDR_EPK: %s", exc)
        return EpkCheck(a2l_epk, None, "")
    return EpkCheck(a2l_epk, text.decode("latin-1"), "ADDR_EPK")
