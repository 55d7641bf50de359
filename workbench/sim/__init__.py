"""The simulated ECU: an XCP slave (on CAN or on Ethernet) running the FLCU demo application (docs/demo-ecu.md).

* :func:`serve_demo` — the demo ECU served in one call (what ``workbench sim`` does), returning a
  started :class:`Simulator`; :class:`EthernetEndpoint` says where XCP on UDP/TCP listens;
* :mod:`~workbench.sim.ecu` — :class:`SimulatedEcu`: memory, boot, OS tasks, XCP slave;
  application-agnostic and passive (tests drive it directly);
* :mod:`~workbench.sim.server` — :class:`Simulator`: the ECU with a clock, its XCP front end
  (:mod:`~workbench.sim.can_port` or :mod:`~workbench.sim.eth_port`), the CAN buses, the bus timing
  model and fault injection (:class:`FaultPlan`);
* :mod:`~workbench.sim.demo_ecu` — the FLCU demo assembled from its ELF, s19, A2L and DBC;
* :mod:`~workbench.sim.seedkey` — the seed & key plugin masters load
  (``workbench.sim.seedkey:compute_key``); the transport never imports it.

The names are imported on first use: ``import workbench.sim`` loads no CAN bus, no DBC and no
application until one is asked for.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.lazy_exports import lazy_exports

_EXPORTS = {
    "workbench.sim.demo_ecu": ("DemoEcu", "DemoFiles", "build_demo_ecu"),
    "workbench.sim.ecu": ("EcuState", "SimulatedEcu"),
    "workbench.sim.eth_port": ("EthernetEndpoint",),
    "workbench.sim.faults": ("FaultPlan",),
    "workbench.sim.serve": ("serve_demo",),
    "workbench.sim.server": ("Simulator",),
    "workbench.sim.xcp.parameters": ("DaqParameters", "EventChannel", "StaticDaqList", "XcpParameters"),
}
__all__, __getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

if TYPE_CHECKING:  # for type checkers and IDEs: the same names, imported eagerly
    from workbench.sim.demo_ecu import DemoEcu, DemoFiles, build_demo_ecu
    from workbench.sim.ecu import EcuState, SimulatedEcu
    from workbench.sim.eth_port import EthernetEndpoint
    from workbench.sim.faults import FaultPlan
    from workbench.sim.serve import serve_demo
    from workbench.sim.server import Simulator
    from workbench.sim.xcp.parameters import DaqParameters, EventChannel, StaticDaqList, XcpParameters
