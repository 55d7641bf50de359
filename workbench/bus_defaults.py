"""The CAN bus as one value (:class:`BusSpec`), the bus a workbench command or script uses when it is told
none, and opening one (:func:`open_bus`), shared by the master and the simulator.

Neutral ground (it imports no workbench package but errors, python-can only when a bus is opened): the
simulator serves where the master looks by default, so both take the defaults from here.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

from workbench.errors import InputError, WorkbenchError

if TYPE_CHECKING:
    import can

__all__ = ["DEFAULT_CHANNELS", "DEFAULT_INTERFACE", "SOFTWARE_INTERFACES", "BusSpec", "bus_beside",
           "check_bus_options", "complete_bus_settings", "open_bus", "parse_bus_kwargs"]

DEFAULT_INTERFACE = "udp_multicast"
DEFAULT_CHANNELS = {"udp_multicast": "239.74.163.2", "virtual": "workbench"}
# python-can interfaces without bit timing of their own: a bit rate given for them is the simulator's timing model
SOFTWARE_INTERFACES = frozenset({"virtual", "udp_multicast"})


def complete_bus_settings(settings: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """python-can ``Bus(**settings)`` keyword arguments with the defaults filled in: ``interface``
    udp_multicast, its ``channel`` 239.74.163.2 (virtual: "workbench"), and on udp_multicast
    ``receive_own_messages`` off. Other keys (``bitrate``, udp_multicast's ``port``, Vector's
    ``app_name`` ...) pass through unchanged."""
    completed = dict(settings or {})
    interface = completed.setdefault("interface", DEFAULT_INTERFACE)
    if completed.get("channel") is None and interface in DEFAULT_CHANNELS:
        completed["channel"] = DEFAULT_CHANNELS[interface]
    if interface == "udp_multicast":
        completed.setdefault("receive_own_messages", False)
    return completed


@dataclass(frozen=True)
class BusSpec:
    """A CAN bus, kept whole from the command line (or a script) to the bus python-can opens.

    ``interface`` and ``channel`` are python-can's; ``bitrate`` the bit rate the bus runs at (for a
    software interface, virtual or udp_multicast, which has none of its own: the simulator's bus timing
    model); ``options`` every other keyword of ``can.Bus`` (udp_multicast's ``port``, ``fd``,
    ``data_bitrate``, Vector's ``app_name`` ...). ``BusSpec()`` is the default bus, udp_multicast on
    239.74.163.2, where ``workbench sim`` serves.
    """

    interface: str = DEFAULT_INTERFACE
    channel: str | int | None = None
    bitrate: int | None = None
    options: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:  # the defaults of complete_bus_settings: a channel, udp_multicast's echo off
        given = {"interface": self.interface, "channel": self.channel, **self.options}
        completed = complete_bus_settings({key: value for key, value in given.items() if value is not None})
        completed.pop("interface")
        object.__setattr__(self, "channel", completed.pop("channel", None))
        object.__setattr__(self, "options", completed)

    @classmethod
    def from_kwargs(cls, kwargs: Mapping[str, Any]) -> BusSpec:
        """The bus ``can.Bus(**kwargs)`` opens (None values left out, the workbench's defaults filled in)."""
        given = {key: value for key, value in kwargs.items() if value is not None}
        return cls(given.pop("interface", DEFAULT_INTERFACE), given.pop("channel", None), given.pop("bitrate", None),
                   given)

    def kwargs(self) -> dict[str, Any]:
        """python-can's ``Bus(**kwargs)`` keyword arguments."""
        kwargs: dict[str, Any] = {"interface": self.interface, "channel": self.channel, **self.options}
        if self.bitrate is not None:
            kwargs["bitrate"] = self.bitrate
        return {key: value for key, value in kwargs.items() if value is not None}

    def with_bitrate(self, bitrate: int | None) -> BusSpec:
        return replace(self, bitrate=bitrate)

    def with_options(self, **options: Any) -> BusSpec:
        """These options added (those already given are kept)."""
        return replace(self, options={**options, **self.options})

    def with_channel(self, channel: str | int) -> BusSpec:
        """The same interface and options on another channel (a udp_multicast ``port`` stays)."""
        return replace(self, channel=channel)

    @property
    def software(self) -> bool:
        """A bus of python-can's own making (no bit timing of its own)."""
        return self.interface in SOFTWARE_INTERFACES

    @property
    def fd(self) -> bool:
        return bool(self.options.get("fd"))

    def describe(self) -> str:
        """``udp_multicast 239.74.163.2 port 43200``: interface, channel, and a udp_multicast port when given."""
        port = self.options.get("port") if self.interface == "udp_multicast" else None
        return " ".join(str(part) for part in (self.interface, self.channel, f"port {port}" if port else None) if part)


def bus_beside(base: BusSpec | None, interface: str | None = None, channel: str | int | None = None,
               options: Mapping[str, Any] | None = None) -> BusSpec | None:
    """The bus ``interface``, ``channel`` and ``options`` (``Bus`` keywords: a udp_multicast ``port``, ``bitrate``
    ...) name beside ``base`` (CAN2 beside the XCP bus), or None when they name none (``base`` itself then).

    On ``base``'s interface (or none named) the bus keeps ``base``'s channel, bit rate and options where none
    is given; on another interface it is only what is given.
    """
    options = dict(options or {})
    if interface is None and channel is None and not options:
        return None
    if base is not None and interface in (None, base.interface):
        kwargs = base.kwargs()
    else:
        kwargs = {"interface": interface or (base.interface if base is not None else DEFAULT_INTERFACE)}
    if channel is not None:
        kwargs["channel"] = channel
    return BusSpec.from_kwargs({**kwargs, **options})


def parse_bus_kwargs(pairs: Iterable[str]) -> dict[str, Any]:
    """``--bus-kwargs KEY=VALUE ...`` as python-can's command line tools read them (values cast by
    ``can.util.cast_from_string``: numbers, booleans, text): ``["port=43200"]`` -> ``{"port": 43200}``.

    :raises ValueError: a pair that is not KEY=VALUE (the message names it).
    """
    from can.util import cast_from_string

    kwargs = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key.isidentifier():
            raise ValueError(f"{pair!r}: expected KEY=VALUE (e.g. port=43200)")
        kwargs[key] = cast_from_string(value)
    return kwargs


def open_bus(config: Mapping[str, Any], role: str | None = None) -> can.BusABC:
    """A python-can bus from ``Bus(**config)`` keyword arguments, errors as one line naming ``role``
    (the simulator's ``CAN1``; the master's bus is "the CAN bus").

    Every bus the workbench opens is opened here (master, simulator, scan, CAN2, flash), so an option the
    interface would ignore (:func:`check_bus_options`) is refused for each of them, before any frame is sent.

    :raises InputError: an unknown interface (naming the known ones), an option the bus would ignore (naming the
        closest one), or options the interface refuses (``--bus-kwargs port=abc``: python-can's ValueError or
        TypeError).
    :raises WorkbenchError: the bus cannot be opened (driver missing, device busy ...).
    """
    import can

    interface = config.get("interface")
    if interface not in can.interfaces.VALID_INTERFACES:
        raise InputError(f"{role + ': ' if role else ''}unknown python-can interface {interface!r} "
                         f"(known: {', '.join(sorted(can.interfaces.VALID_INTERFACES))})")
    check_bus_options(interface, {key: value for key, value in config.items() if key not in ("interface", "channel")},
                      role)
    try:
        return can.Bus(**dict(config))
    except (can.CanError, OSError, ValueError, ImportError, TypeError) as exc:
        where = f"{interface} {config.get('channel', '')}".strip()
        # python-can's own errors (CanError) are no ValueError: a ValueError or TypeError is the interface
        # refusing the options the user gave
        error = InputError if isinstance(exc, (ValueError, TypeError)) else WorkbenchError
        raise error(f"cannot open {role or 'the CAN'} bus ({where}): {exc}") from exc


# python-can interfaces whose bus takes its options by name and ignores any other keyword without a word: a typo
# there (``prot=43200``) would reach another bus (the default port's: someone else's ECU)
_OPTIONS_BY_NAME = frozenset({"udp_multicast", "virtual", "socketcan"})
# python-can's common bus settings (its config file's too), taken for every bus: a software bus's bit rate is the
# simulator's timing model
_BUS_KEYS = frozenset({"bitrate", "fd", "data_bitrate", "can_filters", "timing"})
_BUS_CALL_KEYS = frozenset({"config_context", "ignore_config"})  # can.Bus() takes these itself, no bus class does


def check_bus_options(interface: str | None, options: Mapping[str, Any], role: str | None = None) -> None:
    """Refuse an option of ``options`` that the bus of ``interface`` (None: the default) would ignore
    (:func:`open_bus` asks this of every bus; a dialog may ask it before).

    :param role: the bus's name in the message (``CAN2``), as :func:`open_bus` takes it.
    :raises InputError: one line naming the key, the closest option and the options the interface takes.
    """
    interface = interface or DEFAULT_INTERFACE
    if interface not in _OPTIONS_BY_NAME:
        return
    import difflib
    import importlib
    import inspect

    import can

    module, name = can.interfaces.BACKENDS[interface]
    try:
        bus_class = getattr(importlib.import_module(module), name)
    except ImportError:  # socketcan off Linux: opening the bus says so
        return
    from can.typechecking import BitTimingDict, BitTimingFdDict

    taken = {name for cls in bus_class.__mro__ if "__init__" in vars(cls)
             for name, parameter in inspect.signature(cls.__init__).parameters.items()
             if parameter.kind not in (parameter.VAR_POSITIONAL, parameter.VAR_KEYWORD)}
    taken = (taken | _BUS_KEYS) - {"self", "channel", "interface"}
    # can.Bus() builds ``timing`` of the bit timing keys (f_clock, brp, tseg1 ...), as it does of its config file's:
    # no bus class names them, yet they are taken
    quiet = _BUS_CALL_KEYS | set(BitTimingDict.__annotations__) | set(BitTimingFdDict.__annotations__)
    for key, value in options.items():
        if key not in taken | quiet:
            close = difflib.get_close_matches(key, sorted(taken | quiet), n=1)
            hint = f"did you mean {close[0]}? " if close else ""
            raise InputError(f"{role + ': ' if role else ''}bus option {key}={value}: python-can's {interface} bus has "
                             f"no option {key!r} and would ignore it ({hint}it takes {', '.join(sorted(taken))})")
