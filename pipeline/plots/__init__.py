"""Every PNG plot of flexbed (matplotlib on its Agg backend):

- :mod:`~flexbed.plots.figure`: what they share (the backend, line styles,
  :func:`~flexbed.plots.figure.save_figure`: 120 dpi, atomic writes);
- :mod:`~flexbed.plots.runs`: a run over time (the compared cases, a
  point's axes, the base's input, the mount forces);
- :mod:`~flexbed.plots.frequency`: over frequency (the decoupling map, Bode
  plots, shock response spectra);
- :mod:`~flexbed.plots.bench`: the benchmark's error against cost;
- :mod:`~flexbed.plots.study`: a study's metrics against its parameters;
- :mod:`~flexbed.plots.stress`: the map of the bed's peak stress.

The plots take plain arrays (and a study's table) and write files; they
may import matplotlib, NumPy and :mod:`flexbed.files.destination`, nothing
that computes. This ``__init__`` imports nothing: matplotlib loads only
with a plot module, and the commands import those only when they plot
(``flexbed simulate`` never does).
"""
