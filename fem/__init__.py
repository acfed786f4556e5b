"""Plate model of the common bed: scikit-fem Kirchhoff plate, free-free
modes, modal invariants. The only package that imports scikit-fem."""
