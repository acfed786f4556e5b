"""The pipeline's stages, each reading the previous stage's output:

- :mod:`~flexbed.stages.modes`: the bed's modes file, reused or computed
  (:mod:`~flexbed.stages.modes_auto`: ``modes = "auto"``;
  :mod:`~flexbed.stages.residual_modes`: the static correction);
- :mod:`~flexbed.stages.flexible_bed`: the modes file handed to the
  dynamics as a flexible body;
- :mod:`~flexbed.stages.system`: a scene file compiled into the dynamics'
  system;
- :mod:`~flexbed.stages.simulation`: the static equilibrium and the motion
  (:mod:`~flexbed.stages.motion`: integrators or the linear path);
- :mod:`~flexbed.stages.keep`: what an interrupted run keeps.

It may import :mod:`flexbed.files`, :mod:`flexbed.fem`,
:mod:`flexbed.dynamics`, :mod:`flexbed.errors` and
:mod:`flexbed.interrupts`; not analyses, plots or commands.
"""
