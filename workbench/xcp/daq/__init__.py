"""DAQ: planning lists within the slave's limits, assembling DTOs into samples, the slave's clock."""

from workbench.xcp.daq.assemble import DtoAssembler, RawSample
from workbench.xcp.daq.clock import DaqClock
from workbench.xcp.daq.plan import DaqListPlan, DaqPlan, DaqSignal, Odt, OdtEntry, plan_daq
from workbench.xcp.daq.stream import DaqBatch, DaqStats, DaqStream

__all__ = ["DaqBatch", "DaqClock", "DaqListPlan", "DaqPlan", "DaqSignal", "DaqStats", "DaqStream", "DtoAssembler",
           "Odt", "OdtEntry", "RawSample", "plan_daq"]
