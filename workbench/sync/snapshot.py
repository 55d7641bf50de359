"""The ECU's calibrations kept in files: a page as a dataset (DCM, CDFX), the working page as a CAL ROM image.

::

    dataset = read_dataset(session)                          # every calibration of the working page
    save_dataset(dataset, "base.dcm")
    calibration_image(session, "CALIB").save("cal.s19")      # what `workbench flash cal.s19 --region CALIB` flashes

The image comes from the flashing code's own reading of the working page
(:func:`workbench.flash.plan_working_page`): the segment's ADDRESS_MAPPING places it in CAL ROM,
the EPK and whatever else the page holds outside the A2L's objects come along, erased blocks are
not read, and the result is exactly what flashing the working page would program.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import replace
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from workbench.a2l.model import A2lModel
from workbench.calib.dataset import Dataset, ObjectInfo
from workbench.calib.values import CalValue
from workbench.errors import InputError, WorkbenchError, epk_text, same_epk
from workbench.findings import Finding, Severity
from workbench.image import MemoryImage
from workbench.progress import Progress
from workbench.session import Session
from workbench.sync.areas import ImageView, calibration_areas, image_epks
from workbench.sync.ecu import EcuReader, on_pages
from workbench.sync.values import as_typed_value, calibration_names, decode_values, object_layouts

__all__ = ["calibration_image", "dataset_of", "file_dataset", "image_dataset", "read_dataset"]


def read_dataset(session: Session, names: Iterable[str] | None = None, *, page: str | int | None = "working",
                 progress: Progress | None = None) -> Dataset:
    """The ECU's values of every calibration (or of ``names``: names and globs) as a dataset.

    :param page: ``"working"`` (CAL RAM), ``"reference"`` (CAL ROM) or None (the page XCP is on).
    :raises UnknownSymbolError, InputError: a name the A2L lacks, a glob that matches nothing.
    :raises XcpCommandError, XcpTimeoutError: the ECU refused or did not answer.
    :raises Cancelled: ``progress`` was cancelled.

    Objects the codec cannot decode are left out, each named in ``dataset.notes`` (a warning); when
    they were named explicitly that is an :class:`InputError` instead.
    """
    model = session.model
    wanted = calibration_names(model, names)
    layouts, problems = object_layouts(model, wanted)
    reader = EcuReader(session, progress, f"reading the {page or 'current'} page")
    with session.lock, on_pages(session, page):
        values, failed = decode_values(layouts, reader)
    problems.update(failed)
    if problems and names is not None:
        name, why = next(iter(problems.items()))
        raise InputError(f"{name}: {why}" if not why.startswith(name) else why)
    where = f"the ECU's {page} page" if page else "the ECU"
    dataset = dataset_of(model, values, problems, f"{where}, EPK {session.epk.ecu or 'not read'}")
    dataset.source = f"ECU ({page} page)" if page else "ECU"
    return dataset


def image_dataset(model: A2lModel, image: MemoryImage, names: Iterable[str] | None = None, *,
                  source: str = "image") -> Dataset:
    """The values an s19/hex holds for every calibration (or ``names``), read through the A2L (no ECU):
    the calibration segments' ADDRESS_MAPPING finds them in a CAL ROM image."""
    from workbench.a2l import read_xcp_config

    module = model.name or None
    areas = calibration_areas(model.doc, read_xcp_config(model.doc, module), module)
    layouts, problems = object_layouts(model, calibration_names(model, names))
    view = ImageView(image, areas)
    values, failed = decode_values(layouts, view.fetch)
    problems.update(failed)
    dataset = dataset_of(model, values, problems, source)
    dataset.source = source
    expected = model.doc.epk(module)
    for found in image_epks(view, model.doc, module):  # as cal get --image says it: read, but perhaps not this build's
        if found.text is not None and not same_epk(found.text, expected):
            dataset.notes.append(Finding("epk-mismatch", source, f"{source} holds the EPK {epk_text(found.text)} in "
                                         f"{found.label}, the A2L {epk_text(expected)}: the A2L may not describe this "
                                         "software; its values are read at the A2L's addresses",
                                         severity=Severity.WARNING))
    return dataset


def file_dataset(model: A2lModel, path: str | Path) -> Dataset:
    """The values of a file as ``cal diff`` and the window compare them: an s19/hex read through the A2L
    (:func:`image_dataset`), or a DCM/CDFX whose floats are taken as the A2L's types hold them
    (:func:`~workbench.sync.values.as_typed_value`: a FLOAT32 object's 0.019999999552965164, as INCA and CANape write
    it, is the 0.02 an image reads), so a file and an image differ only where writing would change the ECU.

    :raises InputError: the file is missing or malformed (located).
    """
    from workbench.calib.dataset import load_dataset
    from workbench.image import load_image
    from workbench.image.files import is_image_file, refuse_elf

    refuse_elf(path)
    if is_image_file(path):
        return image_dataset(model, load_image(path), source=str(path))
    dataset = load_dataset(path)
    for name in list(dataset):
        try:
            dataset[name] = _as_held(model, dataset[name])
        except WorkbenchError:  # not in the A2L, or not a calibration it can type: compared as the file holds it
            continue
    return dataset


def _as_held(model: A2lModel, value: CalValue) -> CalValue:
    """A file's ``value`` as the ECU would hold it, then as typed: a FLOAT32_IEEE object without conversion stores
    INCA's 16 decimals 0.2000000029802322 as float32's 0.2 (other objects: :func:`as_typed_value` alone)."""
    obj = model.object(value.name)
    if model.datatype_of(obj) == "FLOAT32_IEEE" and model.conversion(obj).conversion_type == "IDENTICAL":
        value = replace(value, value=_float32(value.value))
    return as_typed_value(model, value)


def _float32(number):
    if isinstance(number, np.ndarray):
        return number.astype(np.float32).astype(np.float64) if number.dtype.kind == "f" else number
    return float(np.float32(number)) if isinstance(number, (float, np.floating)) else number


def dataset_of(model: A2lModel, values: dict, problems: dict[str, str], origin: str) -> Dataset:
    """A dataset of ``values`` (name -> CalValue, typed as a dataset keeps them), each object not read (``problems``:
    name -> why) named in its notes; ``origin`` says where the values were read, in its comment."""
    dataset = Dataset()
    stamp = datetime.now(timezone.utc).astimezone().isoformat(timespec="seconds")
    a2l = f" ({model.doc.path.name})" if model.doc.path is not None else ""
    dataset.comments.append(f"calibrations of {origin} through the A2L{a2l}, read by workbench on {stamp}")
    for name, value in values.items():
        functions = tuple(getattr(model.object(name), "functions", ()) or ())
        dataset.add(as_typed_value(model, value), ObjectInfo(functions=functions[:1]))
    dataset.notes.extend(Finding("not-read", name, f"{name}: not read ({why})", severity=Severity.WARNING)
                         for name, why in problems.items())
    return dataset


def calibration_image(session: Session, region: str = "CALIB", *, progress: Progress | None = None) -> MemoryImage:
    """The working page as the flash region ``region`` holds it once flashed (CAL ROM addresses; EPK
    included; erased flash left out), ready to save as s19/hex and flash with ``--region``.

    :raises InputError: the working page is not flashed into ``region`` (the message names the regions it is).
    :raises FlashRefused: the ECU runs no application, or the A2L maps no working page to flash.
    """
    from workbench.flash import plan_working_page

    plan = plan_working_page(session, app_key=None, progress=progress)
    for part in plan.regions:
        if part.region.name.upper() == region.upper():
            return part.image
    regions = ", ".join(p.region.name for p in plan.regions) or "none"
    raise InputError(f"the working page is flashed into {regions}, not into {region!r}")
