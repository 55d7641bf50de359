"""Static DAQ lists for a measurement: every event to a list of its own that takes it, or a refusal that says why.

A slave with a static DAQ configuration has a fixed number of lists, each with MAX_ODT ODTs of
MAX_ODT_ENTRIES entries, some tied to one event (EVENT_FIXED). An event's signals fit a list when
the list takes that event and their ODTs, packed with that list's entry limit, number no more than
its MAX_ODT. Which event gets which list is a bipartite matching (augmenting paths): it finds an
assignment whenever one exists, preferring for each event the list fixed to it, then the smallest
list it fits, so that big lists stay free for big groups.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from workbench.errors import InputError
from workbench.xcp.info import DaqListInfo

__all__ = ["assign_static_lists"]


def assign_static_lists(events: Sequence[int], lists: Sequence[DaqListInfo],
                        odts_needed: Callable[[int, DaqListInfo], int],
                        event_name: Callable[[int], str] | None = None) -> dict[int, DaqListInfo]:
    """Event -> the static list it goes to; ``odts_needed(event, info)``: ODTs the event's signals take in that list;
    ``event_name(number)`` names an event in a refusal.

    Predefined, STIM-only and empty lists are never chosen.

    :raises InputError: no assignment places every event; the message names each event left out and
        why: the lists that take it are too small (its need and their size), fixed to other events,
        or all taken by other events.
    """
    usable = [info for info in lists if info.configurable_daq]
    if not usable:
        raise InputError(f"none of the slave's {len(lists)} static DAQ lists can be filled for measuring "
                         f"(predefined or STIM only)")
    needs = {(event, info.number): odts_needed(event, info)
             for event in events for info in usable if info.fixed_event in (None, event)}
    candidates = {event: sorted((info for info in usable if needs.get((event, info.number), info.max_odt + 1) <= info.max_odt),
                                key=lambda info: (info.fixed_event != event, info.max_odt * info.max_odt_entries, info.number))
                  for event in events}
    owner: dict[int, int] = {}  # list number -> event

    def place(event: int, visited: set[int]) -> bool:
        for info in candidates[event]:
            if info.number in visited:
                continue
            visited.add(info.number)
            if info.number not in owner or place(owner[info.number], visited):
                owner[info.number] = event
                return True
        return False

    unplaced = [event for event in sorted(events, key=lambda event: len(candidates[event])) if not place(event, set())]
    if unplaced:
        def name(event: int) -> str:
            return f"event {event} ({event_name(event)})" if event_name is not None else f"event {event}"

        reasons = [_why_not(event, usable, candidates[event], needs, owner, name) for event in sorted(unplaced)]
        raise InputError("the slave's static DAQ lists cannot take this measurement: " + "; ".join(reasons)
                         + "; measure fewer signals or events at once")
    by_number = {info.number: info for info in usable}
    return {event: by_number[number] for number, event in owner.items()}


def _why_not(event: int, usable: list[DaqListInfo], candidates: list[DaqListInfo], needs: dict[tuple[int, int], int],
             owner: dict[int, int], name: Callable[[int], str]) -> str:
    if candidates:  # every list it fits went to another event
        return f"{name(event)} fits only " + ", ".join(
            f"list {info.number} (taken by {name(owner[info.number])})" for info in candidates)
    reasons = [f"list {info.number} samples {name(info.fixed_event)} only" if (event, info.number) not in needs else
               f"list {info.number} has {info.max_odt} ODTs of {info.max_odt_entries} entries, "
               f"the signals need {needs[event, info.number]}" for info in usable]
    return f"{name(event)} fits no list ({'; '.join(reasons)})"
