"""The group ``stress`` of the modes file (schema 1.4): each mode's stress
fields at the element centres (:mod:`flexbed.fem.modal_stress`).

=====================================  ================  ====================
dataset                                shape             units
=====================================  ================  ====================
``stress/centres``                     (ne, 2)           m
``stress/membrane``                    (n, ne, 3)        Pa kg^-1/2
``stress/bending_top``                 (n, ne, 3)        Pa kg^-1/2
``stress/von_mises``                   (n, ne, 2)        Pa kg^-1/2
``stress/principal``                   (n, ne, 2, 2)     Pa kg^-1/2
``stress/stiffener_<k>/centres``       (k_e, 2)          m
``stress/stiffener_<k>/axial``         (n, k_e)          Pa kg^-1/2
``stress/stiffener_<k>/gradient``      (n, k_e)          Pa m^-1 kg^-1/2
``stress/stiffener_<k>/fibres``        (f,)              m
=====================================  ================  ====================

Components are (σxx, σyy, τxy) in the bed frame; the bottom face's
bending stress is minus the top's. ``von_mises`` and ``principal`` are
each mode's own (top face, bottom face): a combination of modes takes its
measures from the superposed components, never from these. A stiffener
group's attribute ``name`` is its name in the scene. A file older than 1.4
has no group ``stress``: it reads as None.
"""

from __future__ import annotations

import numpy as np

from flexbed.errors import InputError
from flexbed.fem.modal_stress import ModalStress, StiffenerModalStress
from flexbed.fem.stresses import principal, von_mises
from flexbed.files.store import Dataset

__all__ = ["stress_datasets", "read_stress"]

_PER_MODE = "per mass-normalised mode"


def stress_datasets(s: ModalStress) -> tuple[dict, dict]:
    """Datasets and group attributes of the group ``stress``."""
    faces = s.faces(np.eye(s.n_modes))                      # (n, ne, 2, 3)
    d = {
        "stress/centres": Dataset(s.centres, "m", "element centres where the stresses are "
                                                  "recovered (bed frame)"),
        "stress/membrane": Dataset(s.membrane, "Pa kg^-1/2",
                                   f"membrane stress (xx, yy, xy) {_PER_MODE}"),
        "stress/bending_top": Dataset(s.bending, "Pa kg^-1/2",
                                      "bending stress (xx, yy, xy) at the top face (z = +t/2; "
                                      f"the bottom face's is its negative) {_PER_MODE}"),
        "stress/von_mises": Dataset(von_mises(faces), "Pa kg^-1/2",
                                    f"von Mises stress at the (top, bottom) face {_PER_MODE}"),
        "stress/principal": Dataset(principal(faces), "Pa kg^-1/2",
                                    "principal stresses (largest first) at the (top, bottom) "
                                    f"face {_PER_MODE}"),
    }
    attrs = {}
    for k, st in enumerate(s.stiffeners):
        g = f"stress/stiffener_{k}"
        d[f"{g}/centres"] = Dataset(st.centres, "m", "beam elements' mid-points (bed frame)")
        d[f"{g}/axial"] = Dataset(st.axial, "Pa kg^-1/2",
                                  f"axial stress at the section's centroid {_PER_MODE}")
        d[f"{g}/gradient"] = Dataset(st.gradient, "Pa m^-1 kg^-1/2",
                                     "bending stress per metre above the centroid "
                                     f"{_PER_MODE}")
        d[f"{g}/fibres"] = Dataset(np.asarray(st.fibres, dtype=float), "m",
                                   "extreme fibres' heights above the centroid")
        attrs[g] = {"name": st.name}
    attrs["stress"] = {"where": "element centres", "stiffeners": len(s.stiffeners)}
    return d, attrs


def read_stress(c, n: int) -> ModalStress | None:
    """The group ``stress`` of read contents ``c`` holding ``n`` modes
    (None when the file has none)."""
    if "stress/membrane" not in c.datasets:
        return None
    centres = np.asarray(c.get("stress/centres"), dtype=float)
    ne = centres.shape[0] if centres.ndim == 2 else -1
    arrays = {}
    for name in ("membrane", "bending_top"):
        arrays[name] = np.asarray(c.get(f"stress/{name}"), dtype=float)
        if arrays[name].shape != (n, ne, 3):
            raise InputError(f"{c.path}: dataset 'stress/{name}' has shape "
                             f"{arrays[name].shape}, expected ({n}, {ne}, 3)")
    count = int(c.attrs.get("stress", {}).get("stiffeners", 0))
    stiff = []
    for k in range(count):
        g = f"stress/stiffener_{k}"
        cen = np.asarray(c.get(f"{g}/centres"), dtype=float)
        ax = np.asarray(c.get(f"{g}/axial"), dtype=float)
        gr = np.asarray(c.get(f"{g}/gradient"), dtype=float)
        if cen.ndim != 2 or ax.shape != (n, cen.shape[0]) or gr.shape != ax.shape:
            raise InputError(f"{c.path}: group '{g}' has inconsistent shapes "
                             f"(centres {cen.shape}, axial {ax.shape}, gradient {gr.shape})")
        stiff.append(StiffenerModalStress(str(c.attrs.get(g, {}).get("name", g)), cen, ax, gr,
                                          np.asarray(c.get(f"{g}/fibres"), dtype=float)))
    return ModalStress(centres=centres, membrane=arrays["membrane"],
                       bending=arrays["bending_top"], stiffeners=tuple(stiff))
