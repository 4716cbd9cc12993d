"""The accessory drive with its back-side idler fixed and on an automatic
tensioner arm, each coupled with the idling 4-cylinder engine of
engine_alternator.py (2nd order firing pulsation) through FMPy.

    .venv/bin/python examples/accessory_tensioner.py --out-dir docs    # 1.5 s, figures over 1.0-1.5 s

Runs parameters/accessory-drive-decoupler.ssv (V-ribbed grooves, decoupler on
the alternator, idler fixed) and parameters/accessory-drive-tensioner.ssv (the
same drive with the idler, pulley 4, on a tensioner arm), both with the stiff
method (solver.method = 2, relTol 1e-4). Prints, over the idle window after
the run-up, the slack span tensions (mean and range), the arm's angle and the
idler's hub load; writes <out-dir>/accessory_tensioner.png (arm angle and
spring torque, hub loads, span tensions, alternator rotor vs pulley speed).
"""
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import engine_alternator as ea  # noqa: E402
from accessory_decoupler import run_sets, save_figure  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
SETS = {"idler fixed": ROOT / "parameters/accessory-drive-decoupler.ssv",
        "tensioner arm": ROOT / "parameters/accessory-drive-tensioner.ssv"}
ARM = ["pulley[4].arm.angle", "pulley[4].arm.omega", "pulley[4].arm.springTorque"]


def summary(res, t_from):
    """Figures over t >= t_from: span tensions, arm angle, idler hub load."""
    w = res["time"] >= t_from
    spans = [res[f"span[{k}].tension"][w] for k in range(1, res["nPulleys"] + 1)]
    arm = np.degrees(res["pulley[4].arm.angle"][w])
    hub = res["pulley[4].hubLoad"][w]
    return {"span tensions [N] (mean, min, max)": [(s.mean(), s.min(), s.max()) for s in spans],
            "arm angle [deg] (min, max)": (arm.min(), arm.max()),
            "idler hub load [N] (min, max)": (hub.min(), hub.max())}


def plot(results, t_from, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(4, 2, figsize=(12, 11), sharex=True)
    for col, (name, res) in enumerate(results.items()):
        t = res["time"]
        w = t >= t_from
        a = ax[0, col]
        if name == "tensioner arm":
            a.plot(t[w], np.degrees(res["pulley[4].arm.angle"][w]), label="arm angle [deg]")
            b = a.twinx()
            b.plot(t[w], res["pulley[4].arm.springTorque"][w], "C1", lw=0.8,
                   label="spring torque [N m]")
            b.set_ylabel("spring torque [N m]")
            b.legend(loc="lower right", fontsize="x-small")
            a.set_ylabel("arm angle, ccw [deg]")
        else:
            a.text(0.5, 0.5, "idler fixed: no arm", ha="center", va="center",
                   transform=a.transAxes)
        a.set_title(name)
        for j in range(1, res["nPulleys"] + 1):
            ax[1, col].plot(t[w], res[f"pulley[{j}].hubLoad"][w], label=f"pulley {j}")
        ax[1, col].set_ylabel("hub load [N]")
        for k in range(1, res["nPulleys"] + 1):
            ax[2, col].plot(t[w], res[f"span[{k}].tension"][w], label=f"span {k}")
        ax[2, col].set_ylabel("span tension [N]")
        ax[3, col].plot(t[w], -res["alternator.omega"][w] * ea.RPM, label="alternator pulley")
        ax[3, col].plot(t[w], -res["alternator.rotorOmega"][w] * ea.RPM, label="alternator rotor")
        ax[3, col].set_ylabel("speed (clockwise) [rpm]")
        ax[3, col].set_xlabel("time [s]")
    save_figure(fig, ax, "Accessory drive at idle with firing pulsation: idler fixed vs on a tensioner arm "
                "(decoupler on the alternator in both)", path)
    plt.close(fig)


def main():
    # the arm outputs are 0 without an arm
    args, results = run_sets(SETS, __doc__.splitlines()[0],
                             "figures from this time on [s] (the run-up transient decays by then)",
                             extra_outputs=ARM)
    for name, res in results.items():
        s = summary(res, args.window)
        spans = ", ".join(f"{m:.0f} ({lo:.0f}-{hi:.0f})"
                          for m, lo, hi in s["span tensions [N] (mean, min, max)"])
        line = f"{name:13s}: span tensions {spans} N; idler hub load " \
               f"{s['idler hub load [N] (min, max)'][0]:.0f}-{s['idler hub load [N] (min, max)'][1]:.0f} N"
        if name == "tensioner arm":
            lo, hi = s["arm angle [deg] (min, max)"]
            line += f"; arm angle {lo:.2f} to {hi:.2f} deg"
        print(line)
    plot(results, args.window, args.out_dir / "accessory_tensioner.png")


if __name__ == "__main__":
    main()
