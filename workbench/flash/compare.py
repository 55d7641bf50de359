"""Compare the ECU's flash with a plan's ranges, changing nothing (``workbench flash --verify-only``)."""

from __future__ import annotations

from dataclasses import dataclass

from workbench.flash.checksums import ChecksumVerifier
from workbench.flash.plan import FlashPlan
from workbench.image import AddressRange
from workbench.progress import Progress, report
from workbench.session import Session

__all__ = ["RangeCheck", "verify_ecu"]


@dataclass(frozen=True)
class RangeCheck:
    region: str
    range: AddressRange
    differing: tuple[AddressRange, ...]  # the checksum blocks that differ; empty: the range matches

    @property
    def matches(self) -> bool:
        return not self.differing

    def __str__(self) -> str:
        verdict = "matches" if self.matches else "DIFFERS: " + " ".join(map(str, self.differing))
        return f"{self.region} {self.range} {verdict}"


def verify_ecu(session: Session, plan: FlashPlan, *, progress: Progress | None = None) -> list[RangeCheck]:
    """BUILD_CHECKSUM of every range the plan would program against the image's bytes (no PGM needed)."""
    verifier = ChecksumVerifier(session.master)
    checks = []
    done = 0
    with session.lock:
        for region in plan.regions:
            for address, data in region.image.segments:
                report(progress, done, plan.size, f"comparing {region.region.name} {address:X}h")
                checks.append(RangeCheck(region.region.name, AddressRange(address, address + len(data)),
                                         tuple(verifier.differing(address, data))))
                done += len(data)
    report(progress, done, plan.size, "compared")
    return checks
