"""CAN databases (cantools): the thesis's CAN library (chapter 6.3) without MATLAB.

One module per concern; import them directly (this package's ``__init__`` stays light so
that ``workbench.can.naming`` does not pull in cantools):

* :mod:`~workbench.can.naming` — fix-calibration and mailbox names;
* :mod:`~workbench.can.dbc_file` — :func:`load_dbc`: cantools with located errors;
* :mod:`~workbench.can.model` — the Message/SignalOfMsg properties of a DBC's messages;
* :mod:`~workbench.can.mailboxes` — the canMap: mailboxes per network and role;
* :mod:`~workbench.can.table` — a node's message table over one or more DBCs;
* :mod:`~workbench.can.table_export` — the table as text and CSV;
* :mod:`~workbench.can.validation` — DBC findings (overlaps, DLC, duplicates, attributes, ...);
* :mod:`~workbench.can.fixcal`, :mod:`~workbench.can.fixcal_c`, :mod:`~workbench.can.fixcal_a2l`,
  :mod:`~workbench.can.fixcal_output` — the fix calibrations and their C/A2L files;
* :mod:`~workbench.can.callbacks` — the driver configuration between api.c's ``// <initCbk>`` markers.
"""

from workbench.can.naming import (
    fix_enable_name,
    fix_value_name,
    mailbox_name,
    raw_c_type,
    rx_bit_status_name,
    rx_signal_name,
    rx_status_name,
    tx_enable_name,
)

__all__ = ["fix_enable_name", "fix_value_name", "mailbox_name", "raw_c_type", "rx_bit_status_name", "rx_signal_name",
           "rx_status_name", "tx_enable_name"]
