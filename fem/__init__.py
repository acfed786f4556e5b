"""The common bed's finite-element model, installed as ``flexbed.fem``
(the folder ``fem/``): plate inputs → mesh → stiffness and mass → free–free
modes → nodal mode shapes and modal invariants.

- the inputs and their hash: :mod:`~flexbed.fem.spec`,
  :mod:`~flexbed.fem.geometry` (outline, cut-outs, zones, a mesh file),
  :mod:`~flexbed.fem.stiffeners`, :mod:`~flexbed.fem.fixed_masses`;
- meshes: :mod:`~flexbed.fem.mesher`, :mod:`~flexbed.fem.cells`,
  :mod:`~flexbed.fem.layout`, :mod:`~flexbed.fem.mass_properties`;
- the Kirchhoff plate (Bogner–Fox–Schmit): :mod:`~flexbed.fem.plate`,
  :mod:`~flexbed.fem.element`, :mod:`~flexbed.fem.hermite`; the Mindlin
  shell: :mod:`~flexbed.fem.shell` (:mod:`~flexbed.fem.mitc4`;
  triangles: :mod:`~flexbed.fem.mitc3`, :mod:`~flexbed.fem.edge_smoothing`,
  :mod:`~flexbed.fem.triangle_shell`), :mod:`~flexbed.fem.stiffener_face`;
- modes: :mod:`~flexbed.fem.modes` (with :mod:`~flexbed.fem.banded`);
  :mod:`~flexbed.fem.bed` the whole stage in one call;
- what the dynamics gets: :mod:`~flexbed.fem.invariants` (the modal
  invariants, whose contract is :data:`flexbed.files.modes.INVARIANTS`),
  mode shapes anywhere on the bed (:mod:`~flexbed.fem.grid_shapes` on the
  Kirchhoff grid, :mod:`~flexbed.fem.quad_shapes` on the shell's mesh),
  :mod:`~flexbed.fem.export` (VTU for ParaView), stresses
  (:mod:`~flexbed.fem.stresses`, each mode's: :mod:`~flexbed.fem.modal_stress`);
- a 3D-solid reference for checks only: :mod:`~flexbed.fem.solid`,
  :mod:`~flexbed.fem.solid_check`, :mod:`~flexbed.fem.solid_stress`.

It may import NumPy, SciPy, scikit-fem (the only package that does) and
meshio; never :mod:`flexbed.dynamics` (the modes file and plain arrays are
the contract between them), h5py, or the rest of flexbed.
"""
