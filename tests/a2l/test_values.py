"""Token values: the vectorized integer reader agrees with the one-at-a-time parser."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from workbench.a2l.values import format_int_like, hex_digits_like, int_or_none, int_values

number = st.one_of(
    st.integers(0, 2**70).map(lambda v: b"%d" % v),
    st.tuples(st.integers(0, 2**70), st.sampled_from([b"0x", b"0X"]), st.integers(1, 20), st.booleans()).map(
        lambda t: t[1] + (b"%0*X" if t[3] else b"%0*x") % (t[2], t[0])),
    st.tuples(st.sampled_from([b"+", b"-"]), st.integers(0, 2**40)).map(lambda t: t[0] + b"%d" % t[1]),
    st.binary(min_size=1, max_size=12).map(lambda b: bytes(c for c in b if c > 0x20) or b"x"),
)


@given(st.lists(number, min_size=1, max_size=30))
def test_int_values_agree_with_int_or_none(tokens):
    data = b" ".join(tokens)
    starts = np.cumsum([0] + [len(t) + 1 for t in tokens[:-1]])
    ends = starts + np.array([len(t) for t in tokens])
    values, read = int_values(data, starts, ends)
    for token, value, was_read in zip(tokens, values.tolist(), read.tolist()):
        expected = int_or_none(token)
        assert (value == expected) if was_read else (expected is None or len(token) > 15 or token[:1] in b"+-"), token


def test_format_keeps_the_spelling():
    assert [format_int_like(old, 0x4031A0) for old in (b"0x00000000", b"0X0", b"0xabcd", b"17", b"-0x1")] == [
        b"0x004031A0", b"0X4031A0", b"0x4031a0", b"4207008", b"0x4031A0"]


@settings(deadline=None)  # no time limit per example: the machine may be loaded
@given(st.lists(st.tuples(number, st.integers(0, 2**63 - 1)), min_size=1, max_size=30))
def test_hex_digits_for_many_tokens_are_what_format_int_like_writes(pairs):
    """The vectorized rewrite of an update's hex addresses: the same bytes as one token at a time,
    for every token it takes (the hex tokens of 1-15 digits the value fits)."""
    tokens = [token for token, _ in pairs]
    data = b" ".join(tokens)
    starts = np.cumsum([0] + [len(t) + 1 for t in tokens[:-1]])
    ends = starts + np.array([len(t) for t in tokens])
    values = np.array([value for _, value in pairs], dtype=np.int64)
    _, read = int_values(data, starts, ends)
    rows = np.flatnonzero(read)
    done, digit_starts, digits = hex_digits_like(data, starts[rows], ends[rows], values[rows])
    written = bytearray(data)
    np.frombuffer(written, np.uint8)[np.concatenate([np.arange(s, e) for s, e in zip(
        digit_starts.tolist(), ends[rows[done]].tolist())] or [np.zeros(0, np.int64)])] = digits
    for row in rows.tolist():
        token, value = tokens[row], int(values[row])
        expected = format_int_like(token, value)
        hexadecimal = token[:2] in (b"0x", b"0X") and value < 16 ** (len(token) - 2)
        if row in rows[done].tolist():
            assert hexadecimal and written[int(starts[row]) : int(ends[row])] == expected, (token, value)
        else:  # left to format_int_like: not hex, too big for its digits, or among the data's last 8 bytes
            assert not hexadecimal or int(starts[row]) + 10 > len(data), token
