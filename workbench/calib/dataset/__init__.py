"""Calibration datasets as files, the way CANape and INCA users keep them: DCM and CDFX.

``load_dataset("base.dcm")`` gives a :class:`Dataset` (name -> :class:`~workbench.calib.values.CalValue`
plus the file's metadata), ``save_dataset(ds, "base.cdfx")`` writes one, ``diff_datasets(a, b)``
compares two. Every value survives a trip through either format exactly. Public names are
imported on first use (``import workbench.calib.dataset`` loads neither numpy nor lxml).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.lazy_exports import lazy_exports

_EXPORTS = {
    "workbench.calib.dataset.model": ("CsFlag", "Dataset", "FunctionInfo", "HistoryEntry", "InstancePart", "ObjectInfo",
                                      "member_name"),
    "workbench.calib.dataset.formats": ("FORMATS", "dataset_losses", "dump_dataset", "format_of", "load_dataset",
                                        "load_dataset_string", "save_dataset"),
    "workbench.calib.dataset.diff": ("DatasetDiff", "ObjectDiff", "diff_datasets"),
}
__all__, __getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

if TYPE_CHECKING:  # for type checkers and IDEs: the same names, imported eagerly
    from workbench.calib.dataset.diff import DatasetDiff, ObjectDiff, diff_datasets
    from workbench.calib.dataset.formats import (FORMATS, dataset_losses, dump_dataset, format_of, load_dataset,
                                                 load_dataset_string, save_dataset)
    from workbench.calib.dataset.model import (CsFlag, Dataset, FunctionInfo, HistoryEntry, InstancePart, ObjectInfo,
                                               member_name)
