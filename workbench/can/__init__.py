"""CAN databases (cantools): the thesis's CAN library (chapter 6.3) without MATLAB.

One module per concern; their public names are also this package's, imported on first use
(``import workbench.can`` loads no cantools):

* :mod:`~workbench.can.naming` — fix-calibration and mailbox names;
* :mod:`~workbench.can.dbc_file` — :func:`load_dbc`: as cantools reads, with located errors and warnings;
* :mod:`~workbench.can.dbc_text`, :mod:`~workbench.can.dbc_repair`, :mod:`~workbench.can.dbc_repair_attributes`
  — what CANdb++ reads and cantools refuses, repaired in the text with a warning per problem;
* :mod:`~workbench.can.dbc_read`, :mod:`~workbench.can.dbc_database` — a DBC's content read from its
  statements by cantools' rules, or (where that reader is not sure) taken from cantools' database;
* :mod:`~workbench.can.model` — the Message/SignalOfMsg properties of a DBC's messages;
* :mod:`~workbench.can.mailboxes` — the canMap: mailboxes per network and role;
* :mod:`~workbench.can.table` — a node's message table over one or more DBCs;
* :mod:`~workbench.can.table_export` — the table as text and CSV;
* :mod:`~workbench.can.validation` — DBC findings (overlaps, DLC, duplicates, attributes, ...);
* :mod:`~workbench.can.fixcal`, :mod:`~workbench.can.fixcal_c`, :mod:`~workbench.can.fixcal_a2l`,
  :mod:`~workbench.can.fixcal_output` — the fix calibrations and their C/A2L files;
* :mod:`~workbench.can.callbacks` — the driver configuration between api.c's ``// <initCbk>`` markers.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.lazy_exports import lazy_exports

_EXPORTS = {
    "workbench.can.callbacks": ("callback_lines", "write_callbacks"),
    "workbench.can.dbc_file": ("DbcFile", "load_dbc"),
    "workbench.can.fixcal": ("FixCalibration", "fix_calibrations"),
    "workbench.can.fixcal_output": ("FixcalFiles", "fixcal_files"),
    "workbench.can.mailboxes": ("MailboxOrder",),
    "workbench.can.model": ("Message", "Role", "SignalOfMsg", "messages_of"),
    "workbench.can.naming": ("fix_enable_name", "fix_value_name", "mailbox_name", "raw_c_type", "rx_bit_status_name",
                             "rx_signal_name", "rx_status_name", "tx_enable_name"),
    "workbench.can.table": ("CanTable", "build_table", "load_networks"),
    "workbench.can.table_export": ("table_csv", "table_text"),
    "workbench.can.validation": ("check_dbcs",),
}
__all__, __getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

if TYPE_CHECKING:  # for type checkers and IDEs: the same names, imported eagerly
    from workbench.can.callbacks import callback_lines, write_callbacks
    from workbench.can.dbc_file import DbcFile, load_dbc
    from workbench.can.fixcal import FixCalibration, fix_calibrations
    from workbench.can.fixcal_output import FixcalFiles, fixcal_files
    from workbench.can.mailboxes import MailboxOrder
    from workbench.can.model import Message, Role, SignalOfMsg, messages_of
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
    from workbench.can.table import CanTable, build_table, load_networks
    from workbench.can.table_export import table_csv, table_text
    from workbench.can.validation import check_dbcs
