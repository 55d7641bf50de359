"""The polled read's decoder (``value_decoder``) gives what the full decode gives, value and type, for every data
type, byte order and kind of conversion of a VALUE, with a BIT_MASK, for the other kinds, and for every calibration
of the demo A2L, over random bytes."""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from workbench import demo
from workbench.a2l import load_a2l, load_a2l_string
from workbench.calib import object_layout
from workbench.calib.codec import value_decoder

DATATYPES = ("UBYTE", "SBYTE", "UWORD", "SWORD", "ULONG", "SLONG", "A_UINT64", "A_INT64", "FLOAT16_IEEE",
             "FLOAT32_IEEE", "FLOAT64_IEEE")
BYTE_ORDERS = ("MSB_FIRST", "MSB_LAST", "MSB_FIRST_MSW_LAST", "MSB_LAST_MSW_FIRST")
CONVERSIONS = ("NO_COMPU_METHOD", "ident", "lin", "rat", "verb")


@lru_cache(maxsize=None)
def model_for(datatype: str, byte_order: str):
    text = f"""ASAP2_VERSION 1 71
/begin PROJECT P "" /begin MODULE M ""
/begin MOD_COMMON "" BYTE_ORDER {byte_order} /end MOD_COMMON
/begin COMPU_METHOD ident "" IDENTICAL "%6.2" "" /end COMPU_METHOD
/begin COMPU_METHOD lin "" LINEAR "%6.2" "bar" COEFFS_LINEAR 0.5 -3 /end COMPU_METHOD
/begin COMPU_METHOD rat "" RAT_FUNC "%6.2" "" COEFFS 0 4 1 0 0 2 /end COMPU_METHOD
/begin COMPU_METHOD verb "" TAB_VERB "%6.2" "" COMPU_TAB_REF states /end COMPU_METHOD
/begin COMPU_VTAB states "" TAB_VERB 2 0 "OFF" 1 "ON" DEFAULT_VALUE "other" /end COMPU_VTAB
/begin RECORD_LAYOUT V FNC_VALUES 1 {datatype} ROW_DIR DIRECT /end RECORD_LAYOUT
{"".join(f'/begin CHARACTERISTIC {c.lower()} "" VALUE 0x100 V 0 {c} 0 1 /end CHARACTERISTIC{chr(10)}'
         for c in CONVERSIONS)}
/begin CHARACTERISTIC masked "" VALUE 0x100 V 0 NO_COMPU_METHOD 0 1 BIT_MASK 0x6 /end CHARACTERISTIC
/begin CHARACTERISTIC blk "" VAL_BLK 0x100 V 0 lin 0 1 MATRIX_DIM 2 /end CHARACTERISTIC
/end MODULE /end PROJECT
"""
    return load_a2l_string(text).model()


def same(fast, full) -> bool:
    if isinstance(full, np.ndarray):
        return isinstance(fast, np.ndarray) and np.array_equal(fast, full, equal_nan=True)
    if isinstance(full, float) and math.isnan(full):
        return isinstance(fast, float) and math.isnan(fast)
    return type(fast) is type(full) and fast == full


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # random bytes are inf and NaN too: arithmetic on them warns
@settings(max_examples=200, deadline=None)
@given(st.sampled_from(DATATYPES), st.sampled_from(BYTE_ORDERS),
       st.sampled_from([c.lower() for c in CONVERSIONS] + ["masked", "blk"]), st.binary(min_size=16, max_size=16))
def test_the_fast_decoder_gives_what_decode_gives(datatype, byte_order, name, data):
    resolved = object_layout(model_for(datatype, byte_order), name).resolve()
    data = data[:resolved.span().size]
    full = resolved.decode({resolved.span(): data}).value
    assert same(value_decoder(resolved)(data), full), (datatype, byte_order, name, data.hex())


def test_every_calibration_of_the_demo_in_one_span_decodes_alike():
    model = load_a2l(demo.a2l()).model()
    rng = np.random.default_rng(21)
    checked = 0
    for name in model.names("CHARACTERISTIC"):
        layout = object_layout(model, name)
        if layout.needs_counts:
            continue
        resolved = layout.resolve()
        if resolved.spans() != [resolved.span()]:
            continue
        data = rng.integers(0, 256, resolved.span().size, dtype=np.uint8).tobytes()
        assert same(value_decoder(resolved)(data), resolved.decode({resolved.span(): data}).value), name
        checked += 1
    assert checked > 50
