"""Reading a recording back with asammdf the way the tests check it: a group by its acquisition name."""

from __future__ import annotations

import numpy as np


def group_index(mdf, acq_name: str) -> int:
    names = [group.channel_group.acq_name for group in mdf.groups]
    assert acq_name in names, names
    return names.index(acq_name)


def channel(mdf, acq_name: str, name: str, *, raw: bool = False):
    """The Signal ``name`` of the group ``acq_name``."""
    return mdf.get(name, group=group_index(mdf, acq_name), raw=raw)


def master(mdf, acq_name: str) -> np.ndarray:
    return mdf.get_master(group_index(mdf, acq_name))


def texts(samples) -> list:
    """Value-to-text samples as str (asammdf gives bytes), numbers as they are."""
    return [value.decode() if isinstance(value, bytes) else value for value in samples.tolist()]
