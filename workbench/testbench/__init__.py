"""Requirement tests on the session: a step vocabulary, a pytest plugin, evidence in MDF4, a traced report.

* :mod:`~workbench.testbench.bench` — :class:`Bench`: stimulate (write, override, send a CAN2 frame, the
  simulator's faults), wait (a time, a condition) and expect (a band for a duration, an edge within a
  deadline, a CAN2 signal, a message's period) on a :class:`~workbench.session.Session`, by name, in
  physical units; :class:`ExpectationFailed`, :class:`NotJudged` (the ECU lost, CAN2 silent);
* :mod:`~workbench.testbench.conditions` — :func:`within`, :func:`equals`, :func:`at_least`,
  :func:`at_most`, :func:`other_than`;
* :mod:`~workbench.testbench.markers` — :func:`requirement` and :data:`needs_simulator`;
* :mod:`~workbench.testbench.simulator` — what only the simulated ECU does (:class:`SimulatorUnavailable`
  elsewhere);
* :mod:`~workbench.testbench.plugin` — the pytest plugin (the ``ecu`` fixture, the ECU options,
  evidence and report); :mod:`~workbench.testbench.report` — the HTML report;
* :mod:`~workbench.testbench.run` — :class:`RequirementRun`: ``workbench test`` in a process of its own, its
  verdicts followed as they come (:mod:`~workbench.testbench.verdicts`), cancelled as Ctrl-C;
* ``workbench/testbench/flcu_suite/`` — the FLCU's software requirements as tests (``workbench test``).

The names are imported on first use: ``import workbench.testbench`` loads neither pytest nor a bus.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.lazy_exports import lazy_exports

_EXPORTS = {
    "workbench.testbench.bench": ("Bench", "ExpectationFailed", "NotJudged", "Step"),
    "workbench.testbench.conditions": ("Condition", "at_least", "at_most", "equals", "other_than", "within"),
    "workbench.testbench.markers": ("needs_simulator", "requirement"),
    "workbench.testbench.run": ("RequirementRun", "RunOptions"),
    "workbench.testbench.simulator": ("SimulatorUnavailable",),
}
__all__, __getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

if TYPE_CHECKING:  # for type checkers and IDEs: the same names, imported eagerly
    from workbench.testbench.bench import Bench, ExpectationFailed, NotJudged, Step
    from workbench.testbench.conditions import Condition, at_least, at_most, equals, other_than, within
    from workbench.testbench.markers import needs_simulator, requirement
    from workbench.testbench.run import RequirementRun, RunOptions
    from workbench.testbench.simulator import SimulatorUnavailable
