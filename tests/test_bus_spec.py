"""BusSpec: a CAN bus as one value, from python-can keywords to python-can keywords, with the workbench's defaults."""

import pytest

from workbench.bus_defaults import BusSpec, check_bus_options
from workbench.errors import InputError


def test_the_default_bus_is_where_workbench_sim_serves():
    assert BusSpec().kwargs() == {"interface": "udp_multicast", "channel": "239.74.163.2",
                                  "receive_own_messages": False}
    assert BusSpec("virtual").kwargs() == {"interface": "virtual", "channel": "workbench"}


def test_python_can_keywords_travel_whole_and_come_back():
    kwargs = {"interface": "vector", "channel": 1, "bitrate": 500_000, "app_name": "Bench", "fd": True,
              "data_bitrate": 2_000_000}
    spec = BusSpec.from_kwargs(kwargs)
    assert (spec.interface, spec.channel, spec.bitrate, spec.fd, spec.software) == ("vector", 1, 500_000, True, False)
    assert spec.kwargs() == kwargs
    assert BusSpec.from_kwargs({"interface": "virtual", "channel": None, "bitrate": None}) == BusSpec("virtual")


def test_another_channel_keeps_the_options_a_udp_multicast_port_too():
    spec = BusSpec.from_kwargs({"port": 43210})
    other = spec.with_channel("239.74.163.9")
    assert other.kwargs() == {"interface": "udp_multicast", "channel": "239.74.163.9", "port": 43210,
                              "receive_own_messages": False}
    assert other.describe() == "udp_multicast 239.74.163.9 port 43210"


def test_options_added_never_replace_those_given():
    spec = BusSpec("socketcan", "can0", options={"fd": False}).with_options(fd=True, data_bitrate=2_000_000)
    assert spec.options == {"fd": False, "data_bitrate": 2_000_000}
    assert spec.with_bitrate(250_000).bitrate == 250_000


def test_a_bus_beside_another_keeps_its_interface_options_and_takes_those_given():
    from workbench.bus_defaults import bus_beside

    xcp = BusSpec.from_kwargs({"interface": "udp_multicast", "port": 43210, "bitrate": 500_000})
    assert bus_beside(xcp) is None  # none named: the XCP bus itself
    assert bus_beside(xcp, channel="239.74.163.9", options={"port": 43211}).kwargs() == {
        "interface": "udp_multicast", "channel": "239.74.163.9", "port": 43211, "receive_own_messages": False,
        "bitrate": 500_000}
    assert bus_beside(xcp, options={"port": 43211}).channel == "239.74.163.2"  # the same group on a port of its own
    other = bus_beside(xcp, "socketcan", "can1", {"bitrate": 250_000, "fd": True})  # another interface: only these
    assert other.kwargs() == {"interface": "socketcan", "channel": "can1", "fd": True, "bitrate": 250_000}
    assert bus_beside(None, channel="239.74.163.9", options={"port": 1}).describe() == "udp_multicast 239.74.163.9 port 1"


def test_bus_kwargs_are_read_as_python_can_reads_them():
    import pytest

    from workbench.bus_defaults import parse_bus_kwargs

    assert parse_bus_kwargs(["port=43200", "app_name=CANape", "fd=True", "bitrate=500000"]) == {
        "port": 43200, "app_name": "CANape", "fd": True, "bitrate": 500_000}
    with pytest.raises(ValueError, match="'port': expected KEY=VALUE"):
        parse_bus_kwargs(["port"])


def test_an_option_the_bus_would_ignore_is_refused_with_the_closest():
    check_bus_options(None, {"port": 43200, "fd": False, "hop_limit": 2})  # udp_multicast's, by default
    check_bus_options("vector", {"app_name": "CANape", "anything": 1})  # its options come by **kwargs: not judged
    with pytest.raises(InputError, match=r"^--bus-kwargs prot=43200: python-can's udp_multicast bus has no option "
                                         r"'prot' and would ignore it \(did you mean port\? it takes "):
        check_bus_options("udp_multicast", {"prot": 43200}, "--bus-kwargs ")
    with pytest.raises(InputError, match="virtual bus has no option 'port'"):
        check_bus_options("virtual", {"port": 43200})
