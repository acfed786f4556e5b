"""Scene files, the command line, stage hand-offs through HDF5, plots."""
