"""DAQ against the simulated ECU: the configured lists, values equal to ECU memory, ECU timestamps, losses."""

from __future__ import annotations

import time

import numpy as np

from workbench.elf import ElfSymbols
from workbench.xcp.daq import DaqSignal, DaqStream, plan_daq


def collect(stream, seconds: float):
    batches, deadline = [], time.monotonic() + seconds
    while time.monotonic() < deadline:
        batches += stream.read(0.05)
    return batches


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
        batches = collect(stream, 1.0)
    fast = [b for b in batches if b.daq_list.event == 0]
    slow = [b for b in batches if b.daq_list.event == 1]
    times = np.concatenate([b.time for b in fast])
    assert len(times) > 150  # 4 ms for a second, minus start-up
    assert np.allclose(np.diff(times), 0.004)  # the ECU's clock, not the host's bursts
    slow_times = np.concatenate([b.time for b in slow])
    assert np.allclose(np.diff(slow_times), 0.05)
    volts = np.concatenate([b.column("zsSensVolt") for b in fast]).view("<f4")
    assert volts.shape[1] == 4 and np.all((volts >= 0) & (volts <= 5))
    assert stream.stats.lost == 0 and stream.stats.unknown == 0


def test_a_dropped_dto_is_a_lost_sample_not_a_wrong_one(rig):
    with start_stream(rig, {1: ["xsDC", "xsPidP", "xsPidI", "xsPidD", "xsPidFF"]}) as stream:
        collect(stream, 0.2)
        rig.demo.ecu.faults.drop_frame(2, "tx")
        batches = collect(stream, 0.5)
    assert stream.stats.lost == 1
    assert rig.demo.ecu.faults.fired
    times = np.concatenate([b.time for b in batches])
    assert np.all(np.diff(times) > 0)


def test_stop_and_close_leave_the_ecu_quiet(rig):
    stream = start_stream(rig, {0: ["zsRailPressure"]})
    with stream:
        collect(stream, 0.1)
    assert not rig.master.get_status().daq_running
    received = stream.stats.dtos
    time.sleep(0.1)
    assert stream.stats.dtos == received
