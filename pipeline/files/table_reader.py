"""Checked reading of parsed TOML tables: the one place that turns a value a
user typed into a number, a list or a choice, or into a one-line
:class:`~flexbed.errors.InputError` naming the file, the entry and the value."""

from __future__ import annotations

import math
import unicodedata
from pathlib import Path
from typing import Any, NoReturn

from flexbed.errors import InputError

__all__ = ["TableReader", "is_number", "is_finite_number", "LARGEST", "SMALLEST", "out_of_range",
           "short_repr", "MAX_WORKERS", "MAX_BATCH", "FREQUENCY_LIMITS",
           "MAX_SEED"]

#: the largest magnitude a number in a scene may have: products of three
#: such numbers (a mass, an acceleration, a length) stay inside double
#: precision (1.8e308), so an entry cannot overflow the equations of motion
#: unnoticed
LARGEST = 1e100
#: the smallest non-zero magnitude: its reciprocal stays below LARGEST, and
#: subnormal numbers (5e-324) are refused instead of vanishing in a product
SMALLEST = 1e-100
#: [Hz] the frequencies a response may be asked at, and a PSD given at:
#: below 1 µHz a period is 11 days, above 10 MHz no mount model means
#: anything, and outside these the dynamic stiffness's terms (ω² M against
#: K) differ by more than the doubles can hold
FREQUENCY_LIMITS = (1e-6, 1e7)
#: the most workers a local Dask cluster is started with (``--workers``,
#: ``workers=``): far past any machine's cores, short of the thousands of
#: processes that would hang the start
MAX_WORKERS = 1024
#: the most points one Dask task takes (``--batch``, ``batch=``)
MAX_BATCH = 10_000
#: the largest random seed (``--seed``, ``seed=``; NumPy's take non-negative
#: integers)
MAX_SEED = 2 ** 63 - 1


def out_of_range(v: float) -> bool:
    """True for a finite number that is not 0 and not within
    [SMALLEST, LARGEST] in magnitude."""
    return v != 0.0 and not (SMALLEST <= abs(v) <= LARGEST)


def is_number(v: Any) -> bool:
    """True for an int or float (not a bool)."""
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def is_finite_number(v: Any) -> bool:
    """True for an int or float (not a bool) that is finite as a double (an
    integer beyond double precision is not)."""
    if not is_number(v):
        return False
    try:
        return math.isfinite(v)
    except OverflowError:
        return False


class TableReader:
    """Value checks for one file.

    Parameters
    ----------
    label : str
        The file's name as messages show it.
    folder : Path
        Where files the tables refer to (CSV data) are looked up.
    """

    def __init__(self, label: str, folder: Path):
        self.label = label
        self.folder = folder
        self.csv: dict[str, str] = {}

    def fail(self, where: str, msg: str) -> NoReturn:
        raise InputError(f"{self.label}: {where}: {msg}" if where else f"{self.label}: {msg}")

    def keys(self, where: str, table: Any, allowed: tuple, required: tuple = ()) -> dict:
        if not isinstance(table, dict):
            self.fail(where, f"must be a table, got {short_repr(table)}")
        for key in table:
            if key not in allowed:
                self.fail(where, f"unknown key '{key}' (known: {', '.join(allowed)})")
        for key in required:
            if key not in table:
                self.fail(where, f"'{key}' is required")
        return table

    def number(self, where, key, value, *, positive=False, non_negative=False) -> float:
        if not is_number(value):
            self.fail(where, f"{key} = {short_repr(value)} must be a number")
        try:
            v = float(value)
        except OverflowError:                  # an integer beyond double precision
            self.fail(where, f"{key} = {short_repr(value)} is out of range (magnitudes from "
                             f"{SMALLEST:g} to {LARGEST:g}, or 0)")
        if not math.isfinite(v):
            self.fail(where, f"{key} = {v!r} must be finite")
        if out_of_range(v):
            self.fail(where, f"{key} = {short_repr(value)} is out of range (magnitudes from "
                             f"{SMALLEST:g} to {LARGEST:g}, or 0)")
        if positive and not v > 0:
            self.fail(where, f"{key} = {v!r} must be > 0")
        if non_negative and v < 0:
            self.fail(where, f"{key} = {v!r} must be >= 0")
        return v

    def numbers(self, where, key, value, n=None, *, positive=False, non_negative=False,
                min_len=1) -> list[float]:
        if not isinstance(value, list):
            self.fail(where, f"{key} = {short_repr(value)} must be a list of numbers")
        if n is not None and len(value) != n:
            self.fail(where, f"{key} = {short_repr(value)} must have {n} numbers, has {len(value)}")
        if len(value) < min_len:
            self.fail(where, f"{key} has {len(value)} numbers, needs at least {min_len}")
        return [self.number(where, f"{key}[{i}]", v, positive=positive, non_negative=non_negative)
                for i, v in enumerate(value)]

    def string(self, where, key, value, choices=None) -> str:
        if not isinstance(value, str):
            self.fail(where, f"{key} = {short_repr(value)} must be a string")
        if key != "description" and any(unicodedata.category(c) == "Cc" for c in value):
            self.fail(where, f"{key} = {short_repr(value)} holds a control character (a line "
                             f"break, a tab, …); names are one line of text")
        if choices is not None and value not in choices:
            self.fail(where, f"{key} = {short_repr(value)} "
                             f"must be one of {', '.join(map(repr, choices))}")
        return value

    def tables(self, where, value) -> list:
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            self.fail("", f"{where} must be an array of tables ([[{where}]])")
        return value


def short_repr(value: Any, limit: int = 60) -> str:
    """``repr(value)``, cut to ``limit`` characters with the length said
    (a 300-digit number is not echoed whole)."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10 ** limit:
        return f"<an integer of {int(abs(value).bit_length() * 0.30103) + 1} digits>"
    text = repr(value)
    return text if len(text) <= limit else f"{text[:limit - 12]}… ({len(text)} characters)"
