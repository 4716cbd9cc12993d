"""Independent importers against FMPy, and the cross-check files beside the FMU.

* Open Simulation Platform's libcosim (`libcosimpy`), Ecos (`ecospy`) and
  fmu-manipulation-toolbox's checker: wheels pinned in requirements.txt, always run.
* rust-fmi's `fmi-sim` (crates.io, pinned in xtask/src/tools.rs): built from
  source by `cargo xtask fmi-sim` or `cargo xtask test --fmi-sim` into .tools/;
  its tests are skipped (with the reason printed) when it is not installed.
  The path of the executable comes in the environment variable FMI_SIM.

`cargo xtask test` writes dist/BeltDrive_{ref.csv,ref.opt,in.csv}
(`cargo xtask crosscheck`) before running pytest.

Why the importers do not agree bit for bit over the reference run: FMPy steps
to the communication point start + (n + 1) h and passes the difference to the
previous point as the step size, fmi-sim passes h itself, so t + h differs in
the last bit now and then; the adaptive integrator then ends a sub-step a hair
differently, and the stiff belt contacts amplify that to the level of the
integration error. Hence two checks:
* with the same call sequence as fmi-sim (doStep(n h, h)) FMPy's C-level
  calls give bit-identical results;
* over the reference run, the two importers differ by at most 4 e per signal,
  where e is the reference's integration error, estimated by a run at RelTol/10:
  two solutions each within e of the exact one differ by at most 2 e, and a
  single difference to a tighter run estimates e only to within about a factor
  2 (the error of a variable-step run depends on where its steps fall).
"""
import os
import pathlib
import subprocess

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.fmi2 import FMU2Slave
from fmpy.cross_check.validate_vendor_repo import validate_test_fmu
from fmpy.util import read_ref_opt_file

from conftest import FMU, ROOT

DIST = FMU.parent
MODEL = "BeltDrive"


@pytest.fixture(scope="session")
def fmi_sim():
    exe = os.environ.get("FMI_SIM")
    if not exe:
        found = sorted((ROOT / ".tools").glob("fmi-sim-*/bin/fmi-sim"))
        exe = str(found[-1]) if found else None
    if not exe or not pathlib.Path(exe).exists():
        pytest.skip("fmi-sim not installed: `cargo xtask test --fmi-sim` builds it (about 5 min)")
    return exe


@pytest.fixture(scope="session")
def crosscheck(fmu_path):
    files = {s: DIST / f"{MODEL}_{s}" for s in ("ref.csv", "ref.opt", "in.csv")}
    missing = [str(p) for p in files.values() if not p.exists()]
    if missing:
        pytest.fail(f"{missing} missing: run `cargo xtask crosscheck` first")
    return files


def read_csv(path):
    return np.genfromtxt(path, delimiter=",", names=True, deletechars="")


def run_fmi_sim(exe, out, stop, step, tol, input_file=None, init_values=()):
    cmd = [exe, "--model", str(FMU), "-o", str(out)]
    if input_file:
        cmd += ["-i", str(input_file)]
    cmd += ["co-simulation", "-s", "0", "-f", repr(stop), "--output-interval", repr(step),
            "--tolerance", repr(tol)]
    for name, value in init_values:
        cmd += ["--init-values", f"{name}={value}"]
    env = dict(os.environ, RUST_LOG="warn")
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return read_csv(out)


def assert_agree(result, reference, names, bound):
    """max |result - reference| <= bound[name] (an array, or a number for all)."""
    np.testing.assert_array_equal(result["time"], reference["time"])
    for n in names:
        dev = np.max(np.abs(result[n] - reference[n]))
        b = bound[n] if isinstance(bound, dict) else bound
        assert dev <= b, f"{n}: importers differ by {dev:.3g} > {b:.3g}"
        print(f"  {n:22s} max difference {dev:.3g} (allowed {b:.3g})")


def test_crosscheck_files_follow_the_rules(crosscheck, fmu_path, md, tmp_path):
    """FMPy's validator of the cross-check repository on the usual layout
    fmus/2.0/cs/linux64/<tool>/<version>/<model>/."""
    d = tmp_path / "fmus/2.0/cs/linux64/BeltDrive" / md.version / MODEL
    d.mkdir(parents=True)
    (d / f"{MODEL}.fmu").symlink_to(fmu_path)
    for suffix, path in crosscheck.items():
        (d / f"{MODEL}_{suffix}").symlink_to(path)
    assert validate_test_fmu(str(d)) == []
    opt = read_ref_opt_file(str(crosscheck["ref.opt"]))
    ref = read_csv(crosscheck["ref.csv"])
    assert ref["time"][0] == opt["StartTime"] and np.isclose(ref["time"][-1], opt["StopTime"])
    assert len(ref.dtype.names) - 1 <= 10, "at most 10 variables recommended"
    inputs = [v.name for v in md.modelVariables if v.causality == "input"]
    assert list(read_csv(crosscheck["in.csv"]).dtype.names) == ["time"] + inputs
    for path in crosscheck.values():
        assert path.stat().st_size < 1e6
        text = path.read_text()
        assert "\r" not in text and not any(line.endswith(",") for line in text.splitlines())


def test_same_calls_give_identical_results(fmi_sim, md, unzipdir, tmp_path):
    """FMPy's FMU2Slave making fmi-sim's calls (doStep(n h, h)) on a short run
    of the default drive: every output bit-identical."""
    stop, step, tol, n_steps = 0.03, 1e-3, 1e-4, 30
    out = run_fmi_sim(fmi_sim, tmp_path / "out.csv", stop, step, tol)
    outputs = [v for v in md.modelVariables if v.causality == "output"]
    vrs = [v.valueReference for v in outputs]
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir,
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="same-calls")
    fmu.instantiate()
    fmu.setupExperiment(tolerance=tol, startTime=0.0, stopTime=stop)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    rows = [fmu.getReal(vrs)]
    for n in range(n_steps):
        fmu.doStep(n * step, step)
        rows.append(fmu.getReal(vrs))
    fmu.terminate()
    fmu.freeInstance()
    rows = np.array(rows)
    assert len(out) == n_steps + 1
    for i, v in enumerate(outputs):
        np.testing.assert_array_equal(out[v.name], rows[:, i], err_msg=v.name)


def test_fmi_sim_reproduces_the_reference(fmi_sim, crosscheck, tmp_path):
    """The default drive over the .opt horizon with the _in.csv inputs:
    fmi-sim against the FMPy reference, within 4 e (module docstring)."""
    opt = read_ref_opt_file(str(crosscheck["ref.opt"]))
    ref = read_csv(crosscheck["ref.csv"])
    names = ref.dtype.names[1:]
    out = run_fmi_sim(fmi_sim, tmp_path / f"{MODEL}_out.csv", opt["StopTime"], opt["StepSize"],
                      opt["RelTol"], input_file=crosscheck["in.csv"])
    tight = simulate_fmu(str(FMU), start_time=opt["StartTime"], stop_time=opt["StopTime"],
                         output_interval=opt["StepSize"], relative_tolerance=opt["RelTol"] / 10,
                         output=list(names))
    error = {n: np.max(np.abs(ref[n] - tight[n])) for n in names}
    assert_agree(out, ref, names, {n: 4 * error[n] for n in names})


def test_fmi_sim_sets_parameters_like_fmpy(fmi_sim, tmp_path):
    """Start values through fmi-sim's --init-values (Integer, Real, Boolean
    parameters) give FMPy's result with the same start values: a lighter,
    speed-driven variant of the default drive."""
    start = {"belt.nBodies": 100, "probe.body": 1, "belt.preload": 400.0,
             "pulley[1].speedDriven": True, "pulley[1].torqueRamp": 0.0,
             "pulley[1].omegaRamp": -20.0, "pulley[1].rampTime": 0.02}
    names = ["pulley[1].omega", "pulley[2].omega", "pulley[1].driveTorque",
             "span[1].tension", "span[2].tension", "pulley[2].meanHubForce.x"]
    # the hub force as its mean over the communication step: the instantaneous
    # one carries the body-passing ripple, which the two masters' step
    # sequences sample differently by more than the error estimate below
    stop, step, tol = 0.03, 1e-3, 1e-4
    ref = simulate_fmu(str(FMU), stop_time=stop, output_interval=step, relative_tolerance=tol,
                       start_values=start, output=names)
    fmt = {bool: lambda b: "true" if b else "false", int: str, float: repr}
    out = run_fmi_sim(fmi_sim, tmp_path / "out.csv", stop, step, tol,
                      init_values=[(k, fmt[type(v)](v)) for k, v in start.items()])
    # The speed-driven pulley follows the ramp exactly (-20 rad/s after 0.02 s).
    assert np.isclose(out["pulley[1].omega"][-1], -20.0, rtol=1e-12)
    # Same start values and communication points: the runs differ by FMPy's
    # step-size arithmetic (see above), so to the level of the integration
    # error: 4 e, e estimated from FMPy at tol and tol / 10 (module docstring),
    # plus round-off (1e-12 of the signal) for the prescribed speed, which
    # both tolerances give to the last bits.
    tight = simulate_fmu(str(FMU), stop_time=stop, output_interval=step, relative_tolerance=tol / 10,
                         start_values=start, output=names)
    assert_agree(out, ref, names, {n: 4 * np.max(np.abs(ref[n] - tight[n]))
                                   + 1e-12 * np.max(np.abs(ref[n])) for n in names})


# --- libcosim, Ecos, fmu-manipulation-toolbox --------------------------------
#
# Each runs the default drive (the FMU's start values, 1 ms communication
# steps, the DefaultExperiment's tolerance) over SHORT_STOP seconds: the
# start-up with its contact transients, where the integrator works hardest.
# Like fmi-sim, these masters pass h = 1e-3 while FMPy passes the difference of
# two communication points, so the runs agree to the level of the integration
# error, not bit for bit: allowed 4 e per signal with e estimated from FMPy at
# RelTol and RelTol/10 (module docstring).

SHORT_STOP, STEP = 0.05, 1e-3
HEADLINE = ["pulley[1].omega", "pulley[2].omega", "pulley[1].driveTorque",
            "span[1].tension", "span[2].tension", "pulley[2].hubForce.x",
            "pulley[2].hubForce.y", "probe.sdeForce"]


@pytest.fixture(scope="session")
def fmpy_short():
    """FMPy's run of the default drive at the default tolerance and the bound
    4 e per signal."""
    ref = simulate_fmu(str(FMU), stop_time=SHORT_STOP, output_interval=STEP, output=HEADLINE)
    tight = simulate_fmu(str(FMU), stop_time=SHORT_STOP, output_interval=STEP,
                         relative_tolerance=1e-5, output=HEADLINE)
    bound = {n: 4 * np.max(np.abs(ref[n] - tight[n])) for n in HEADLINE}
    return ref, bound


def compare_rows(ref, rows, bound, who):
    """rows[k] = outputs after communication step k + 1, against FMPy."""
    rows = np.asarray(rows)
    assert rows.shape == (len(ref) - 1, len(HEADLINE)), rows.shape
    assert np.all(np.isfinite(rows))
    for i, n in enumerate(HEADLINE):
        dev = np.max(np.abs(rows[:, i] - ref[n][1:]))
        print(f"  {who}: {n:22s} max difference to FMPy {dev:.3g} (allowed {bound[n]:.3g})")
        assert dev <= bound[n], f"{who}: {n} differs from FMPy by {dev:.3g} > {bound[n]:.3g}"


def test_libcosim_runs_the_default_drive_like_fmpy(md, fmpy_short):
    """Open Simulation Platform's libcosim (C++ co-simulation library behind
    the OSP tools) through libcosimpy: FMU loaded, stepped with its fixed-step
    algorithm, outputs read by a last-value observer after every step."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimSlave import CosimLocalSlave
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level

    log_output_level(CosimLogLevel.WARNING)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    ex = CosimExecution.from_step_size(step_size=round(STEP * 1e9))  # nanoseconds
    idx = ex.add_local_slave(CosimLocalSlave(fmu_path=str(FMU), instance_name="belt"))
    assert idx >= 0
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    ref, bound = fmpy_short
    rows = []
    for _ in range(len(ref) - 1):
        assert ex.step(1)
        rows.append(obs.last_real_values(idx, [vr[n] for n in HEADLINE]))
    compare_rows(ref, rows, bound, "libcosim")


def test_ecos_runs_the_default_drive_like_fmpy(fmpy_short):
    """Ecos (ecospy), a C++ co-simulation engine: the FMU as the one model of
    a simulation structure, fixed 1 ms steps, outputs read by name."""
    from ecospy.EcosSimulation import EcosSimulation
    from ecospy.EcosSimulationStructure import EcosSimulationStructure

    ref, bound = fmpy_short
    structure = EcosSimulationStructure()
    structure.add_model("belt", str(FMU))
    sim = EcosSimulation(structure=structure, step_size=STEP)
    try:
        assert sim.init()
        rows = []
        for _ in range(len(ref) - 1):
            sim.step(1)
            rows.append([sim.get_real(f"belt::{n}") for n in HEADLINE])
        assert np.isclose(sim.get_time(), SHORT_STOP)
        sim.terminate()
    finally:
        sim.free()
    compare_rows(ref, rows, bound, "Ecos")


def test_fmu_manipulation_toolbox_checker_passes(fmu_path):
    """fmu-manipulation-toolbox's checker (`fmutool -check`): the model
    description against the FMI 2.0 schema and its semantic rules. It reads the
    archive only (no simulation), so it complements the masters above."""
    exe = pathlib.Path(os.environ.get("VIRTUAL_ENV", ROOT / ".venv")) / "bin" / "fmutool"
    if not exe.exists():
        exe = pathlib.Path(__import__("sys").executable).parent / "fmutool"
    proc = subprocess.run([str(exe), "-input", fmu_path, "-check"], capture_output=True,
                          text=True, timeout=300)
    log = proc.stdout + proc.stderr
    assert proc.returncode == 0, log
    assert "compliant with FMI-2.0" in log, log
    assert "No semantic error" in log, log
    bad = [line for line in log.splitlines() if line.startswith(("WARNING", "ERROR"))]
    assert bad == [], log


def test_crosscheck_compare_command(crosscheck, tmp_path):
    """`cargo xtask crosscheck -- --compare` (tests/python/crosscheck.py):
    passes on an import of the files, fails on a result that is off by far
    more than the integration error."""
    script = ROOT / "tests/python/crosscheck.py"
    run = lambda *a: subprocess.run([__import__("sys").executable, str(script), "--compare",  # noqa: E731
                                     "--dir", str(DIST), *a], capture_output=True, text=True,
                                    timeout=600)
    ok = run()
    assert ok.returncode == 0, ok.stdout + ok.stderr
    ref = read_csv(crosscheck["ref.csv"])
    # 100 N off (12 % of the tight-span force): 30 times the allowed 4 e,
    # which is 3.3 N for span 1 over this run (e at RelTol 1e-4 is ~0.8 N).
    ref["span[1].tension"] += 100.0
    names = ref.dtype.names
    bad = tmp_path / "bad.csv"
    bad.write_text(",".join(f'"{n}"' for n in names) + "\n"
                   + "\n".join(",".join(repr(float(x)) for x in row) for row in ref) + "\n")
    off = run("--result", str(bad))
    assert off.returncode != 0 and "span[1].tension" in off.stdout, off.stdout + off.stderr
