"""The coefficients of Dormand–Prince 8(5,3), the compiled ``dop853`` stepper's.

Hairer's DOP853 (``dop853.f``; Hairer, Nørsett & Wanner, *Solving Ordinary
Differential Equations I*, 2nd ed., Springer 1993, II.10), in the form
SciPy's ``DOP853`` uses: the same decimal literals (30 digits, rounded to
float64 when this module is compiled) and the same operations, so the same
float64 values bit for bit (``tests/test_method_coefficients.py`` compares
them with SciPy's). They are flexbed's own data because SciPy keeps its copy
in a private module (``scipy.integrate._ivp``) that may change in any
release, and importing it runs ``scipy.integrate``'s ``__init__`` (about
0.3 s of CPU) that a dop853 run does not need.

:data:`DOP853` holds them as read-only arrays, checked when this module is
imported (:class:`DOP853Tableau`): shapes, an explicit method (A strictly
lower triangular), C_i = Σ_j A_ij, the quadrature order conditions
Σ_i b_i c_i^(k−1) = 1/k for k = 1 … 8, and error weights that sum to zero.

Stages 0–11 are the method's (stage 0 is f at the step's start, the
previous step's stage 12); row 12 of A is B, the 8th-order solution, at
which stage 12 is evaluated (first same as last); stages 13–15 are the
extra stages of the 7th-order dense output.

Numba compiles these arrays into the stepper as constants: a change here
reaches the cached stepper through the stamp of
:mod:`flexbed.dynamics.jitcache`, which covers this file.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .tables import freeze_arrays

__all__ = ["DOP853Tableau", "DOP853", "N_STAGES", "N_STAGES_EXTENDED", "INTERPOLATOR_POWER",
           "ORDER"]

#: stages of a step (stage 12, f at the new point, is the next step's stage 0)
N_STAGES = 12
#: stages with the dense output's three extra ones
N_STAGES_EXTENDED = 16
#: degree of the dense output's polynomial
INTERPOLATOR_POWER = 7
#: order of the solution
ORDER = 8


@dataclass(frozen=True, slots=True)
class DOP853Tableau:
    """The Butcher tableau of DOP853 with its error weights and dense output.

    Every array is copied, made read-only and checked (see the module
    docstring); a violation raises ValueError naming the entry.

    Parameters
    ----------
    A : (16, 16) float64
        Stage weights, strictly lower triangular: rows 1–11 the method's
        stages, row 12 the solution (:attr:`B`), rows 13–15 the dense
        output's extra stages.
    C : (16,) float64
        Stage times as fractions of the step, C_i = Σ_j A_ij.
    E3, E5 : (13,) float64
        Weights of the 3rd- and 5th-order error estimates over stages 0–12
        (SciPy's error norm combines the two).
    D : (4, 16) float64
        Coefficients of the dense output's four highest terms over the 16
        stages (its three lowest come from the step's ends).
    """

    A: np.ndarray
    C: np.ndarray
    E3: np.ndarray
    E5: np.ndarray
    D: np.ndarray

    def __post_init__(self):
        shapes = {"A": (N_STAGES_EXTENDED, N_STAGES_EXTENDED), "C": (N_STAGES_EXTENDED,),
                  "E3": (N_STAGES + 1,), "E5": (N_STAGES + 1,),
                  "D": (INTERPOLATOR_POWER - 3, N_STAGES_EXTENDED)}
        freeze_arrays(self, "DOP853", shapes)
        A, C = self.A, self.C
        if np.any(np.triu(A) != 0.0):
            raise ValueError("DOP853 A: not strictly lower triangular (an explicit method's is)")
        row_error = np.abs(A.sum(axis=1) - C) / (1.0 + np.abs(A).sum(axis=1))
        if np.any(row_error > 1e-14):
            i = int(np.argmax(row_error))
            raise ValueError(f"DOP853 C[{i}] = {C[i]!r} is not the sum of A's row {i}, "
                             f"{A[i].sum()!r}")
        b, c = self.B, C[:N_STAGES]
        for k in range(1, ORDER + 1):
            moment = float(b @ c ** (k - 1))
            if abs(moment - 1.0 / k) > 1e-14:
                raise ValueError(f"DOP853 B: order condition Σ b_i c_i^{k - 1} = 1/{k} fails "
                                 f"({moment!r})")
        for name in ("E3", "E5"):
            e = getattr(self, name)
            if abs(e.sum()) > 1e-14 * np.abs(e).sum():
                raise ValueError(f"DOP853 {name}: error weights sum to {e.sum()!r}, not 0")

    @property
    def B(self) -> np.ndarray:
        """(12,) float64: the solution's weights, row 12 of A (a read-only view)."""
        return self.A[N_STAGES, :N_STAGES]


def _stage_times() -> np.ndarray:
    return np.array([
        0.0,
        0.526001519587677318785587544488e-01,
        0.789002279381515978178381316732e-01,
        0.118350341907227396726757197510,
        0.281649658092772603273242802490,
        0.333333333333333333333333333333,
        0.25,
        0.307692307692307692307692307692,
        0.651282051282051282051282051282,
        0.6,
        0.857142857142857142857142857142,
        1.0,
        1.0,
        0.1,
        0.2,
        0.777777777777777777777777777778,
    ])


def _stage_weights() -> np.ndarray:
    a = np.zeros((N_STAGES_EXTENDED, N_STAGES_EXTENDED))
    a[1, 0] = 5.26001519587677318785587544488e-2

    a[2, 0] = 1.97250569845378994544595329183e-2
    a[2, 1] = 5.91751709536136983633785987549e-2

    a[3, 0] = 2.95875854768068491816892993775e-2
    a[3, 2] = 8.87627564304205475450678981324e-2

    a[4, 0] = 2.41365134159266685502369798665e-1
    a[4, 2] = -8.84549479328286085344864962717e-1
    a[4, 3] = 9.24834003261792003115737966543e-1

    a[5, 0] = 3.7037037037037037037037037037e-2
    a[5, 3] = 1.70828608729473871279604482173e-1
    a[5, 4] = 1.25467687566822425016691814123e-1

    a[6, 0] = 3.7109375e-2
    a[6, 3] = 1.70252211019544039314978060272e-1
    a[6, 4] = 6.02165389804559606850219397283e-2
    a[6, 5] = -1.7578125e-2

    a[7, 0] = 3.70920001185047927108779319836e-2
    a[7, 3] = 1.70383925712239993810214054705e-1
    a[7, 4] = 1.07262030446373284651809199168e-1
    a[7, 5] = -1.53194377486244017527936158236e-2
    a[7, 6] = 8.27378916381402288758473766002e-3

    a[8, 0] = 6.24110958716075717114429577812e-1
    a[8, 3] = -3.36089262944694129406857109825
    a[8, 4] = -8.68219346841726006818189891453e-1
    a[8, 5] = 2.75920996994467083049415600797e1
    a[8, 6] = 2.01540675504778934086186788979e1
    a[8, 7] = -4.34898841810699588477366255144e1

    a[9, 0] = 4.77662536438264365890433908527e-1
    a[9, 3] = -2.48811461997166764192642586468
    a[9, 4] = -5.90290826836842996371446475743e-1
    a[9, 5] = 2.12300514481811942347288949897e1
    a[9, 6] = 1.52792336328824235832596922938e1
    a[9, 7] = -3.32882109689848629194453265587e1
    a[9, 8] = -2.03312017085086261358222928593e-2

    a[10, 0] = -9.3714243008598732571704021658e-1
    a[10, 3] = 5.18637242884406370830023853209
    a[10, 4] = 1.09143734899672957818500254654
    a[10, 5] = -8.14978701074692612513997267357
    a[10, 6] = -1.85200656599969598641566180701e1
    a[10, 7] = 2.27394870993505042818970056734e1
    a[10, 8] = 2.49360555267965238987089396762
    a[10, 9] = -3.0467644718982195003823669022

    a[11, 0] = 2.27331014751653820792359768449
    a[11, 3] = -1.05344954667372501984066689879e1
    a[11, 4] = -2.00087205822486249909675718444
    a[11, 5] = -1.79589318631187989172765950534e1
    a[11, 6] = 2.79488845294199600508499808837e1
    a[11, 7] = -2.85899827713502369474065508674
    a[11, 8] = -8.87285693353062954433549289258
    a[11, 9] = 1.23605671757943030647266201528e1
    a[11, 10] = 6.43392746015763530355970484046e-1

    a[12, 0] = 5.42937341165687622380535766363e-2
    a[12, 5] = 4.45031289275240888144113950566
    a[12, 6] = 1.89151789931450038304281599044
    a[12, 7] = -5.8012039600105847814672114227
    a[12, 8] = 3.1116436695781989440891606237e-1
    a[12, 9] = -1.52160949662516078556178806805e-1
    a[12, 10] = 2.01365400804030348374776537501e-1
    a[12, 11] = 4.47106157277725905176885569043e-2

    a[13, 0] = 5.61675022830479523392909219681e-2
    a[13, 6] = 2.53500210216624811088794765333e-1
    a[13, 7] = -2.46239037470802489917441475441e-1
    a[13, 8] = -1.24191423263816360469010140626e-1
    a[13, 9] = 1.5329179827876569731206322685e-1
    a[13, 10] = 8.20105229563468988491666602057e-3
    a[13, 11] = 7.56789766054569976138603589584e-3
    a[13, 12] = -8.298e-3

    a[14, 0] = 3.18346481635021405060768473261e-2
    a[14, 5] = 2.83009096723667755288322961402e-2
    a[14, 6] = 5.35419883074385676223797384372e-2
    a[14, 7] = -5.49237485713909884646569340306e-2
    a[14, 10] = -1.08347328697249322858509316994e-4
    a[14, 11] = 3.82571090835658412954920192323e-4
    a[14, 12] = -3.40465008687404560802977114492e-4
    a[14, 13] = 1.41312443674632500278074618366e-1

    a[15, 0] = -4.28896301583791923408573538692e-1
    a[15, 5] = -4.69762141536116384314449447206
    a[15, 6] = 7.68342119606259904184240953878
    a[15, 7] = 4.06898981839711007970213554331
    a[15, 8] = 3.56727187455281109270669543021e-1
    a[15, 12] = -1.39902416515901462129418009734e-3
    a[15, 13] = 2.9475147891527723389556272149
    a[15, 14] = -9.15095847217987001081870187138
    return a


def _error_weights(b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(E3, E5): E3 = B − b̂ of the 3rd-order method (Hairer's bhh1–3)."""
    e3 = np.zeros(N_STAGES + 1)
    e3[:-1] = b
    e3[0] -= 0.244094488188976377952755905512
    e3[8] -= 0.733846688281611857341361741547
    e3[11] -= 0.220588235294117647058823529412e-1
    e5 = np.zeros(N_STAGES + 1)
    e5[0] = 0.1312004499419488073250102996e-1
    e5[5] = -0.1225156446376204440720569753e+1
    e5[6] = -0.4957589496572501915214079952
    e5[7] = 0.1664377182454986536961530415e+1
    e5[8] = -0.3503288487499736816886487290
    e5[9] = 0.3341791187130174790297318841
    e5[10] = 0.8192320648511571246570742613e-1
    e5[11] = -0.2235530786388629525884427845e-1
    return e3, e5


def _dense_output() -> np.ndarray:
    d = np.zeros((INTERPOLATOR_POWER - 3, N_STAGES_EXTENDED))
    d[0, 0] = -0.84289382761090128651353491142e+1
    d[0, 5] = 0.56671495351937776962531783590
    d[0, 6] = -0.30689499459498916912797304727e+1
    d[0, 7] = 0.23846676565120698287728149680e+1
    d[0, 8] = 0.21170345824450282767155149946e+1
    d[0, 9] = -0.87139158377797299206789907490
    d[0, 10] = 0.22404374302607882758541771650e+1
    d[0, 11] = 0.63157877876946881815570249290
    d[0, 12] = -0.88990336451333310820698117400e-1
    d[0, 13] = 0.18148505520854727256656404962e+2
    d[0, 14] = -0.91946323924783554000451984436e+1
    d[0, 15] = -0.44360363875948939664310572000e+1

    d[1, 0] = 0.10427508642579134603413151009e+2
    d[1, 5] = 0.24228349177525818288430175319e+3
    d[1, 6] = 0.16520045171727028198505394887e+3
    d[1, 7] = -0.37454675472269020279518312152e+3
    d[1, 8] = -0.22113666853125306036270938578e+2
    d[1, 9] = 0.77334326684722638389603898808e+1
    d[1, 10] = -0.30674084731089398182061213626e+2
    d[1, 11] = -0.93321305264302278729567221706e+1
    d[1, 12] = 0.15697238121770843886131091075e+2
    d[1, 13] = -0.31139403219565177677282850411e+2
    d[1, 14] = -0.93529243588444783865713862664e+1
    d[1, 15] = 0.35816841486394083752465898540e+2

    d[2, 0] = 0.19985053242002433820987653617e+2
    d[2, 5] = -0.38703730874935176555105901742e+3
    d[2, 6] = -0.18917813819516756882830838328e+3
    d[2, 7] = 0.52780815920542364900561016686e+3
    d[2, 8] = -0.11573902539959630126141871134e+2
    d[2, 9] = 0.68812326946963000169666922661e+1
    d[2, 10] = -0.10006050966910838403183860980e+1
    d[2, 11] = 0.77771377980534432092869265740
    d[2, 12] = -0.27782057523535084065932004339e+1
    d[2, 13] = -0.60196695231264120758267380846e+2
    d[2, 14] = 0.84320405506677161018159903784e+2
    d[2, 15] = 0.11992291136182789328035130030e+2

    d[3, 0] = -0.25693933462703749003312586129e+2
    d[3, 5] = -0.15418974869023643374053993627e+3
    d[3, 6] = -0.23152937917604549567536039109e+3
    d[3, 7] = 0.35763911791061412378285349910e+3
    d[3, 8] = 0.93405324183624310003907691704e+2
    d[3, 9] = -0.37458323136451633156875139351e+2
    d[3, 10] = 0.10409964950896230045147246184e+3
    d[3, 11] = 0.29840293426660503123344363579e+2
    d[3, 12] = -0.43533456590011143754432175058e+2
    d[3, 13] = 0.96324553959188282948394950600e+2
    d[3, 14] = -0.39177261675615439165231486172e+2
    d[3, 15] = -0.14972683625798562581422125276e+3
    return d


def _tableau() -> DOP853Tableau:
    a = _stage_weights()
    e3, e5 = _error_weights(a[N_STAGES, :N_STAGES])
    return DOP853Tableau(A=a, C=_stage_times(), E3=e3, E5=e5, D=_dense_output())


#: DOP853's coefficients, read-only and checked
DOP853 = _tableau()
