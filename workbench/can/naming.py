"""Names the thesis's CAN library gives to the calibrations it creates (chapter 6.3).

* every CAN signal (RX and TX) gets a fix switch: ``cf<SIGNAL>_EN`` (uint8 0/1) and
  ``cf<SIGNAL>_VALUE`` (the signal's *raw* value, an integer of the signal's width,
  shown in physical units through a COMPU_METHOD built from factor/offset). The signal
  name is upper-cased: ``FuelLevel`` → ``cfFUELLEVEL_EN``. Where signal names repeat
  across messages (the CAN3 validation DBC has ``Sgn1`` in 64 messages) the names can be
  message-qualified, as the thesis names the published signal (``csC3RXAAA_Sgn1``):
  ``cf<MESSAGE>_<SIGNAL>_EN`` → ``cfC3RXAAA_SGN1_EN``;
* every TX message gets a transmission enable ``cs<MessageName>_En`` (uint8 0/1);
* a received signal is published as ``cs<MessageName>_<Signal>``, with the message's
  diagnostic ``cs<MessageName>_Status`` (tCANRxStatus) and ``cs<MessageName>_BitStatus``.

While ``_EN`` is 1 the signal's value is replaced by ``_VALUE``.

The driver's mailboxes (the thesis's ``canMap``, chapter 6.3.2) are named per network and
role: ``CAN2_MSG_TX_000``, ``CAN2_MSG_RX_000``, ...
"""

from __future__ import annotations

__all__ = [
    "CAN_NETWORKS", "FIX_ENABLE_SUFFIX", "FIX_VALUE_SUFFIX", "dbc_signal_name", "find_dbc_signal", "fix_enable_name",
    "fix_stem", "fix_value_name", "mailbox_name", "raw_c_type", "rx_bit_status_name", "rx_signal_name",
    "rx_status_name", "tx_enable_name",
]

FIX_ENABLE_SUFFIX = "_EN"
FIX_VALUE_SUFFIX = "_VALUE"


def fix_stem(signal: str, message: str | None = None) -> str:
    """``cf<SIGNAL>``, or ``cf<MESSAGE>_<SIGNAL>`` when ``message`` is given: the fix names without suffix."""
    qualified = f"{message}_{signal}" if message else signal
    return f"cf{qualified.upper()}"


def fix_enable_name(signal: str, message: str | None = None) -> str:
    """``cf<SIGNAL>_EN`` (``cf<MESSAGE>_<SIGNAL>_EN`` with ``message``)."""
    return fix_stem(signal, message) + FIX_ENABLE_SUFFIX


def fix_value_name(signal: str, message: str | None = None) -> str:
    """``cf<SIGNAL>_VALUE`` (``cf<MESSAGE>_<SIGNAL>_VALUE`` with ``message``)."""
    return fix_stem(signal, message) + FIX_VALUE_SUFFIX


def dbc_signal_name(message: str, signal: str) -> str:
    """``Message.Signal``: a CAN signal of a DBC by name, as the window lists and plots it and ``measure`` and
    ``cal fix`` take it."""
    return f"{message}.{signal}"


def find_dbc_signal(databases, name: str):
    """``(message, signal)`` (cantools) that ``name`` names in ``databases``: ``Message.Signal``, or the signal's
    bare name when one message alone has it.

    :raises UnknownSymbolError: no such signal (the closest names suggested).
    :raises InputError: the bare name is a signal of several messages (their qualified names are given).
    """
    from workbench.errors import InputError, UnknownSymbolError

    found, known = [], []
    for database in databases:
        for message in database.messages:
            for signal in message.signals:
                qualified = dbc_signal_name(message.name, signal.name)
                known.append(qualified)
                if name in (qualified, signal.name):
                    found.append((message, signal))
    if len(found) == 1:
        return found[0]
    if found:
        names = ", ".join(dbc_signal_name(m.name, s.name) for m, s in found)
        raise InputError(f"{name!r} is a signal of {len(found)} messages: {names}; name it as Message.Signal")
    import difflib

    close = difflib.get_close_matches(name, known + [k.split(".", 1)[1] for k in known], n=3, cutoff=0.6)
    raise UnknownSymbolError(name, "the CAN2 database's signals", close)


def tx_enable_name(message: str) -> str:
    return f"cs{message}_En"


def rx_signal_name(message: str, signal: str) -> str:
    return f"cs{message}_{signal}"


def rx_status_name(message: str) -> str:
    """``cs<Message>_Status``: the message's tCANRxStatus (the highest-priority error)."""
    return f"cs{message}_Status"


def rx_bit_status_name(message: str) -> str:
    """``cs<Message>_BitStatus``: one bit per RX error (bit0 DLC ... bit4 SignalOutOfRange)."""
    return f"cs{message}_BitStatus"


def raw_c_type(length: int, is_signed: bool, is_float: bool = False) -> str:
    """The Simulink coder type that holds a signal's raw value of ``length`` bits.

    An IEEE float signal (DBC ``SIG_VALTYPE_`` 1 or 2) is held as ``real32_T``/``real_T``.

    :raises ValueError: a length no CAN signal can have.
    """
    if is_float:
        if length not in (32, 64):
            raise ValueError(f"a float CAN signal is 32 or 64 bits long, not {length}")
        return "real32_T" if length == 32 else "real_T"
    for width in (8, 16, 32, 64):
        if length <= width:
            return f"{'int' if is_signed else 'uint'}{width}_T"
    raise ValueError(f"a CAN signal cannot be {length} bits long")


CAN_NETWORKS = ("CAN1", "CAN2", "CAN3", "CAN4")


def mailbox_name(network: str, role: str, index: int) -> str:
    """The driver's mailbox (frame) id, e.g. ``mailbox_name("CAN2", "TX", 0)`` is ``CAN2_MSG_TX_000``."""
    return f"{network}_MSG_{role}_{index:03d}"
