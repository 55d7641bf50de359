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
    with pytest.raises(InputError, match=r"^CAN2: bus option prot=43200: python-can's udp_multicast bus has no "
                                         r"option 'prot' and would ignore it \(did you mean port\? it takes "):
        check_bus_options("udp_multicast", {"prot": 43200}, "CAN2")
    with pytest.raises(InputError, match="^bus option port=43200: python-can's virtual bus has no option 'port'"):
        check_bus_options("virtual", {"port": 43200})


@pytest.mark.parametrize(("interface", "options"), [
    ("udp_multicast", {"port": 43200, "fd": True, "hop_limit": 2, "receive_own_messages": False, "bitrate": 500_000}),
    ("socketcan", {"fd": True, "receive_own_messages": True, "local_loopback": False, "ignore_rx_error_frames": True,
                   "can_filters": [{"can_id": 0x7F1, "can_mask": 0x7FF}]}),
    ("virtual", {"rx_queue_size": 10, "preserve_timestamps": True, "data_bitrate": 2_000_000}),
    # python-can's Bus() reads these itself, and builds ``timing`` of the bit timing keys (its config file's)
    ("udp_multicast", {"config_context": "bench", "ignore_config": True, "f_clock": 80_000_000, "brp": 10,
                       "tseg1": 13, "tseg2": 2, "sjw": 1, "nof_samples": 1}),
    ("socketcan", {"f_clock": 80_000_000, "nom_brp": 1, "nom_tseg1": 119, "nom_tseg2": 40, "nom_sjw": 40,
                   "data_brp": 1, "data_tseg1": 29, "data_tseg2": 10, "data_sjw": 10}),
    # interfaces that read their options from **kwargs (Vector's app_name, PCAN's and Kvaser's bit timing): not judged
    ("vector", {"app_name": "CANape", "serial": 1234, "rx_queue_size": 2 ** 14}),
    ("pcan", {"device_id": 1, "f_clock_mhz": 80, "auto_reset": True}),
    ("kvaser", {"accept_virtual": True, "driver_mode": True, "single_handle": True}),
])
def test_the_options_interfaces_take_are_not_refused(interface, options):
    check_bus_options(interface, options)


def test_every_bus_opened_is_checked_before_it_opens(monkeypatch):
    """open_bus is where the master, the simulator, scan, CAN2 and flash open their buses: a typo there reached the
    default port's bus (someone else's simulator) from a script, which the CLI alone refused."""
    import can

    from workbench.bus_defaults import open_bus

    opened = []
    monkeypatch.setattr(can, "Bus", lambda **kwargs: opened.append(kwargs))
    with pytest.raises(InputError, match=r"^CAN1: bus option prot=44001: python-can's udp_multicast bus has no option "
                                         r"'prot' and would ignore it \(did you mean port\? "):
        open_bus(BusSpec.from_kwargs({"prot": 44001}).kwargs(), "CAN1")
    assert opened == []
    open_bus(BusSpec.from_kwargs({"port": 44001}).kwargs())  # valid options: opened as before
    assert opened == [{"interface": "udp_multicast", "channel": "239.74.163.2", "port": 44001,
                       "receive_own_messages": False}]
