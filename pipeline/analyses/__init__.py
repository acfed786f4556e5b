"""Analyses after a run or about the equilibrium, and their tables:

- :mod:`~flexbed.analyses.points`: a finished run's points of interest and
  mount forces (:mod:`~flexbed.analyses.linear_points`: the same in the
  linear mounted system);
- :mod:`~flexbed.analyses.compare`: the rigid, flexible and damped flexible
  bed side by side;
- :mod:`~flexbed.analyses.modal`: the mounted system's modes;
  :mod:`~flexbed.analyses.mode_shapes`: their shapes on meshes;
- :mod:`~flexbed.analyses.frf`: transmissibility;
- :mod:`~flexbed.analyses.random`: random vibration under base acceleration
  PSDs (read by :mod:`~flexbed.files.psd`);
- :mod:`~flexbed.analyses.shock`: shock response spectra;
- :mod:`~flexbed.analyses.bed_stress`: the bed's stresses over a run;
- :mod:`~flexbed.analyses.summary`: the tables of ``flexbed run``.

It may import :mod:`flexbed.stages`, :mod:`flexbed.files`,
:mod:`flexbed.fem`, :mod:`flexbed.dynamics` and flexbed's top-level
modules (errors, interrupts, words); not plots (the commands draw), api or
commands.
"""
