"""Calibration data between the ECU and files: datasets and images in and out, and the cache sync.

::

    from workbench import Session
    from workbench.calib.dataset import load_dataset, save_dataset
    from workbench.sync import apply_dataset, calibration_image, read_dataset, sync_compare, sync_download

    with Session.open() as ecu:
        save_dataset(read_dataset(ecu), "base.dcm")              # the working page as a dataset
        calibration_image(ecu, "CALIB").save("cal.s19")          # ... as the CAL ROM image flash takes
        print(apply_dataset(ecu, load_dataset("tuned.cdfx")).summary())  # checked first, then written
        report = sync_compare(ecu, "assets/FLCU.s19")           # BUILD_CHECKSUM first, objects after
        if not report.equal:
            print(report.to_text())
            sync_download(ecu, report)                           # or sync_upload(report): ECU -> file

A package of its own rather than part of the session: it stands on the session (values by name,
pages, raw memory), the codec (decoding an s19 by name), the images and the flashing code (the
checksum comparison and the working page as CAL ROM), and none of them needs it. Public names
are imported on first use.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.lazy_exports import lazy_exports

_EXPORTS = {
    "workbench.image.files": ("is_image_file",),
    "workbench.sync.apply": ("ApplyFailed", "ApplyRefused", "ApplyReport", "ObjectOutcome", "apply_dataset"),
    "workbench.sync.areas": ("CalibrationArea", "ImageView", "calibration_areas"),
    "workbench.sync.cache": ("AreaCheck", "ByteDifference", "SyncReport", "sync_compare"),
    "workbench.sync.offline": ("ImageCalibration",),
    "workbench.sync.reference": ("DatasetReference", "ImageReference", "load_reference"),
    "workbench.sync.snapshot": ("calibration_image", "file_dataset", "image_dataset", "read_dataset"),
    "workbench.sync.transfer": ("DownloadResult", "sync_download", "sync_upload"),
}
__all__, __getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

if TYPE_CHECKING:  # for type checkers and IDEs: the same names, imported eagerly
    from workbench.image.files import is_image_file
    from workbench.sync.apply import ApplyFailed, ApplyRefused, ApplyReport, ObjectOutcome, apply_dataset
    from workbench.sync.areas import CalibrationArea, ImageView, calibration_areas
    from workbench.sync.cache import AreaCheck, ByteDifference, SyncReport, sync_compare
    from workbench.sync.offline import ImageCalibration
    from workbench.sync.reference import DatasetReference, ImageReference, load_reference
    from workbench.sync.snapshot import calibration_image, file_dataset, image_dataset, read_dataset
    from workbench.sync.transfer import DownloadResult, sync_download, sync_upload
