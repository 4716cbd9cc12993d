"""The main job's computation (tests/python/run_default.py, `cargo xtask run`)
on the FMU's default drive, and what the user meets through FMPy:

* the FMU manual's validation table (docs/fmu-manual.md, the FMU's
  documentation/index.html) shows the main job's figures for the default
  drive, digit for digit;
* a long communication step (0.5 s, 2 s) with RKF45 completes and agrees with
  1 ms steps;
* a discarded step and a refused call are logged at FMPy's default logging
  settings, and FMPy's `--validate` refuses a misspelt start value, as the
  README says.
"""
import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "python"))
import run_default  # noqa: E402

STOP = 2.0


@pytest.fixture(scope="module")
def start(fmu_path):
    return {v.name: v.start for v in read_model_description(fmu_path).modelVariables}


@pytest.fixture(scope="module")
def rkf45_1ms():
    """The main job's RKF45 run: 2 s, 1 ms communication steps (its outputs
    include every one the tests here compare)."""
    res, _ = run_default.simulate(1, STOP, 1e-3)
    return res


# The manual's row labels and the report's keys they show.
MANUAL_ROWS = {
    "drive pulley speed, clockwise": "w1",
    "driven pulley speed, clockwise": "w2",
    "slip": "slip",
    "creep theory (T_t − T_s)/(EA + T_t)": "creep",
    "tight span tension": "tight",
    "slack span tension": "slack",
    "torque r (T_t − T_s)": "torque",
    "hub load on the drive pulley": "hub1",
}


def manual_table():
    """{label: cell of the FMU's default drive} of the manual's validation
    table (its third column)."""
    text = (ROOT / "docs" / "fmu-manual.md").read_text()
    section = text.split("## Validation", 1)[1]
    rows = {}
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("|") and len(cells) >= 3 and cells[0] in MANUAL_ROWS:
            rows[cells[0]] = cells[2]
    return rows


def test_manual_validation_table_is_the_main_jobs(rkf45_1ms, start):
    """The manual's column for the FMU's default drive is what the main job
    prints for RKF45 (same run, same window 1-2 s, same rounding)."""
    ours = run_default.formatted(run_default.figures(rkf45_1ms, start, STOP))
    manual = manual_table()
    assert set(manual) == set(MANUAL_ROWS), f"rows found in the manual: {sorted(manual)}"
    wrong = {label: (manual[label], ours[key]) for label, key in MANUAL_ROWS.items()
             if manual[label] != ours[key]}
    assert not wrong, f"manual against the main job (manual, main job): {wrong}"


@pytest.mark.parametrize("interval", [0.5, 2.0])
def test_long_communication_step_completes_and_agrees(rkf45_1ms, interval):
    """A communication step of 0.5 s or 2 s with RKF45 (the default) completes
    (the step-count guard scales with the interval) and gives at the common
    communication points what 1 ms steps give. The runs integrate the same
    equations from the same state at relTol 1e-4 and differ only where a step
    is clipped to land on a communication point, so they agree to the
    integration error, not bit for bit: pulley angles and speeds and span
    tensions within relTol of their value (measured: at most 6e-7; a run
    that ended 1 ms early would be 3e-3 off in the angles)."""
    outputs = ["pulley[1].angle", "pulley[2].angle", "pulley[1].omega", "pulley[2].omega",
               "span[1].tension", "span[2].tension"]
    res = simulate_fmu(str(run_default.FMU), stop_time=STOP, output_interval=interval, output=outputs)
    assert res["time"][-1] == pytest.approx(STOP), "the run stopped early"
    assert len(res) == round(STOP / interval) + 1
    t_fine = rkf45_1ms["time"]
    for row in res[1:]:
        i = int(np.argmin(np.abs(t_fine - row["time"])))
        assert abs(t_fine[i] - row["time"]) < 1e-9
        for name in outputs:
            ref = rkf45_1ms[name][i]
            assert abs(row[name] - ref) <= 1e-4 * abs(ref), (interval, row["time"], name, row[name], ref)


def test_discard_is_logged_at_default_logging(fmu_path, capfd):
    """A step the FMU discards (its step-count guard at 1 step per ms) ends
    FMPy's run early with the reason printed, debug logging off."""
    res = simulate_fmu(fmu_path, stop_time=0.01, output_interval=1e-3,
                       start_values={"solver.maxSteps": 1}, output=["pulley[2].omega"])
    assert res["time"][-1] < 0.01
    out = capfd.readouterr().out
    assert "[DISCARD]" in out and "solver.maxSteps" in out, out


def test_refusal_is_logged_at_default_logging(fmu_path, capfd):
    """A parameter set the FMU refuses is an exception in FMPy with the
    reason printed, debug logging off."""
    with pytest.raises(Exception):
        simulate_fmu(fmu_path, stop_time=0.01, start_values={"belt.nBodies": 5})
    out = capfd.readouterr().out
    assert "[ERROR]" in out and "belt.nBodies" in out, out


def test_fmpy_validate_refuses_a_misspelt_start_value(fmu_path):
    """The README's FMPy command line: with `--validate` a misspelt start
    value fails (without it FMPy ignores it and simulates the default)."""
    fmpy = pathlib.Path(sys.executable).with_name("fmpy")
    cmd = [str(fmpy), "simulate", fmu_path, "--validate", "--stop-time", "0.001",
           "--start-values", "belt.preLoad", "600"]
    run = subprocess.run(cmd, capture_output=True, text=True)
    assert run.returncode != 0, run.stdout + run.stderr
    assert "belt.preLoad" in run.stdout + run.stderr
    ok = subprocess.run(cmd[:-2] + ["belt.preload", "600"], capture_output=True, text=True)
    assert ok.returncode == 0, ok.stdout + ok.stderr


def test_manual_cites_no_repository_path():
    """The FMU's manual stands alone: what it cites is in it or linked by
    URL. No path into the repository (docs/, parameters/, src/, ...) and no
    .ssv file as a reference; its own pictures (packaged beside it in
    documentation/) aside."""
    text = (ROOT / "docs" / "fmu-manual.md").read_text()
    text = re.sub(r"<!--.*?-->", "", text, flags=re.S)  # the source's own note
    text = re.sub(r"!\[[^\]]*\]\(validation/[\w.-]+\.png\)", "", text)  # packaged pictures
    text = re.sub(r"\]\(https?://[^)]*\)", "]", text)  # URLs
    paths = re.findall(r"\b(?:docs|src|tests|parameters|examples|xtask|validation|python|studies|"
                       r"benches|modelDescription)/[\w./-]*|\b[\w-]+\.(?:ssv|md|rs|py)\b|README", text)
    assert paths == [], paths
