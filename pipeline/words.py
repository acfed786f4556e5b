"""Words for messages: counts with the noun in the right number."""

from __future__ import annotations


def count(n: int, noun: str, plural: str | None = None) -> str:
    """``n`` and ``noun``, singular for one: ``count(1, "segment")`` is
    "1 segment", ``count(3, "segment")`` "3 segments".

    >>> count(1, "elastic mode"), count(2, "elastic mode"), count(0, "right-hand side")
    ('1 elastic mode', '2 elastic modes', '0 right-hand sides')
    >>> count(2, "Newton iteration"), count(1, "Jacobian"), count(2, "point", "points")
    ('2 Newton iterations', '1 Jacobian', '2 points')
    """
    return f"{n} {noun if n == 1 else (plural or noun + 's')}"
