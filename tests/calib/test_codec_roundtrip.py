"""Encode then decode gives the value back, for every data type, byte order, index mode, alignment and
bit mask, over memory that starts with random bytes; only the object's own bytes change."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from workbench.a2l import load_a2l_string
from workbench.a2l.datatypes import datatype_range
from workbench.calib import Axis, CalValue, Span, object_layout, read_spans

DATATYPES = ("UBYTE", "SBYTE", "UWORD", "SWORD", "ULONG", "SLONG", "A_UINT64", "A_INT64", "FLOAT16_IEEE",
             "FLOAT32_IEEE", "FLOAT64_IEEE")
BYTE_ORDERS = ("MSB_FIRST", "MSB_LAST", "MSB_FIRST_MSW_LAST", "MSB_LAST_MSW_FIRST")
MODES = ("ROW_DIR", "COLUMN_DIR")
ALIGNMENTS = (1, 2, 4, 8)
SIZE = 0x600


@lru_cache(maxsize=None)
def model_for(datatype: str, byte_order: str, mode: str, alignment: int):
    aligned = " ".join(f"ALIGNMENT_{slot} {alignment}" for slot in (
        "WORD", "LONG", "INT64", "FLOAT16_IEEE", "FLOAT32_IEEE", "FLOAT64_IEEE"))
    text = f"""ASAP2_VERSION 1 71
/begin PROJECT P "" /begin MODULE M ""
/begin MOD_COMMON "" BYTE_ORDER {byte_order} ALIGNMENT_BYTE 1 {aligned} /end MOD_COMMON
/begin RECORD_LAYOUT V FNC_VALUES 1 {datatype} {mode} DIRECT /end RECORD_LAYOUT
/begin RECORD_LAYOUT K NO_AXIS_PTS_X 1 UBYTE NO_AXIS_PTS_Y 2 UBYTE AXIS_PTS_X 3 {datatype} INDEX_INCR DIRECT
  AXIS_PTS_Y 4 {datatype} INDEX_DECR DIRECT FNC_VALUES 5 {datatype} {mode} DIRECT /end RECORD_LAYOUT
/begin CHARACTERISTIC val "" VALUE 0x101 V 0 NO_COMPU_METHOD 0 1 /end CHARACTERISTIC
/begin CHARACTERISTIC blk "" VAL_BLK 0x201 V 0 NO_COMPU_METHOD 0 1 MATRIX_DIM 3 2 4 /end CHARACTERISTIC
/begin CHARACTERISTIC map "" MAP 0x401 K 0 NO_COMPU_METHOD 0 1
  /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 4 0 1 /end AXIS_DESCR
  /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 3 0 1 /end AXIS_DESCR
/end CHARACTERISTIC
/end MODULE /end PROJECT
"""
    return load_a2l_string(text).model()


def elements(datatype: str, shape: tuple[int, ...]):
    """Arrays of values a ``datatype`` holds exactly (NaN left out: its payload is not a value)."""
    count = int(np.prod(shape)) if shape else 1
    limits = datatype_range(datatype)
    if limits is not None:
        items = st.integers(*limits)
        dtype = np.uint64 if datatype == "A_UINT64" else np.int64
    else:
        width = {"FLOAT16_IEEE": 16, "FLOAT32_IEEE": 32, "FLOAT64_IEEE": 64}[datatype]
        items = st.floats(allow_nan=False, width=width)
        dtype = np.float64
    return st.lists(items, min_size=count, max_size=count).map(lambda v: np.array(v, dtype=dtype).reshape(shape))


def noise(data, size: int = SIZE) -> bytearray:
    """Memory full of random bytes (drawn as a seed: a large binary would choke the shrinker)."""
    return bytearray(np.random.default_rng(data.draw(st.integers(0, 2**32 - 1))).bytes(size))


configs = st.tuples(st.sampled_from(DATATYPES), st.sampled_from(BYTE_ORDERS), st.sampled_from(MODES),
                    st.sampled_from(ALIGNMENTS))


def round_trip(model, name: str, value, memory: bytearray):
    """Write ``value`` into ``memory`` (edits over its current bytes), read it back; returns what was read."""
    read = lambda span: bytes(memory[span.address:span.end])  # noqa: E731
    layout = object_layout(model, name)
    resolved = layout.resolve(read_spans(layout.fixed_part(), read))
    for edit in resolved.encode(value, read_spans(resolved.spans(), read)):
        memory[edit.address:edit.address + len(edit.data)] = edit.data
    layout = object_layout(model, name)
    resolved = layout.resolve(read_spans(layout.fixed_part(), read))
    return resolved.decode(read_spans(resolved.spans(), read)), resolved


@settings(max_examples=300, deadline=None)
@given(configs, st.data())
def test_values_and_blocks_round_trip(config, data):
    model = model_for(*config)
    datatype = config[0]
    memory = noise(data)
    before = bytes(memory)
    scalar = data.draw(elements(datatype, ()))
    got, layout = round_trip(model, "val", scalar.reshape(()).item(), memory)
    assert got.value == scalar.reshape(()).item()
    block = data.draw(elements(datatype, (3, 2, 4)))
    got, block_layout = round_trip(model, "blk", block, memory)
    assert np.array_equal(got.value, block)
    touched = {layout.span(), block_layout.span()}
    untouched = [i for i in range(SIZE) if not any(s.address <= i < s.end for s in touched)]
    assert bytes(memory[i] for i in untouched) == bytes(before[i] for i in untouched)


@settings(max_examples=300, deadline=None)
@given(configs, st.integers(1, 4), st.integers(1, 3), st.data())
def test_maps_with_their_counts_in_memory_round_trip(config, nx, ny, data):
    model = model_for(*config)
    datatype = config[0]
    memory = noise(data)
    memory[0x401], memory[0x402] = data.draw(st.integers(1, 4)), data.draw(st.integers(1, 3))  # a valid start
    values = data.draw(elements(datatype, (nx, ny)))
    x, y = data.draw(elements(datatype, (nx,))), data.draw(elements(datatype, (ny,)))
    value = CalValue("map", "MAP", values, (Axis(x), Axis(y)))
    got, layout = round_trip(model, "map", value, memory)
    assert layout.counts == (nx, ny)
    assert np.array_equal(got.value, values)
    assert np.array_equal(got.axes[0].values, x.astype(np.float64)) or np.array_equal(got.axes[0].values, x)
    assert np.array_equal(got.axes[1].values, y.astype(np.float64)) or np.array_equal(got.axes[1].values, y)


@lru_cache(maxsize=None)
def masked_model(datatype: str, byte_order: str, mask: int):
    text = f"""/begin PROJECT P "" /begin MODULE M ""
/begin MOD_COMMON "" BYTE_ORDER {byte_order} /end MOD_COMMON
/begin RECORD_LAYOUT V FNC_VALUES 1 {datatype} ROW_DIR DIRECT /end RECORD_LAYOUT
/begin CHARACTERISTIC bits "" VALUE 0x11 V 0 NO_COMPU_METHOD -1e20 1e20 BIT_MASK 0x{mask:X} /end CHARACTERISTIC
/end MODULE /end PROJECT"""
    return load_a2l_string(text).model()


integer_types = st.sampled_from(DATATYPES[:8])


@settings(max_examples=400, deadline=None)
@given(integer_types, st.sampled_from(BYTE_ORDERS), st.data())
def test_bit_masks_write_their_bits_only(datatype, byte_order, data):
    bits = 8 * {"UBYTE": 1, "SBYTE": 1, "UWORD": 2, "SWORD": 2, "ULONG": 4, "SLONG": 4}.get(datatype, 8)
    shift = data.draw(st.integers(0, bits - 1))
    width = data.draw(st.integers(1, bits - shift))
    mask = ((1 << width) - 1) << shift
    signed = datatype in ("SBYTE", "SWORD", "SLONG", "A_INT64")
    low, high = (-(1 << (width - 1)), (1 << (width - 1)) - 1) if signed else (0, (1 << width) - 1)
    field = data.draw(st.integers(low, high))
    memory = noise(data, 64)
    size = bits // 8
    before = int.from_bytes(_plain(memory[0x11:0x11 + size], byte_order), "big")
    got, _ = round_trip(masked_model(datatype, byte_order, mask), "bits", field, memory)
    after = int.from_bytes(_plain(memory[0x11:0x11 + size], byte_order), "big")
    assert got.value == field
    assert after & ~mask == before & ~mask  # the other bits stay
    assert (after & mask) >> shift == field & ((1 << width) - 1)


def _plain(data: bytes, byte_order: str) -> bytes:
    """Stored bytes as big-endian."""
    data = bytes(data)
    if byte_order in ("MSB_FIRST_MSW_LAST", "MSB_LAST_MSW_FIRST") and len(data) > 2:
        data = b"".join(data[i:i + 2] for i in range(len(data) - 2, -1, -2))
    return data[::-1] if byte_order in ("MSB_LAST", "MSB_LAST_MSW_FIRST") else data


def test_spans_cover_every_field():
    model = model_for("UWORD", "MSB_LAST", "ROW_DIR", 2)
    memory = bytearray(SIZE)
    memory[0x401], memory[0x402] = 4, 3
    read = lambda span: bytes(memory[span.address:span.end])  # noqa: E731
    layout = object_layout(model, "map")
    resolved = layout.resolve(read_spans(layout.fixed_part(), read))
    assert resolved.spans() == [Span(0x401, 2 + 1 + 8 + 6 + 24)]  # counts, pad to 0x404, X, Y, 4 x 3 values
