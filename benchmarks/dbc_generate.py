"""A large powertrain-like DBC for ``dbc_bench.py``: hundreds of messages, as a vehicle bus has them.

    python benchmarks/dbc_generate.py OUT.dbc [--kib 1000] [--defects]

Every message has a sender among a dozen nodes, 3 to 12 signals packed into its DLC (Intel
and Motorola, signed, unsigned, IEEE floats), receivers, a comment and ``GenMsgCycleTime``/
``GenMsgTimeoutTime``/``GenMsgSendType`` attributes; one in six is multiplexed (a multiplexer
and four groups); a tenth have extended ids (with ``VFrameFormat``); a quarter of the signals
have value descriptions (``VAL_``), some from ``VAL_TABLE_`` s, and start values. With
``--defects`` the same file carries, at about one statement in fifty, what CANdb++ reads and
cantools refuses: ids above 0x7FF without the extended flag, names that start with a digit,
``VAL_`` without ``;``, numbers without the leading zero, comments without text, receivers
separated by spaces, references to signals that do not exist, an attribute without definition.
The text is the same for the same arguments (a fixed seed).
"""

from __future__ import annotations

import argparse
import random
from pathlib import Path

NODES = ("ECM", "TCM", "ABS", "ESP", "BCM", "IPC", "EPS", "ACU", "HVAC", "GW", "PCM", "FLCU")
_UNITS = ("", "rpm", "km/h", "degC", "bar", "%", "Nm", "V", "A", "deg", "m/s2", "ms")
_WORDS = ("Engine", "Torque", "Speed", "Wheel", "Brake", "Pressure", "Temp", "Fuel", "Rail", "Gear", "Clutch",
          "Pedal", "Yaw", "Rate", "Lateral", "Accel", "Battery", "Voltage", "Current", "Status", "Request",
          "Target", "Actual", "Limit", "Counter", "Checksum", "Mode", "Fault", "Valve", "Pump")
_CHOICES = ("OFF", "ON", "INIT", "ACTIVE", "FAULT", "NOT_AVAILABLE", "STANDBY", "LIMITED", "RESERVED", "ERROR")
_VALUE_TABLES = {f"VT_{name}": [(value, text) for value, text in enumerate(_CHOICES[:count])]
                 for name, count in (("OnOff", 2), ("State", 4), ("Health", 6), ("Mode", 8))}
_HEADER = """VERSION "PT_CAN2 benchmark"


NS_ :
\tNS_DESC_
\tCM_
\tBA_DEF_
\tBA_
\tVAL_
\tBA_DEF_DEF_
\tVAL_TABLE_
\tSIG_VALTYPE_
\tBO_TX_BU_

BS_:

BU_: {nodes}

"""
_DEFINITIONS = """BA_DEF_ "BusType" STRING ;
BA_DEF_ "DBName" STRING ;
BA_DEF_ BO_ "GenMsgCycleTime" INT 0 65535;
BA_DEF_ BO_ "GenMsgTimeoutTime" INT 0 65535;
BA_DEF_ BO_ "GenMsgSendType" ENUM "Cyclic","Event","CyclicIfActive","NoMsgSendType";
BA_DEF_ BO_ "VFrameFormat" ENUM "StandardCAN","ExtendedCAN","reserved","J1939PG";
BA_DEF_ SG_ "GenSigStartValue" FLOAT -1e+09 1e+09;
BA_DEF_ BU_ "NodeLayerModules" STRING ;
BA_DEF_DEF_ "BusType" "CAN";
BA_DEF_DEF_ "DBName" "";
BA_DEF_DEF_ "GenMsgCycleTime" 0;
BA_DEF_DEF_ "GenMsgTimeoutTime" 0;
BA_DEF_DEF_ "GenMsgSendType" "Cyclic";
BA_DEF_DEF_ "VFrameFormat" "StandardCAN";
BA_DEF_DEF_ "GenSigStartValue" 0;
BA_DEF_DEF_ "NodeLayerModules" "";
BA_ "BusType" "CAN";
BA_ "DBName" "PT_CAN2";
"""
_DEFECT_RATE = 50  # about one statement in this many carries a defect


def generate(kib: int, defects: bool = False) -> str:
    """A DBC text of about ``kib`` KiB (with the defects cantools refuses when ``defects``)."""
    messages = max(2, kib * 1024 // 1700)
    for _ in range(6):  # the size per message is about constant: a few corrections reach the target
        text = _dbc(messages, defects)
        messages = max(2, round(messages * kib * 1024 / len(text)))
    return _dbc(messages, defects)


class _Writer:
    def __init__(self, defects: bool) -> None:
        self.random = random.Random(25)
        self.defects = defects
        self.defect_random = random.Random(27)  # its own: the file with defects is the clean one, spoiled
        self.messages: list[str] = []
        self.comments: list[str] = []
        self.attributes: list[str] = []
        self.values: list[str] = []
        self.used_names: set[str] = set()

    def defect(self) -> bool:
        return self.defects and self.defect_random.randrange(_DEFECT_RATE) == 0

    def name(self, words: int) -> str:
        while True:
            name = "".join(self.random.choice(_WORDS) for _ in range(words)) + f"_{self.random.randrange(1000):03d}"
            if name not in self.used_names:
                self.used_names.add(name)
                return name

    def message(self, index: int) -> None:
        rnd = self.random
        sender = rnd.choice(NODES)
        receivers = rnd.sample([n for n in NODES if n != sender], rnd.randint(1, 3))
        extended = rnd.randrange(10) == 0
        frame_id = 0x100 + index if not extended else 0x18F00000 + index * 0x100 + rnd.randrange(0x100)
        written = frame_id | 0x80000000 if extended else frame_id
        if extended and self.defect():
            written = frame_id  # above 0x7FF without the extended flag: CANdb++ reads it as extended
        name = f"{sender}_{self.name(2)}"
        if self.defect():
            name = f"{self.defect_random.randint(1, 9)}{name}"
        dlc = 8 if rnd.randrange(4) else rnd.choice((2, 4, 6))
        lines = [f"BO_ {written} {name}: {dlc} {sender}"]
        multiplexed = dlc == 8 and rnd.randrange(6) == 0
        if multiplexed:
            lines.append(self.signal(written, 0, 8, False, "M", receivers))
            for group in range(4):
                lines += self.signals(written, 8, 64, f"m{group}", receivers)
        else:
            lines += self.signals(written, 0, dlc * 8, "", receivers)
        self.messages.append("\n".join(lines) + "\n")
        period = rnd.choice((10, 20, 50, 100, 100, 100, 200, 500, 1000))
        self.comments.append(f'CM_ BO_ {written} "{name}: sent by {sender} every {period} ms.";')
        self.attributes.append(f'BA_ "GenMsgCycleTime" BO_ {written} {period};')
        if rnd.randrange(5):
            self.attributes.append(f'BA_ "GenMsgTimeoutTime" BO_ {written} {period * 3};')
        self.attributes.append(f'BA_ "GenMsgSendType" BO_ {written} {rnd.randrange(3)};')
        if extended:
            self.attributes.append(f'BA_ "VFrameFormat" BO_ {written} 1;')
        if self.defect():
            self.attributes.append(f'BA_ "GenMsgILSupport" BO_ {written} 1;')  # no BA_DEF_
        if self.defect():
            self.comments.append(f"CM_ BO_ {written};")  # a comment without text
        if self.defect():
            self.values.append(f'VAL_ {written} NoSuchSignal 0 "OFF" 1 "ON" ;')

    def signals(self, frame_id: int, first: int, end: int, multiplexing: str, receivers: list[str]) -> list[str]:
        rnd, lines, position = self.random, [], first
        motorola = rnd.randrange(4) == 0
        while position < end and len(lines) < 12:
            length = min(rnd.choice((1, 2, 4, 8, 8, 12, 16, 16, 32)), end - position)
            lines.append(self.signal(frame_id, position, length, motorola, multiplexing, receivers))
            position += length + rnd.choice((0, 0, 0, 1, 4))
        return lines

    def signal(self, frame_id: int, position: int, length: int, motorola: bool, multiplexing: str,
               receivers: list[str]) -> str:
        rnd = self.random
        name = self.name(3)
        if self.defect():
            name = f"{self.defect_random.randint(0, 9)}_{name}"
        if motorola:  # the MSB's bit in DBC numbering, the signal running through the bytes from there
            start = position // 8 * 8 + 7 - position % 8
        else:
            start = position
        signed = length > 1 and rnd.randrange(3) == 0
        is_float = length == 32 and rnd.randrange(4) == 0
        factor, offset = (1, 0) if length == 1 or is_float else rnd.choice(
            ((1, 0), (0.1, 0), (0.01, 0), (0.5, -40), (0.25, 0), (0.0625, 0), (2, -100)))
        factor_text = str(factor)
        if factor_text.startswith("0.") and self.defect():
            factor_text = factor_text[1:]  # .25: a number without its leading zero
        raw_max = (1 << (length - 1)) - 1 if signed else (1 << length) - 1
        raw_min = -(1 << (length - 1)) if signed else 0
        minimum, maximum = _number(raw_min * factor + offset), _number(raw_max * factor + offset)
        unit = "" if length == 1 else rnd.choice(_UNITS)
        separator = " " if self.defect() and len(receivers) > 1 else ","
        mux = f" {multiplexing}" if multiplexing else ""
        line = (f" SG_ {name}{mux} : {start}|{length}@{0 if motorola else 1}{'-' if signed else '+'} "
                f'({factor_text},{offset}) [{minimum}|{maximum}] "{unit}" {separator.join(receivers)}')
        if rnd.randrange(2):
            self.comments.append(f'CM_ SG_ {frame_id} {name} "{name}: {rnd.choice(_WORDS).lower()} of the '
                                 f'{rnd.choice(_WORDS).lower()} {rnd.choice(_WORDS).lower()}.";')
        if is_float:
            self.values.append(f"SIG_VALTYPE_ {frame_id} {name} : 1;")
        elif length <= 4 and rnd.randrange(2):
            table = rnd.choice(list(_VALUE_TABLES.values()))
            entries = [(v, t) for v, t in table if v < (1 << length)]
            text = " ".join(f'{v} "{t}"' for v, t in reversed(entries))
            self.values.append(f"VAL_ {frame_id} {name} {text} " + ("" if self.defect() else ";"))
        if rnd.randrange(8) == 0:
            self.attributes.append(f'BA_ "GenSigStartValue" SG_ {frame_id} {name} {rnd.randrange(2)};')
        return line


def _number(value: float) -> str:
    return f"{value:.10g}"


def _dbc(messages: int, defects: bool) -> str:
    writer = _Writer(defects)
    for index in range(messages):
        writer.message(index)
    tables = "".join(f"VAL_TABLE_ {name} " + " ".join(f'{v} "{t}"' for v, t in reversed(entries)) + " ;\n"
                     for name, entries in _VALUE_TABLES.items())
    node_comments = "".join(f'CM_ BU_ {node} "The {node} control unit.";\n' for node in NODES)
    return (_HEADER.format(nodes=" ".join(NODES)) + tables + "\n" + "\n".join(writer.messages) + "\n\n"
            + 'CM_ "Powertrain CAN2, generated for the DBC benchmark.";\n' + node_comments
            + "\n".join(writer.comments) + "\n" + _DEFINITIONS + "\n".join(writer.attributes) + "\n"
            + "\n".join(writer.values) + "\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("output", type=Path)
    parser.add_argument("--kib", type=int, default=1000)
    parser.add_argument("--defects", action="store_true")
    args = parser.parse_args()
    args.output.write_text(generate(args.kib, args.defects), encoding="utf-8")


if __name__ == "__main__":
    main()
