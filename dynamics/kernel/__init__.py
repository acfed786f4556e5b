"""The right-hand side of the equations of motion, compiled (numba).

:func:`evaluate` is the one implementation of the physics of a scene at a
time t and state y (layout: :mod:`flexbed.dynamics.layout`), compiled once
as a C function (:func:`rhs_function`) that every compiled caller calls
through its pointer. It reads a scene compiled into flat arrays (the
fields of :class:`Compiled`, built by
:func:`flexbed.dynamics.kernel_tables.kernel_storage` for a
:class:`flexbed.dynamics.system.System`, packed into two arrays by
:func:`pack`) and does arithmetic only, in this order, one compiled
function per step (:mod:`.rhs`):

1. the base: prescribed position, velocity and acceleration from the
   drives (their exact integrals), or the state of a free base and its
   external loads (piecewise polynomials or windowed sinusoids);
2. every body: ``A = Q(p)/|p|²`` (so a slightly non-unit p still gives a
   rotation) and ``ṗ = ½ p ⊗ (0, ω̄)``;
3. every mount end e on body b at body-frame point ū_e = s̄_e (+ Φ_e a on a
   flexible body): ``P = r + A ū``, ``Ṗ = ṙ + A (ω̄ × ū + Φ_e ȧ)``;
4. every mount (paper eq. 2–4): ``l = P_j − P_i``, ``Δx = U (A_iᵀ l) − d0``,
   ``Δẋ = U (A_iᵀ l̇)``, forces f from the mount's laws (plus a bump stop's
   contact force past its gap: decided by Δx, or held by an integrator,
   :mod:`flexbed.dynamics.contacts`), ``F = A_i Uᵀ f`` on P_i and ``−F``
   on P_j;
4b. every load on a body (force or moment, inertial or body axis, at a
   body-frame point ū that moves with the modes on a flexible body): added
   to the body's force, its moment ``ū × F̄`` and, on a flexible body, the
   modal forces ``Φᵀ F̄``, as a mount end's force is;
5. Newton–Euler per rigid body (``m r̈ = F + m g``,
   ``J ω̄̇ = n̄ − ω̄ × J ω̄``) and, per flexible body, the floating-frame
   equations in the body frame ``M̄(a) [Aᵀ r̈, ω̄̇, ä] = Q̄`` from the modal
   invariants (:func:`flex_mass_body`, :func:`flex_forces_body`; the
   formulas are in :mod:`flexbed.dynamics.flexible`), solved by Cholesky;
6. the velocity rates into dy, a free base's equations, and the powers
   that feed the energy quadratures;
7. the elastomer mounts' Maxwell terms (:mod:`flexbed.dynamics.maxwell_terms`):
   their forces k_i (Δx − z_i) were added to the mount's in step 4 (their
   sums per mount direction taken just before it, 4a); here their rates
   ż_i = (Δx − z_i)/τ_i.

Everything per call writes into arrays of :class:`Compiled` (the ``w_*``
work arrays), so a call allocates nothing; ``w_dx``, ``w_dxd``, ``w_f``,
``w_F``, ``w_acc`` and ``w_base`` keep the last call's mount deflections,
rates, forces, inertial mount forces, accelerations and base motion, and
``w_M`` each flexible body's mass matrix as its Cholesky factor, for
:func:`flexbed.dynamics.observation.observe` and
:mod:`flexbed.dynamics.history` (:func:`evaluate_batch` evaluates many
states in one call).

Modules: :mod:`.storage` (the fields, packing, views), :mod:`.inputs`
(the base's inputs), :mod:`.mount_laws`, :mod:`.flexible_body`,
:mod:`.rhs` (:func:`evaluate`, its sections, its C function),
:mod:`.batch`. The package imports NumPy, numba and
:mod:`flexbed.dynamics.jitcache` only, nothing else of flexbed: the scene
reaches it as arrays.

Inputs (drives and loads of the base, loads on bodies), one row each: ``in_kind`` 0 for a
piecewise polynomial (value, first and second integral as three tables of
breaks, origins and ascending coefficients, padded with +inf breaks and
zero rows), 1 for a windowed sinusoid (``in_sin`` = amplitude, ω, phase,
start, end). At t ≥ ``seg_end`` an input gives its limit from the left
(from inside the segment an integrator is stepping through); elsewhere it
is right-continuous. ``seg_end = inf`` means right-continuous everywhere.
"""

from __future__ import annotations

from ..jitcache import refresh as _refresh

_refresh()   # before any compiled function is loaded (flexbed.dynamics.jitcache)

from .batch import evaluate_batch
from .flexible_body import flex_forces_body, flex_mass_body, flex_T
from .inputs import piecewise_value
from .rhs import PROTOTYPE, evaluate, evaluate_many, rhs_function
from .storage import FIELDS, HEADER, KINDS, Compiled, pack

__all__ = ["Compiled", "FIELDS", "KINDS", "HEADER", "pack", "evaluate", "rhs_function",
           "PROTOTYPE", "evaluate_many", "evaluate_batch", "flex_T", "flex_mass_body",
           "flex_forces_body", "piecewise_value"]
