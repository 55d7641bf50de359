"""What an expectation asks of a signal: bands, values, texts, opposites, as the log and the plots show them."""

from __future__ import annotations

import numpy as np
import pytest

from workbench.errors import InputError
from workbench.testbench import at_least, at_most, equals, other_than, within
from workbench.testbench.conditions import as_condition


def test_bands_and_bounds():
    values = np.array([23.9, 24.0, 25.0, 26.0, 26.1])
    assert within(24, 26).test(values).tolist() == [False, True, True, True, False]
    assert at_least(25).test(values).tolist() == [False, False, True, True, True]
    assert at_most(24).test(values).tolist() == [True, True, False, False, False]
    assert within(24, 26).describe("bar") == "within [24, 26] bar" and at_least(0.5).describe("V") == ">= 0.5 V"
    assert within(24, 26).band() == (24.0, 26.0) and at_most(3).band() == (-np.inf, 3.0)
    with pytest.raises(InputError, match="low bound is above"):
        within(2, 1)


def test_values_texts_and_opposites():
    assert equals(33.33, 0.006).test(np.array([33.325, 33.34])).tolist() == [True, False]
    assert equals(33.33, 0.006).describe("bar") == "= 33.33 ± 0.006 bar"
    states = np.array(["OFF", "TANK1_ON", b"TANK1_ON"], dtype=object)
    assert equals("TANK1_ON").test(states).tolist() == [False, True, True]
    assert other_than("OFF").test(states).tolist() == [False, True, True]
    assert other_than("CAN_RX_TIMEOUT_ERR").describe() == "!= CAN_RX_TIMEOUT_ERR"
    assert equals("ON").band() is None and other_than(1).band() == (1.0, 1.0)


def test_shorthands():
    assert as_condition((1, 2)) == within(1, 2)
    assert as_condition("ON") == equals("ON") and as_condition(0) == equals(0)
    assert as_condition(at_least(3)) == at_least(3)
