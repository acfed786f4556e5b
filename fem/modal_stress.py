"""The modal stress fields stored with the modes: each mode's stresses at
the element centres (:mod:`flexbed.fem.stresses`), so that any response
a(t) of the modal coordinates gives the bed's stresses by superposition,
σ(t) = Σ_i σ_i a_i(t), without the FE model.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .stresses import face_stresses, plate_stress_operators, shell_stress_operators

__all__ = ["ModalStress", "StiffenerModalStress", "modal_stress"]


@dataclass(frozen=True)
class StiffenerModalStress:
    """One stiffener's modal stresses at its beam elements' mid-points.

    Attributes
    ----------
    name : str
    centres : ndarray (k, 2)
        Mid-points in the bed frame [m].
    axial : ndarray (n, k)
        Axial stress at the centroid [Pa kg^-1/2].
    gradient : ndarray (n, k)
        Bending stress per metre above the centroid [Pa m^-1 kg^-1/2].
    fibres : ndarray (f,)
        Extreme fibres' heights above the centroid [m]
        (:func:`flexbed.fem.stresses.stiffener_fibres`).
    """

    name: str
    centres: np.ndarray
    axial: np.ndarray
    gradient: np.ndarray
    fibres: np.ndarray

    def fibre_stress(self, a: np.ndarray) -> np.ndarray:
        """Stress at each extreme fibre (..., k, f) [Pa] for modal
        coordinates a (..., n) [kg^1/2 m]."""
        ax = a @ self.axial
        gr = a @ self.gradient
        return ax[..., None] + gr[..., None] * self.fibres


@dataclass(frozen=True)
class ModalStress:
    """Each mode's stresses at the bed's element centres.

    Attributes
    ----------
    centres : ndarray (ne, 2)
        Element centres in the bed frame [m].
    membrane : ndarray (n, ne, 3)
        Membrane stress (σxx, σyy, τxy) [Pa kg^-1/2] (zero for a Kirchhoff
        plate).
    bending : ndarray (n, ne, 3)
        Bending stress at the top face (z = +t/2); the bottom face's is
        its negative [Pa kg^-1/2].
    stiffeners : tuple of StiffenerModalStress
    """

    centres: np.ndarray
    membrane: np.ndarray
    bending: np.ndarray
    stiffeners: tuple = ()

    @property
    def n_modes(self) -> int:
        return int(self.membrane.shape[0])

    def faces(self, a: np.ndarray) -> np.ndarray:
        """Stress components at the top and bottom faces (..., ne, 2, 3)
        [Pa] for modal coordinates a (..., n) [kg^1/2 m]."""
        m = np.tensordot(a, self.membrane, axes=(-1, 0))
        b = np.tensordot(a, self.bending, axes=(-1, 0))
        return face_stresses(m, b)

    def transformed(self, T: np.ndarray) -> ModalStress:
        """The stresses of coordinates a' with a = T a' (T (n, n'), e.g.
        the static correction's, :mod:`flexbed.stages.residual_modes`)."""
        return ModalStress(
            centres=self.centres,
            membrane=np.tensordot(T, self.membrane, axes=(0, 0)),
            bending=np.tensordot(T, self.bending, axes=(0, 0)),
            stiffeners=tuple(StiffenerModalStress(s.name, s.centres, T.T @ s.axial,
                                                  T.T @ s.gradient, s.fibres)
                             for s in self.stiffeners))

    def first(self, n: int) -> ModalStress:
        """The lowest n modes' stresses."""
        return self.transformed(np.eye(self.n_modes)[:, :n])


def modal_stress(model, phi: np.ndarray) -> ModalStress:
    """Modal stresses of DOF vectors phi (ndof, n) on a Mindlin
    :class:`~flexbed.fem.shell.ShellModel` or a Kirchhoff
    :class:`~flexbed.fem.plate.PlateModel`."""
    from .shell import ShellModel
    ops = (shell_stress_operators(model) if isinstance(model, ShellModel)
           else plate_stress_operators(model))
    membrane, bending = ops.of(phi)
    stiff = tuple(StiffenerModalStress(s.name, s.centres, (s.axial @ phi).T,
                                       (s.gradient @ phi).T, s.fibres)
                  for s in ops.stiffeners)
    return ModalStress(centres=ops.centres, membrane=membrane, bending=bending,
                       stiffeners=stiff)
