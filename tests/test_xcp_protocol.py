"""The XCP names the simulated slave and the master share."""

import pytest

from workbench.errors import XcpCommandError
from workbench.xcp_protocol import TIME_UNIT_S, Cmd, Err


def test_a_negative_response_names_the_command_and_the_standard_error():
    assert str(XcpCommandError(Cmd.UPLOAD.name, Err.OUT_OF_RANGE)) == "XCP UPLOAD failed: ERR_OUT_OF_RANGE (0x22)"
    assert str(XcpCommandError("UPLOAD", 0x99)) == "XCP UPLOAD failed: unknown error (0x99)"
    assert XcpCommandError("UNLOCK", 0x25, "ERR_ACCESS_LOCKED").name == "ERR_ACCESS_LOCKED"


@pytest.mark.parametrize("code", range(10))
def test_time_unit_codes_count_powers_of_ten_from_a_nanosecond(code):
    assert TIME_UNIT_S[code] == pytest.approx(10.0 ** (code - 9))
