"""The work-precision report of ``flexbed bench``: every integrator and
modelling choice as error against cost, measured against a reference the
project computes at far tighter settings.

:mod:`~flexbed.bench.report` writes ``benchmarks.md`` from its sections
(:mod:`~flexbed.bench.dynamics`, :mod:`~flexbed.bench.fastpath`,
:mod:`~flexbed.bench.modelling`, :mod:`~flexbed.bench.modes`,
:mod:`~flexbed.bench.beds`, :mod:`~flexbed.bench.frequency`,
:mod:`~flexbed.bench.inputs`, :mod:`~flexbed.bench.scaling` on the tiled scenes of
:mod:`~flexbed.bench.tiling`, :mod:`~flexbed.bench.verdict`,
:mod:`~flexbed.bench.stress`) over shared cases
(:mod:`~flexbed.bench.context`, :mod:`~flexbed.bench.cases`,
:mod:`~flexbed.bench.reference`) and Markdown pieces
(:mod:`~flexbed.bench.markdown`); its diagrams are
:mod:`flexbed.plots.bench`.

It may import :mod:`flexbed.analyses`, :mod:`flexbed.stages`, :mod:`flexbed.api`
(the verdict section times :func:`flexbed.qualify`'s parts),
:mod:`flexbed.files`, :mod:`flexbed.plots`, :mod:`flexbed.fem` and
:mod:`flexbed.dynamics`; only ``flexbed bench`` imports it.
"""
