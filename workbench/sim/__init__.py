"""The simulated ECU: an XCP-on-CAN slave running the FLCU demo application (docs/demo-ecu.md).

* :mod:`~workbench.sim.ecu` — :class:`SimulatedEcu`: memory, boot, OS tasks, XCP slave;
  application-agnostic and passive (tests drive it directly);
* :mod:`~workbench.sim.server` — :class:`Simulator`: the ECU on python-can buses with a clock,
  the bus timing model and fault injection (:class:`FaultPlan`);
* :mod:`~workbench.sim.demo_ecu` — the FLCU demo assembled from its ELF, s19, A2L and DBC;
* :mod:`~workbench.sim.seedkey` — the seed & key plugin masters load
  (``workbench.sim.seedkey:compute_key``); the transport never imports it.

Importing this package loads no CAN bus and no application.
"""

from workbench.sim.demo_ecu import DemoEcu, DemoFiles, build_demo_ecu
from workbench.sim.ecu import EcuState, SimulatedEcu
from workbench.sim.faults import FaultPlan
from workbench.sim.server import Simulator
from workbench.sim.xcp.parameters import DaqParameters, EventChannel, XcpParameters

__all__ = ["DaqParameters", "DemoEcu", "DemoFiles", "EcuState", "EventChannel", "FaultPlan", "SimulatedEcu", "Simulator",
           "XcpParameters", "build_demo_ecu"]
