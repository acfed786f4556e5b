"""Markdown pieces of the benchmark report: tables and number formats."""

from __future__ import annotations

import math

__all__ = ["md_table", "fmt_error", "fmt_time"]


def md_table(head: list[str], rows: list[list[str]], align: str | None = None) -> str:
    """A Markdown table.

    Parameters
    ----------
    head : column titles
    rows : one list of cell strings per row, as long as ``head``
    align : one letter per column, "l" or "r" (default: all left)
    """
    align = align or "l" * len(head)
    rule = ["---:" if a == "r" else "---" for a in align]
    lines = ["| " + " | ".join(head) + " |", "|" + "|".join(rule) + "|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def fmt_error(value: float) -> str:
    """An error in scientific notation, three digits; "n/a" for NaN."""
    return "n/a" if not math.isfinite(value) else f"{value:.2e}"


def fmt_time(seconds: float) -> str:
    """A duration: "0.123 s", "12.3 s", "4 min 05 s"."""
    if not math.isfinite(seconds):
        return "n/a"
    if seconds < 10:
        return f"{seconds:.3f} s"
    if seconds < 120:
        return f"{seconds:.1f} s"
    m, s = divmod(int(round(seconds)), 60)
    return f"{m} min {s:02d} s"
