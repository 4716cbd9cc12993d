"""docs/fead-design.md in short: the tutorial's parameter set and the
commands of its steps, each on a short horizon.

- every `pulley[j].*`, `belt.*` name the page gives is a variable of the FMU;
- the pictures the page shows are committed;
- step 3 (idle with firing pulsation): examples/engine_alternator.py with
  parameters/fead-7.ssv, the engine brought to idle in 40 ms, 0.1 s in all:
  it runs, writes its plot, the alternator turns at the crank speed times
  the radius ratio less creep (3 %, as tests/python/test_example_coupling.py)
  and the belt stays in tension;
- step 5 (run-up): examples/run_up.py from idle to 1,600 rpm in 0.2 s: the
  crank reaches the speed asked for, the alternator follows it at the radius
  ratio less creep, the loads keep their idle torques, the belt stays in
  tension;
- step 6 (belt length x spring rate): the study file of the page on a 2 x 2
  corner of its grid, 50 ms each: a longer belt installs at a lower tension
  with the arm swung out, and the stiffer spring, specified by its torque at
  the nominal angle, gives the higher tension on the short belt and the lower
  on the long one (its torque changes by k times the arm's swing).
"""
import importlib.util
import math
import re
import sys
import tomllib

import pytest

from conftest import FMU, ROOT

PAGE = ROOT / "docs/fead-design.md"
SSV = ROOT / "parameters/fead-7.ssv"


def test_page_names_fmu_variables(md):
    names = {v.name for v in md.modelVariables}
    text = PAGE.read_text()
    given = set(re.findall(r"`((?:pulley\[j\]|belt)\.[A-Za-z.]+)`", text))
    assert given, "the page names parameters"
    for name in given:
        assert name.replace("[j]", "[1]") in names, name


def test_page_pictures_exist():
    for target in re.findall(r"!\[[^]]*\]\(([^)]+)\)", PAGE.read_text()):
        assert (PAGE.parent / target).is_file(), target


@pytest.fixture(scope="module")
def idle(tmp_path_factory):
    spec = importlib.util.spec_from_file_location(
        "engine_alternator", ROOT / "examples/engine_alternator.py")
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    out = tmp_path_factory.mktemp("fead-design")
    res = ex.simulate(stop_time=0.1, step=1e-3, parameters=SSV, crank=1, alternator=3,
                      ramp_time=0.04, fmu=FMU, out_dir=out)
    return res, out


def test_idle_with_firing_pulsation_runs(idle):
    res, out = idle
    png = (out / "engine_alternator.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    window = res["time"] >= res["time"][-1] - 0.03
    ratio = res["alternator.omega"][window].mean() / res["crank.omega"][window].mean()
    assert ratio == pytest.approx(res["radius.crank"] / res["radius.alternator"], rel=0.03)
    assert res["belt.minTension"].min() > 0


def _example(name):
    spec = importlib.util.spec_from_file_location(name, ROOT / f"examples/{name}.py")
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    return ex


def test_run_up_short(tmp_path):
    ex = _example("run_up")
    res = ex.simulate(SSV, top_rpm=1600.0, ramp=0.2, settle=0.55, fmu=FMU, out_dir=tmp_path)
    assert (tmp_path / "run_up.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rpm = abs(res["crank.omega"][-1]) * 60.0 / (2.0 * math.pi)
    assert rpm == pytest.approx(1600.0, rel=1e-6)
    # the loads at their idle torques: loadDamping times the pulley's idle speed, opposing it
    start = ex.start_values(SSV)
    w_crank = float(start["pulley[1].omegaRamp"])
    for j, torque in res["load_torques"].items():
        w = w_crank * res["radius"][0] / res["radius"][j - 1]
        assert torque == pytest.approx(-float(start[f"pulley[{j}].loadDamping"]) * w, rel=1e-12)
        assert torque * w < 0
    # during the ramp the alternator's pulley turns at the radius ratio less creep (3 %)
    ramping = (res["time"] > 0.6) & (res["time"] < 0.74)
    ratio = res["pulley3.omega"][ramping] / res["crank.omega"][ramping]
    assert ratio.mean() == pytest.approx(res["radius"][0] / res["radius"][2], rel=0.03)
    assert res["belt.intervalMinTension"][res["time"] > 0.1].min() > 0


def test_length_spring_study_short(tmp_path):
    sys.path.insert(0, str(ROOT / "python"))
    import pandas as pd
    from beltdrive.sweep import run_study

    doc = (ROOT / "studies/fead-7-length-spring.toml").read_text()
    spec = tomllib.loads(doc)
    lengths = spec["parameter"][0]["values"]
    short, long_ = lengths[0], lengths[-1]
    doc = doc.replace('fmu = "../dist/BeltDrive.fmu"', f'fmu = "{FMU}"')
    doc = doc.replace('base = "../parameters/fead-7.ssv"', f'base = "{SSV}"')
    doc = doc.replace("stop_time = 0.8", "stop_time = 0.05")
    doc = re.sub(r"values = \[1\.68[^]]*\]", f"values = [{short}, {long_}]", doc)
    doc = doc.replace("values = [30.0, 40.0, 50.0]", "values = [30.0, 50.0]")
    doc = doc.replace("window = [0.6, 0.8]", "window = [0.02, 0.05]")
    path = tmp_path / "study.toml"
    path.write_text(doc.replace('out = "../target/studies/fead-7-length-spring"', f'out = "{tmp_path / "out"}"'))
    summary = run_study(path, workers=2, progress=False)
    t = pd.read_parquet(summary["results"])
    assert (t["status"] == "ok").all(), t["message"].tolist()
    tension = {(r["belt.naturalLength"], r["pulley[7].arm.stiffness"]): r["mean(belt.installedTension)"]
               for _, r in t.iterrows()}
    angle = {(r["belt.naturalLength"], r["pulley[7].arm.stiffness"]): r["mean(pulley[7].arm.installedAngle)"]
             for _, r in t.iterrows()}
    for k in (30.0, 50.0):
        assert tension[(short, k)] > tension[(long_, k)]
        assert angle[(short, k)] < 0 < angle[(long_, k)]
    assert tension[(short, 50.0)] > tension[(short, 30.0)]
    assert tension[(long_, 50.0)] < tension[(long_, 30.0)]
