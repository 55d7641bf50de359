"""Static DAQ against the simulated ECU: the slave's lists read, filled and cleared (never allocated), samples equal
to ECU memory with the ECU's timestamps."""

from __future__ import annotations

import time

import numpy as np
import pytest

from workbench.elf import ElfSymbols
from workbench.errors import InputError, XcpCommandError
from workbench.xcp.daq import DaqSignal, DaqStream, plan_daq
from workbench.xcp.info import DaqListInfo
from workbench.xcp_protocol import Cmd

ALLOCATION = (Cmd.FREE_DAQ, Cmd.ALLOC_DAQ, Cmd.ALLOC_ODT, Cmd.ALLOC_ODT_ENTRY)


def signals_of(rig, groups):
    symbols = ElfSymbols(rig.demo.files.elf)
    return {event: [DaqSignal(name, symbols.symbol(name).address, symbols.symbol(name).size) for name in names]
            for event, names in groups.items()}


def static_stream(rig, groups) -> DaqStream:
    master = rig.master
    processor, resolution = master.get_daq_processor_info(), master.get_daq_resolution_info()
    lists = [master.get_daq_list_info(number) for number in range(processor.max_daq)]
    consistency = {event: master.get_daq_event_info(event).consistency for event in groups}
    plan = plan_daq(signals_of(rig, groups), processor, resolution, master.max_dto, consistency=consistency,
                    static_lists=lists)
    return DaqStream(master, plan, processor, resolution, {0: 0.004, 1: 0.05, 2: 0.1})


def test_the_slave_reports_static_lists_and_has_no_allocation(static_rig):
    master = static_rig.master
    processor = master.get_daq_processor_info()
    assert (processor.dynamic, processor.max_daq, processor.min_daq) == (False, 4, 0)
    assert [master.get_daq_list_info(number) for number in range(4)] == [
        DaqListInfo(0, False, 0, "DAQ", 8, 3), DaqListInfo(1, False, 1, "DAQ", 12, 3),
        DaqListInfo(2, False, None, "DAQ", 16, 4), DaqListInfo(3, False, None, "DAQ", 4, 4)]
    with pytest.raises(XcpCommandError, match="ALLOC_DAQ.*ERR_CMD_UNKNOWN"):
        master.alloc_daq(1)


def test_samples_of_two_events_equal_ecu_memory_and_carry_its_timestamps(static_rig):
    sim, ecu = static_rig.simulator, static_rig.demo.ecu
    groups = {0: ["zsRailPressure", "zsSensVolt", "zsTank1Pressure"], 1: ["xsDC", "xsTankCtrlState", "xsFuelLevel"]}
    addresses = {signal.key: (signal.address, signal.size) for signals in signals_of(static_rig, groups).values()
                 for signal in signals}
    batches: dict[int, list] = {0: [], 1: []}
    with static_stream(static_rig, groups) as stream:
        assert {daq.event: daq.number for daq in stream.plan.lists} == {0: 0, 1: 1}  # the lists fixed to them
        for step in range(1, 5):
            sim.advance(0.05)  # one Task50ms sample; the Task4ms samples before it come first on the bus
            deadline = time.monotonic() + 3.0
            while len(batches[1]) < step and time.monotonic() < deadline:
                for batch in stream.read(0.05):
                    batches[batch.daq_list.event] += [batch]
            for event, names in groups.items():  # the tasks ran last at the last samples: memory holds their values
                last = batches[event][-1]
                for name in names:
                    assert last.column(name)[-1].tobytes() == ecu.read(*addresses[name]), (step, name)
        assert stream.stats.lost == 0 and stream.stats.unknown == 0
    fast = np.concatenate([b.time for b in batches[0]])
    assert len(fast) >= 48 and np.allclose(np.diff(fast), 0.004)  # the ECU's clock, though they came in bursts
    assert np.allclose(np.diff(np.concatenate([b.time for b in batches[1]])), 0.05)
    faults = ecu.faults
    assert [faults.commands_seen(command) for command in ALLOCATION] == [0, 0, 0, 0]
    assert faults.commands_seen(Cmd.CLEAR_DAQ_LIST) == 4  # the two lists, before and after
    assert not any(entry.size for daq in ecu.slave.daq.lists for odt in daq.odts for entry in odt)


def test_an_event_needing_a_taken_list_is_refused(static_rig):
    everything = ["zsSensVolt", "zsRailPressure", "zsTank1Pressure", "zsTank2Pressure", "zsManifoldPressure",
                  "zsRailPressureTmp", "zsTank1VoltFilt", "zsTank2VoltFilt", "xsDC", "xsPidP", "xsPidI"]
    # 56 bytes need 9 ODTs (3 + 7 + 7 ...): one more than list 0 has, so event 0 needs list 2; event 2's 52 bytes
    # need 8, and the only other list for any event, list 3, has 4
    with pytest.raises(InputError, match=r"event 2 fits only list 2 \(taken by event 0\)"):
        static_stream(static_rig, {0: everything, 2: everything[:-1]})


def test_a_plan_for_dynamic_lists_is_refused(static_rig):
    master = static_rig.master
    processor, resolution = master.get_daq_processor_info(), master.get_daq_resolution_info()
    dynamic = plan_daq(signals_of(static_rig, {0: ["zsRailPressure"]}),
                       processor.__class__(**{**processor.__dict__, "dynamic": True}), resolution, master.max_dto)
    with pytest.raises(InputError, match="plan is for dynamic lists but the slave's are static"):
        DaqStream(master, dynamic, processor, resolution).start()
