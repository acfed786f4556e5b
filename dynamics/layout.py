"""The state vector: the one place that says where everything lives.

``y = [ q | v | z | w ]`` with

``q`` — coordinates, one block per moving body:

- free base (body 1 with ``motion = "free"``): ``r`` (3) [m]
- every other body: ``r`` (3) [m], position of the body-frame origin (the
  centre of mass; for a flexible body the undeformed one) in the inertial
  frame; ``p`` (4) [–], Euler parameters, scalar first
- then the modal coordinates ``a`` of the flexible bodies, one block per
  flexible body in scene order [kg^1/2 m]

``v`` — velocities, the same blocks in the same order:

- free base: ``ṙ`` (3) [m/s]
- every other body: ``ṙ`` (3) [m/s], inertial frame; ``ω̄`` (3) [rad/s],
  angular velocity in the body frame (``ṗ = ½ G(p)ᵀ ω̄``)
- then the modal rates ``ȧ``, same blocks as ``a``

``z`` — internal states of the elastomer mounts' Maxwell terms [m], one
per term, in (mount, direction) order (:mod:`flexbed.dynamics.maxwell_terms`;
none in a scene without them)

``w`` — energy quadratures (4) [J], integrated along with the motion:
``W_mount`` (work of all mount forces on the bodies, springs and dampers),
``W_ext`` (work of the external loads: the base's, its support, loads on bodies),
``W_drive`` (work of the force that makes a driven base follow its drive),
``W_struct`` (work of the flexible bodies' structural damping, ≤ 0).

Block order: the base (if it has a state), then bodies 2… in scene order
(contiguous, so that ``q[...].reshape(n, 7)`` views them all at once,
flexible bodies included: their frame coordinates sit with the others'),
then the modal blocks. A fixed or driven base has no state. With no
flexible body the modal blocks are empty.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Layout", "N_WORK"]

N_WORK = 4


@dataclass(frozen=True, slots=True)
class Layout:
    """Offsets of every body's blocks in y.

    Parameters
    ----------
    n_bodies : int
        All bodies, the base included.
    base_free : bool
        Whether the base has a translation state.
    rigid : tuple of int
        Scene indices of the bodies with a frame state (1..n_bodies-1),
        rigid or flexible.
    modal : tuple of (int, int)
        (scene index, number of modes) of each flexible body, in scene order.
    n_internal : int
        Internal states z (the Maxwell terms).
    """

    n_bodies: int
    base_free: bool
    rigid: tuple
    modal: tuple = ()
    n_internal: int = 0
    # the offsets, computed once (every evaluation of the physics reads them)
    _sizes: tuple = field(init=False, repr=False, compare=False)
    _slices: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        nb3 = 3 * int(bool(self.base_free))
        n = len(self.rigid)
        nm = int(sum(k for _, k in self.modal))
        nq = nb3 + 7 * n + nm
        nv = nb3 + 6 * n + nm
        n_motion = nq + nv + self.n_internal
        object.__setattr__(self, "_sizes", (nm, nq, nv, n_motion, n_motion + N_WORK))
        object.__setattr__(self, "_slices", (
            slice(nb3 + 7 * n, nq),                           # q_modal
            slice(nq + nb3 + 6 * n, nq + nv),                 # v_modal
            slice(nq + nv, n_motion),                         # internal
            slice(nb3, nb3 + 7 * n),                          # q_rigid
            slice(nq + nb3, nq + nb3 + 6 * n),                # v_rigid
            slice(0, nb3),                                    # q_base
            slice(nq, nq + nb3),                              # v_base
            slice(n_motion, n_motion + N_WORK)))              # work

    @property
    def n_modal(self) -> int:
        """Modal coordinates of all flexible bodies together."""
        return self._sizes[0]

    @property
    def nq(self) -> int:
        return self._sizes[1]

    @property
    def nv(self) -> int:
        return self._sizes[2]

    @property
    def q_modal(self) -> slice:
        return self._slices[0]

    @property
    def v_modal(self) -> slice:
        return self._slices[1]

    def modal_block(self, body: int) -> slice:
        """Offsets of a flexible body's modes within the modal blocks."""
        a = 0
        for b, n in self.modal:
            if b == body:
                return slice(a, a + n)
            a += n
        raise KeyError(body)

    @property
    def n_motion(self) -> int:
        """The states that evolve by the physics (q, v, z): all but the work."""
        return self._sizes[3]

    @property
    def internal(self) -> slice:
        """The internal states z."""
        return self._slices[2]

    @property
    def ny(self) -> int:
        return self._sizes[4]

    @property
    def q_rigid(self) -> slice:
        return self._slices[3]

    @property
    def v_rigid(self) -> slice:
        return self._slices[4]

    @property
    def q_base(self) -> slice:
        return self._slices[5]

    @property
    def v_base(self) -> slice:
        return self._slices[6]

    @property
    def work(self) -> slice:
        return self._slices[7]

    def p_indices(self) -> np.ndarray:
        """Indices in y of all Euler parameters, shape (n_rigid, 4)."""
        a = 3 * self.base_free
        return a + 7 * np.arange(len(self.rigid))[:, None] + np.arange(3, 7)[None, :]

    def split(self, y: np.ndarray):
        """Views of a state (or of a stack of states, y : (..., ny)).

        Returns dict with ``r_base`` (..., 3) or None, ``rd_base``,
        ``r`` (..., n, 3), ``p`` (..., n, 4), ``rd`` (..., n, 3),
        ``w`` (..., n, 3) [ω̄], ``a`` (..., n_modal), ``ad`` (..., n_modal),
        ``z`` (..., n_internal), ``work`` (..., 4).
        """
        y = np.asarray(y)
        lead = y.shape[:-1]
        n = len(self.rigid)
        q_modal, v_modal, internal, q_rigid, v_rigid, q_base, v_base, work = self._slices
        qr = y[..., q_rigid].reshape(lead + (n, 7))
        vr = y[..., v_rigid].reshape(lead + (n, 6))
        return {
            "r_base": y[..., q_base] if self.base_free else None,
            "rd_base": y[..., v_base] if self.base_free else None,
            "r": qr[..., :3], "p": qr[..., 3:], "rd": vr[..., :3], "w": vr[..., 3:],
            "a": y[..., q_modal], "ad": y[..., v_modal],
            "z": y[..., internal], "work": y[..., work],
        }
