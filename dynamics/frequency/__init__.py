"""The mounted system in the frequency domain, about its static equilibrium.

- :mod:`.mounted`: the second-order matrices ``M q̈ + C q̇ + K q = 0`` (base
  held) and the mounts' and base's output matrices, from the one
  linearisation of the right-hand side (:mod:`flexbed.dynamics.linear.model`);
- :mod:`.modal`: natural frequencies, damping ratios, mode shapes, the
  kinetic- and strain-energy tables and modal effective masses;
  :mod:`.star` and :mod:`.star_modes`: the eigen-solutions of large
  systems by their hub-and-leaves structure (a bed carrying many pieces
  of equipment);
- :mod:`.frf`: transmissibility and mount forces per frequency, on a grid
  refined until every resonance is resolved;
- :mod:`.load_inputs`: loads on bodies (forces, unbalances) as inputs.
- :mod:`.random`: stationary random response: PSD interpolation, the
  grid that resolves every half-power band, response PSDs, mean squares
  with their error, Miles' equation.
- :mod:`.elastomer`: elastomer mounts' complex stiffness k(f)(1 + iη(f))
  added to the dynamic stiffness and the force outputs;
  :mod:`.elastomer_modes`: modes with each elastomer at the mode's own
  frequency; :mod:`.maxwell`: the generalised Maxwell fit a time run needs.

May import NumPy, SciPy and, from :mod:`flexbed.dynamics`, the compiled
system, the rotations and the linear room's linearisation; never ``fem``
or ``pipeline``. Names, tables and files of these results are
:mod:`flexbed.analyses.modal` and :mod:`flexbed.analyses.frf`.
"""
