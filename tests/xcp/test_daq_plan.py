"""DAQ planning against slaves with different limits: every byte placed once, no limit exceeded."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from workbench.errors import InputError
from workbench.xcp.daq.plan import DaqSignal, plan_daq
from workbench.xcp.info import DaqProcessorInfo, DaqResolutionInfo


def processor(identification="ABSOLUTE", max_daq=16, timestamps=True) -> DaqProcessorInfo:
    return DaqProcessorInfo(dynamic=True, prescaler_supported=False, resume_supported=False,
                            timestamp_supported=timestamps, pid_off_supported=False, overload_indication="none",
                            max_daq=max_daq, max_event_channels=3, min_daq=0, optimisation_type=0,
                            address_extension="free", identification_field=identification)


def resolution(granularity=1, max_entry=4, timestamp_size=4) -> DaqResolutionInfo:
    return DaqResolutionInfo(granularity, max_entry, timestamp_size, False, 1e-5, 1)


DEMO = dict(processor=processor(), resolution=resolution(), max_dto=8)  # the demo ECU on CAN
ETHERNET = dict(processor=processor("RELATIVE_WORD_ALIGNED"), resolution=resolution(4, 252, 4), max_dto=512)


def check_limits(plan, limits, signals):
    pid, ts = plan.pid_size, plan.timestamp_size
    granule, max_entry = limits["resolution"].granularity, limits["resolution"].max_entry_size
    for daq in plan.lists:
        for number, odt in enumerate(daq.odts):
            room = limits["max_dto"] - pid - (ts if number == 0 and daq.timestamps else 0)
            assert odt.size <= room
            assert len(odt.entries) <= room // granule
            for entry in odt.entries:
                assert 0 < entry.size <= max_entry and entry.size % granule == 0 and entry.address % granule == 0
        covered = {}
        for odt in daq.odts:
            offset = sum(o.size for o in daq.odts[:daq.odts.index(odt)])
            for entry in odt.entries:
                for i in range(entry.size):
                    covered.setdefault(entry.address + i, offset + i)
                offset += entry.size
        for signal in signals[daq.event]:
            expected = [covered[signal.address + i] for i in range(signal.size)]
            assert daq.positions[signal.key].tolist() == expected


def test_demo_limits_keep_a_float_in_one_odt_under_odt_consistency():
    signals = {0: [DaqSignal("a", 0x1000, 4), DaqSignal("b", 0x2000, 4), DaqSignal("c", 0x3000, 1)]}
    plan = plan_daq(signals, **DEMO)
    check_limits(plan, DEMO, signals)
    (daq,) = plan.lists
    for name in ("a", "b"):  # 4 bytes each: never cut between ODTs
        positions = daq.positions[name]
        boundaries = np.cumsum([odt.size for odt in daq.odts])
        assert all(not (positions[0] < b <= positions[-1]) for b in boundaries)
    assert daq.odts[0].size <= 3  # the timestamp takes 4 of the first ODT's 7 bytes


def test_daq_consistency_fills_every_odt_to_the_last_byte():
    signals = {1: [DaqSignal(f"s{i}", 0x1000 + 0x10 * i, 4) for i in range(5)]}
    plan = plan_daq(signals, **DEMO, consistency={1: "DAQ"})
    check_limits(plan, DEMO, signals)
    sizes = [odt.size for odt in plan.lists[0].odts]
    assert sizes == [3, 7, 7, 3]  # 20 bytes in 4 frames, the least possible


def test_neighbours_share_entries():
    signals = {0: [DaqSignal("lo", 0x100, 1), DaqSignal("hi", 0x101, 1), DaqSignal("w", 0x102, 2)]}
    plan = plan_daq(signals, **DEMO, timestamps=False)
    check_limits(plan, DEMO, signals)
    assert [(e.address, e.size) for odt in plan.lists[0].odts for e in odt.entries] == [(0x100, 4)]


def test_a_foreign_ethernet_slave_gets_big_odts_and_its_granularity():
    signals = {5: [DaqSignal("byte", 0x2001, 1), DaqSignal("arr", 0x3000, 400, element_size=4),
                   DaqSignal("dbl", 0x4000, 8)]}
    plan = plan_daq(signals, **ETHERNET)
    check_limits(plan, ETHERNET, signals)
    assert plan.pid_size == 4 and len(plan.lists[0].odts) == 1  # 1 + 400 + 8 bytes fit one 512-byte DTO
    assert (0x2000, 4) in [(e.address, e.size) for e in plan.lists[0].odts[0].entries]  # widened to a DWORD


def test_a_double_on_classic_can_is_split_into_entries():
    signals = {0: [DaqSignal("dbl", 0x4000, 8)]}
    plan = plan_daq(signals, **DEMO)
    check_limits(plan, DEMO, signals)


def test_one_list_per_event_numbered_from_the_first_dynamic_list():
    signals = {2: [DaqSignal("x", 0x10, 4)], 0: [DaqSignal("y", 0x20, 4)]}
    plan = plan_daq(signals, **DEMO, first_list=3)
    assert [(daq.number, daq.event) for daq in plan.lists] == [(3, 0), (4, 2)]


def test_too_many_odts_for_absolute_pids_is_refused():
    signals = {0: [DaqSignal("big", 0x1000, 4 * 300, element_size=4)]}
    with pytest.raises(InputError, match="ODTs .*absolute ODT numbers allow 252"):
        plan_daq(signals, **DEMO)


def test_too_many_lists_is_refused():
    signals = {e: [DaqSignal(e, 0x10 * e, 1)] for e in range(3)}
    with pytest.raises(InputError, match="MAX_DAQ"):
        plan_daq(signals, processor=processor(max_daq=2), resolution=resolution(), max_dto=8)


def test_no_room_for_data_is_refused():
    with pytest.raises(InputError, match="no room for data"):
        plan_daq({0: [DaqSignal("x", 0, 1)]}, processor=processor("RELATIVE_WORD_ALIGNED"),
                 resolution=resolution(timestamp_size=4), max_dto=8)


@settings(max_examples=150, deadline=None)
@given(
    sizes=st.lists(st.tuples(st.integers(0, 300), st.sampled_from([1, 2, 4, 8]), st.integers(1, 6)), min_size=1, max_size=25),
    identification=st.sampled_from(["ABSOLUTE", "RELATIVE_BYTE", "RELATIVE_WORD", "RELATIVE_WORD_ALIGNED"]),
    granularity=st.sampled_from([1, 2, 4]),
    max_entry=st.sampled_from([4, 8, 255]),
    max_dto=st.sampled_from([8, 64, 512]),
    timestamp_size=st.sampled_from([0, 1, 2, 4]),
    consistency=st.sampled_from(["ODT", "DAQ"]),
)
def test_random_signals_fit_random_slaves(sizes, identification, granularity, max_entry, max_dto, timestamp_size,
                                          consistency):
    limits = dict(processor=processor(identification), resolution=resolution(granularity, max_entry, timestamp_size),
                  max_dto=max_dto)
    signals = {0: [DaqSignal(i, 0x1000 + offset * 4, element * count, element_size=element)
                   for i, (offset, element, count) in enumerate(sizes)]}
    try:
        plan = plan_daq(signals, **limits, consistency={0: consistency})
    except InputError:
        return  # too many ODTs for these limits: refused, not mis-planned
    check_limits(plan, limits, signals)


def test_a_prescaler_needs_the_slave_to_offer_one():
    signals = {0: [DaqSignal("x", 0x10, 4)]}
    with pytest.raises(InputError, match="no prescaler"):
        plan_daq(signals, **DEMO, prescaler=4)
    offering = DaqProcessorInfo(**{**processor().__dict__, "prescaler_supported": True})
    plan = plan_daq(signals, processor=offering, resolution=resolution(), max_dto=8, prescaler=4)
    assert plan.lists[0].prescaler == 4
