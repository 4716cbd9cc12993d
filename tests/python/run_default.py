"""Main job: simulate the FMU's default drive (the paper's section-4 5PK drive)
through FMPy, print the headline figures and plot them to dist/default_drive.png.

Usage: python tests/python/run_default.py [--stop-time 2.0] [--step 1e-3]
"""
import argparse
import pathlib
import time

import numpy as np
from fmpy import read_model_description, simulate_fmu

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU = ROOT / "dist" / "BeltDrive.fmu"
OUTPUTS = [
    "pulley[1].omega", "pulley[2].omega", "pulley[1].angle", "pulley[2].angle", "pulley[2].slip",
    "span[1].tension", "span[2].tension", "belt.minTension", "belt.maxTension",
    "probe.sdeForce", "solver.steps", "energy.input", "energy.dissipated",
]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--stop-time", type=float, default=None)
    ap.add_argument("--step", type=float, default=None)
    args = ap.parse_args()
    md = read_model_description(str(FMU))
    stop = float(args.stop_time or md.defaultExperiment.stopTime)
    step = float(args.step or md.defaultExperiment.stepSize)
    t0 = time.perf_counter()
    res = simulate_fmu(str(FMU), stop_time=stop, output_interval=step, output=OUTPUTS)
    wall = time.perf_counter() - t0
    t = res["time"]
    window = t >= t[-1] - min(0.2, 0.5 * t[-1])
    dt = t[window][-1] - t[window][0]
    # Mean speeds over the window from the angle change (exact mean, not
    # sampled): the slip between them is the belt's creep loss.
    w1 = (res["pulley[1].angle"][window][-1] - res["pulley[1].angle"][window][0]) / dt
    w2 = (res["pulley[2].angle"][window][-1] - res["pulley[2].angle"][window][0]) / dt
    start = {v.name: v.start for v in md.modelVariables}
    r1 = float(start["pulley[1].radius"])
    r2 = float(start["pulley[2].radius"])
    print(f"BeltDrive default drive (paper section 4), 0..{stop} s, communication step {step} s")
    print(f"  {'output':22s} {'final':>11s} {'mean last %.3f s' % dt:>18s}")
    for name, label in [
        ("pulley[1].omega", "drive speed [rad/s]"),
        ("pulley[2].omega", "driven speed [rad/s]"),
        ("pulley[2].slip", "slip [%]"),
        ("span[1].tension", "tight span [N]"),
        ("span[2].tension", "slack span [N]"),
        ("belt.minTension", "belt min tension [N]"),
        ("belt.maxTension", "belt max tension [N]"),
    ]:
        y = res[name] * (100.0 if name.endswith("slip") else 1.0)
        print(f"  {label:22s} {y[-1]:11.4g} {y[window].mean():18.4g}")
    tight = res["span[1].tension"][window].mean()
    slack = res["span[2].tension"][window].mean()
    slip = 1 - (w2 * r2) / (w1 * r1) if w1 else float("nan")
    print(f"  mean speeds from the angle change: {w1:.4f} / {w2:.4f} rad/s, slip {100 * slip:.3f} %")
    print(f"  (T_tight - T_slack) r1 = {(tight - slack) * r1:.3f} N m (drive torque 15 N m at steady state)")
    steps = res["solver.steps"][-1]
    print(f"  solver steps {steps:.0f} ({steps / stop:.0f} per simulated second)")
    print(f"  wall time {wall:.1f} s, real-time factor {stop / wall:.3f}")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
        ax[0].plot(t, res["pulley[1].omega"], label="drive pulley")
        ax[0].plot(t, res["pulley[2].omega"], label="driven pulley")
        ax[0].set_ylabel("angular speed [rad/s]")
        ax[0].legend()
        ax[1].plot(t, res["span[1].tension"], label="span 1 (bottom, tight)")
        ax[1].plot(t, res["span[2].tension"], label="span 2 (top, slack)")
        ax[1].set_ylabel("span tension [N]")
        ax[1].legend()
        ax[2].plot(t, res["probe.sdeForce"])
        ax[2].set_ylabel("probe SDE force [N]")
        ax[2].set_xlabel("time [s]")
        fig.tight_layout()
        out = ROOT / "dist" / "default_drive.png"
        fig.savefig(out, dpi=110)
        print(f"  plot                 {out}")
    except ImportError:
        print("  (matplotlib missing: no plot)")
    assert np.isfinite(w1) and np.isfinite(w2)


if __name__ == "__main__":
    main()
