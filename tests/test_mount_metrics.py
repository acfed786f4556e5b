"""The study's peak mount metrics signed and split (issue 23): along an
axis the largest compression (−Δx) or extension (+Δx), in total or less the
static value — equal to the run's own arrays, and refused where a sign has
no meaning."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import flexbed
from flexbed.errors import InputError
from flexbed.study.metrics import build_metric
from flexbed.study.spec import MetricTable


@pytest.fixture(scope="module")
def scene_and_run():
    sc = flexbed.load_scene()
    sc = dataclasses.replace(sc, bed=dataclasses.replace(sc.bed, model="rigid"))
    return sc, flexbed.simulate(sc, t_end=0.3)


def metric(scene, **options):
    kind = options.pop("kind", "peak_mount_deflection")
    return build_metric(MetricTable(1, kind, tuple(options.items())), scene, "s.toml: metric 1")


@pytest.mark.parametrize("sense, part", [("compression", "total"), ("extension", "total"),
                                         ("compression", "dynamic"), ("extension", "dynamic"),
                                         ("magnitude", "dynamic")])
def test_signed_and_dynamic_peaks_equal_the_run_s_arrays(scene_and_run, sense, part):
    sc, run = scene_and_run
    m = metric(sc, mounts=["M1", "M5"], axis=3, sense=sense, part=part)
    dx = run.mount_deflection[:, [0, 4], 2]
    if part == "dynamic":
        dx = dx - dx[0]
    want = {"compression": -dx, "extension": dx, "magnitude": np.abs(dx)}[sense].max(axis=0)
    assert m.values({"simulate": run}) == tuple(want)
    tail = ("" if sense == "magnitude" else f".{sense}") + \
        ("" if part == "total" else ".dynamic")
    assert m.columns == (f"peak_mount_deflection.M1.axis3{tail}",
                         f"peak_mount_deflection.M5.axis3{tail}")


def test_the_static_part_is_what_dynamic_takes_away(scene_and_run):
    """Mount M1 carries the bed: compressed at rest, so its total
    compression exceeds its dynamic one by the static deflection exactly."""
    sc, run = scene_and_run
    total = metric(sc, mounts=["M1"], axis=3, sense="compression").values({"simulate": run})
    dyn = metric(sc, mounts=["M1"], axis=3, sense="compression", part="dynamic").values(
        {"simulate": run})
    static = -run.mount_deflection[0, 0, 2]
    assert static > 0
    assert total[0] == pytest.approx(dyn[0] + static, rel=1e-12)


@pytest.mark.parametrize("options, words", [
    ({"sense": "compression"}, "axis = 1, 2 or 3"),
    ({"sense": "compression", "axis": 3, "kind": "peak_mount_force"}, "peak_mount_deflection"),
    ({"sense": "down", "axis": 3}, "sense = 'down' must be one of"),
    ({"part": "static", "axis": 3}, "part = 'static' must be one of"),
])
def test_a_sense_without_meaning_is_refused(scene_and_run, options, words):
    sc, _ = scene_and_run
    with pytest.raises(InputError) as info:
        metric(sc, mounts=["M1"], **options)
    assert str(info.value).startswith("s.toml: metric 1: ") and words in str(info.value)
