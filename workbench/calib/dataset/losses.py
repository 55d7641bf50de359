"""What a format cannot keep of a dataset, as findings a writer lists before it writes."""

from __future__ import annotations

from workbench.errors import InputError
from workbench.findings import Finding, Severity

__all__ = ["loss", "refuse_errors"]


def loss(kind: str, name: str, message: str, severity: Severity = Severity.WARNING) -> Finding:
    """A finding ``name: message`` of ``kind`` ("not-in-dcm", "not-in-cdfx")."""
    return Finding(kind, name, f"{name}: {message}", severity=severity)


def refuse_errors(findings: list[Finding]) -> None:
    """:raises InputError: naming the first finding of severity error (and how many more there are)."""
    errors = [f for f in findings if f.severity == Severity.ERROR]
    if errors:
        more = f" (and {len(errors) - 1} more)" if len(errors) > 1 else ""
        raise InputError(errors[0].message + more)
