"""Fix pairs and the measurement that shows each signal's live value: the A2L's COMPARISON_QUANTITY link
first, the names for A2Ls without it."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from workbench.a2l import load_a2l, load_a2l_string
from workbench.calib.fixes import find_fix_pairs, fix_pairs_of, live_as_override

ROOT = Path(__file__).resolve().parents[2]
FUEL_LOW = ["cfFUELLEVELLOW_EN", "cfFUELLEVELLOW_VALUE"]


def _pair(pairs, stem):
    return next(pair for pair in pairs if pair.stem == stem)


def test_the_link_names_the_live_measurement_where_no_name_does():
    measurements = ["xsLEDEn", "xsFuelLevel"]
    assert _pair(find_fix_pairs(FUEL_LOW, measurements), "cfFUELLEVELLOW").live is None
    linked = _pair(find_fix_pairs(FUEL_LOW, measurements, links={"cfFUELLEVELLOW_VALUE": "xsLEDEn"}),
                   "cfFUELLEVELLOW")
    assert (linked.live, linked.source, linked.measurement, linked.signal) == ("xsLEDEn", "xsLEDEn", None,
                                                                               "FUELLEVELLOW")
    by_switch = find_fix_pairs(FUEL_LOW, measurements, links={"cfFUELLEVELLOW_EN": "xsLEDEn"})
    assert _pair(by_switch, "cfFUELLEVELLOW").live == "xsLEDEn"  # the _EN's link when the _VALUE has none


def test_the_link_wins_over_a_name_and_a_link_to_nothing_is_ignored():
    names = ["cfFUELLEVEL_EN", "cfFUELLEVEL_VALUE"]
    measurements = ["xsFuelLevel", "xsFuelLevelFilt"]
    assert _pair(find_fix_pairs(names, measurements), "cfFUELLEVEL").live == "xsFuelLevel"  # by its name
    linked = find_fix_pairs(names, measurements, links={"cfFUELLEVEL_VALUE": "xsFuelLevelFilt"})
    assert _pair(linked, "cfFUELLEVEL").live == "xsFuelLevelFilt"
    dangling = find_fix_pairs(names, measurements, links={"cfFUELLEVEL_VALUE": "xsNoSuchSignal"})
    assert _pair(dangling, "cfFUELLEVEL").live == "xsFuelLevel"


def test_a_link_to_the_overridden_measurement_keeps_it_the_signal():
    names = ["cfENABLEFLCU_EN", "cfENABLEFLCU_VALUE"]
    pair = _pair(find_fix_pairs(names, ["csPCM_TO_FLCU_001_EnableFLCU"],
                                links={"cfENABLEFLCU_VALUE": "csPCM_TO_FLCU_001_EnableFLCU"}), "cfENABLEFLCU")
    assert (pair.measurement, pair.source, pair.signal) == ("csPCM_TO_FLCU_001_EnableFLCU", None,
                                                            "csPCM_TO_FLCU_001_EnableFLCU")


@pytest.fixture(scope="module")
def demo_text() -> str:
    return (ROOT / "assets" / "FLCU.a2l").read_text(encoding="utf-8")


def test_every_fix_of_the_demo_a2l_is_linked_to_its_live_measurement(demo_text):
    pairs = fix_pairs_of(load_a2l(ROOT / "assets" / "FLCU.a2l").model())
    assert len(pairs) == 17 and demo_text.count("COMPARISON_QUANTITY") == 17
    assert _pair(pairs, "cfFUELLEVELLOW").live == "xsLEDEn"
    assert _pair(pairs, "cfRAILPSDIAGNOSTICSTATUS").live == "xsRailPSDiagStatus"
    assert _pair(pairs, "zfRAILPRESSURE").live == "zsRailPressure"


def test_an_a2l_without_links_is_read_by_the_names(demo_text):
    """A third-party A2L: no COMPARISON_QUANTITY, the names decide (FuelLevelLow's source is not named so)."""
    plain = re.sub(r"^\s*COMPARISON_QUANTITY \w+\n", "", demo_text, flags=re.M)
    pairs = fix_pairs_of(load_a2l_string(plain, "plain.a2l").model())
    assert _pair(pairs, "cfFUELLEVELLOW").live is None
    assert _pair(pairs, "cfRAILPSDIAGNOSTICSTATUS").live == "xsRailPSDiagStatus"  # its words abbreviated
    assert _pair(pairs, "cfENABLEFLCU").live == "csPCM_TO_FLCU_001_EnableFLCU"
    assert _pair(pairs, "cfFUELLEVEL").live == "xsFuelLevel"


def test_the_live_value_reads_in_the_terms_of_the_override():
    """FuelLevelLow is sent from xsLEDEn (OFF/ON): the override's table calls those raw values Normal/Low."""
    model = load_a2l(ROOT / "assets" / "FLCU.a2l").model()
    pairs = fix_pairs_of(model)
    low = _pair(pairs, "cfFUELLEVELLOW")
    assert [live_as_override(model, low, v) for v in ("ON", "OFF", 1, None)] == ["Low", "Normal", "Low", None]
    assert live_as_override(model, low, 7) == 7 and live_as_override(model, low, "BROKEN") == "BROKEN"  # no such entry
    assert live_as_override(model, _pair(pairs, "cfENABLEFLCU"), "ON") == "Enabled"
    assert live_as_override(model, _pair(pairs, "zfRAILPRESSURE"), 25.06) == 25.06  # a number: the same quantity


def test_a_typo_is_answered_with_names_as_the_a2l_writes_them():
    from workbench.calib.fixes import resolve_fix
    from workbench.errors import UnknownSymbolError

    with pytest.raises(UnknownSymbolError, match=r"did you mean zfRAILPRESSURE, zsRailPressure, cfRAILPRESSURE\?"):
        resolve_fix(fix_pairs_of(load_a2l(ROOT / "assets" / "FLCU.a2l").model()), "zfRAILPRESSUR")
