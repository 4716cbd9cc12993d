"""docs/fead-design.md in short: the tutorial's parameter set and the
commands of its steps, each on a short horizon.

- every `pulley[j].*`, `belt.*` name the page gives is a variable of the FMU;
- the pictures the page shows are committed;
- step 3 (idle with firing pulsation): examples/engine_alternator.py with
  parameters/fead-7.ssv, the engine brought to idle in 40 ms, 0.1 s in all:
  it runs, writes its plot, the alternator turns at the crank speed times
  the radius ratio less creep (3 %, as tests/python/test_example_coupling.py)
  and the belt stays in tension.
"""
import importlib.util
import re

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
