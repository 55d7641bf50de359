"""XCP checksums against the standard's check values and pyxcp's independent implementation."""

import pytest
from hypothesis import given
from hypothesis import strategies as st
from pyxcp import checksum as pyxcp_checksum

from workbench.image import ChecksumType, checksum

CHECK = b"123456789"  # the CRC catalogue's check input


@pytest.mark.parametrize(
    ("kind", "expected"),
    [(ChecksumType.CRC_16, 0xBB3D), (ChecksumType.CRC_16_CITT, 0x29B1), (ChecksumType.CRC_32, 0xCBF43926)],
)
def test_crc_check_values(kind, expected):
    assert checksum(CHECK, kind) == expected


def test_add_sums_wrap_at_their_width():
    data = bytes([0xFF] * 4)
    assert checksum(data, ChecksumType.ADD_11) == 0xFC
    assert checksum(data, ChecksumType.ADD_12) == 0x3FC
    assert checksum(data, ChecksumType.ADD_22) == 0xFFFE
    assert checksum(data, ChecksumType.ADD_24) == 0x1FFFE
    assert checksum(data, ChecksumType.ADD_44) == 0xFFFFFFFF


def test_word_sums_follow_the_byte_order():
    data = bytes([0x01, 0x02])
    assert checksum(data, ChecksumType.ADD_22, little_endian=True) == 0x0201
    assert checksum(data, ChecksumType.ADD_22, little_endian=False) == 0x0102


def test_word_sum_of_odd_length_is_refused():
    with pytest.raises(ValueError, match="multiple of 2"):
        checksum(b"\x01\x02\x03", ChecksumType.ADD_24)


@given(st.binary(max_size=64).map(lambda b: b[: len(b) // 4 * 4]), st.sampled_from(list(ChecksumType)))
def test_matches_pyxcp(data, kind):
    assert checksum(data, kind) == pyxcp_checksum.check(data, "XCP_" + kind.name)
