"""What a communication step costs through the FMU's C ABI (FMPy's
FMU2Slave): CPU time of 0.1 ms against 1 ms communication steps on the
FMU's default 5PK drive with the stiff method at relTol 1e-4, reading after
every step either speeds and means (pulley speeds and angles, mean belt
torques, mean span tensions) or every Real output. Several builds run
alternately in one process, so the machine's drift hits them alike.

    .venv/bin/python benches/comm_step_cost.py FMU [FMU ...]

prints one Markdown table: per build and read set, the CPU time of 0.2 s
simulated (after 0.1 s settling) at each communication step, their ratio,
and the integrator's accepted steps (deterministic)."""

import shutil
import sys
import tempfile
import time

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

T0, T1, REPEAT = 0.1, 0.3, 3


def open_fmu(path):
    md = read_model_description(path)
    unzipdir = extract(path)
    return md, unzipdir


def run(md, unzipdir, h, read):
    vr = {v.name: v.valueReference for v in md.modelVariables}
    outputs = [v.valueReference for v in md.modelVariables
               if v.causality == "output" and v.type == "Real"]
    cheap = [vr[f"pulley[{j}].{n}"] for j in (1, 2) for n in ("omega", "angle", "meanBeltTorque")]
    cheap += [vr["span[1].meanTension"], vr["span[2].meanTension"]]
    reads = outputs if read == "all" else cheap
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir,
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="cost")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.setInteger([vr["solver.method"]], [2])
    fmu.setReal([vr["solver.relTol"]], [1e-4])
    fmu.exitInitializationMode()
    t = 0.0
    while t < T0 - 1e-12:
        fmu.doStep(t, 1e-3)
        t += 1e-3
    steps0 = fmu.getReal([vr["solver.steps"]])[0]
    n = round((T1 - T0) / h)
    start = time.process_time()
    for k in range(n):
        fmu.doStep(T0 + k * h, h)
        fmu.getReal(reads)
    cpu = time.process_time() - start
    steps = fmu.getReal([vr["solver.steps"]])[0] - steps0
    fmu.terminate()
    fmu.freeInstance()
    return cpu, steps


def main(paths):
    builds = [(p, *open_fmu(p)) for p in paths]
    best = {}
    for _ in range(REPEAT):
        for p, md, unzipdir in builds:
            for read in ("speeds and means", "all"):
                for h in (1e-3, 1e-4):
                    cpu, steps = run(md, unzipdir, h, read)
                    key = (p, read, h)
                    best[key] = (min(cpu, best.get(key, (cpu,))[0]), steps)
    print("| build | read after each step | CPU 1 ms [s] | CPU 0.1 ms [s] | ratio | steps 1 ms / 0.1 ms |")
    print("|---|---|---|---|---|---|")
    for p, _, _ in builds:
        for read in ("speeds and means", "all"):
            (c1, s1), (c2, s2) = best[(p, read, 1e-3)], best[(p, read, 1e-4)]
            print(f"| {p} | {read} | {c1:.3f} | {c2:.3f} | {c2 / c1:.2f} | {s1:.0f} / {s2:.0f} |")
    for _, _, unzipdir in builds:
        shutil.rmtree(unzipdir, ignore_errors=True)


if __name__ == "__main__":
    main(sys.argv[1:])
