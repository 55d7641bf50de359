"""The demo DBCs load cleanly and every message survives an encode/decode round trip."""

from __future__ import annotations

import functools
import logging
import warnings

import cantools
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from workbench import demo

DBC_PATHS = [demo.dbc_can2(), demo.dbc_can3()]


def _load(path):
    return cantools.database.load_file(str(path), strict=True)


@functools.cache
def _database(path):
    return _load(path)


def _messages():
    return [pytest.param(path, message.name, id=f"{path.stem}:{message.name}") for path in DBC_PATHS for message in _database(path).messages]


@pytest.mark.parametrize("path", DBC_PATHS, ids=lambda p: p.name)
def test_dbc_loads_strictly_without_warnings(path, caplog):
    with warnings.catch_warnings(record=True) as caught, caplog.at_level(logging.WARNING):
        warnings.simplefilter("always")
        database = _load(path)
    assert database.messages
    assert [str(w.message) for w in caught] == []
    assert [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING] == []


@pytest.mark.parametrize("path", DBC_PATHS, ids=lambda p: p.name)
def test_every_signal_states_its_physical_range(path):
    for message in _load(path).messages:
        for signal in message.signals:
            assert signal.minimum is not None and signal.maximum is not None, f"{message.name}.{signal.name}"
            raw_lo, raw_hi = (-(2 ** (signal.length - 1)), 2 ** (signal.length - 1) - 1) if signal.is_signed else (0, 2**signal.length - 1)
            for limit in (signal.minimum, signal.maximum):
                raw = (limit - signal.offset) / signal.scale
                assert raw_lo <= raw <= raw_hi, f"{message.name}.{signal.name}: {limit} does not fit {signal.length} bits"


def _physical_values(message):
    return st.fixed_dictionaries(
        {signal.name: st.floats(signal.minimum, signal.maximum, allow_nan=False) for signal in message.signals}
    )


@pytest.mark.parametrize(("path", "message_name"), _messages())
@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_message_round_trip(path, message_name, data):
    message = _database(path).get_message_by_name(message_name)
    values = data.draw(_physical_values(message))
    payload = message.encode(values, strict=True)
    assert len(payload) == message.length
    decoded = message.decode(payload, decode_choices=False)
    for signal in message.signals:
        # cantools rounds the raw value, so the physical value is off by half a step at most
        tolerance = signal.scale / 2 + 1e-9 * max(1.0, abs(values[signal.name]))
        assert abs(decoded[signal.name] - values[signal.name]) <= tolerance, signal.name
