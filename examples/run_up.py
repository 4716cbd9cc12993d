"""Run-up of an accessory drive from idle to a top crank speed (FMPy).

    .venv/bin/python examples/run_up.py --parameters parameters/fead-7.ssv --to 6000 --time 2.0 \\
        --out-dir docs/fead

* The set's crank (pulley 1, speed-driven) reaches idle along its built-in ramp and stays there until
  `--settle` s; then `pulley[1].omegaRef` adds a linear ramp that brings it to `--to` rpm in `--time` s
  (value and slope given every communication step: the FMU interpolates its inputs).
* The accessory loads: each speed-proportional load of the set (`pulley[j].loadDamping`, the catalogue power
  at idle) is replaced by the constant torque it takes at idle (`pulley[j].torque`), so that the loads keep
  their idle torques while the speed rises. With the set's loads, which grow with the speed squared, fead-7
  would ask for 160 kW at 6,000 rpm. `--loads damping` keeps the set's loads.
* The stiff method (`solver.method` = 2) at relTol 1e-4, 1 ms communication steps.

Writes <out-dir>/run_up.csv (every communication point) and run_up.png: against the crank speed, the
slip of each driven pulley, the interval mean tension of every span with its interval minimum (the slack side),
the tensioner arms' angles and the decoupler's overrun (rotor against pulley speed).
"""
import argparse
import math
import pathlib
import shutil
import sys
import tempfile
import time

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from simulate_ssv import start_values  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
RPM = 60.0 / (2.0 * math.pi)


def crank_reference(t, settle, ramp, idle, top):
    """Added crank speed [rad/s] and its slope at time t: 0 until `settle`, then a linear ramp from idle to top
    (speeds signed as the set's crank turns) over `ramp` seconds, then held."""
    if t <= settle:
        return 0.0, 0.0
    s = min((t - settle) / ramp, 1.0)
    slope = (top - idle) / ramp if s < 1.0 else 0.0
    return s * (top - idle), slope


def simulate(parameters, top_rpm=6000.0, ramp=2.0, settle=0.6, step=1e-3, loads="torque", fmu=None,
             out_dir=None):
    """Runs the run-up; returns a dict of arrays (and writes the CSV and PNG into out_dir when given)."""
    fmu = pathlib.Path(fmu or ROOT / "dist/BeltDrive.fmu")
    start = start_values(parameters)
    n = int(start["nPulleys"])
    idle = float(start["pulley[1].omegaRamp"])
    if not start.get("pulley[1].speedDriven", False) or idle == 0.0:
        raise SystemExit(f"{parameters}: pulley 1 must be speed-driven with an idle speed (omegaRamp)")
    top = math.copysign(top_rpm / RPM, idle)
    radius = [float(start[f"pulley[{j}].radius"]) for j in range(1, n + 1)]
    decouplers = [j for j in range(1, n + 1) if start.get(f"pulley[{j}].decoupler", False)]
    arms = [j for j in range(1, n + 1) if start.get(f"pulley[{j}].tensioner", False)]
    # the idle torque of each speed-proportional load: loadDamping times its pulley's idle speed (the crank's
    # speed times the radius ratio; a back-side pulley turns the other way, which the torque's sign follows)
    torques = {}
    if loads == "torque":
        for j in range(2, n + 1):
            c = float(start.get(f"pulley[{j}].loadDamping", 0.0))
            if c != 0.0:
                back = -1.0 if start.get(f"pulley[{j}].backSide", False) else 1.0
                w = back * idle * radius[0] / radius[j - 1]
                torques[j] = -c * w
                start[f"pulley[{j}].loadDamping"] = 0.0
    md = read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    names = {"crank.omega": "pulley[1].omega", "belt.intervalMinTension": "belt.intervalMinTension"}
    for j in range(2, n + 1):
        names[f"slip.{j}"] = f"pulley[{j}].slip"
    for k in range(1, n + 1):
        names[f"span{k}.mean"] = f"span[{k}].meanTension"
        names[f"span{k}.min"] = f"span[{k}].minTension"
    for j in decouplers:
        names[f"pulley{j}.omega"] = f"pulley[{j}].omega"
        names[f"rotor{j}.omega"] = f"pulley[{j}].rotor.omega"
    for j in arms:
        names[f"arm{j}.angle"] = f"pulley[{j}].arm.angle"
    out_vrs = [vr[v] for v in names.values()]

    unzipdir = extract(str(fmu), unzipdir=tempfile.mkdtemp())
    fmu2 = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir,
                     modelIdentifier=md.coSimulation.modelIdentifier, instanceName="runup")
    stop = settle + ramp + 0.05
    rows = []
    cpu = time.process_time()
    try:
        fmu2.instantiate()
        start["solver.method"] = 2
        start["solver.relTol"] = 1e-4
        for name, value in start.items():
            if isinstance(value, bool):
                fmu2.setBoolean([vr[name]], [value])
            elif isinstance(value, int):
                fmu2.setInteger([vr[name]], [value])
            else:
                fmu2.setReal([vr[name]], [float(value)])
        fmu2.setupExperiment(startTime=0.0, stopTime=stop)
        fmu2.enterInitializationMode()
        fmu2.exitInitializationMode()
        for j, tq in torques.items():
            fmu2.setReal([vr[f"pulley[{j}].torque"]], [tq])
        t = 0.0
        steps = int(round(stop / step))
        for k in range(steps):
            ref, slope = crank_reference(t, settle, ramp, idle, top)
            fmu2.setReal([vr["pulley[1].omegaRef"]], [ref])
            fmu2.setRealInputDerivatives([vr["pulley[1].omegaRef"]], [1], [slope])
            fmu2.doStep(currentCommunicationPoint=t, communicationStepSize=step)
            t = (k + 1) * step
            rows.append([t] + list(fmu2.getReal(out_vrs)))
        fmu2.terminate()
    finally:
        fmu2.freeInstance()
        shutil.rmtree(unzipdir, ignore_errors=True)
    cpu = time.process_time() - cpu
    data = np.array(rows)
    res = {"time": data[:, 0], "cpu": cpu, "radius": radius, "decouplers": decouplers, "arms": arms,
           "load_torques": torques, "n": n}
    for i, key in enumerate(names):
        res[key] = data[:, i + 1]
    if out_dir is not None:
        write(res, pathlib.Path(out_dir), parameters)
    return res


def smooth(x, width):
    """Moving mean over `width` samples (the body-passing ripple of instantaneous outputs averaged out)."""
    if width <= 1 or len(x) < width:
        return x
    return np.convolve(x, np.ones(width) / width, mode="same")


def write(res, out_dir, parameters):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir.mkdir(parents=True, exist_ok=True)
    keys = [k for k in res if isinstance(res[k], np.ndarray)]
    np.savetxt(out_dir / "run_up.csv", np.column_stack([res[k] for k in keys]), delimiter=",",
               header=",".join(keys), comments="", fmt="%.6g")
    rpm = np.abs(res["crank.omega"]) * RPM
    running = res["time"] > 0.55
    n = res["n"]
    fig, ax = plt.subplots(4, 1, figsize=(8, 11), sharex=True)
    for j in range(2, n + 1):
        ax[0].plot(rpm[running], 100 * smooth(res[f"slip.{j}"], 10)[running], label=f"pulley {j}")
    ax[0].set_ylabel("slip [%] (10 ms mean)")
    ax[0].legend(fontsize=7, ncol=3)
    for k in range(1, n + 1):
        line, = ax[1].plot(rpm[running], res[f"span{k}.mean"][running], label=f"span {k}")
        ax[1].plot(rpm[running], res[f"span{k}.min"][running], color=line.get_color(), linewidth=0.4)
    ax[1].set_ylabel("span tension [N]\n(interval mean; thin: minimum)")
    ax[1].legend(fontsize=7, ncol=4)
    ax[2].plot(rpm[running], res["belt.intervalMinTension"][running], color="black")
    ax[2].set_ylabel("belt's smallest\ntension [N]")
    for j in res["arms"]:
        ax[3].plot(rpm[running], np.degrees(res[f"arm{j}.angle"][running]), label=f"tensioner arm, pulley {j} [deg]")
    for j in res["decouplers"]:
        overrun = (res[f"rotor{j}.omega"] - res[f"pulley{j}.omega"]) * RPM
        ax[3].plot(rpm[running], smooth(overrun, 10)[running], label=f"decoupler overrun, pulley {j} [rpm]")
    ax[3].set_ylabel("arm angle / overrun")
    ax[3].legend(fontsize=7)
    ax[3].set_xlabel("crank speed [rpm]")
    for a in ax:
        a.grid(True, alpha=0.3)
    loads = ", ".join(f"{j}: {tq:.2f} N m" for j, tq in res["load_torques"].items()) or "the set's"
    fig.suptitle(f"{pathlib.Path(parameters).name}: run-up (loads held at idle torques: {loads})", fontsize=9)
    fig.tight_layout()
    fig.savefig(out_dir / "run_up.png", dpi=90)
    print(f"wrote {out_dir / 'run_up.csv'} and {out_dir / 'run_up.png'}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--parameters", type=pathlib.Path, default=ROOT / "parameters/fead-7.ssv")
    ap.add_argument("--to", type=float, default=6000.0, help="top crank speed [rpm]")
    ap.add_argument("--time", type=float, default=2.0, help="ramp time from idle to the top speed [s]")
    ap.add_argument("--settle", type=float, default=0.6, help="time at idle before the ramp [s]")
    ap.add_argument("--step", type=float, default=1e-3, help="communication step [s]")
    ap.add_argument("--loads", choices=["torque", "damping"], default="torque")
    ap.add_argument("--fmu", type=pathlib.Path, default=ROOT / "dist/BeltDrive.fmu")
    ap.add_argument("--out-dir", type=pathlib.Path, default=ROOT / "dist")
    a = ap.parse_args()
    res = simulate(a.parameters, a.to, a.time, a.settle, a.step, a.loads, a.fmu, a.out_dir)
    sim = res["time"][-1]
    print(f"{sim:.2f} s simulated in {res['cpu']:.1f} s CPU ({sim / res['cpu']:.2f} times real time)")


if __name__ == "__main__":
    main()
