"""Self-describing HDF5 files: the only module that imports h5py.

Every file written here carries, at its root, the attributes ``schema``,
``schema_version`` ("MAJOR.MINOR"), ``creator`` ("flexbed X.Y.Z") and
``created`` (ISO 8601, UTC); every dataset carries a ``units`` attribute.
Files are written atomically: to a temporary file in the same folder, then
renamed, so a reader never sees half a file; a dataset holding a
non-finite value (NaN, ±inf) is refused (NumericalError) and nothing is written.

A file is described as a flat mapping from dataset paths ("group/name") to
:class:`Dataset` values, plus a mapping from group paths ("" for the root)
to attribute dictionaries. Attribute values are str, int, float, bool or
1-D arrays.
"""

from __future__ import annotations

import functools
import io
import os
from dataclasses import dataclass, field
from datetime import datetime, timezone
from importlib import metadata
from pathlib import Path
from typing import Any, Mapping

import h5py
import numpy as np

from flexbed.errors import InputError, NumericalError
from flexbed.files.destination import atomic_write, check_source


@functools.cache
def package_version() -> str:
    """Version string of the installed flexbed distribution (looked up once:
    reading the distribution's metadata costs milliseconds)."""
    try:
        return metadata.version("flexbed")
    except metadata.PackageNotFoundError:  # running from a source tree
        return "0+unknown"


@dataclass(frozen=True, slots=True)
class Dataset:
    """One array and its unit.

    Parameters
    ----------
    data : array_like
        Numeric array (any shape) or a string.
    units : str
        SI unit ("m", "kg m^2", "1" for dimensionless, "" for labels).
    description : str
        One line saying what it is (stored as the ``description`` attribute).
    attrs : mapping, optional
        Further attributes of the dataset.
    missing : bool
        NaN marks a missing value here (a study's metric at a point that
        failed); it is allowed and recorded as the attribute
        ``missing_value = "nan"``. ±inf is refused all the same.
    """

    data: Any
    units: str
    description: str = ""
    attrs: Mapping[str, Any] | None = None
    missing: bool = False


@dataclass(frozen=True, slots=True)
class Contents:
    """What :func:`read_file` found: datasets, their units, group attributes."""

    path: Path
    datasets: Mapping[str, Any]
    units: Mapping[str, str]
    attrs: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)

    def get(self, name: str) -> Any:
        """Return dataset ``name``, or raise :class:`InputError` naming it."""
        try:
            return self.datasets[name]
        except KeyError:
            raise InputError(f"{self.path}: dataset '{name}' is missing") from None


def in_memory(datasets: Mapping[str, Dataset],
              attrs: Mapping[str, Mapping[str, Any]] | None = None) -> Contents:
    """What :func:`read_file` would give for a file written from these
    datasets and attributes, without writing it (``path`` is None)."""
    return Contents(path=None, datasets={k: ds.data for k, ds in datasets.items()},
                    units={k: ds.units for k, ds in datasets.items()},
                    attrs={k: dict(v) for k, v in (attrs or {}).items()})


def write_file(path: str | os.PathLike, *, schema: str, version: str,
               datasets: Mapping[str, Dataset],
               attrs: Mapping[str, Mapping[str, Any]] | None = None) -> Path:
    """Write an HDF5 file atomically.

    Parameters
    ----------
    path : path-like
        Destination (absent or a regular file, :mod:`flexbed.files.destination`);
        its folder is created if needed.
    schema : str
        Schema name, e.g. "flexbed.modes".
    version : str
        Schema version "MAJOR.MINOR".
    datasets : mapping str -> Dataset
        Dataset paths ("group/sub/name") and their values.
    attrs : mapping str -> dict, optional
        Attributes per group path ("" is the root).

    Returns
    -------
    Path
        The path written.
    """
    for name, ds in datasets.items():
        if not isinstance(ds.data, str):
            arr = np.asarray(ds.data)
            finite = np.isfinite(arr) if arr.dtype.kind in "fc" else True
            if ds.missing and arr.dtype.kind in "fc":
                finite = finite | np.isnan(arr)
            if not np.all(finite):
                bad = np.argwhere(~finite)[0]
                raise NumericalError(f"{path}: not written: dataset '{name}' holds "
                                     f"{int(np.sum(~finite))} non-finite values "
                                     f"(first at index {tuple(int(i) for i in bad)}; a "
                                     f"floating-point overflow or a diverging solution)")

    def fill(tmp: Path) -> None:
        # built in memory, then written with plain file I/O: a full disk or a
        # size limit is then an OSError of one write, where HDF5's own
        # writes fail again on closing (and crash the process at exit)
        buffer = io.BytesIO()
        with h5py.File(buffer, "w") as f:
            _fill(f)
        with open(tmp, "wb") as out:
            out.write(buffer.getbuffer())

    def _fill(f) -> None:
        f.attrs["schema"] = schema
        f.attrs["schema_version"] = version
        f.attrs["creator"] = f"flexbed {package_version()}"
        f.attrs["created"] = datetime.now(timezone.utc).isoformat(timespec="seconds")
        for name, ds in datasets.items():
            data = ds.data
            if isinstance(data, str):
                d = f.create_dataset(name, data=data, dtype=h5py.string_dtype())
            else:
                arr = np.asarray(data)
                if arr.dtype.kind in "US":
                    d = f.create_dataset(name, data=arr.astype(object),
                                         dtype=h5py.string_dtype())
                else:
                    d = f.create_dataset(name, data=arr)
            d.attrs["units"] = ds.units
            if ds.description:
                d.attrs["description"] = ds.description
            if ds.missing:
                d.attrs["missing_value"] = "nan"
            for key, value in (ds.attrs or {}).items():
                d.attrs[key] = value
        for group, values in (attrs or {}).items():
            g = f.require_group(group) if group else f
            for key, value in values.items():
                g.attrs[key] = value
    return atomic_write(path, fill)


def _decode(value: Any) -> Any:
    if isinstance(value, bytes):
        return value.decode()
    if isinstance(value, np.ndarray) and value.dtype.kind == "O":
        return np.array([v.decode() if isinstance(v, bytes) else v for v in value.ravel()],
                        dtype=object).reshape(value.shape)
    if isinstance(value, np.generic):
        return value.item()
    return value


def read_file(path: str | os.PathLike, *, schema: str, major: int,
              required: tuple[str, ...] = ()) -> Contents:
    """Read a file written by :func:`write_file`, checking what it is.

    Parameters
    ----------
    path : path-like
        File to read.
    schema : str
        Expected schema name.
    major : int
        Expected major schema version; a newer minor version is accepted.
    required : tuple of str
        Dataset paths that must be present.

    Raises
    ------
    InputError
        Missing, unreadable, truncated or corrupt file; another schema or
        version; a required dataset missing or without units. The message
        names the file and, where it applies, the dataset.
    """
    path = check_source(path, f"{schema.removeprefix('flexbed.')} file")
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise InputError(f"{path}: not a readable HDF5 file (truncated or corrupt?): "
                         f"{str(exc).splitlines()[0]}") from None
    datasets: dict[str, Any] = {}
    units: dict[str, str] = {}
    attrs: dict[str, dict[str, Any]] = {}
    current = None
    try:
        with f:
            found = _decode(f.attrs.get("schema", ""))
            if found != schema:
                raise InputError(f"{path}: schema is '{found or 'none'}', expected '{schema}'")
            ver = str(_decode(f.attrs.get("schema_version", "")))
            try:
                got_major = int(ver.split(".")[0])
            except ValueError:
                raise InputError(f"{path}: schema_version '{ver}' is not MAJOR.MINOR") from None
            if got_major != major:
                how = ("written by a newer flexbed: upgrade flexbed"
                       if got_major > major else
                       "written by an older flexbed: re-run the stage that made it")
                raise InputError(f"{path}: {schema} version {ver} is not supported "
                                 f"(this flexbed reads {major}.x; {how})")

            def visit(name: str, obj: Any) -> None:
                nonlocal current
                current = name
                if isinstance(obj, h5py.Dataset):
                    if obj.dtype.kind == "O" or h5py.check_string_dtype(obj.dtype):
                        value = obj.asstr()[()]
                        if isinstance(value, np.ndarray):
                            value = value.astype(object)
                    else:
                        value = obj[()]
                    datasets[name] = value
                    units[name] = _decode(obj.attrs.get("units", None))
                else:
                    attrs[name] = {k: _decode(v) for k, v in obj.attrs.items()}

            attrs[""] = {k: _decode(v) for k, v in f.attrs.items()}
            f.visititems(visit)
    except InputError:
        raise
    except Exception as exc:  # h5py raises OSError/KeyError/RuntimeError on damage
        where = f" at dataset '{current}'" if current else ""
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputError(f"{path}: corrupt HDF5 file{where}: {first}") from None
    for name in required:
        if name not in datasets:
            raise InputError(f"{path}: dataset '{name}' is missing")
    for name, unit in units.items():
        if unit is None:
            raise InputError(f"{path}: dataset '{name}' has no 'units' attribute")
    return Contents(path=path, datasets=datasets, units=units, attrs=attrs)
