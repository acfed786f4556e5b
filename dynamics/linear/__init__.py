"""The linear fast path: the motion linearised about the static equilibrium,
propagated exactly, with an estimate of its error against the nonlinear
model.

What the room holds
-------------------
:mod:`.model`
    The linear model: minimal deviations from the equilibrium
    (:class:`Coordinates`), the one linearisation of the equations of
    motion, ``ż ≈ A z + b0 + B (u(t) − u(0))`` (:func:`linearise`, central
    differences of the one right-hand side; also used by
    :mod:`flexbed.dynamics.frequency.mounted`, :mod:`flexbed.dynamics.stability` and
    through them the modal and frequency analyses), the base's inputs as
    channels, and A balanced by powers of 2 (LAPACK's ``dgebal`` through
    :func:`scipy.linalg.matrix_balance`, once per :class:`Linearisation`).
:mod:`.propagation`
    The exact propagation over the output samples and the inputs' knots:
    one matrix exponential of the state augmented with the inputs
    (polynomial pieces, analytic sinusoids as rotating pairs) per distinct
    piece length (without sinusoids by the φ-functions' series on the
    balanced A), then the recursion ``z ← Φ z + Ψ w``.
:mod:`.estimate`
    The error estimate: the defect of the linear solution in the nonlinear
    right-hand side at nodes among the pieces' ends, refined where its
    local cubics need it, propagated exactly through the linear model;
    also the energy quadratures' works.
:mod:`.run`
    :func:`run_linear`: the three above in one run, handed back as an
    integrator's :class:`flexbed.dynamics.integrate.Run`
    (:class:`LinearRun`).
:mod:`.sweep`, :mod:`.phi`, :mod:`.defect`
    Their compiled loops (numba): the recursion over the pieces and the
    conversions between states and deviations; the φ-functions' series
    and their exact doublings; the estimate's defect, node refinement,
    local cubics and error peaks.

How they fit: ``run_linear`` linearises (model), propagates (propagation,
with sweep and phi), then estimates (estimate, with defect, phi and
sweep); model, propagation and estimate share one :class:`Linearisation`
and its balanced A.

What it may import
------------------
NumPy, SciPy, numba, and of :mod:`flexbed.dynamics` the compiled system
(:mod:`flexbed.dynamics.system`, whose right-hand side the estimate calls
through its pointer, and its layout), :mod:`flexbed.dynamics.integrate`
(the run's containers and output grid), :mod:`flexbed.dynamics.piecewise`
and :mod:`flexbed.dynamics.jitcache`. Never ``flexbed.fem``, never the
pipeline (``flexbed`` itself). The time steppers
(:mod:`flexbed.dynamics.steppers`) do not import this room.
"""

from __future__ import annotations

from ..jitcache import refresh as _refresh

_refresh()   # before any compiled function is loaded (flexbed.dynamics.jitcache)

from .estimate import ErrorEstimate, estimate_error
from .model import Coordinates, Linearisation, linearise
from .propagation import propagate, propagate_pieces
from .run import LinearRun, run_linear, unstable_rate

__all__ = ["Coordinates", "Linearisation", "LinearRun", "linearise", "propagate",
           "propagate_pieces", "run_linear", "estimate_error", "ErrorEstimate", "unstable_rate"]
