"""The workbench's modules are imported before any test here runs pytest in this process (pytester).

After each in-process run pytester drops the modules the run imported, and the next run imports them again:
a second generation of every class. A module kept from before the run then meets the new one: a lazy package
(``workbench.a2l``) hands out the ``A2lDocument`` of the first run, which ``Session.open`` of the second run
takes for no document ('expected str ... not A2lDocument'), depending on which test ran first. Modules imported
here are kept by every run. The window's modules (Qt) and the FLCU suite's test files (which pytest imports
itself) are left out.
"""

import importlib
import pkgutil

import workbench

for _module in pkgutil.walk_packages(workbench.__path__, "workbench."):
    if not _module.name.startswith(("workbench.gui", "workbench.testbench.flcu_suite", "workbench.__main__")):
        importlib.import_module(_module.name)
