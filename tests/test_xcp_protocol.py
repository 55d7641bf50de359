"""The XCP names the simulated slave and the master share."""

import pytest

from workbench.errors import XcpCommandError
from workbench.xcp_protocol import TIME_UNIT_S, CanId, Cmd, Err


def test_a_negative_response_names_the_command_and_the_standard_error():
    assert str(XcpCommandError(Cmd.UPLOAD.name, Err.OUT_OF_RANGE)) == "XCP UPLOAD failed: ERR_OUT_OF_RANGE (0x22)"
    assert str(XcpCommandError("UPLOAD", 0x99)) == "XCP UPLOAD failed: unknown error (0x99)"
    assert XcpCommandError("UNLOCK", 0x25, "ERR_ACCESS_LOCKED").name == "ERR_ACCESS_LOCKED"


@pytest.mark.parametrize("code", range(10))
def test_time_unit_codes_count_powers_of_ten_from_a_nanosecond(code):
    assert TIME_UNIT_S[code] == pytest.approx(10.0 ** (code - 9))


@pytest.mark.parametrize(("number", "can_id"), [(0x7F0, CanId(0x7F0)), (0x80000100, CanId(0x100, extended=True)),
                                                (0x9FFFFFFF, CanId(0x1FFFFFFF, extended=True))])
def test_a_can_id_and_the_a2l_number_with_bit_31_are_one_value(number, can_id):
    assert CanId.from_a2l(number) == can_id and can_id.a2l == number


def test_a_can_id_matches_frames_of_its_format_only():
    class Frame:
        def __init__(self, arbitration_id, is_extended_id):
            self.arbitration_id, self.is_extended_id = arbitration_id, is_extended_id

    assert CanId(0x100).matches(Frame(0x100, False)) and not CanId(0x100).matches(Frame(0x100, True))
    assert (CanId(0x100).mask, CanId(0x100, extended=True).mask) == (0x7FF, 0x1FFFFFFF)


@pytest.mark.parametrize(("can_id", "message"), [
    (lambda: CanId(0x800), r"CAN id 0x800 does not fit a standard frame; a 29-bit id has bit 31 set in the A2L "
                           r"\(0x80000800\)"),
    (lambda: CanId(0x20000000, extended=True), r"CAN id 0x20000000 does not fit an extended frame$"),
    (lambda: CanId(-1), "does not fit a standard frame"),
])
def test_an_id_the_frame_format_cannot_carry_is_refused(can_id, message):
    with pytest.raises(ValueError, match=message):
        can_id()
