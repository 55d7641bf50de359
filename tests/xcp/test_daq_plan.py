"""DAQ planning against slaves with different limits: every byte placed once, no limit exceeded; static
lists: each event in a list that takes it, within that list's ODTs and entries, or a refusal that says why."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from workbench.errors import InputError
from workbench.xcp.daq.assign import assign_static_lists
from workbench.xcp.daq.plan import DaqSignal, plan_daq
from workbench.xcp.info import DaqListInfo, DaqProcessorInfo, DaqResolutionInfo


def processor(identification="ABSOLUTE", max_daq=16, timestamps=True, dynamic=True) -> DaqProcessorInfo:
    return DaqProcessorInfo(dynamic=dynamic, prescaler_supported=False, resume_supported=False,
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
                for i in range(0 if entry.filler else entry.size):
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


def test_max_daq_is_no_limit_of_a_dynamic_plan():
    """A dynamic configuration may count in MAX_DAQ only the lists allocated so far (0 before ALLOC_DAQ):
    ALLOC_DAQ tells whether the lists fit, not the plan."""
    signals = {e: [DaqSignal(e, 0x10 * e, 1)] for e in range(3)}
    plan = plan_daq(signals, processor=processor(max_daq=0), resolution=resolution(), max_dto=8)
    assert [daq.number for daq in plan.lists] == [0, 1, 2]


def test_a_relative_odt_number_is_a_pid_too():
    signals = {0: [DaqSignal("big", 0x1000, 6 * 253, element_size=2)]}
    with pytest.raises(InputError, match="holds 252 at most"):
        plan_daq(signals, processor=processor("RELATIVE_BYTE"), resolution=resolution(timestamp_size=0), max_dto=8)


def test_timestamps_that_leave_no_room_for_data_are_left_out_unless_fixed():
    """RELATIVE_WORD_ALIGNED (4 bytes) and a 4-byte timestamp fill a CAN DTO: the samples go by arrival time."""
    plan = plan_daq({0: [DaqSignal("x", 0, 1)]}, processor=processor("RELATIVE_WORD_ALIGNED"),
                    resolution=resolution(timestamp_size=4), max_dto=8)
    assert plan.timestamp_size == 0 and not plan.lists[0].timestamps
    fixed = DaqResolutionInfo(1, 4, 4, True, 1e-5, 1)
    with pytest.raises(InputError, match="no room for data"):
        plan_daq({0: [DaqSignal("x", 0, 1)]}, processor=processor("RELATIVE_WORD_ALIGNED"), resolution=fixed, max_dto=8)


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


# --- static DAQ lists ---------------------------------------------------------------------------------

def static_list(number, odts, entries, fixed_event=None, predefined=False, direction="DAQ") -> DaqListInfo:
    return DaqListInfo(number, predefined, fixed_event, direction, odts, entries)


STATIC = dict(processor=processor(dynamic=False), resolution=resolution(), max_dto=8)


def floats(event, count, base=0x1000):
    return [DaqSignal((event, i), base + 0x100 * event + 0x10 * i, 4) for i in range(count)]


def check_static(plan, lists, signals):
    """Each event in its own list, one that takes it, within its ODTs and entries; no ODT starts empty."""
    by_number = {info.number: info for info in lists}
    assert plan.static and len({daq.number for daq in plan.lists}) == len(plan.lists) == len(signals)
    for daq in plan.lists:
        info = by_number[daq.number]
        assert info.fixed_event in (None, daq.event) and not info.predefined and "DAQ" in info.direction
        assert len(daq.odts) <= info.max_odt
        assert all(0 < len(odt.entries) <= info.max_odt_entries for odt in daq.odts)


def test_a_fixed_event_list_takes_its_event_and_the_smallest_fitting_list_the_other():
    lists = [static_list(0, 10, 4), static_list(1, 4, 3, fixed_event=1), static_list(2, 3, 4)]
    signals = {0: floats(0, 2), 1: floats(1, 2)}
    plan = plan_daq(signals, **STATIC, static_lists=lists)
    check_limits(plan, STATIC, signals)
    check_static(plan, lists, signals)
    assert {daq.event: daq.number for daq in plan.lists} == {0: 2, 1: 1}  # list 0 stays free for a big group


def test_an_event_too_big_for_every_list_is_refused_with_the_reasons():
    lists = [static_list(0, 2, 4), static_list(1, 8, 4, fixed_event=1), static_list(2, 4, 4, predefined=True)]
    with pytest.raises(InputError) as refused:
        plan_daq({0: floats(0, 5)}, **STATIC, static_lists=lists, consistency={0: "ODT"})
    assert str(refused.value) == (
        "the slave's static DAQ lists cannot take this measurement: event 0 fits no list (list 0 has 2 ODTs of 4 "
        "entries, the signals need 6; list 1 samples event 1 only); measure fewer signals or events at once")


def test_two_events_that_fit_only_one_list_are_refused_naming_the_taker():
    lists = [static_list(0, 6, 4), static_list(1, 2, 4)]
    with pytest.raises(InputError, match=r"event [01] fits only list 0 \(taken by event [01]\)"):
        plan_daq({0: floats(0, 4), 1: floats(1, 4)}, **STATIC, static_lists=lists)


def test_the_assignment_moves_an_event_to_make_room():
    lists = [static_list(0, 2, 4), static_list(1, 10, 1), static_list(2, 3, 2)]
    # ODTs each event needs per entry limit: event 0 fits lists 0 and 1 (prefers the smaller 0), events 1 and 2
    # fit lists 0 and 2 only; taking the first fit in turn would leave event 2 without a list
    needs = {0: {4: 2, 1: 2, 2: 5}, 1: {4: 2, 1: 11, 2: 3}, 2: {4: 2, 1: 11, 2: 3}}
    chosen = assign_static_lists([0, 1, 2], lists, lambda event, info: needs[event][info.max_odt_entries])
    assert {event: info.number for event, info in chosen.items()} in ({0: 1, 1: 0, 2: 2}, {0: 1, 1: 2, 2: 0})


def test_predefined_and_stim_lists_are_never_filled():
    lists = [static_list(0, 8, 4, predefined=True), static_list(1, 8, 4, direction="STIM")]
    with pytest.raises(InputError, match="none of the slave's 2 static DAQ lists can be filled"):
        plan_daq({0: floats(0, 1)}, **STATIC, static_lists=lists)


def test_a_static_list_never_starts_with_an_empty_odt():
    signals = {0: floats(0, 3)}  # ODT consistency: no float fits the 3 bytes beside the timestamp
    plan = plan_daq(signals, **STATIC, static_lists=[static_list(0, 8, 2)], consistency={0: "ODT"})
    (daq,) = plan.lists
    (filler,) = daq.odts[0].entries
    assert filler.filler and filler.size == 1 and len(daq.odts) == 4
    check_limits(plan, STATIC, signals)
    assert all(daq.positions[key].min() >= 1 for key in daq.positions)  # no signal is read from the filler
    dynamic = plan_daq(signals, **DEMO, consistency={0: "ODT"})
    assert dynamic.lists[0].odts[0].entries == ()  # a dynamic list may allocate an empty ODT


def test_max_odt_entries_splits_a_run_of_neighbours():
    signals = {0: [DaqSignal(i, 0x100 + i, 1) for i in range(7)]}  # one 7-byte run: entries of 4 and 3
    plan = plan_daq(signals, **STATIC, static_lists=[static_list(0, 8, 1)], timestamps=False)
    check_limits(plan, STATIC, signals)
    assert [[(e.address, e.size) for e in odt.entries] for odt in plan.lists[0].odts] == [[(0x100, 4)], [(0x104, 3)]]


def test_a_static_slave_needs_its_lists():
    with pytest.raises(ValueError, match="static_lists"):
        plan_daq({0: floats(0, 1)}, **STATIC)


def _assignable(signals, lists, limits, consistency) -> bool:
    """Whether some assignment of events to lists exists, each pair decided by planning that event alone."""
    def fits(event, info):
        try:
            plan_daq({event: signals[event]}, **limits, consistency={event: consistency}, static_lists=[info])
        except InputError:
            return False
        return True

    events = list(signals)
    ok = {(event, info.number) for event in events for info in lists if fits(event, info)}
    return any(all((event, info.number) in ok for event, info in zip(events, chosen))
               for chosen in itertools.permutations(lists, len(events)))


@settings(max_examples=120, deadline=None)
@given(
    groups=st.dictionaries(st.integers(0, 2), st.lists(st.tuples(st.integers(0, 60), st.sampled_from([1, 2, 4, 8]),
                                                                 st.integers(1, 3)), min_size=1, max_size=10),
                           min_size=1, max_size=3),
    shapes=st.lists(st.tuples(st.integers(1, 12), st.integers(1, 8), st.one_of(st.none(), st.integers(0, 2)),
                              st.booleans()), min_size=1, max_size=4),
    identification=st.sampled_from(["ABSOLUTE", "RELATIVE_BYTE", "RELATIVE_WORD_ALIGNED"]),
    granularity=st.sampled_from([1, 2, 4]),
    max_entry=st.sampled_from([4, 8, 255]),
    max_dto=st.sampled_from([8, 64]),
    timestamp_size=st.sampled_from([0, 2, 4]),
    consistency=st.sampled_from(["ODT", "DAQ"]),
)
def test_random_signals_fit_random_static_lists(groups, shapes, identification, granularity, max_entry, max_dto,
                                                timestamp_size, consistency):
    limits = dict(processor=processor(identification, dynamic=False),
                  resolution=resolution(granularity, max_entry, timestamp_size), max_dto=max_dto)
    lists = [static_list(n, odts, entries, fixed, predefined=n > 0 and predefined)
             for n, (odts, entries, fixed, predefined) in enumerate(shapes)]
    signals = {event: [DaqSignal((event, i), 0x10000 * (event + 1) + offset * 4, element * count, element_size=element)
                       for i, (offset, element, count) in enumerate(sizes)] for event, sizes in groups.items()}
    try:
        plan = plan_daq(signals, **limits, consistency=dict.fromkeys(signals, consistency), static_lists=lists)
    except InputError:
        assert not _assignable(signals, lists, limits, consistency)  # refused only when nothing fits
        return
    check_limits(plan, limits, signals)
    check_static(plan, lists, signals)
