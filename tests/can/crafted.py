"""Text of crafted DBCs for the CAN tests: a header, attribute definitions, timing lines."""

from __future__ import annotations

HEADER = """VERSION ""

NS_ :
\tCM_
\tBA_DEF_
\tBA_
\tBA_DEF_DEF_

BS_:

BU_: {nodes}

"""

ATTRIBUTE_DEFINITIONS = """
BA_DEF_ BO_ "GenMsgCycleTime" INT 0 65535;
BA_DEF_ BO_ "GenMsgTimeoutTime" INT 0 65535;
BA_DEF_ BO_ "VFrameFormat" ENUM "StandardCAN","ExtendedCAN";
BA_DEF_DEF_ "GenMsgCycleTime" 0;
BA_DEF_DEF_ "GenMsgTimeoutTime" 0;
BA_DEF_DEF_ "VFrameFormat" "StandardCAN";
"""


def timing(frame_id: int, period: int, timeout: int | None = None) -> str:
    """The BA_ lines of a message's period (and timeout) in ms."""
    lines = f'BA_ "GenMsgCycleTime" BO_ {frame_id} {period};\n'
    if timeout is not None:
        lines += f'BA_ "GenMsgTimeoutTime" BO_ {frame_id} {timeout};\n'
    return lines
