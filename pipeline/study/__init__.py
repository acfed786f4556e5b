"""Design studies: many variants of one scene, run on Dask.

- :mod:`~flexbed.study.spec` reads the study file (TOML) into frozen dataclasses;
- :mod:`~flexbed.study.samplers` turns its parameters into points (grid,
  list, zip, Latin hypercube);
- :mod:`~flexbed.study.analyses` runs the analyses of one point (static,
  simulate, compare; a registry other analyses join);
- :mod:`~flexbed.study.outputs` holds a point's run and evaluates only what
  its metrics read;
- :mod:`~flexbed.study.metrics` reduces them to the numbers kept;
- :mod:`~flexbed.study.plan` checks the whole study before anything runs;
- :mod:`~flexbed.study.point` is what a Dask worker runs;
- :mod:`~flexbed.study.engine` starts or joins the Dask cluster;
- :mod:`~flexbed.study.runner` submits the points and gathers the rows;
- :mod:`~flexbed.study.table` is the output (its plots: :mod:`flexbed.plots.study`).

It may import :mod:`flexbed.api` (a point's analyses are the API's
functions), :mod:`flexbed.files`, :mod:`flexbed.plots` (on writing them)
and :mod:`flexbed.dynamics`. Only ``flexbed sweep`` and
:func:`flexbed.sweep` import this package (and through it
``dask.distributed``).
"""
