"""The study of ``docs/sweep-study.toml`` run by Exudyn's ``ParameterVariation``:
the throughput comparison of ``docs/sweep-benchmark.md``.

Two steps, two Python environments (Exudyn is not a dependency of flexbed):

1. ``python docs/sweep_exudyn.py variants OUT.json [POINTS]`` (flexbed's
   environment): the study's points as flexbed plans them (Latin hypercube,
   seed 1), each as its bodies (mass, inertia, position) and mounts (bodies,
   points, axes, k, c), the base's force and the solver's end time and
   output step; and flexbed's own metrics of the first points (statics,
   simulate, the study's metrics), to check the Exudyn model against.
2. ``EXUDYN_PYTHON docs/sweep_exudyn.py run OUT.json [PROCESSES [ROUNDS [SOLVER]]]``
   (an environment with ``pip install exudyn``): the same model in Exudyn —
   rigid bodies with Euler parameters, one ``RigidBodySpringDamper`` per
   mount acting along the mount's axes in body i's frame (marker 0's frame;
   offset: the mount's length at the scene's positions, so unloaded there),
   gravity, the base free with the ground's static support (the whole
   weight, upward) and the 5 Hz, 1 MN sine force on 0-1 s; per point the
   static equilibrium with the base held (``SolveStatic``, a generic joint to
   the ground, then released), then ``SolveDynamic`` with DOPRI5 (automatic
   step, relative accuracy 1e-8, absolute 1e-10, as the scene's rtol/atol)
   to 3 s (SOLVER ``dopri5``, the default; ``alpha``: Exudyn's default
   generalized-alpha with one step per output step, 1 ms, no error
   control), sensors stored every 1 ms (3,001 samples); the point's figures:
   the peak displacement of the two equipment tops relative to the bed, the
   peak force of each mount, the static deflections of M5 and M9 along axis
   3 and the largest static deflection (the study's 17 columns).
   ``ParameterVariation`` with ``PROCESSES`` processes (default 2) over the
   points; the wall time and the CPU of every process. Prints one line of
   JSON: points per second, CPU per point, the load average, and the largest
   relative difference of the figures from flexbed's on the checked points.
"""

from __future__ import annotations

import json
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


# ------------------------------------------------------------ 1. flexbed side
def variants(out: str, n: int) -> None:
    import dataclasses
    from pathlib import Path

    from flexbed.study.plan import make_plan
    from flexbed.study.point import run_point, warm
    from flexbed.study.spec import read_study

    study = read_study(Path(HERE) / "sweep-study.toml")
    if n != study.samples:
        study = dataclasses.replace(study, samples=n)
    plan = make_plan(study)
    base = plan.base
    points = []
    for p in plan.points:
        sc = p.scene.scene
        bodies = [{"name": b.name, "mass": float(b.mass),
                   "inertia": np.asarray(b.inertia, dtype=float).reshape(3, 3).tolist()
                   if np.size(b.inertia) == 9 else np.diag(b.inertia).tolist(),
                   "position": np.asarray(b.position, dtype=float).tolist()}
                  for b in sc.bodies]
        mounts = [{"name": m.name, "body_i": m.body_i, "body_j": m.body_j,
                   "point_i": np.asarray(m.point_i, float).tolist(),
                   "point_j": np.asarray(m.point_j, float).tolist(),
                   "axes": np.asarray(m.axes, float).tolist(),
                   "k": [float(law.k) for law in m.laws], "c": [float(law.c) for law in m.laws]}
                  for m in sc.mounts]
        points.append({"bodies": bodies, "mounts": mounts})
    warm(base)
    check = [list(run_point(p.scene, plan.analyses, plan.metrics).values) for p in plan.points[:4]]
    s = base.solver
    json.dump({"points": points, "t_end": s.t_end, "output_dt": s.output_dt, "rtol": s.rtol,
               "atol": s.atol, "gravity": np.asarray(base.scene.gravity, float).tolist(),
               "columns": list(plan.metric_columns), "flexbed": check},
              open(out, "w"))
    print(f"{len(points)} points written to {out}")


# ------------------------------------------------------------- 2. Exudyn side
DATA: dict = {}


def _model(point: dict, held: bool):
    """(mbs, the mounts' connectors, sensors, force sensors) of one point:
    the base held (a ground object where it stands: for the statics) or
    free (with its loads)."""
    import exudyn as exu
    from exudyn.itemInterface import (LoadForceVector, MarkerBodyRigid,
                                      ObjectConnectorRigidBodySpringDamper, ObjectGround,
                                      SensorBody, SensorObject)
    from exudyn.rigidBodyUtilities import HomogeneousTransformation, RigidBodyInertia
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    g = DATA["gravity"]
    index, positions = {}, {}
    base = point["bodies"][0]
    for b in point["bodies"]:
        positions[b["name"]] = np.array(b["position"])
        if b is base and held:
            index[b["name"]] = mbs.AddObject(ObjectGround(referencePosition=b["position"]))
            continue
        inertia = RigidBodyInertia(mass=b["mass"], inertiaTensor=np.array(b["inertia"]))
        index[b["name"]] = mbs.CreateRigidBody(
            inertia=inertia, referencePosition=b["position"], gravity=g,
            nodeType=exu.NodeType.RotationRotationVector, create2D=False)
    if not held:
        total = sum(b["mass"] for b in point["bodies"])
        support = -total * np.array(g)
        mb = mbs.AddMarker(MarkerBodyRigid(bodyNumber=index[base["name"]], localPosition=[0, 0, 0]))

        def load(mbs, t, load):
            f = 1.0e6 * math.sin(2.0 * math.pi * 5.0 * t) if t < 1.0 else 0.0
            return [support[0], support[1], support[2] + f]

        mbs.AddLoad(LoadForceVector(markerNumber=mb, loadVector=[0, 0, 0],
                                    loadVectorUserFunction=load))
    springs = []
    for m in point["mounts"]:
        R0 = np.array(m["axes"]).T                     # columns: the mount's axes in body i
        pi, pj = np.array(m["point_i"]), np.array(m["point_j"])
        # the length at the scene's positions (orientations: identity)
        l0 = positions[m["body_j"]] + pj - positions[m["body_i"]] - pi
        m0 = mbs.AddMarker(MarkerBodyRigid(bodyNumber=index[m["body_i"]],
                                           localHT=HomogeneousTransformation(R0, pi)))
        m1 = mbs.AddMarker(MarkerBodyRigid(bodyNumber=index[m["body_j"]],
                                           localHT=HomogeneousTransformation(R0, pj)))
        springs.append(mbs.AddObject(ObjectConnectorRigidBodySpringDamper(
            markerNumbers=[m0, m1], stiffness=np.diag(m["k"] + [0.0, 0.0, 0.0]),
            damping=np.diag(m["c"] + [0.0, 0.0, 0.0]),
            offset=list(np.array(m["axes"]) @ l0) + [0.0, 0.0, 0.0])))
    sensors, forces = {}, []
    if not held:
        store = dict(storeInternal=True, writeToFile=False)
        out = exu.OutputVariableType
        sensors["bed_r"] = mbs.AddSensor(SensorBody(bodyNumber=index["bed"],
                                                    outputVariableType=out.Position, **store))
        sensors["bed_A"] = mbs.AddSensor(SensorBody(bodyNumber=index["bed"],
                                                    outputVariableType=out.RotationMatrix, **store))
        for name in ("equipment A", "equipment B"):
            sensors[name] = mbs.AddSensor(SensorBody(bodyNumber=index[name],
                                                     localPosition=[0, 0, 0.15],
                                                     outputVariableType=out.Position, **store))
        forces = [mbs.AddSensor(SensorObject(objectNumber=s, outputVariableType=out.ForceLocal,
                                             **store)) for s in springs]
    mbs.Assemble()
    return SC, mbs, springs, sensors, forces


def point_figures(parameters: dict) -> list:
    """The 17 figures of point ``parameters["i"]`` (see the module)."""
    import exudyn as exu
    point = DATA["points"][int(parameters["i"])]
    settings = exu.SimulationSettings()
    settings.solutionSettings.writeSolutionToFile = False
    settings.solutionSettings.sensorsWritePeriod = DATA["output_dt"]
    settings.displayComputationTime = False
    settings.displayStatistics = False
    settings.linearSolverType = exu.LinearSolverType.EXUdense
    settings.staticSolver.verboseMode = 0
    settings.staticSolver.newton.relativeTolerance = 1e-12
    settings.staticSolver.newton.absoluteTolerance = 1e-10
    SC0, statics, springs, _, _ = _model(point, held=True)
    statics.SolveStatic(settings)
    static = [np.array(statics.GetObjectOutput(s, exu.OutputVariableType.DisplacementLocal))
              - np.array(statics.GetObjectParameter(s, "offset"))[:3] for s in springs]
    q = statics.systemData.GetODE2Coordinates()
    SC, mbs, springs, sensors, forces = _model(point, held=False)
    mbs.systemData.SetODE2Coordinates(np.concatenate([np.zeros(6), q]),
                                      configuration=exu.ConfigurationType.Initial)
    ti = settings.timeIntegration
    ti.verboseMode = 0
    ti.endTime = DATA["t_end"]
    ti.numberOfSteps = int(round(DATA["t_end"] / DATA["output_dt"]))
    if DATA.get("solver", "dopri5") == "dopri5":
        ti.automaticStepSize = True
        ti.absoluteTolerance = DATA["atol"]
        ti.relativeTolerance = DATA["rtol"]
        ti.explicit.useLieGroupIntegration = True
        mbs.SolveDynamic(settings, solverType=exu.DynamicSolverType.DOPRI5)
    else:                       # Exudyn's default: generalized-alpha, one step per output step
        mbs.SolveDynamic(settings, solverType=exu.DynamicSolverType.GeneralizedAlpha)
    r = mbs.GetSensorStoredData(sensors["bed_r"])[:, 1:]
    A = mbs.GetSensorStoredData(sensors["bed_A"])[:, 1:].reshape(-1, 3, 3)
    out = []
    for name in ("equipment A", "equipment B"):
        P = mbs.GetSensorStoredData(sensors[name])[:, 1:]
        rho = np.einsum("kji,kj->ki", A, P - r)
        out.append(float(np.linalg.norm(rho - rho[0], axis=1).max()))
    for f in forces:
        F = mbs.GetSensorStoredData(f)[:, 1:]
        out.append(float(np.linalg.norm(F, axis=1).max()))
    names = [m["name"] for m in point["mounts"]]
    out += [float(static[names.index("M5")][2]), float(static[names.index("M9")][2])]
    out.append(float(max(np.linalg.norm(d) for d in static)))
    return out


def run(path: str, processes: int, rounds: int, solver: str) -> None:
    from exudyn.processing import ParameterVariation
    DATA.update(json.load(open(path)))
    DATA["solver"] = solver
    n = len(DATA["points"])
    check = [point_figures({"i": i}) for i in range(len(DATA["flexbed"]))]
    worst = max(abs(a - b) / abs(b) for x, y in zip(check, DATA["flexbed"])
                for a, b in zip(x, y))
    per_col = [max(abs(x[c] - y[c]) / abs(y[c]) for x, y in zip(check, DATA["flexbed"]))
               for c in range(len(check[0]))]
    t0 = time.perf_counter()
    point_figures({"i": 0})
    one = time.perf_counter() - t0
    results = []
    for _ in range(rounds):
        load = os.getloadavg()[0]
        t0, c0 = time.perf_counter(), os.times()
        ParameterVariation(point_figures, {"i": list(range(n))}, useMultiProcessing=processes > 1,
                           numberOfThreads=processes, showProgress=False)
        wall, c1 = time.perf_counter() - t0, os.times()
        cpu = (c1.user - c0.user + c1.system - c0.system
               + c1.children_user - c0.children_user + c1.children_system - c0.children_system)
        results.append({"wall": wall, "points_per_s": n / wall, "cpu_per_point_ms": 1e3 * cpu / n,
                        "load": load})
    import exudyn
    print(json.dumps({"exudyn": exudyn.__version__, "solver": solver, "points": n,
                      "processes": processes,
                      "one_point_wall_ms": 1e3 * one, "rounds": results,
                      "largest_relative_difference_from_flexbed": worst,
                      "by_column": dict(zip(DATA["columns"], per_col))}))


if __name__ == "__main__":
    if sys.argv[1] == "variants":
        variants(sys.argv[2], int(sys.argv[3]) if len(sys.argv) > 3 else 200)
    else:
        run(sys.argv[2], int(sys.argv[3]) if len(sys.argv) > 3 else 2,
            int(sys.argv[4]) if len(sys.argv) > 4 else 1,
            sys.argv[5] if len(sys.argv) > 5 else "dopri5")
