"""The workbench window (PySide6 + pyqtgraph): loaded only by ``workbench gui`` / ``workbench demo``.

``models/`` holds the Qt item models over the library's data, ``widgets/`` one widget class per
file talking through Qt signals; :mod:`~workbench.gui.ecu` is the one door to the session,
:mod:`~workbench.gui.worker` runs library calls off the GUI thread, :mod:`~workbench.gui.acquisition`
and :mod:`~workbench.gui.can_monitor` feed live samples into :mod:`~workbench.gui.signal_hub`.
Importing this package imports Qt; the core library never does.
"""
