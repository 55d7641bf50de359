"""XCP on Ethernet framing: LEN/CTR headers, several packets per datagram, a stream cut anywhere."""

from __future__ import annotations

import pytest

from workbench.xcp_framing import FramingError, StreamDecoder, frame, split_datagram


def test_a_packet_behind_its_little_endian_header():
    assert frame(b"\xff\x00", 0x1234) == b"\x02\x00\x34\x12\xff\x00"
    assert frame(b"\xfd", 0x10001) == b"\x01\x00\x01\x00\xfd"  # CTR wraps after 0xFFFF


def test_a_datagram_with_several_packets():
    datagram = frame(b"\xfd", 7) + frame(b"\xf4\x04\x00\x00\x10\x00\x00\x40", 8)
    assert split_datagram(datagram, 255) == [(7, b"\xfd"), (8, b"\xf4\x04\x00\x00\x10\x00\x00\x40")]


@pytest.mark.parametrize("datagram, reason", [
    (b"", "empty datagram"),
    (b"\x01\x00\x00", "no room for a header"),
    (frame(b"\xfd", 0) + b"\x01\x00", "after packet 1: no room for a header"),
    (b"\x05\x00\x00\x00\xff\x00", "LEN 5 but 2 byte"),
    (b"\x00\x00\x00\x00", "LEN 0"),
    (frame(bytes(9), 0), "LEN 9 exceeds the largest packet taken \\(8 bytes\\)"),
])
def test_a_malformed_datagram_is_refused_whole(datagram, reason):
    with pytest.raises(FramingError, match=reason):
        split_datagram(datagram, 8)


def test_a_stream_cut_anywhere_gives_the_same_packets():
    stream = b"".join(frame(bytes([0xF5, n]), n) for n in range(1, 40))
    for cut in (1, 2, 3, 5, 7, len(stream)):
        decoder = StreamDecoder(255)
        packets = []
        for start in range(0, len(stream), cut):
            packets += decoder.feed(stream[start : start + cut])
        assert packets == [(n, bytes([0xF5, n])) for n in range(1, 40)], cut


def test_a_stream_with_an_impossible_length_cannot_be_resynchronised():
    decoder = StreamDecoder(255)
    assert decoder.feed(frame(b"\xfd", 0) + b"\x00\x01") == [(0, b"\xfd")]  # LEN 256 announced
    with pytest.raises(FramingError, match="LEN 256"):
        decoder.feed(b"\x00\x00")
