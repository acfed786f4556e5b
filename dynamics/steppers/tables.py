"""What the method coefficients' tables share: arrays checked and frozen.

Used by :mod:`.dop853_coefficients` and :mod:`.radau_coefficients` when
their frozen dataclasses are built.
"""

from __future__ import annotations

import numpy as np

__all__ = ["freeze_arrays"]


def freeze_arrays(table, method: str, shapes: dict) -> None:
    """Replace each named field of a frozen dataclass by a read-only float64
    array of the given shape, checked finite.

    Parameters
    ----------
    table : frozen dataclass instance
        The coefficient table being built (from its ``__post_init__``).
    method : str
        The method's name, for the message (e.g. ``"DOP853"``).
    shapes : dict of str to tuple of int
        Field name → expected shape.

    Raises
    ------
    ValueError
        A field of another shape, or with a non-finite entry, named.
    """
    for name, shape in shapes.items():
        value = np.array(getattr(table, name), dtype=np.float64)
        if value.shape != shape or not np.all(np.isfinite(value)):
            raise ValueError(f"{method} {name}: expected finite values of shape {shape}, got "
                             f"shape {value.shape}")
        value.setflags(write=False)
        object.__setattr__(table, name, value)
