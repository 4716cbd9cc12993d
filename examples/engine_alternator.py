"""Co-simulation master (FMPy): BeltDrive.fmu between an engine model and an
alternator model, exchanging speeds and torques every communication step.

    .venv/bin/python examples/engine_alternator.py --stop-time 1.0

* Belt drive: the FMU with a parameter set (default
  parameters/accessory-drive-4.ssv: crank, AC compressor, alternator, back-side
  idler). The crank pulley is speed-driven: its speed is the engine's.
* Engine (this file): a 4-cylinder four-stroke engine, crank inertia J_e.
  Two firing strokes per revolution give a 2nd-order gas torque pulsation
  T_gas = T_mean + A sin(2 theta); an idle-speed governor (PI) sets T_mean and
  brings the engine from rest to idle along a speed ramp. The engine
  integrates J_e dw/dt = T_gas - T_belt, where T_belt is the torque the belt
  drive takes from the crank (the FMU output pulley[c].driveTorque).
* Alternator (this file): load torque from speed, drag plus the electrical
  power P_el / (eta w) above the cut-in speed (linear below it); fed to the
  FMU's torque input of the alternator pulley. With a decoupler on that
  pulley (parameters/accessory-drive-decoupler.ssv) the torque input acts on
  the rotor, and the load follows the rotor's speed (pulley[a].rotor.omega,
  the pulley's speed without a decoupler).

Each step [t, t + h]: the engine speed goes to pulley[c].omegaRef with the
engine's acceleration as input derivative, the alternator torque to
pulley[a].torque with dT/dw times the pulley's acceleration (FMU output
derivative of pulley[a].omega) as derivative (the FMU declares
canInterpolateInputs, so the inputs ramp within the step); then the FMU and
the engine (RK4 sub-steps, belt torque held) advance in parallel (Jacobi).
Signs follow the FMU: positive = counterclockwise; the engine turns clockwise
(negative speeds), as the paper's drives do.

Writes <out-dir>/engine_alternator.csv and engine_alternator.png (crank and
alternator speed, span tensions, hub loads).
"""
import argparse
import math
import pathlib
import shutil
import sys
import tempfile

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from simulate_ssv import start_values  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
RPM = 60.0 / (2.0 * math.pi)


class Engine:
    """Crank dynamics of a 4-cylinder four-stroke engine at idle."""

    def __init__(self, idle_rpm=800.0, ramp_time=0.3, inertia=0.15, pulsation=60.0,
                 kp=8.0, ki=80.0, max_torque=150.0):
        self.w_idle = -idle_rpm / RPM  # clockwise
        self.ramp_time = ramp_time
        self.J = inertia  # crank, flywheel, clutch [kg m^2]
        self.A = pulsation  # 2nd-order gas torque amplitude at idle [N m]
        self.kp, self.ki, self.max_torque = kp, ki, max_torque
        self.theta = 0.0  # crank angle [rad]
        self.w = 0.0  # crank speed [rad/s]
        self.integral = 0.0  # governor integral of the speed error [rad]

    def setpoint(self, t):
        return self.w_idle * min(t / self.ramp_time, 1.0)

    def gas_torque(self, t, theta, w, integral):
        """Governor mean torque plus the firing pulsation (2nd order: two
        firings per crank revolution), both in the FMU's sign convention."""
        err = self.setpoint(t) - w
        mean = np.clip(self.kp * err + self.ki * integral, -self.max_torque, self.max_torque)
        return mean + self.A * math.sin(2.0 * theta)

    def rates(self, t, y, belt_torque):
        theta, w, integral = y
        return np.array([w, (self.gas_torque(t, theta, w, integral) - belt_torque) / self.J,
                         self.setpoint(t) - w])

    def acceleration(self, t, belt_torque):
        return self.rates(t, self.state(), belt_torque)[1]

    def state(self):
        return np.array([self.theta, self.w, self.integral])

    def advance(self, t, h, belt_torque, substeps=4):
        """RK4 over [t, t + h] with the belt torque held."""
        y, dt = self.state(), h / substeps
        for k in range(substeps):
            s = t + k * dt
            k1 = self.rates(s, y, belt_torque)
            k2 = self.rates(s + dt / 2, y + dt / 2 * k1, belt_torque)
            k3 = self.rates(s + dt / 2, y + dt / 2 * k2, belt_torque)
            k4 = self.rates(s + dt, y + dt * k3, belt_torque)
            y = y + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        self.theta, self.w, self.integral = y


class Alternator:
    """Load torque magnitude of an alternator from its speed magnitude."""

    def __init__(self, power=600.0, efficiency=0.6, cut_in_rpm=1200.0, drag=2e-3):
        self.p_mech = power / efficiency  # [W]
        self.w_cut = cut_in_rpm / RPM  # [rad/s]
        self.drag = drag  # [N m s/rad]

    def torque(self, w):
        """Torque opposing the rotation (sign(w) * load) and dT/dw."""
        a = abs(w)
        if a >= self.w_cut:
            load, dload = self.drag * a + self.p_mech / a, self.drag - self.p_mech / a ** 2
        else:
            load, dload = (self.drag + self.p_mech / self.w_cut ** 2) * a, self.drag + self.p_mech / self.w_cut ** 2
        # The load opposes the rotation: T = -sign(w) load(|w|), odd in w.
        return -math.copysign(load, w) if w != 0 else 0.0, -dload


def simulate(stop_time=1.0, step=1e-3, parameters=ROOT / "parameters/accessory-drive-4.ssv",
             crank=1, alternator=3, ramp_time=0.3, fmu=ROOT / "dist/BeltDrive.fmu", out_dir=None,
             extra_outputs=()):
    """Run the coupled system; returns a dict of time series (NumPy arrays),
    with the FMU outputs named in `extra_outputs` recorded too."""
    md = read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    var = {v.name: v for v in md.modelVariables}
    start = start_values(parameters)
    n = start["nPulleys"]
    c, a = f"pulley[{crank}]", f"pulley[{alternator}]"
    # The crank follows the engine (no built-in ramp); the alternator's load is
    # the alternator model's torque instead of the parameter set's damping.
    start.update({f"{c}.speedDriven": True, f"{c}.omegaRamp": 0.0, f"{c}.torqueRamp": 0.0,
                  f"{a}.speedDriven": False, f"{a}.loadDamping": 0.0, f"{a}.torqueRamp": 0.0})

    unzipdir = extract(str(fmu), unzipdir=tempfile.mkdtemp(prefix="engine-alternator-"))
    fmu2 = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir,
                     modelIdentifier=md.coSimulation.modelIdentifier, instanceName="beltDrive")
    fmu2.instantiate()
    for name, value in start.items():
        t = var[name].type
        if t == "Real":
            fmu2.setReal([vr[name]], [float(value)])
        elif t == "Integer":
            fmu2.setInteger([vr[name]], [int(value)])
        else:
            fmu2.setBoolean([vr[name]], [bool(value)])
    fmu2.setupExperiment(startTime=0.0, stopTime=stop_time)
    fmu2.enterInitializationMode()
    fmu2.exitInitializationMode()

    can_interpolate = md.coSimulation.canInterpolateInputs
    engine, alt = Engine(ramp_time=ramp_time), Alternator()
    names = {
        "crank.omega": f"{c}.omega", "alternator.omega": f"{a}.omega",
        "alternator.rotorOmega": f"{a}.rotor.omega", "alternator.beltTorque": f"{a}.beltTorque",
        "alternator.decouplerTorque": f"{a}.decoupler.torque",
        "crank.driveTorque": f"{c}.driveTorque", "belt.minTension": "belt.minTension",
        **{f"span[{k}].tension": f"span[{k}].tension" for k in range(1, n + 1)},
        **{f"pulley[{j}].hubForce.{x}": f"pulley[{j}].hubForce.{x}"
           for j in range(1, n + 1) for x in "xy"},
        **{name: name for name in extra_outputs},
    }
    out_vrs = [vr[v] for v in names.values()]
    rows = []
    steps = int(round(stop_time / step))
    decoupler = bool(start.get(f"{a}.decoupler", False))
    w_rotor_prev = 0.0
    try:
        for i in range(steps + 1):
            t = i * step
            values = dict(zip(names, fmu2.getReal(out_vrs)))
            w_alt = values["alternator.rotorOmega"]
            if decoupler:
                # the rotor's speed has no output derivative: backward difference
                alpha_alt = (w_alt - w_rotor_prev) / step if i > 0 else 0.0
                w_rotor_prev = w_alt
            else:
                alpha_alt = fmu2.getRealOutputDerivatives([vr[f"{a}.omega"]], [1])[0]
            t_alt, dt_dw = alt.torque(w_alt)
            belt_torque = values["crank.driveTorque"]
            rows.append({"time": t, "engine.omega": engine.w, "engine.gasTorque":
                         engine.gas_torque(t, engine.theta, engine.w, engine.integral),
                         "alternator.torque": t_alt, **values})
            if i == steps:
                break
            # Inputs at t, with their rates over the step where the FMU takes them.
            fmu2.setReal([vr[f"{c}.omegaRef"], vr[f"{a}.torque"]], [engine.w, t_alt])
            if can_interpolate:
                fmu2.setRealInputDerivatives(
                    [vr[f"{c}.omegaRef"], vr[f"{a}.torque"]], [1, 1],
                    [engine.acceleration(t, belt_torque), dt_dw * alpha_alt])
            fmu2.doStep(currentCommunicationPoint=t, communicationStepSize=step)
            engine.advance(t, step, belt_torque)
    finally:
        fmu2.terminate()
        fmu2.freeInstance()
        shutil.rmtree(unzipdir, ignore_errors=True)

    res = {k: np.array([r[k] for r in rows]) for k in rows[0]}
    for j in range(1, n + 1):
        res[f"pulley[{j}].hubLoad"] = np.hypot(res[f"pulley[{j}].hubForce.x"],
                                               res[f"pulley[{j}].hubForce.y"])
    res["radius.crank"] = start[f"{c}.radius"]
    res["radius.alternator"] = start[f"{a}.radius"]
    res["nPulleys"] = n
    if out_dir is not None:
        write_outputs(res, pathlib.Path(out_dir), crank, alternator)
    return res


def write_outputs(res, out_dir, crank, alternator):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir.mkdir(parents=True, exist_ok=True)
    n = res["nPulleys"]
    series = [k for k, v in res.items() if isinstance(v, np.ndarray)]
    with open(out_dir / "engine_alternator.csv", "w") as f:
        f.write(",".join(f'"{k}"' for k in series) + "\n")
        for row in zip(*(res[k] for k in series)):
            f.write(",".join(repr(float(x)) for x in row) + "\n")

    t = res["time"]
    fig, ax = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    ratio = res["radius.crank"] / res["radius.alternator"]
    ax[0].plot(t, -res["crank.omega"] * RPM, label=f"crank (pulley {crank})")
    ax[0].plot(t, -res["alternator.omega"] * RPM, label=f"alternator (pulley {alternator})")
    ax[0].plot(t, -res["crank.omega"] * RPM * ratio, "k:", lw=0.8,
               label=f"crank x radius ratio {ratio:.2f}")
    ax[0].set_ylabel("speed (clockwise) [rpm]")
    for k in range(1, n + 1):
        ax[1].plot(t, res[f"span[{k}].tension"], label=f"span {k}")
    ax[1].set_ylabel("span tension [N]")
    for j in range(1, n + 1):
        ax[2].plot(t, res[f"pulley[{j}].hubLoad"], label=f"pulley {j}")
    ax[2].set_ylabel("hub load [N]")
    ax[2].set_xlabel("time [s]")
    for a in ax:
        a.grid(True, alpha=0.3)
        a.legend(loc="best", fontsize="small")
    fig.suptitle("BeltDrive.fmu coupled with an engine (4 cyl., 2nd order) and an alternator")
    fig.tight_layout()
    fig.savefig(out_dir / "engine_alternator.png", dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stop-time", type=float, default=1.0)
    ap.add_argument("--step", type=float, default=1e-3, help="communication step [s]")
    ap.add_argument("--parameters", type=pathlib.Path,
                    default=ROOT / "parameters/accessory-drive-4.ssv")
    ap.add_argument("--crank", type=int, default=1, help="pulley slot of the crank")
    ap.add_argument("--alternator", type=int, default=3, help="pulley slot of the alternator")
    ap.add_argument("--ramp-time", type=float, default=0.3, help="engine run-up to idle [s]")
    ap.add_argument("--fmu", type=pathlib.Path, default=ROOT / "dist/BeltDrive.fmu")
    ap.add_argument("--out-dir", type=pathlib.Path, default=ROOT / "dist")
    args = ap.parse_args()
    res = simulate(args.stop_time, args.step, args.parameters, args.crank, args.alternator,
                   args.ramp_time, args.fmu, args.out_dir)
    t = res["time"]
    last = t >= t[-1] - min(0.1, t[-1] / 3)
    ratio = res["alternator.omega"][last].mean() / res["crank.omega"][last].mean()
    print(f"t = {t[-1]:g} s: crank {-res['crank.omega'][-1] * RPM:.0f} rpm, alternator "
          f"{-res['alternator.omega'][-1] * RPM:.0f} rpm; mean speed ratio {ratio:.3f} "
          f"(radius ratio {res['radius.crank'] / res['radius.alternator']:.3f})")
    print(f"min belt tension {res['belt.minTension'].min():.0f} N; wrote "
          f"{args.out_dir / 'engine_alternator.png'} and engine_alternator.csv")


if __name__ == "__main__":
    main()
