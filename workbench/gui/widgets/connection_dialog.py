"""Connection settings, prefilled from the A2L's IF_DATA XCP: CAN (python-can interface, channel, bit
rate, the XCP ids) or Ethernet (UDP/TCP host and port). Gives a
:class:`~workbench.gui.project.Connection`."""

from __future__ import annotations

from PySide6.QtWidgets import (
    QComboBox,
    QDialog,
    QDialogButtonBox,
    QFileDialog,
    QFormLayout,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QPushButton,
    QSpinBox,
    QStackedWidget,
    QVBoxLayout,
    QWidget,
)

from workbench import bus_defaults
from workbench.errors import InputError
from workbench.gui import theme
from workbench.gui.project import Connection
from workbench.gui.widgets.slave_scan import SlaveScan, id_text
from workbench.session.connection import parse_daq_can_ids

__all__ = ["ConnectionDialog", "parse_bus_kwargs"]

INTERFACES = ("udp_multicast", "virtual", "socketcan", "vector", "pcan", "kvaser", "ixxat", "slcan", "gs_usb")


def parse_bus_kwargs(text: str) -> dict:
    """``port=43200 app_name=CANape`` (spaces or commas between) -> {"port": 43200, "app_name": "CANape"}, the
    values read as ``--bus-kwargs`` reads them (:func:`workbench.bus_defaults.parse_bus_kwargs`).

    :raises InputError: an item that is not KEY=VALUE.
    """
    try:
        return bus_defaults.parse_bus_kwargs(text.replace(",", " ").split())
    except ValueError as exc:
        raise InputError(f"bus option {exc}") from None


class ConnectionDialog(QDialog):
    """``config``: the A2L's :class:`~workbench.a2l.xcp.XcpConfig` (None: no A2L yet)."""

    def __init__(self, connection: Connection, config=None, parent=None):
        super().__init__(parent)
        self.setWindowTitle("Connection")
        self.setMinimumWidth(520)  # the placeholders say what the A2L gives: let them show whole
        layout = QVBoxLayout(self)
        self.transport = QComboBox()
        for label, key in (("XCP on CAN", "CAN"), ("XCP on UDP", "udp"), ("XCP on TCP", "tcp")):
            self.transport.addItem(label, key)
        form = QFormLayout()
        form.addRow("transport", self.transport)
        self.key_function = QLineEdit()
        self.key_function.setToolTip("module:function, file.py:function, a plugin's name, or a key library with "
                                     "ASAM's XCP_ComputeKeyFromSeed (SeedNKeyXcp.dll on Windows, a .so on Linux)")
        self.key_library = QPushButton("Library…")
        self.key_library.setToolTip("choose the supplier's key library (SeedNKeyXcp.dll, a .so), as CANape asks for it")
        self.key_library.clicked.connect(self._choose_key_library)
        key_row = QWidget()  # a widget, not a layout: the label's "&&" shows as "&" only with a buddy
        key_layout = QHBoxLayout(key_row)
        key_layout.setContentsMargins(0, 0, 0, 0)
        key_layout.addWidget(self.key_function, 1)
        key_layout.addWidget(self.key_library)
        form.addRow("seed && key", key_row)  # "&&": a single & would mark a shortcut
        layout.addLayout(form)
        self.pages = QStackedWidget()
        can_page, can_form = QWidget(), QFormLayout()
        can_page.setLayout(can_form)
        self.interface = QComboBox()
        self.interface.setEditable(True)
        self.interface.addItems(INTERFACES)
        self.channel = QLineEdit()
        self.channel.setPlaceholderText("239.74.163.2 (udp_multicast), can0, 0 ...")
        self.bitrate = QSpinBox()
        self.bitrate.setRange(0, 8_000_000)
        self.bitrate.setSingleStep(125_000)
        self.bitrate.setSpecialValueText("as the A2L says")
        self.bitrate.setSuffix(" bit/s")
        self.bus_kwargs = QLineEdit()
        self.bus_kwargs.setPlaceholderText("python-can options, e.g. port=43200 app_name=CANape")
        can_form.addRow("interface", self.interface)
        can_form.addRow("channel", self.channel)
        can_form.addRow("bit rate", self.bitrate)
        can_form.addRow("bus options", self.bus_kwargs)
        self.daq_can_ids = QLineEdit()
        self.daq_can_ids.setToolTip("DAQ list=CAN id: where SET_DAQ_ID moves a list the A2L's DAQ_LIST_CAN_ID calls "
                                    "VARIABLE (bit 31 set for an extended id); the others VARIABLE: on CAN_ID_SLAVE")
        can_form.addRow("DAQ list ids", self.daq_can_ids)
        self.ids = QLabel()
        self.ids.setStyleSheet(f"color: {theme.MUTED};")
        can_form.addRow("A2L", self.ids)
        self.slave_scan = None
        if getattr(config, "can", None) is not None:  # GET_SLAVE_ID on its CAN_ID_BROADCAST: which ids answer
            self.slave_scan = SlaveScan(config.can, self._bus)
            can_form.addRow("slaves", self.slave_scan)
        eth_page, eth_form = QWidget(), QFormLayout()
        eth_page.setLayout(eth_form)
        self.host = QLineEdit()
        self.port = QSpinBox()
        self.port.setRange(0, 65535)
        self.port.setSpecialValueText("as the A2L says")
        eth_form.addRow("host", self.host)
        eth_form.addRow("port", self.port)
        self.pages.addWidget(can_page)
        self.pages.addWidget(eth_page)
        layout.addWidget(self.pages)
        self.transport.currentIndexChanged.connect(lambda i: self.pages.setCurrentIndex(0 if i == 0 else 1))
        self.error = QLabel()
        self.error.setStyleSheet(f"color: {theme.BAD};")
        layout.addWidget(self.error)
        buttons = QDialogButtonBox(QDialogButtonBox.Ok | QDialogButtonBox.Cancel)
        buttons.accepted.connect(self._accept)
        buttons.rejected.connect(self.reject)
        layout.addWidget(buttons)
        self._prefill(connection, config)

    def _prefill(self, connection: Connection, config) -> None:
        can = getattr(config, "can", None)
        if can is not None:
            self.ids.setText(f"master {id_text(can.can_id_master)}, slave {id_text(can.can_id_slave)}, "
                             f"{can.baudrate // 1000} kbit/s")
        ethernet = getattr(config, "udp", None) or getattr(config, "tcp", None)
        if connection.host or connection.port or connection.protocol:
            self.transport.setCurrentIndex(2 if (connection.protocol or "").lower() == "tcp" else 1)
        elif can is None and ethernet is not None:
            self.transport.setCurrentIndex(1 if getattr(config, "udp", None) else 2)
        named = getattr(config, "seed_and_key_function", None)
        self.key_function.setPlaceholderText(f"as the A2L says: {named}" if named else "none (the A2L names none)")
        self.key_function.setText(connection.key_function or "")
        self.interface.setCurrentText(connection.interface or "udp_multicast")
        self.channel.setText("" if connection.channel is None else str(connection.channel))
        self.bitrate.setValue(connection.bitrate or 0)
        self.bus_kwargs.setText(" ".join(f"{k}={v}" for k, v in connection.bus_kwargs.items()))
        variable = [item.daq_list for item in getattr(can, "daq_list_can_ids", ()) if item.can_id is None]
        self.daq_can_ids.setPlaceholderText(
            f"VARIABLE lists {', '.join(map(str, variable))} on CAN_ID_SLAVE; e.g. {variable[0]}=0x7F6" if variable
            else "as the A2L says (no VARIABLE list); e.g. 1=0x7F6")
        self.daq_can_ids.setText(" ".join(f"{number}=0x{can_id:X}" for number, can_id in connection.daq_can_ids.items()))
        for edit in (self.key_function, self.bus_kwargs, self.daq_can_ids):  # whole, not '...seedkey:co'
            _fit_placeholder(edit)
        self.host.setText(connection.host or (ethernet.host if ethernet is not None else ""))
        self.port.setValue(connection.port or (ethernet.port if ethernet is not None else 0))

    def connection(self) -> Connection:
        """The settings entered. :raises InputError: bus options that do not parse."""
        key_function = self.key_function.text().strip() or None
        if self.transport.currentData() == "CAN":
            interface = self.interface.currentText().strip() or None
            bus_kwargs = parse_bus_kwargs(self.bus_kwargs.text())
            bus_defaults.check_bus_options(interface, bus_kwargs)  # prot=43200 would go to another bus
            return Connection(interface=interface, channel=self.channel.text().strip() or None,
                              bitrate=self.bitrate.value() or None, bus_kwargs=bus_kwargs, key_function=key_function,
                              daq_can_ids=parse_daq_can_ids(self.daq_can_ids.text()))
        return Connection(host=self.host.text().strip() or None, port=self.port.value() or None,
                          protocol=self.transport.currentData(), key_function=key_function)

    def _bus(self) -> bus_defaults.BusSpec:
        """The CAN bus entered. :raises InputError: bus options that do not parse."""
        options = self.connection().session_options()
        return bus_defaults.BusSpec.from_kwargs({**{key: options[key] for key in ("interface", "channel", "bitrate")},
                                                 **options["bus_kwargs"]})

    def _choose_key_library(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self, "Seed & key library", self.key_function.text().strip(),
                                              "Key libraries (*.dll *.so);;All files (*)")
        if path:
            self.key_function.setText(path)

    def _accept(self) -> None:
        try:
            self.connection()
        except InputError as exc:
            self.error.setText(str(exc))
            return
        self.accept()


def _fit_placeholder(edit: QLineEdit, most_px: int = 640) -> None:
    """``edit`` wide enough for its placeholder (what the A2L gives) up to ``most_px``; the whole in its tooltip."""
    text = edit.placeholderText()
    edit.setMinimumWidth(min(most_px, edit.fontMetrics().horizontalAdvance(text) + 24))  # + the frame and margins
    if not edit.toolTip():
        edit.setToolTip(text)
