"""The accessory-drive parameter set with the idler on a tensioner arm
(parameters/accessory-drive-tensioner.ssv) through FMPy: mounted at rest the
spring balances the belt's hub moment about the pivot, both integrators give
the same drive after the run-up to idle, and the arm holds the slack span."""
import math

import numpy as np
import pytest

from conftest import ROOT, runs_of_both_methods, window

SSV = ROOT / "parameters/accessory-drive-tensioner.ssv"
OUTPUTS = ["pulley[1].omega", "pulley[3].omega", "pulley[3].rotor.omega",
           "pulley[4].arm.angle", "pulley[4].arm.omega", "pulley[4].arm.springTorque",
           "pulley[4].arm.freeAngle", "pulley[4].hubForce.x", "pulley[4].hubForce.y",
           "span[1].tension", "span[2].tension", "span[3].tension", "span[4].tension"]


@pytest.fixture(scope="module")
def runs():
    return runs_of_both_methods(SSV, OUTPUTS)


def hub_moment(start, row):
    """Moment of the reported hub force about the pivot, the pulley centre
    rotated by the reported arm angle."""
    rx = start["pulley[4].x"] - start["pulley[4].arm.pivot.x"]
    ry = start["pulley[4].y"] - start["pulley[4].arm.pivot.y"]
    s, c = math.sin(row["pulley[4].arm.angle"]), math.cos(row["pulley[4].arm.angle"])
    lx, ly = c * rx - s * ry, s * rx + c * ry
    return lx * row["pulley[4].hubForce.y"] - ly * row["pulley[4].hubForce.x"]


def test_mounted_at_rest_the_spring_balances_the_hub_moment(runs):
    """At t = 0 the arm is where it was placed and the spring torque is the
    negative of the hub force's moment about the pivot (0.5 %, the issue's
    figure; by the mounting's construction it is exact to rounding)."""
    start, res = runs
    for r in res.values():
        row = r[0]
        assert row["pulley[4].arm.angle"] == 0.0
        m = hub_moment(start, row)
        assert -row["pulley[4].arm.springTorque"] == pytest.approx(m, rel=5e-3)
        # the spring is wound up: 40 N m/rad times the free angle
        assert row["pulley[4].arm.springTorque"] == pytest.approx(
            40.0 * row["pulley[4].arm.freeAngle"], rel=1e-12)


def test_integrators_agree_on_the_tensioner_set(runs):
    """Means over 0.6-0.8 s (idle reached at 0.5 s): speeds and span
    tensions within 0.5 % (the issue's figure), the arm's mean angle within
    2 % of its swing from the mounting."""
    _, res = runs
    for name in ["pulley[3].omega", "pulley[3].rotor.omega", "span[1].tension",
                 "span[2].tension", "span[3].tension", "span[4].tension"]:
        a, b = window(res[1], name).mean(), window(res[2], name).mean()
        print(f"{name}: RKF45 {a:.6g}, stiff {b:.6g}")
        assert b == pytest.approx(a, rel=5e-3), name
    a = window(res[1], "pulley[4].arm.angle").mean()
    b = window(res[2], "pulley[4].arm.angle").mean()
    print(f"arm angle: RKF45 {a:.6g}, stiff {b:.6g}")
    assert b == pytest.approx(a, rel=0.02)
    for r in res.values():
        assert np.all(np.isfinite(r["pulley[4].arm.angle"]))
