"""Mount-system dynamics: scene model, equations of motion in the floating
frame, static equilibrium, time integration. Imports neither scikit-fem
nor h5py."""
