"""The master session: an ECU and its A2L, measured and calibrated by name (:class:`Session`)."""

from workbench.session.session import Session

__all__ = ["Session"]
