"""Fixtures of the flash tests: the bench (see :mod:`flash_images`)."""

from __future__ import annotations

import pytest
from flash_images import open_bench


@pytest.fixture
def bench():
    with open_bench() as bench:
        yield bench
