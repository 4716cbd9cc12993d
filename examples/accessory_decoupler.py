"""The accessory drive with and without a one-way decoupler on the alternator,
each coupled with the idling 4-cylinder engine of engine_alternator.py (2nd
order firing pulsation) through FMPy.

    .venv/bin/python examples/accessory_decoupler.py    # 1.5 s, figures over 1.0-1.5 s

Runs parameters/accessory-drive-4.ssv (rigid alternator pulley) and
parameters/accessory-drive-decoupler.ssv (the same drive with V-ribbed grooves
and a decoupler on the alternator, pulley 3), both with the stiff method
(solver.method = 2, relTol 1e-4). Prints, over the idle window after the
run-up, the share of time the belt brakes the alternator pulley (its belt
torque against the driving sense), the alternator's speed fluctuation, and the
span tension range; writes <out-dir>/accessory_decoupler.png (crank,
alternator pulley and rotor speed, alternator belt torque, span tensions, hub
loads).
"""
import argparse
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import engine_alternator as ea  # noqa: E402
from simulate_ssv import start_values  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
SETS = {"rigid": ROOT / "parameters/accessory-drive-4.ssv",
        "decoupler": ROOT / "parameters/accessory-drive-decoupler.ssv"}


def with_method(ssv, method, tmp_dir):
    """A copy of the .ssv with solver.method set (the sets use RKF45)."""
    text = pathlib.Path(ssv).read_text()
    key = '<ssv:Parameter name="solver.method">\n      <ssv:Integer value="1"/>'
    assert key in text, ssv
    out = pathlib.Path(tmp_dir) / pathlib.Path(ssv).name
    out.write_text(text.replace(key, key.replace('value="1"', f'value="{method}"')))
    return out


def summary(res, t_from):
    """Figures over t >= t_from: braking share, alternator speed range, tensions."""
    w = res["time"] >= t_from
    # the crank turns clockwise: the belt drives the alternator with a
    # negative torque, and brakes it with a positive one
    braking = np.mean(res["alternator.beltTorque"][w] > 0.0)
    rotor = -res["alternator.rotorOmega"][w] * ea.RPM
    pulley = -res["alternator.omega"][w] * ea.RPM
    spans = [res[f"span[{k}].tension"][w] for k in range(1, res["nPulleys"] + 1)]
    return {"braking share": braking,
            "pulley speed range [rpm]": (pulley.min(), pulley.max()),
            "rotor speed range [rpm]": (rotor.min(), rotor.max()),
            "span tension ranges [N]": [(s.min(), s.max()) for s in spans]}


def plot(results, t_from, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(4, 2, figsize=(12, 11), sharex=True)
    for col, (name, res) in enumerate(results.items()):
        t = res["time"]
        w = t >= t_from
        a = ax[0, col]
        a.plot(t[w], -res["alternator.omega"][w] * ea.RPM, label="alternator pulley")
        a.plot(t[w], -res["alternator.rotorOmega"][w] * ea.RPM, label="alternator rotor")
        ratio = res["radius.crank"] / res["radius.alternator"]
        a.plot(t[w], -res["crank.omega"][w] * ea.RPM * ratio, "k:", lw=0.8,
               label=f"crank x {ratio:.2f}")
        a.set_ylabel("speed (clockwise) [rpm]")
        a.set_title(name)
        ax[1, col].plot(t[w], -res["alternator.beltTorque"][w], label="belt on alternator pulley")
        ax[1, col].plot(t[w], res["alternator.decouplerTorque"][w], label="decoupler clutch")
        ax[1, col].axhline(0.0, color="k", lw=0.6)
        ax[1, col].set_ylabel("torque, driving sense [N m]")
        for k in range(1, res["nPulleys"] + 1):
            ax[2, col].plot(t[w], res[f"span[{k}].tension"][w], label=f"span {k}")
        ax[2, col].set_ylabel("span tension [N]")
        for j in range(1, res["nPulleys"] + 1):
            ax[3, col].plot(t[w], res[f"pulley[{j}].hubLoad"][w], label=f"pulley {j}")
        ax[3, col].set_ylabel("hub load [N]")
        ax[3, col].set_xlabel("time [s]")
    save_figure(fig, ax, "Accessory drive at idle with firing pulsation: rigid alternator pulley vs decoupler",
                path)
    plt.close(fig)


def run_sets(sets, description, window_help, extra_outputs=()):
    """Command line (--stop-time, --window, --fmu, --out-dir) and the runs of
    each 4-pulley set with the stiff method, coupled with the idling engine:
    (args, {name: result})."""
    import tempfile
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--stop-time", type=float, default=1.5)
    ap.add_argument("--window", type=float, default=1.0, help=window_help)
    ap.add_argument("--fmu", type=pathlib.Path, default=ROOT / "dist/BeltDrive.fmu")
    ap.add_argument("--out-dir", type=pathlib.Path, default=ROOT / "dist")
    args = ap.parse_args()
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, ssv in sets.items():
            assert start_values(ssv)["nPulleys"] == 4
            results[name] = ea.simulate(args.stop_time, 1e-3, with_method(ssv, 2, tmp), crank=1,
                                        alternator=3, fmu=args.fmu, extra_outputs=extra_outputs)
    args.out_dir.mkdir(parents=True, exist_ok=True)
    return args, results


def save_figure(fig, ax, title, path):
    """Grid and legends on every panel that has lines, the title, and the PNG."""
    for a in ax.flat:
        a.grid(True, alpha=0.3)
        if a.get_legend_handles_labels()[0]:
            a.legend(loc="upper right", fontsize="x-small")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    print(f"wrote {path}")


def main():
    args, results = run_sets(SETS, __doc__.splitlines()[0],
                             "figures from this time on [s] (the rotor's run-up transient decays by then)")
    for name, res in results.items():
        s = summary(res, args.window)
        spans = ", ".join(f"{lo:.0f}-{hi:.0f}" for lo, hi in s["span tension ranges [N]"])
        print(f"{name:9s}: belt brakes the alternator {100 * s['braking share']:.1f} % of the time; "
              f"pulley {s['pulley speed range [rpm]'][0]:.0f}-{s['pulley speed range [rpm]'][1]:.0f} rpm, "
              f"rotor {s['rotor speed range [rpm]'][0]:.0f}-{s['rotor speed range [rpm]'][1]:.0f} rpm; "
              f"span tensions {spans} N")
    plot(results, args.window, args.out_dir / "accessory_decoupler.png")


if __name__ == "__main__":
    main()
