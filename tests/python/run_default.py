"""Main job (`cargo xtask run`): simulate the FMU's default drive through FMPy
with its default integrator (RKF45) and with the stiff method side by side,
print a report of both with their times, plot the RKF45 run and write the
animation.

Usage: python tests/python/run_default.py [--stop-time 2.0] [--step 1e-3] [--fast]
           [--shape-exe PATH] [--frame-step 0.01]

Files it writes (all in dist/):
  default_drive.png          the RKF45 run: speeds, slip, span tensions, the
                             probe body's spring-damper force
  default_drive.html         the animation (self-contained page, no network)
  default_drive_frames.json  the belt shape at every frame, from
                             examples/belt_shape.rs (the FMU has no output for
                             every body's position); the page embeds it
  default_drive.json         the report's figures for both integrators (the
                             FMU manual's validation table is checked against
                             the same computation, tests/python/test_main_job.py)

--fast runs the stiff method only (solver.method = 2); --shape-exe is the
`belt_shape` example (built by `cargo xtask run`): without it no animation is
written.
"""
import argparse
import json
import math
import pathlib
import subprocess
import sys
import threading
import time

import numpy as np
from fmpy import read_model_description, simulate_fmu

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import animation  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
DIST = ROOT / "dist"
FMU = DIST / "BeltDrive.fmu"
# The validation's tracked body (docs/validation.md, "Time windows of the
# tracked SDE"): the one that reaches the driven pulley at the paper's 0.75 s.
PROBE = 127
RPM = 60 / (2 * math.pi)
OUTPUTS = [
    "pulley[1].omega", "pulley[2].omega", "pulley[1].angle", "pulley[2].angle", "pulley[2].slip",
    "span[1].tension", "span[2].tension", "belt.minTension", "belt.maxTension",
    "pulley[1].meanHubForce.x", "pulley[1].meanHubForce.y",
    "pulley[2].meanHubForce.x", "pulley[2].meanHubForce.y",
    "probe.sdeForce", "probe.normalForce[1]", "probe.normalForce[2]", "probe.y",
    "solver.steps", "solver.rejectedSteps", "energy.input", "energy.dissipated",
]
# The paper's section-4 figures (Kubas 2014, Figs. 14-15 and text; the same
# readings as the table in docs/validation.md). Speeds as clockwise
# magnitudes, like the report's.
PAPER = {
    "w1": "about 22.5 rad/s", "w2": "a little slower than pulley 1", "slip": "about 1.5 %",
    "tight": "about 780 N", "slack": "about 250 N", "torque": "15 N m applied",
    "windows": "top span 0-0.75 s; driven pulley ~0.75-0.9 s; bottom span ~0.9-1.74 s; "
               "drive pulley after 1.74 s",
}
LAWS = {1: "kubas2014 (the paper's velocity-regularised Coulomb law)",
        2: "creep (elastic-plastic creep displacement; the default)"}
METHODS = {1: "RKF45 (Fehlberg 4(5), explicit, adaptive; the FMU's default)",
           2: "ROS34PW2 (stiff Rosenbrock-W, linearly implicit, adaptive; solver.method = 2)"}
SHORT = {1: "RKF45", 2: "stiff (ROS34PW2)"}
# The report's rows: key, label, format. The FMU manual's validation table
# shows the same keys in the same formats (tests/python/test_main_job.py).
ROWS = [
    ("w1", "pulley 1 (drive) speed, clockwise", "{:.2f} rad/s"),
    ("w2", "pulley 2 (driven) speed, clockwise", "{:.2f} rad/s"),
    ("w1_rpm", "  pulley 1 (drive) in rpm", "{:.1f} rpm"),
    ("w2_rpm", "  pulley 2 (driven) in rpm", "{:.1f} rpm"),
    ("slip", "slip s", "{:.3f} %"),
    ("creep", "  creep theory (T1 - T2)/(EA + T1)", "{:.3f} %"),
    ("tight", "span 1 tension (bottom, tight)", "{:.1f} N"),
    ("slack", "span 2 tension (top, slack)", "{:.1f} N"),
    ("torque", "r1 (T1 - T2), torque transmitted", "{:.2f} N m"),
    ("hub1", "hub load on pulley 1", "{:.1f} N"),
    ("hub2", "hub load on pulley 2", "{:.1f} N"),
    ("hubsum", "  two-span estimate T1 + T2", "{:.1f} N"),
]


class Progress:
    """One line per second of wall time: simulated time, speed, ETA."""

    def __init__(self, stop, label):
        self.stop, self.label = stop, label
        self.t0 = time.perf_counter()
        self.last = self.t0
        self.extra = None

    def __call__(self, t, *_):
        now = time.perf_counter()
        if now - self.last >= 1.0 or t >= self.stop:
            self.last = now
            wall = now - self.t0
            rate = t / wall if wall > 0 else 0.0
            eta = (self.stop - t) / rate if rate > 0 else float("inf")
            line = (f"  {self.label}: t = {t:6.3f} of {self.stop:g} s simulated, "
                    f"{rate:6.3f} s simulated per wall second, ETA {eta:5.0f} s")
            if self.extra:
                line += f" | {self.extra()}"
            print(line, flush=True)
        return True


def windows_of(res, threshold=1.0):
    """Where the probe body is when (the validation's rule: in contact with
    pulley 1 or 2 when its normal force exceeds 1 N, else in the top or
    bottom span by the sign of y)."""
    t = res["time"]
    place = np.where(res["probe.normalForce[1]"] > threshold, "drive pulley",
                     np.where(res["probe.normalForce[2]"] > threshold, "driven pulley",
                              np.where(res["probe.y"] > 0, "top span", "bottom span")))
    out = []
    begin = 0
    for i in range(1, len(t) + 1):
        if i == len(t) or place[i] != place[begin]:
            out.append((float(t[begin]), float(t[i - 1]), str(place[begin])))
            begin = i
    merged = []  # a contact force flickering around the threshold
    for w in out:
        if merged and (w[1] - w[0] < 0.01) and merged[-1][2] != w[2]:
            merged[-1] = (merged[-1][0], w[1], merged[-1][2])
        elif merged and merged[-1][2] == w[2]:
            merged[-1] = (merged[-1][0], w[1], w[2])
        else:
            merged.append(w)
    return merged


def window_of(stop):
    """The report's averaging window: the second half of the run, at most the
    last 1 s (steady state after the 0.3 s torque ramp), as in
    docs/validation.md."""
    return max(stop / 2, stop - 1.0), stop


def simulate(method, stop, step, progress=None):
    """The default drive through FMPy with `method`, the probe body set; the
    result and the wall time of the simulation."""
    t0 = time.perf_counter()
    res = simulate_fmu(str(FMU), stop_time=stop, output_interval=step, output=OUTPUTS,
                       start_values={"probe.body": PROBE, "solver.method": method},
                       step_finished=progress)
    return res, time.perf_counter() - t0


def figures(res, start, stop):
    """The report's figures from a run: mean speeds (clockwise, from the angle
    change over the window), slip, span tensions, hub loads (the magnitude of
    the belt's mean force on each pulley's hub) over the window."""
    t = res["time"]
    w_from, _ = window_of(stop)
    win = t >= w_from - 1e-12
    dt = t[win][-1] - t[win][0]

    def mean(name):
        return float(res[name][win].mean())

    r1, r2 = float(start["pulley[1].radius"]), float(start["pulley[2].radius"])
    ea = float(start["belt.EA"])
    # clockwise: the angles decrease
    w1 = -(res["pulley[1].angle"][win][-1] - res["pulley[1].angle"][win][0]) / dt
    w2 = -(res["pulley[2].angle"][win][-1] - res["pulley[2].angle"][win][0]) / dt
    tight, slack = mean("span[1].tension"), mean("span[2].tension")
    hub = [math.hypot(mean(f"pulley[{j}].meanHubForce.x"), mean(f"pulley[{j}].meanHubForce.y"))
           for j in (1, 2)]
    return {
        "w1": w1, "w2": w2, "w1_rpm": w1 * RPM, "w2_rpm": w2 * RPM, "slip": 100 * (1 - (w2 * r2) / (w1 * r1)),
        "creep": 100 * (tight - slack) / (ea + tight), "tight": tight, "slack": slack,
        "torque": (tight - slack) * r1, "hub1": hub[0], "hub2": hub[1], "hubsum": tight + slack,
        "min_tension": mean("belt.minTension"), "max_tension": mean("belt.maxTension"),
        "steps": float(res["solver.steps"][-1]), "rejected": float(res["solver.rejectedSteps"][-1]),
    }


def formatted(fig):
    """The report's rows as printed: {key: text}."""
    return {key: fmt.format(fig[key]) for key, _, fmt in ROWS}


def speed_text(wall, stop):
    if wall >= stop:
        return f"{wall / stop:.1f} times slower than real time"
    return f"{stop / wall:.1f} times faster than real time"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--stop-time", type=float, default=None)
    ap.add_argument("--step", type=float, default=None)
    ap.add_argument("--fast", action="store_true",
                    help="the stiff method (solver.method = 2) only, not RKF45 beside it")
    ap.add_argument("--shape-exe", default=None)
    ap.add_argument("--frame-step", type=float, default=0.01)
    args = ap.parse_args()
    md = read_model_description(str(FMU))
    start = {v.name: v.start for v in md.modelVariables}
    stop = float(args.stop_time or md.defaultExperiment.stopTime)
    step = float(args.step or md.defaultExperiment.stepSize)
    rel_tol = float(md.defaultExperiment.tolerance)
    methods = [2] if args.fast else [1, 2]
    law = int(start["friction.law"])
    r1, r2 = float(start["pulley[1].radius"]), float(start["pulley[2].radius"])
    d2 = float(start["pulley[2].loadDamping"])
    DIST.mkdir(exist_ok=True)

    print("BeltDrive: the FMU's default drive (the paper's section-4 5PK drive, Kubas 2014, with the FMU's")
    print("  contact and belt damping defaults), every parameter at its start value")
    print(f"  pulley 1 = drive pulley, r = {r1 * 1e3:g} mm at x = {float(start['pulley[1].x']):g} m: "
          f"torque {float(start['pulley[1].torqueRamp']):g} N m ramped in over "
          f"{float(start['pulley[1].rampTime']):g} s")
    print(f"  pulley 2 = driven pulley, r = {r2 * 1e3:g} mm at x = {float(start['pulley[2].x']):g} m: "
          f"load torque -{d2:.4f} N m s * omega (15 N m at 8 pi rad/s)")
    print(f"  belt: {start['belt.nBodies']} bodies, preload {float(start['belt.preload']):g} N, "
          f"EA {float(start['belt.EA']):g} N; friction law {LAWS[law]}")
    print(f"  run 0-{stop:g} s, communication step {step * 1e3:g} ms, relTol {rel_tol:g}, probe body {PROBE} "
          "(the validation's tracked body)")
    for m in methods:
        print(f"  integrator {m}: {METHODS[m]}")

    # The belt shape for the animation, computed alongside by the physics core.
    shape = None
    shape_state = {"t": 0.0}
    frames_path = DIST / "default_drive_frames.json"
    shape_method = methods[0]
    if args.shape_exe:
        cmd = [args.shape_exe, str(frames_path), "--stop-time", repr(stop),
               "--frame-step", repr(args.frame_step), "--method", str(shape_method),
               "--rel-tol", repr(rel_tol), "--probe", str(PROBE)]
        shape = subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True)

        def follow():
            for line in shape.stdout:
                if line.startswith("progress "):
                    shape_state["t"] = float(line.split()[1])
        threading.Thread(target=follow, daemon=True).start()
        print("  animation: the belt shape is computed alongside by the physics core "
              f"(examples/belt_shape.rs, same parameters, {SHORT[shape_method]})")

    runs = {}
    for m in methods:
        print(f"\nSimulating with {SHORT[m]} ...", flush=True)
        progress = Progress(stop, SHORT[m])
        if shape and m == shape_method:
            progress.extra = lambda: f"belt shape t = {shape_state['t']:.2f} s"
        res, wall = simulate(m, stop, step, progress)
        runs[m] = (res, wall, figures(res, start, stop))

    w_from, _ = window_of(stop)
    print()
    print("Sign convention: x to the right, y up; angles, speeds and torques positive counter-clockwise.")
    print("  The drive turns clockwise: the FMU's speed outputs pulley[j].omega are negative; the report gives")
    print("  their clockwise magnitudes. Span 1 = the bottom span (the drive pulley pulls it: tight),")
    print("  span 2 = the top span (slack).")
    print("Slip s = 1 - (omega2 r2)/(omega1 r1): the driven pulley's surface-speed loss, from the mean speeds")
    print(f"  over the window {w_from:g}-{stop:g} s (angle change / time). Hub load = the magnitude of the belt's")
    print("  force on the pulley's hub (pulley[j].meanHubForce.x/y), the load on its bearing.")
    print()
    cols = [SHORT[m] for m in methods]
    print(f"  {'mean ' + format(w_from, 'g') + '-' + format(stop, 'g') + ' s':36s}"
          + "".join(f"{c:>18s}" for c in cols) + "   paper (section 4)")
    texts = {m: formatted(runs[m][2]) for m in methods}
    for key, label, _ in ROWS:
        print(f"  {label:36s}" + "".join(f"{texts[m][key]:>18s}" for m in methods)
              + f"   {PAPER.get(key, '')}")
    print(f"  {'belt tension min / max':36s}" + "".join(
        f"{runs[m][2]['min_tension']:>9.0f} /{runs[m][2]['max_tension']:>6.0f} N" for m in methods))
    for m in methods:
        f, wall = runs[m][2], runs[m][1]
        rej = f["rejected"] / max(f["steps"], 1)
        print(f"  {SHORT[m]}: {f['steps']:.0f} steps ({f['steps'] / stop:.3g} per simulated second), "
              f"{f['rejected']:.0f} rejected ({100 * rej:.2g} % of the accepted); "
              f"wall time {wall:.1f} s for {stop:g} s simulated, {speed_text(wall, stop)}")
    if len(methods) == 2:
        dev = max(abs(runs[2][2][k] / runs[1][2][k] - 1) for k in ("w1", "w2", "tight", "slack"))
        print(f"  The two integrators agree within {100 * dev:.2g} % in speeds and span tensions.")
    print("  Which to choose: RKF45 (the default) for reference runs and energy bookkeeping; the stiff method")
    print("  (solver.method = 2) for long runs, co-simulation and real time, with relTol 1e-5 where the slip")
    print("  must be within 0.5 % (docs/numerics.md).")
    res = runs[methods[0]][0]
    win_txt = "; ".join(f"{p} {a:.2f}-{b:.2f} s" for a, b, p in windows_of(res))
    print(f"  probe body {PROBE} is in the: {win_txt}")
    print(f"    paper:                   {PAPER['windows']}")
    print("  Why ours differs from the paper (speed set by the paper's own load law, slip of a belt with this EA):")
    print("    docs/validation.md, \"Summary: the paper against us\".")

    figs = {SHORT[m]: dict(runs[m][2], wall_s=runs[m][1]) for m in methods}
    (DIST / "default_drive.json").write_text(json.dumps(
        {"stop_time": stop, "window": [w_from, stop], "figures": figs}, indent=1))
    png = DIST / "default_drive.png"
    plot(res, png, stop, step, rel_tol, methods[0], law, t_window(res, w_from), w_from,
         runs[methods[0]][2]["slip"] / 100, PROBE)
    print("\nFiles written:")
    print(f"  {png.relative_to(ROOT)}: the {SHORT[methods[0]]} run: speeds, slip, span tensions, the probe's force")
    print(f"  {(DIST / 'default_drive.json').relative_to(ROOT)}: the report's figures for each integrator")
    if shape:
        shape.wait()
        if shape.returncode != 0:
            raise SystemExit(f"belt_shape failed ({shape.returncode}): no animation")
        html = DIST / "default_drive.html"
        dev = animation.write(frames_path, res, html, {
            "title": f"BeltDrive: the FMU's default drive, 0-{stop:g} s",
            "settings": f"{SHORT[shape_method]}, relTol {rel_tol:g}, friction law "
                        f"{LAWS[law].split(' ')[0]}, probe body {PROBE}",
        })
        print(f"  {html.relative_to(ROOT)}: the animation, open it in a browser (belt shape and FMU run agree: "
              f"span tensions within {dev:.2g} N at the frame times)")
        print(f"  {frames_path.relative_to(ROOT)}: the belt shape at every frame, embedded in the page")
    for m in methods:
        assert np.isfinite(runs[m][2]["w1"]) and np.isfinite(runs[m][2]["w2"])


def t_window(res, w_from):
    return res["time"] >= w_from - 1e-12


def plot(res, out, stop, step, rel_tol, method, law, win, w_from, slip, probe):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = res["time"]
    fig, ax = plt.subplots(4, 1, figsize=(9, 12), sharex=True)
    fig.suptitle("BeltDrive: the FMU's default drive (the paper's section-4 5PK drive, Kubas 2014)\n"
                 f"{METHODS[method].split(' (')[0]}, relTol {rel_tol:g}, friction law "
                 f"{LAWS[law].split(' ')[0]}, communication step {step * 1e3:g} ms, FMPy",
                 fontsize=11)
    # Speeds as magnitudes in rpm (both are negative: clockwise); the 20 ms
    # moving average shows the slip gap under the polygon ripple.
    k = max(1, int(round(0.02 / (t[1] - t[0]))))
    smooth = lambda y: np.convolve(y, np.ones(k) / k, mode="same")  # noqa: E731
    for j, name, c in ((1, "pulley 1 (drive)", "C0"), (2, "pulley 2 (driven)", "C1")):
        y = -res[f"pulley[{j}].omega"] * RPM
        ax[0].plot(t, y, color=c, alpha=0.3, lw=0.6)
        ax[0].plot(t[k:-k], smooth(y)[k:-k], color=c, label=f"{name}, 20 ms mean")
    ax[0].axhline(8 * math.pi * RPM, color="k", ls=":", lw=0.8, label="load law: 15 N m at 8π rad/s")
    ax[0].set_ylabel("speed, clockwise [rpm]")
    ax[0].legend(loc="lower right", fontsize=8)
    ins = ax[0].inset_axes([0.08, 0.12, 0.38, 0.45])
    zoom = t >= w_from
    for j, c in ((1, "C0"), (2, "C1")):
        y = smooth(-res[f"pulley[{j}].omega"] * RPM)
        ins.plot(t[zoom][k:-k], y[zoom][k:-k], color=c)
    ins.set_title(f"{w_from:g}-{stop:g} s: driven slower by the slip", fontsize=7)
    ins.tick_params(labelsize=7)
    s = res["pulley[2].slip"] * 100
    ax[1].plot(t, s, color="C2", alpha=0.3, lw=0.6, label="pulley[2].slip, instantaneous")
    ax[1].plot(t[k:-k], smooth(s)[k:-k], color="C2", label="20 ms mean")
    ax[1].axhline(100 * slip, color="k", ls="--", lw=1,
                  label=f"mean {w_from:g}-{stop:g} s from the angles: {100 * slip:.3f} %")
    ax[1].axhline(1.5, color="C3", ls=":", lw=1, label="paper: ~1.5 %")
    ax[1].set_ylim(-1, 3)
    ax[1].set_ylabel("slip 1 - ω2 r2 / ω1 r1 [%]")
    ax[1].legend(loc="upper right", fontsize=8)
    ax[2].plot(t, res["span[1].tension"], color="C3", label="span 1 (bottom, tight)")
    ax[2].plot(t, res["span[2].tension"], color="C0", label="span 2 (top, slack)")
    ax[2].axhline(780, color="C3", ls=":", lw=1, label="paper: ~780 N / ~250 N")
    ax[2].axhline(250, color="C0", ls=":", lw=1)
    ax[2].set_ylabel("span tension [N]")
    ax[2].legend(loc="center right", fontsize=8)
    ax[3].plot(t, res["probe.sdeForce"], color="k", lw=0.8)
    colors = {"top span": "white", "driven pulley": "orange", "bottom span": "lightgrey",
              "drive pulley": "lightgreen"}
    for a, b, p in windows_of(res):
        ax[3].axvspan(a, b, color=colors[p], alpha=0.5, lw=0)
        if b - a > 0.08:
            ax[3].text((a + b) / 2, 0.97, p, transform=ax[3].get_xaxis_transform(),
                       ha="center", va="top", fontsize=7)
    for x in (0.75, 0.9, 1.74):
        if x < stop:
            ax[3].axvline(x, color="C3", ls=":", lw=1)
    ax[3].set_ylabel(f"force in the SDE of body {probe} [N]")
    ax[3].set_xlabel("time [s]   (dotted red: the paper's window boundaries 0.75, 0.9, 1.74 s, Fig. 15)")
    ax[3].set_title(f"probe body {probe} (the validation's tracked body) going round the drive",
                    fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    plt.close(fig)


if __name__ == "__main__":
    main()
