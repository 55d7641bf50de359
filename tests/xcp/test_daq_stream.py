"""DAQ against the simulated ECU: the configured lists, values equal to ECU memory, ECU timestamps, losses."""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np
import pytest
from daq_samples import collect_until, samples
from xcp_helpers import FAST, serve

from workbench.elf import ElfSymbols
from workbench.errors import WorkbenchError
from workbench.sim.demo_ecu import build_demo_ecu
from workbench.sim.profiles import SlaveProfile
from workbench.xcp.daq import DaqSignal, DaqStream, plan_daq
from workbench.xcp_protocol import Cmd


def start_stream(rig, groups):
    symbols = ElfSymbols(rig.demo.files.elf)
    signals = {event: [DaqSignal(name, symbols.symbol(name).address, symbols.symbol(name).size) for name in names]
               for event, names in groups.items()}
    master = rig.master
    processor, resolution = master.get_daq_processor_info(), master.get_daq_resolution_info()
    consistency = {event: master.get_daq_event_info(event).consistency for event in groups}
    plan = plan_daq(signals, processor, resolution, master.max_dto, first_list=processor.min_daq,
                    consistency=consistency)
    return DaqStream(master, plan, processor, resolution, {0: 0.004, 1: 0.05, 2: 0.1})


def test_samples_carry_the_ecu_values_and_its_timestamps(rig):
    with start_stream(rig, {0: ["zsRailPressure", "zsSensVolt"], 1: ["xsDC", "xsTankCtrlState"]}) as stream:
        batches = collect_until(stream, lambda got: samples(b for b in got if b.daq_list.event == 0) > 150
                                and samples(b for b in got if b.daq_list.event == 1) > 2)
    fast = [b for b in batches if b.daq_list.event == 0]
    slow = [b for b in batches if b.daq_list.event == 1]
    times = np.concatenate([b.time for b in fast])
    assert len(times) > 150  # 4 ms for a second
    assert np.allclose(np.diff(times), 0.004)  # the ECU's clock, not the host's bursts
    slow_times = np.concatenate([b.time for b in slow])
    assert np.allclose(np.diff(slow_times), 0.05)
    volts = np.concatenate([b.column("zsSensVolt") for b in fast]).view("<f4")
    assert volts.shape[1] == 4 and np.all((volts >= 0) & (volts <= 5))
    assert stream.stats.lost == 0 and stream.stats.unknown == 0


def test_a_dropped_dto_is_a_lost_sample_not_a_wrong_one(rig):
    with start_stream(rig, {1: ["xsDC", "xsPidP", "xsPidI", "xsPidD", "xsPidFF"]}) as stream:
        collect_until(stream, samples)  # sampling
        rig.demo.ecu.faults.drop_frame(2, "tx")
        batches = collect_until(stream, lambda got: stream.stats.lost and samples(got) > 4)
    assert stream.stats.lost == 1
    assert rig.demo.ecu.faults.fired
    times = np.concatenate([b.time for b in batches])
    assert np.all(np.diff(times) > 0)


def test_stop_and_close_leave_the_ecu_quiet(rig):
    stream = start_stream(rig, {0: ["zsRailPressure"]})
    with stream:
        collect_until(stream, samples)
    assert not rig.master.get_status().daq_running
    received = stream.stats.dtos
    time.sleep(0.1)
    assert stream.stats.dtos == received


def test_a_slave_whose_max_daq_counts_allocated_lists_takes_what_fits_and_says_what_does_not():
    """MAX_DAQ 0 before ALLOC_DAQ (ASAM: MIN_DAQ + DAQ_COUNT) is no reason to refuse; ALLOC_DAQ is the judge."""
    counted = SlaveProfile("two-lists", "", "", daq={"max_daq": 2, "max_daq_counts_allocated": True})
    with serve(build_demo_ecu(slave_profile=counted), 1.0) as rig:
        assert rig.master.get_daq_processor_info().max_daq == 0
        with start_stream(rig, {0: ["zsRailPressure"], 1: ["xsDC"]}) as stream:
            batches = collect_until(stream, lambda got: {b.daq_list.event for b in got} == {0, 1})
            assert {b.daq_list.event for b in batches} == {0, 1}
            assert rig.master.get_daq_processor_info().max_daq == 2
        with pytest.raises(WorkbenchError, match=r"no room for the DAQ lists of 3 event\(s\) \(ALLOC_DAQ: "
                                                 r"ERR_MEMORY_OVERFLOW\); measure fewer events"):
            start_stream(rig, {0: ["zsRailPressure"], 1: ["xsDC"], 2: ["xsFuelLevel"]}).start()


def test_a_write_daq_answered_after_its_timeout_starts_the_configuration_over(rig):
    """WRITE_DAQ moves the DAQ pointer: repeated after a timeout it would write the next entry (or run past the
    ODT's last). A late answer makes the stream configure the lists again from FREE_DAQ instead.

    The answer leaves after T1 but within T1 of the SYNCH that follows the timeout (the slave answers SYNCH only
    after it): FAST's T1 of 0.2 s left 0.1 s either side, too little for a timer on a loaded machine."""
    t1 = 0.6
    rig.master.timeouts = replace(FAST, t1=t1)
    faults = rig.demo.ecu.faults
    faults.delay_answer(Cmd.WRITE_DAQ, 1.5 * t1, n=2)
    configured = faults.commands_seen(Cmd.FREE_DAQ)
    with start_stream(rig, {0: ["zsRailPressure", "zsSensVolt"]}) as stream:
        assert faults.commands_seen(Cmd.FREE_DAQ) == configured + 2  # configured twice: the late answer came after T1
        batches = collect_until(stream, lambda got: samples(got) > 20)
    assert faults.fired == [f"answer command 0x{Cmd.WRITE_DAQ:02X} {1.5 * t1} s late"]
    volts = np.concatenate([b.column("zsSensVolt") for b in batches]).view("<f4")
    assert len(volts) > 20 and np.all((volts >= 0) & (volts <= 5)) and stream.stats.lost == 0
