"""The mean force outputs (pulley[j].meanBeltTorque, meanDriveTorque,
meanHubForce.x/y, meanAlpha: means over the last communication step) through
FMPy, on the 4-pulley accessory drive and on a 2-pulley drive unlike it
(unequal pulleys, a belt three times as heavy as the paper's):

* each pulley's means satisfy its momentum balance (eq. 24) over every
  communication step, for both integrators;
* RKF45 and the stiff method give the same means over a window at idle,
  where the stiff method's instantaneous belt torques at the communication
  points are biased (it leaves the fast contact motion unresolved);
* the input energy grows by the drive torque's work over each step."""

import numpy as np
import pytest
from fmpy import simulate_fmu

from conftest import FMU, ROOT, ssv_example

MEANS = ["meanBeltTorque", "meanDriveTorque", "meanHubForce.x", "meanHubForce.y", "meanAlpha"]
H = 1e-3  # communication step [s]


def accessory_drive():
    """parameters/accessory-drive-4.ssv with its run-up to idle shortened
    from 0.5 s to 0.1 s (to keep RKF45's run short)."""
    sv = ssv_example().start_values(ROOT / "parameters/accessory-drive-4.ssv")
    for j in range(1, 5):
        sv[f"pulley[{j}].rampTime"] = 0.1
    return sv, 4


def heavy_two_pulley_drive():
    """Crank r = 60 mm speed-driven to 150 rad/s over 0.1 s, a 27 mm pulley
    0.35 m away loaded by 0.01 N m s/rad (3.3 N m at speed), belt 0.3 kg/m
    (3 x the 5PK belt), 120 bodies."""
    sv = {
        "belt.nBodies": 120,
        "belt.massPerLength": 0.3,
        "pulley[1].radius": 0.06,
        "pulley[1].speedDriven": True,
        "pulley[1].omegaRamp": -150.0,
        "pulley[1].torqueRamp": 0.0,
        "pulley[1].rampTime": 0.1,
        "pulley[2].x": 0.35,
        "pulley[2].loadDamping": 0.01,
        "pulley[2].rampTime": 0.1,
    }
    return sv, 2


def run(start, n_pulleys, method, stop, rel_tol=1e-4):
    names = []
    for j in range(1, n_pulleys + 1):
        names += [f"pulley[{j}].{n}" for n in ["omega", "angle", "beltTorque"] + MEANS]
    names.append("energy.input")
    sv = dict(start, **{"solver.method": method, "solver.relTol": rel_tol})
    return simulate_fmu(str(FMU), stop_time=stop, output_interval=H, start_values=sv,
                        output=names)


STOP, WINDOW = 0.3, 0.2  # idle from 0.1 s; the window 0.2-0.3 s


@pytest.fixture(scope="module", params=["accessory", "heavy"])
def drive(request):
    """RKF45 and the stiff method at relTol 1e-4 and 1e-5."""
    start, n = accessory_drive() if request.param == "accessory" else heavy_two_pulley_drive()
    res = {m: run(start, n, m, STOP) for m in (1, 2)}
    res["stiff 1e-5"] = run(start, n, 2, STOP, 1e-5)
    return request.param, start, n, res


def param(start, name, default):
    return float(start.get(name, default))


def test_means_satisfy_each_pulleys_momentum_balance(drive, md):
    """Over every communication step of both integrators: I meanAlpha +
    d (angle change / H) = meanBeltTorque + applied torque (torque-driven)
    or meanDriveTorque = I meanAlpha + d mean(omega) - meanBeltTorque -
    applied (speed-driven). The impulses are integrated with the same stages
    and, in the stiff method, the same Jacobian rows as the pulley's speed
    and angle, so the balance holds to the integrator's round-off: the
    tolerance is 1e-9 of the torques involved (a 1 ms step of the pulley's
    angle loses ~1e-14 / 1e-3 rad relative to its ~100 rad)."""
    name, start, n, res = drive
    starts = {v.name: v.start for v in md.modelVariables}
    for method, r in res.items():
        t = r["time"]
        k = np.nonzero(t >= 0.1 + H)[0]  # after the ramps: applied torques constant
        for j in range(1, n + 1):
            p = f"pulley[{j}]"
            get = lambda s: param(start, f"{p}.{s}", starts[f"{p}.{s}"])
            inertia, damping = get("inertia"), get("loadDamping")
            applied = get("torqueRamp")
            speed_driven = str(start.get(f"{p}.speedDriven", starts[f"{p}.speedDriven"])) in ("True", "true", "1")
            alpha = r[f"{p}.meanAlpha"][k]
            mean_omega = (r[f"{p}.angle"][k] - r[f"{p}.angle"][k - 1]) / (t[k] - t[k - 1])
            belt = r[f"{p}.meanBeltTorque"][k]
            inertial = inertia * alpha + damping * mean_omega
            if speed_driven:
                residual = r[f"{p}.meanDriveTorque"][k] - (inertial - belt - applied)
            else:
                residual = inertial - belt - applied
            scale = np.abs(inertia * alpha) + np.abs(damping * mean_omega) + np.abs(belt) + abs(applied)
            worst = np.max(np.abs(residual) / scale)
            print(f"{name} {method} {p}: worst residual {worst:.1e} of the torques")
            assert worst < 1e-9, (name, method, p)


def test_input_energy_is_the_drive_torques_work(drive):
    """After the ramps the crank (pulley 1) of both drives turns at a
    constant prescribed speed and every other pulley has no applied torque,
    so the input energy grows over each communication step by omega times
    the crank's drive-torque impulse, H meanDriveTorque: for both
    integrators, to round-off (the stiff method integrates the input power
    with the drive torque's Jacobian row times the prescribed speed at each
    step's start; with the row left out the gain of its energy.input over a
    step was up to 2.3 % (accessory drive) and 3.6 % (heavy belt) of the
    drive's work off, with the speed of a Jacobian kept from before the
    ramp's end 9.3e-7 (heavy belt, relTol 1e-4) and 1.7e-8 (accessory
    drive, 1e-5)). Round-off: energy.input is at most ~300 J against ~1 J
    of work per step, ~1e-13 of it; 1e-9 leaves a margin of 1e4."""
    name, _, n, res = drive
    for method, r in res.items():
        t = r["time"]
        k = np.nonzero(t >= 0.1 + H)[0]
        omega = r["pulley[1].omega"][k]
        work = omega * r["pulley[1].meanDriveTorque"][k] * (t[k] - t[k - 1])
        gain = r["energy.input"][k] - r["energy.input"][k - 1]
        worst = np.max(np.abs(gain - work)) / np.max(np.abs(work))
        print(f"{name} {method}: input energy against the drive's work, worst {worst:.1e}")
        assert worst < 1e-9, (name, method, worst)


def disagreements(drive, stiff):
    """Means over 0.2-0.3 s of RKF45 and of the stiff run `stiff` (printed);
    the outputs that differ by more than 1 % of the drive's largest belt
    torque (torques) or hub force (forces)."""
    name, _, n, res = drive
    a, b = res[1], res[stiff]
    w = a["time"] > WINDOW + 1e-9
    mean = lambda r, s: r[s][w].mean()
    torque_scale = max(abs(mean(a, f"pulley[{j}].meanBeltTorque")) for j in range(1, n + 1))
    force_scale = max(np.hypot(mean(a, f"pulley[{j}].meanHubForce.x"),
                               mean(a, f"pulley[{j}].meanHubForce.y")) for j in range(1, n + 1))
    failed = []
    for j in range(1, n + 1):
        p = f"pulley[{j}]"
        print(f"{name} {p}: instantaneous belt torque RKF45 {mean(a, p + '.beltTorque'):.4f}, "
              f"stiff ({stiff}) {mean(b, p + '.beltTorque'):.4f} N m")
        for s, scale in [("meanBeltTorque", torque_scale), ("meanDriveTorque", torque_scale),
                         ("meanHubForce.x", force_scale), ("meanHubForce.y", force_scale)]:
            x, y = mean(a, f"{p}.{s}"), mean(b, f"{p}.{s}")
            print(f"{name} {p}.{s}: RKF45 {x:.5g}, stiff {y:.5g} ({(y - x) / scale:+.2e} of scale)")
            if abs(y - x) > 0.01 * scale:
                failed.append(f"{p}.{s}")
    return failed


def test_integrators_agree_on_the_means(drive):
    """The means are impulses over the window divided by its length, so they
    agree as far as the two integrators' motions agree: within 1 % of the
    drive's largest belt torque and hub force (the stiff method at relTol
    1e-4 keeps the mean speeds within 0.25 % and the span tensions within
    0.7 % of RKF45, docs/model.md; a hub force is the sum of two span
    tensions, a pulley's mean belt torque its load d omega plus I times its
    mean acceleration). The stiff method at relTol 1e-4 on the accessory
    drive, at 1e-5 on the heavy-belt drive (see the next test). Its
    instantaneous belt torques at the same communication points are up to
    64 % off (printed, not asserted)."""
    name = drive[0]
    stiff = 2 if name == "accessory" else "stiff 1e-5"
    failed = disagreements(drive, stiff)
    assert not failed, failed


def test_heavy_belt_at_the_default_tolerance(drive):
    """The heavy-belt drive with the stiff method at its default relTol 1e-4.
    A fast belt (9 m/s) whose own loss is 3 % of the power it carries: the
    stiff method's error norm alone let its steps feed the belt's fast motion
    with energy (crank torque 2.9 % low, the belt's loss -5 W instead of
    +29 W); its energy check holds each step's energy residual to relTol
    times the belt's stored energy (docs/model.md, "The energy check"), and
    the means agree within the 1 % of the previous test (measured: crank
    torque -7.576 against -7.600 N m)."""
    if drive[0] != "heavy":
        pytest.skip("the accessory drive agrees at 1e-4 (previous test)")
    failed = disagreements(drive, 2)
    assert not failed, failed
