"""DTOs into samples for every identification field type, with losses and overloads counted; the clock."""

from __future__ import annotations

import struct

import numpy as np
import pytest
from test_daq_plan import processor, resolution

from workbench.xcp.daq.assemble import DtoAssembler
from workbench.xcp.daq.clock import DaqClock
from workbench.xcp.daq.plan import DaqSignal, plan_daq
from workbench.xcp.info import DaqListInfo

SIGNALS = {0: [DaqSignal("a", 0x100, 4), DaqSignal("b", 0x200, 4), DaqSignal("c", 0x300, 2)]}


def dtos(plan, first_pid: int, timestamp: int, memory: dict[int, int], order: str = "<") -> list[bytes]:
    """The DTOs a slave would send for one sample of the plan's first list."""
    daq = plan.lists[0]
    frames = []
    for number, odt in enumerate(daq.odts):
        field = plan.identification_field
        if field == "ABSOLUTE":
            head = bytes((first_pid + number,))
        elif field == "RELATIVE_BYTE":
            head = bytes((number, daq.number))
        elif field == "RELATIVE_WORD":
            head = bytes((number,)) + struct.pack(f"{order}H", daq.number)
        else:
            head = bytes((number, 0)) + struct.pack(f"{order}H", daq.number)
        if number == 0 and daq.timestamps:
            head += timestamp.to_bytes(plan.timestamp_size, "little" if order == "<" else "big")
        data = bytes(memory.get(entry.address + i, 0) for entry in odt.entries for i in range(entry.size))
        frames.append((head + data).ljust(8, b"\0") if plan.max_dto == 8 else head + data)
    return frames


MEMORY = {**{0x100 + i: 1 + i for i in range(4)}, **{0x200 + i: 0x10 + i for i in range(4)}, 0x300: 0xAA, 0x301: 0xBB}


@pytest.mark.parametrize("field", ["ABSOLUTE", "RELATIVE_BYTE", "RELATIVE_WORD", "RELATIVE_WORD_ALIGNED"])
@pytest.mark.parametrize("order", ["<", ">"])
def test_every_identification_field_reassembles(field, order):
    max_dto = 8 if field in ("ABSOLUTE", "RELATIVE_BYTE") else 16
    plan = plan_daq(SIGNALS, processor(field), resolution(timestamp_size=2), max_dto, first_list=2)
    assembler = DtoAssembler(plan, {2: 40}, order)
    for timestamp in (1000, 1250):
        for dto in dtos(plan, 40, timestamp, MEMORY, order):
            assembler.feed(dto, 5)
    samples = assembler.take()
    assert [s.timestamp for s in samples] == [1000, 1250]
    positions = plan.lists[0].positions
    data = np.frombuffer(samples[0].data, dtype=np.uint8)
    assert bytes(data[positions["a"]]) == bytes((1, 2, 3, 4))
    assert bytes(data[positions["c"]]) == bytes((0xAA, 0xBB))
    assert (assembler.lost, assembler.unknown) == (0, 0)


@pytest.mark.parametrize("field", ["ABSOLUTE", "RELATIVE_BYTE", "RELATIVE_WORD"])
def test_a_static_list_reassembles_with_its_number_and_the_first_pid_the_slave_gave(field):
    lists = [DaqListInfo(0, False, 1, "DAQ", 4, 2), DaqListInfo(1, False, None, "DAQ", 6, 3)]
    max_dto = 8 if field != "RELATIVE_WORD" else 16
    plan = plan_daq(SIGNALS, processor(field, dynamic=False), resolution(timestamp_size=2), max_dto, static_lists=lists)
    assert [daq.number for daq in plan.lists] == [1]  # list 0 samples event 1 only
    assembler = DtoAssembler(plan, {1: 4})  # FIRST_PID 4: after list 0's ODTs
    for dto in dtos(plan, 4, 700, MEMORY) + [bytes((0, 0)) + bytes(6)]:  # and a DTO of list 0, not ours
        assembler.feed(dto, 0)
    (sample,) = assembler.take()
    data = np.frombuffer(sample.data, dtype=np.uint8)
    assert bytes(data[plan.lists[0].positions["b"]]) == bytes((0x10, 0x11, 0x12, 0x13)) and sample.timestamp == 700
    assert assembler.unknown == 1


def test_a_missing_odt_drops_that_sample_only():
    plan = plan_daq(SIGNALS, processor(), resolution(), 8)
    assert len(plan.lists[0].odts) > 2
    assembler = DtoAssembler(plan, {0: 0})
    first, second, third = (dtos(plan, 0, t, MEMORY) for t in (1, 2, 3))
    for dto in first + second[:1] + second[2:] + third:  # the second sample lost its ODT 1
        assembler.feed(dto, 0)
    assert [s.timestamp for s in assembler.take()] == [1, 3]
    assert assembler.lost == 1


def test_a_lost_first_odt_counts_once():
    plan = plan_daq(SIGNALS, processor(), resolution(), 8)
    assembler = DtoAssembler(plan, {0: 0})
    for dto in dtos(plan, 0, 1, MEMORY)[1:] + dtos(plan, 0, 2, MEMORY):
        assembler.feed(dto, 0)
    assert [s.timestamp for s in assembler.take()] == [2]
    assert assembler.lost == 1


def test_overload_bit_in_the_pid_is_counted_and_stripped():
    plan = plan_daq({0: [DaqSignal("a", 0x100, 2)]}, processor(), resolution(timestamp_size=0), 8)
    assembler = DtoAssembler(plan, {0: 3}, overload_in_pid=True)
    assembler.feed(bytes((0x83, 1, 2)), 0)
    assert assembler.overloads == 1 and len(assembler.take()) == 1


def test_foreign_dtos_are_counted_not_decoded():
    plan = plan_daq(SIGNALS, processor(), resolution(), 8)
    assembler = DtoAssembler(plan, {0: 0})
    assembler.feed(bytes((0x70,)) + bytes(7), 0)
    assert assembler.unknown == 1 and assembler.take() == []


def test_a_16_bit_counter_is_unwrapped_with_the_host_clock_even_when_sampled_rarely():
    clock = DaqClock(2, 1e-5)  # wraps every 0.65536 s
    true_s = np.array([0.0, 0.3, 1.0, 2.5, 2.6])
    counts = np.rint(true_s / 1e-5).astype(np.int64) % 65536
    host_ns = (1_000_000_000_000 + true_s * 1e9 + np.array([2e5, 9e5, 1e5, 3e5, 1e5])).astype(np.int64)
    seconds, host = clock.times(0, counts[:2], host_ns[:2])
    more, more_host = clock.times(0, counts[2:], host_ns[2:])
    assert np.allclose(np.concatenate((seconds, more)), true_s, atol=1e-9)
    assert np.all(np.diff(np.concatenate((host, more_host))) > 0)
    assert abs(more_host[-1] - (1000 + 2.6 + 1e-4)) < 2e-4  # the fastest arrival sets the offset


def test_a_byte_counter_survives_a_host_stall_near_its_wrap_and_counts_a_real_gap():
    """A 1-byte millisecond counter (a wrap every 256 ms) on a 4 ms event: a 150 ms stall of the host delivers
    the samples of that time in a burst, which is no wrap; 300 ms without samples (a real gap) is one."""
    clock = DaqClock(1, 1e-3)
    true_s = np.concatenate((np.arange(0, 0.4, 0.004), [0.7, 0.704]))
    counts = np.rint(true_s * 1e3).astype(np.int64) % 256
    arrival_s = true_s + 0.0005
    arrival_s[50:] = np.maximum(arrival_s[50:], 0.35)  # from 0.2 s the host stalls: what came meanwhile, at 0.35 s
    host_ns = (5_000_000_000 + arrival_s * 1e9).astype(np.int64)
    seconds = np.concatenate([clock.times(0, counts[i:i + 20], host_ns[i:i + 20])[0] for i in range(0, len(counts), 20)])
    assert np.allclose(seconds, true_s, atol=1e-9)


def test_a_byte_counter_takes_a_burst_after_a_stall_longer_than_its_wrap_for_no_wrap():
    """A loaded host: the slave (or the master) stalls 300 ms, then what it owes comes in one burst, read at once;
    the burst's last samples travelled fast again, so the first ones after the stall are no wrap (they were
    counted as 256 ms on, their samples as lost, and each such error made the next one likelier)."""
    clock = DaqClock(1, 1e-3)
    true_s = np.arange(0, 2.0, 0.004)
    counts = np.rint(true_s * 1e3).astype(np.int64) % 256
    arrival_s = true_s + 0.0005
    stalled = (true_s > 0.602) & (true_s < 0.91)
    arrival_s[stalled] = 0.9102 + np.arange(stalled.sum()) * 1e-6  # the burst, 1 us a sample
    host_ns = (7_000_000_000 + arrival_s * 1e9).astype(np.int64)
    reads = np.searchsorted(arrival_s, np.arange(0.05, 2.05, 0.05), side="right")  # read every 50 ms, as a recorder
    seconds = np.concatenate([clock.times(0, counts[a:b], host_ns[a:b])[0]
                              for a, b in zip(np.concatenate(([0], reads[:-1])), reads, strict=True) if b > a])
    assert np.allclose(seconds, true_s, atol=1e-9)


def test_a_byte_counter_of_a_list_whose_samples_come_late_keeps_its_cycle_and_its_real_gaps():
    """A loaded host: the slave falls behind, up to 0.7 s (a simulated ECU at load 8 did), and each sample is read
    alone as it comes; a step of the list's 4 ms cycle is the next sample however late it came (each delay past
    220 ms was taken for a wrap), while a step that is no cycle (samples lost) is still unwrapped by arrival."""
    clock = DaqClock(1, 1e-3)
    true_s = np.concatenate((np.arange(0, 3.0, 0.004), 3.0 + 0.3 + np.arange(0, 1.0, 0.004)))  # then 300 ms lost
    counts = np.rint(true_s * 1e3).astype(np.int64) % 256
    lag_s = np.interp(true_s, [0, 1, 2, 3, 5], [0.0005, 0.7, 0.2, 0.0005, 0.0005])
    host_ns = (3_000_000_000 + (true_s + lag_s) * 1e9).astype(np.int64)
    seconds = np.concatenate([clock.times(0, counts[i:i + 1], host_ns[i:i + 1], 0.004)[0] for i in range(len(counts))])
    assert np.allclose(seconds, true_s, atol=1e-9)


def test_a_byte_counter_of_a_slow_slave_clock_keeps_its_wraps_for_an_hour():
    """A slave crystal 100 ppm slower than the host's: every travel grows 0.1 ms a second; after 37 minutes it had
    grown by the margin of 224 ms and each sample was taken 256 ms on (a phantom wrap)."""
    clock = DaqClock(1, 1e-3)
    host_s = np.arange(0, 3600, 0.1)
    slave_ticks = np.rint(host_s * (1 - 1e-4) * 1e3).astype(np.int64)
    host_ns = (9_000_000_000 + (host_s + 0.0005) * 1e9).astype(np.int64)
    seconds = np.concatenate([clock.times(0, slave_ticks[i:i + 100] % 256, host_ns[i:i + 100])[0]
                              for i in range(0, len(host_s), 100)])
    assert np.allclose(seconds, slave_ticks * 1e-3, atol=1e-9)


def test_without_timestamps_the_host_clock_is_used():
    clock = DaqClock(0, 1e-5)
    seconds, host = clock.times(0, None, np.array([2_000_000_000, 2_500_000_000]))
    assert seconds.tolist() == [0.0, 0.5] and host.tolist() == [2.0, 2.5]


def test_a_faster_sample_moves_the_host_time_on_without_going_back():
    """The first samples of a 4 ms list sat 6 ms in a loaded host's queue, the next batch's first travelled
    fastest: its host time may not go back before the samples already shown, the correction is spread over the
    samples after it (at most half their time), and then it holds."""
    clock = DaqClock(4, 1e-5)
    true_s = np.arange(0, 0.1, 0.004)
    counts = np.rint(true_s / 1e-5).astype(np.int64)
    travel_s = np.where(np.arange(len(true_s)) < 5, 0.0065, 0.0005)
    host_ns = (2_000_000_000 + (true_s + travel_s) * 1e9).astype(np.int64)
    host = np.concatenate([clock.times(0, counts[i:i + 5], host_ns[i:i + 5])[1] for i in range(0, len(counts), 5)])
    assert np.all(np.diff(host) >= 0.002 - 1e-9)  # never back: at least half of the slave's 4 ms
    assert np.allclose(host[-10:] - true_s[-10:], 2.0005, atol=1e-9)  # then the fastest travel's offset
