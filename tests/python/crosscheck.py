"""Reference results of the FMU's default drive in the FMI cross-check layout
(https://github.com/modelica/fmi-cross-check, FMI-CROSS-CHECK-RULES.md 9.1.4
and appendix B), written beside the FMU:

    BeltDrive_in.csv   every input variable (all held at their start value 0:
                       the default drive is driven by its parameter ramps)
    BeltDrive_ref.csv  ten headline outputs at every communication point
    BeltDrive_ref.opt  StartTime, StopTime, StepSize (communication step), RelTol

computed with FMPy. StopTime defaults to 0.5 s instead of the DefaultExperiment's
2 s to keep the reference cheap (the default drive runs at about 0.03x real
time); it covers the start-up and most of the 0.3 s torque ramp.

Usage: python tests/python/crosscheck.py [--stop-time 0.5] [--dir dist]
       python tests/python/crosscheck.py --compare [--dir dist] [--result OTHER.csv]

--compare checks existing files instead of writing them: it imports the FMU
with the .opt settings and the _in.csv inputs (FMPy), or reads another tool's
result (--result, a CSV with the same header as _ref.csv), and compares every
column with _ref.csv. Allowed per signal: 4 e, e the reference's integration
error estimated from a run at RelTol/10 (two solutions within e of the exact one
differ by at most 2 e; one difference to a tighter run estimates e to within
about a factor 2). Exit status 1 if any signal is further off.
"""
import argparse
import pathlib

import numpy as np
from fmpy import read_model_description, simulate_fmu

ROOT = pathlib.Path(__file__).resolve().parents[2]
MODEL = "BeltDrive"
REF_VARIABLES = [
    "pulley[1].omega", "pulley[2].omega", "pulley[2].angle",
    "pulley[1].beltTorque", "pulley[2].beltTorque",
    "span[1].tension", "span[2].tension",
    "pulley[1].hubForce.x", "belt.maxTension", "pulley[2].slip",
]


def write_csv(path, names, columns):
    """Cross-check CSV: quoted header starting with "time", comma separated,
    unquoted C floating-point literals (shortest round-trip repr)."""
    lines = [",".join(f'"{n}"' for n in names)]
    for row in zip(*columns):
        lines.append(",".join(repr(float(x)) for x in row))
    path.write_text("\n".join(lines) + "\n")


def read_opt(path):
    opts = {}
    for line in path.read_text().splitlines():
        key, _, value = line.partition(",")
        if key.strip():
            opts[key.strip()] = float(value.split("//")[0])
    return opts


def read_input_csv(path):
    """The _in.csv as the structured array FMPy takes as `input`."""
    return np.genfromtxt(path, delimiter=",", names=True, deletechars="", dtype=None)


def compare(args):
    fmu = args.dir / f"{MODEL}.fmu"
    opt = read_opt(args.dir / f"{MODEL}_ref.opt")
    ref = np.genfromtxt(args.dir / f"{MODEL}_ref.csv", delimiter=",", names=True, deletechars="")
    names = list(ref.dtype.names[1:])
    kw = dict(start_time=opt["StartTime"], stop_time=opt["StopTime"],
              output_interval=opt["StepSize"], output=names,
              input=read_input_csv(args.dir / f"{MODEL}_in.csv"))
    if args.result:
        out = np.genfromtxt(args.result, delimiter=",", names=True, deletechars="")
        who = str(args.result)
    else:
        out = simulate_fmu(str(fmu), relative_tolerance=opt["RelTol"], **kw)
        who = "FMPy import of the .opt and _in.csv"
    tight = simulate_fmu(str(fmu), relative_tolerance=opt["RelTol"] / 10, **kw)
    if len(out) != len(ref) or np.max(np.abs(out["time"] - ref["time"])) > 1e-9:
        raise SystemExit(f"{who}: time points differ from {MODEL}_ref.csv")
    bad = 0
    print(f"{who} against {MODEL}_ref.csv (allowed: 4 x the reference's integration error)")
    for n in names:
        dev = float(np.max(np.abs(out[n] - ref[n])))
        bound = 4 * float(np.max(np.abs(ref[n] - tight[n])))
        ok = dev <= bound
        bad += not ok
        print(f"  {n:22s} max difference {dev:10.3g}  allowed {bound:10.3g}  {'ok' if ok else 'FAIL'}")
    if bad:
        raise SystemExit(f"{bad} signals differ from the reference")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--stop-time", type=float, default=0.5)
    ap.add_argument("--dir", type=pathlib.Path, default=ROOT / "dist")
    ap.add_argument("--compare", action="store_true",
                    help="compare an import (or --result) with the files instead of writing them")
    ap.add_argument("--result", type=pathlib.Path, default=None)
    args = ap.parse_args()
    if args.compare:
        return compare(args)
    fmu = args.dir / f"{MODEL}.fmu"
    md = read_model_description(str(fmu))
    de = md.defaultExperiment
    start, step, tol = float(de.startTime), float(de.stepSize), float(de.tolerance)
    stop = args.stop_time

    inputs = [v for v in md.modelVariables if v.causality == "input"]
    write_csv(args.dir / f"{MODEL}_in.csv", ["time"] + [v.name for v in inputs],
              [[start, stop]] + [[float(v.start)] * 2 for v in inputs])
    (args.dir / f"{MODEL}_ref.opt").write_text(
        f"StartTime, {start!r}\nStopTime, {stop!r}\nStepSize, {step!r}\nRelTol, {tol!r}\n")

    res = simulate_fmu(str(fmu), start_time=start, stop_time=stop, output_interval=step,
                       relative_tolerance=tol, output=REF_VARIABLES,
                       input=read_input_csv(args.dir / f"{MODEL}_in.csv"))
    write_csv(args.dir / f"{MODEL}_ref.csv", ["time"] + REF_VARIABLES,
              [res["time"]] + [res[n] for n in REF_VARIABLES])
    print(f"{args.dir}/{MODEL}_{{ref.csv,ref.opt,in.csv}}: {len(res)} points, 0..{stop} s")


if __name__ == "__main__":
    main()
