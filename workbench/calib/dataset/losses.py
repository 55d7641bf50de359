"""What a format cannot keep of a dataset, as findings a writer lists before it writes.

A loss is a warning: the file is written all the same. Where an object cannot be written at
all (a CUBOID to DCM, a name DCM cannot spell), the object is left out of the file and the
warning says so; the rest of the dataset is written.
"""

from __future__ import annotations

from workbench.findings import Finding, Severity

__all__ = ["LEFT_OUT", "left_out", "loss"]

LEFT_OUT = "left-out"


def loss(kind: str, name: str, message: str) -> Finding:
    """A warning ``name: message`` of ``kind`` ("not-in-dcm", "not-in-cdfx", or :data:`LEFT_OUT`)."""
    if kind == LEFT_OUT:
        message += "; left out of the file"
    return Finding(kind, name, f"{name}: {message}", severity=Severity.WARNING)


def left_out(findings: list[Finding]) -> set[str]:
    """The names of the objects that ``findings`` leave out of the file."""
    return {f.name for f in findings if f.kind == LEFT_OUT}
