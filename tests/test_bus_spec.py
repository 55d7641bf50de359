"""BusSpec: a CAN bus as one value, from python-can keywords to python-can keywords, with the workbench's defaults."""

from workbench.bus_defaults import BusSpec


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
