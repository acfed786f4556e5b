"""Mount layout optimisation on the study's Dask engine.

- :mod:`~flexbed.optimization.spec` reads the optimisation file (TOML);
- :mod:`~flexbed.optimization.problem` checks it against the scene and maps
  the variables (unit coordinates) to a scene and a point's metrics to the
  objective and the constraints;
- :mod:`~flexbed.optimization.evaluate` runs batches of points on Dask, logs
  each and computes none twice (resumable);
- :mod:`~flexbed.optimization.methods` holds SLSQP / trust-constr with
  finite-difference gradients evaluated together, differential evolution,
  multi-start;
- :mod:`~flexbed.optimization.driver` runs one optimisation to its
  :class:`~flexbed.optimization.driver.Optimum`;
- :mod:`~flexbed.optimization.report` writes the optimum scene, the
  convergence plot and the initial-against-optimum comparison.

It may import :mod:`flexbed.study` (metrics, the worker's function, the
engine), :mod:`flexbed.api`, :mod:`flexbed.files` and :mod:`flexbed.plots`.
Only ``flexbed optimize`` and :func:`flexbed.optimize` import it (named apart
from the function :func:`flexbed.optimize`, which would otherwise shadow it).
"""
