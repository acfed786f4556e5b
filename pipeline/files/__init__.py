"""flexbed's files: what is read and written, and nothing that computes.

- the scene file (TOML, :mod:`~flexbed.files.scene`) and its parts:
  :mod:`~flexbed.files.bed_section`, :mod:`~flexbed.files.bed_geometry`,
  :mod:`~flexbed.files.bed_points`, :mod:`~flexbed.files.drives`, checked
  through :mod:`~flexbed.files.table_reader`, warned about by
  :mod:`~flexbed.files.sanity`; the built-in scene
  (:mod:`~flexbed.files.builtin`), variants (:mod:`~flexbed.files.variants`)
  and TOML text (:mod:`~flexbed.files.toml_text`);
- the stages' HDF5 files: modes (:mod:`~flexbed.files.modes`, with the
  modal invariants' contract), equilibrium and results
  (:mod:`~flexbed.files.results`), the frequency-domain analyses
  (:mod:`~flexbed.files.frequency`, :mod:`~flexbed.files.random`), all through
  :mod:`~flexbed.files.store`, the only module that imports h5py;
- the modes file's stresses (:mod:`~flexbed.files.modes_stress`);
- base acceleration PSD specifications (:mod:`~flexbed.files.psd`: TOML
  or CSV g²/Hz tables);
- ParaView's XDMF (:mod:`~flexbed.files.xdmf`,
  :mod:`~flexbed.files.mode_shapes`, :mod:`~flexbed.files.stress_xdmf`);
- :mod:`~flexbed.files.destination`: where flexbed may write, atomically.

It may import :mod:`flexbed.fem` and :mod:`flexbed.dynamics` (the data
classes a file becomes) and :mod:`flexbed.errors`; not stages, analyses or
commands (one exception, on first call: ``modes = "auto"`` asks
:mod:`flexbed.stages.modes_auto` for its cut-off).
"""
