"""Mount-system dynamics (installed as ``flexbed.dynamics``): the scene as
data, the equations of motion in the floating frame, the static
equilibrium, time integration, the linear fast path and the frequency
domain. Imports neither scikit-fem nor h5py, and never ``flexbed.fem`` or
the pipeline (``flexbed``): a flexible body comes in as plain arrays of
modal invariants.

The map, in the order a run uses it:

- the scene as data (frozen dataclasses, validated once): :mod:`.scene`
  (bodies, base, mounts, gravity), :mod:`.laws` (mount force laws),
  :mod:`.time_functions` (drives and loads of the base over time, on
  :mod:`.piecewise` polynomials), :mod:`.flexible` (a flexible body from
  its modal invariants), :mod:`.rotation` (Euler parameters), :mod:`.errors`;
- the scene compiled once into flat arrays, and its one right-hand side:
  :mod:`.layout` (where everything lives in the state vector),
  :mod:`.system` (:class:`~.system.System`, immutable), built by
  :mod:`.kernel_tables` and :mod:`.base_inputs`; the room ``kernel/`` (the
  compiled right-hand side); :mod:`.observation` and :mod:`.history` (what
  a state implies: mount deflections, forces, energies); :mod:`.jitcache`
  (freshness of numba's on-disk cache);
- :mod:`.statics` (Newton–Raphson on the free coordinates) and
  :mod:`.stability` (is the equilibrium stable?);
- time integration: :mod:`.integrate` (segments between breakpoints,
  outputs, faults), :mod:`.contacts` (bump-stop contacts located and
  held), :mod:`.method_choice` (``auto``), :mod:`.stiffness`
  (the explicit methods' stability check); the room ``steppers/`` (rk4,
  dop853, radau compiled, with their coefficients);
- the room ``linear/``: the one linearisation and the linear fast path
  (exact propagation and its error estimate);
- the room ``frequency/``: the mounted system's modes and frequency
  responses;
- :mod:`.shock_spectrum`: shock response spectra of a time history.
"""
