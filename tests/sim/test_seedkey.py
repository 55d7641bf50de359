"""The demo seed & key plugin: the documented example, its argument checks, every resource differs."""

import pytest

from workbench.sim.seedkey import compute_key


def test_documented_example():
    assert compute_key(bytes([1, 2, 3, 4]), 0x04) == bytes([0x69, 0x48, 0x8A, 0xA8])


def test_each_resource_has_its_own_key():
    keys = {compute_key(b"\x10\x20\x30\x40", resource) for resource in (0x01, 0x04, 0x08, 0x10)}
    assert len(keys) == 4


@pytest.mark.parametrize(("seed", "resource"), [(b"\x01\x02\x03", 0x01), (b"\x01\x02\x03\x04", 0x05)])
def test_bad_arguments(seed, resource):
    with pytest.raises(ValueError):
        compute_key(seed, resource)
