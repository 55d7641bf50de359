"""A2L token values: numbers, strings and identifiers, parsed and formatted in the file's style."""

from __future__ import annotations

import re

import numpy as np

__all__ = ["FLOAT_RE", "IDENT_RE", "INT_RE", "format_int_like", "format_ints_like", "hex_digits_like", "int_or_none",
           "int_values", "is_ident", "is_int", "is_number", "is_string", "parse_int", "parse_number", "parse_string",
           "quote_string"]

INT_RE = re.compile(rb"[+-]?(?:0[xX][0-9a-fA-F]+|[0-9]+)")
FLOAT_RE = re.compile(rb"[+-]?(?:0[xX][0-9a-fA-F]+|(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|(?i:inf|nan))")
IDENT_RE = re.compile(rb"[A-Za-z_][A-Za-z0-9_.\[\]]*")
_UNESCAPES = {b'\\"': '"', b"\\\\": "\\", b'""': '"', b"\\n": "\n", b"\\t": "\t", b"\\r": "\r", b"\\'": "'"}
_ESCAPE_RE = re.compile(rb'\\["\\ntr\']|""')


def is_int(raw: bytes) -> bool:
    return INT_RE.fullmatch(raw) is not None


def is_number(raw: bytes) -> bool:
    return FLOAT_RE.fullmatch(raw) is not None


def is_string(raw: bytes) -> bool:
    return raw[:1] == b'"'


def is_ident(raw: bytes) -> bool:
    return IDENT_RE.fullmatch(raw) is not None


def parse_int(raw: bytes) -> int:
    """An A2L integer (decimal or 0x hex, optional sign); raises ValueError otherwise."""
    value = int_or_none(raw)
    if value is None:
        raise ValueError(f"not an integer: {raw.decode('latin-1')!r}")
    return value


def int_or_none(raw: bytes) -> int | None:
    """:func:`parse_int`, or None when ``raw`` is not an integer."""
    if INT_RE.fullmatch(raw) is None:
        return None
    return int(raw, 16) if b"x" in raw or b"X" in raw else int(raw, 10)


_MASKS = [np.uint64((1 << 8 * size) - 1) for size in range(9)]  # the low ``size`` bytes of a word
_DIGIT_VALUE = np.full(256, 99, dtype=np.int8)  # 99: not a digit in any base used here
_DIGIT_VALUE[np.frombuffer(b"0123456789", np.uint8)] = np.arange(10)
_DIGIT_VALUE[np.frombuffer(b"abcdef", np.uint8)] = np.arange(10, 16)
_DIGIT_VALUE[np.frombuffer(b"ABCDEF", np.uint8)] = np.arange(10, 16)
_MOST_DIGITS = 15  # 16**15 and 10**15 fit an int64


def int_values(data: bytes, starts: np.ndarray, ends: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The values of many integer tokens ``data[start:end]`` at once: (values, read). ``read`` is
    False where the token is not a plain ``0x`` hex or decimal integer of at most 15 digits (a
    sign, a longer number, not a number): :func:`int_or_none` decides those one by one."""
    buffer = np.frombuffer(data, np.uint8)
    last = len(buffer) - 1
    lengths = ends - starts
    hexadecimal = (lengths > 2) & (buffer[starts] == ord("0")) & (buffer[np.minimum(starts + 1, last)] | 0x20 == ord("x"))
    first_digit = starts + 2 * hexadecimal
    widths = ends - first_digit
    read = (widths >= 1) & (widths <= _MOST_DIGITS)
    values = np.zeros(len(starts), dtype=np.int64)
    for width in np.flatnonzero(np.bincount(widths[read])).tolist():  # a few widths: Horner's rule by column
        rows = np.flatnonzero(read & (widths == width))
        positions = first_digit[rows]
        base = np.where(hexadecimal[rows], 16, 10)
        value = np.zeros(len(rows), dtype=np.int64)
        bad = np.zeros(len(rows), dtype=bool)
        for column in range(width):
            digit = _DIGIT_VALUE[buffer[positions + column]]
            bad |= digit >= base
            value = value * base + digit
        read[rows[bad]] = False
        values[rows] = value
    return values, read


_LETTER_BITS = np.uint64(0x4040404040404040)  # bit 6 of each byte: set in A-F and a-f, clear in 0-9


def hex_digits_like(data: bytes, starts: np.ndarray, ends: np.ndarray, values: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The new digits of ``0x`` hex tokens ``data[start:end]`` that :func:`int_values` reads, for the
    ``values`` that fit their digit count: what :func:`format_ints_like` writes, made for all of them
    at once. Returns (the rows done, where their digits start, the digit bytes of those rows in order,
    as many as each token has); the other rows need :func:`format_ints_like`."""
    buffer = np.frombuffer(data, np.uint8)
    lengths = ends - starts
    widths = lengths - 2
    hexadecimal = (lengths > 2) & (lengths <= 17) & (starts + 2 + 8 <= len(data)) \
        & (buffer[starts] == ord("0")) & (buffer[np.minimum(starts + 1, len(buffer) - 1)] | 0x20 == ord("x"))
    fitting = hexadecimal & (values >= 0) & (values >> (4 * np.minimum(widths, 15)) == 0)
    done, digits = [], []
    words = np.ndarray((len(data) - 7,), "<u8", data, 0, (1,)) if len(data) >= 8 else None
    for width in np.flatnonzero(np.bincount(widths[fitting], minlength=1)).tolist():  # a few widths
        rows = np.flatnonzero(fitting & (widths == width))
        first = starts[rows] + 2
        # the letter case the token was written in: lower when it has a-f and no A-F (as format_ints_like);
        # in a hex digit bit 6 marks a letter, bit 5 a lower-case one (read eight digits at a time)
        heads = words[first] & _MASKS[min(width, 8)]
        tails = words[first + max(width - 8, 0)] & _MASKS[min(width, 8)]
        letters, lowers = (heads | tails) & _LETTER_BITS, ((heads & (heads << 1)) | (tails & (tails << 1))) & _LETTER_BITS
        lower = (lowers != 0) & (lowers == letters)
        shifts = 4 * np.arange(width - 1, -1, -1, dtype=np.int64)
        nibbles = ((values[rows, None] >> shifts) & 0xF).astype(np.uint8)
        digits.append((nibbles + 48 + (nibbles > 9) * (7 + 32 * lower[:, None]).astype(np.uint8)).ravel())
        done.append(rows)
    if not done:
        return np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.uint8)
    done_rows = np.concatenate(done)
    return done_rows, starts[done_rows] + 2, np.concatenate(digits)


def parse_number(raw: bytes) -> int | float:
    """An A2L number: an int when written as one, else a float; raises ValueError otherwise."""
    if is_int(raw):
        return parse_int(raw)
    if not is_number(raw):
        raise ValueError(f"not a number: {raw.decode('latin-1')!r}")
    return float(raw)


def parse_string(raw: bytes, encoding: str) -> str:
    """The text of a quoted A2L string token (quotes removed, escapes resolved)."""
    body = raw[1:-1]
    if b"\\" not in body and b'""' not in body:
        return body.decode(encoding)
    return _ESCAPE_RE.sub(lambda m: _UNESCAPES[m.group()].encode(encoding), body).decode(encoding)


def quote_string(text: str, encoding: str) -> bytes:
    """``text`` as an A2L string token in ``encoding`` (quotes and backslashes escaped)."""
    return b'"' + text.replace("\\", "\\\\").replace('"', '\\"').encode(encoding) + b'"'


def format_int_like(old: bytes, value: int) -> bytes:
    """``value`` written the way ``old`` was: hex stays hex with the same prefix, letter case and
    (where the value fits) digit count; decimal stays decimal."""
    return format_ints_like([old], [value])[0]


def format_ints_like(olds: list[bytes], values: list[int]) -> list[bytes]:
    """:func:`format_int_like` of many tokens (an update rewrites tens of thousands of addresses,
    most written alike: each distinct spelling is worked out once)."""
    templates = {old: _template(old) for old in set(olds)}
    return [templates[old][0] % value if value >= 0 else templates[old][1] % -value
            for old, value in zip(olds, values)]


def _template(old: bytes) -> tuple[bytes, bytes]:
    """printf templates (for values >= 0, for the magnitude of negative ones) in ``old``'s style."""
    if b"x" not in old and b"X" not in old:
        return b"%d", b"-%d"
    head = old.lstrip(b"+-")
    digits = head[2:]
    conversion = b"x" if digits.islower() else b"X"  # a-f present and A-F absent: lower case
    body = head[:2] + b"%0" + str(len(digits)).encode() + conversion
    return body, b"-" + body
