"""The SSP parameter sets in parameters/*.ssv through FMPy: schema-valid
(SSP 1.0), every entry a parameter of the FMU with its type and unit, the
units' SI exponents those of the model description, and each set applied
with examples/simulate_ssv.py (the README's recipe) simulates a few
milliseconds. (tests/parameter_sets.rs checks the values of the paper's two
drives against src/model/params.rs.)"""
import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from fmpy.ssp.ssd import read_ssv

from conftest import FMU, ROOT, ssv_example

SETS = sorted((ROOT / "parameters").glob("*.ssv"))
NS = {"ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues",
      "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon"}
BASE = ["kg", "m", "s", "A", "K", "mol", "cd", "rad"]


def unit_of(v):
    return v.unit or (v.declaredType.unit if v.declaredType is not None else None)


def test_the_six_sets_are_there():
    assert [p.name for p in SETS] == [
        "accessory-drive-4.ssv", "accessory-drive-decoupler.ssv", "accessory-drive-tensioner.ssv",
        "fead-7.ssv", "kubas2014-section3.ssv", "kubas2014-section4.ssv"]


def test_fead7_runs_with_both_integrators_and_they_agree():
    """Through FMPy, the set as it ships (tests/fead.rs
    eight_pulley_drive_runs_alike_with_both_integrators checks it in Rust with
    an eighth pulley, at the bounds of tests/defaults.rs): the seven-pulley
    drive to idle in 0.2 s, means over the last 50 ms of 0.3 s. Both at relTol
    1e-4: the stiff method's speeds and span tensions within 0.7 % of a tight
    RKF45 run on the accessory drives (studies/accessory-preload-load.toml);
    means: 1 %; the arm's mean angle within 1e-3 rad."""
    from fmpy import simulate_fmu
    ex = ssv_example()
    start = ex.start_values(ROOT / "parameters/fead-7.ssv")
    assert start["nPulleys"] == 7
    outputs = ["pulley[3].rotor.omega", "pulley[7].arm.angle"] + \
              [f"span[{k}].tension" for k in range(1, 8)]
    means = {}
    for method in (1, 2):
        values = dict(start, **{"solver.method": method, "pulley[1].rampTime": 0.2})
        res = simulate_fmu(str(FMU), stop_time=0.3, output_interval=1e-3, start_values=values,
                           output=outputs)
        last = res["time"] > 0.25 + 1e-9
        means[method] = {name: res[name][last].mean() for name in outputs}
    print(means)
    for name in outputs:
        if name == "pulley[7].arm.angle":
            assert abs(means[2][name] - means[1][name]) < 1e-3
        else:
            assert means[2][name] == pytest.approx(means[1][name], rel=0.01), name
    # the crank turns clockwise: span 1 (AC -> crank) tight, span 7 slack
    assert means[1]["span[1].tension"] > means[1]["span[7].tension"]


@pytest.mark.parametrize("path", SETS, ids=lambda p: p.stem)
def test_names_types_units(path, md):
    variables = {v.name: v for v in md.modelVariables}
    parameter_set = read_ssv(str(path))  # validates against the SSP 1.0 schema
    assert parameter_set.name == path.stem
    names = [p.name for p in parameter_set.parameters]
    assert len(names) == len(set(names)), "duplicates"
    root = ET.parse(path).getroot()
    for p in parameter_set.parameters:
        v = variables.get(p.name)
        assert v is not None and v.causality == "parameter", p.name
        assert p.type == v.type, (p.name, p.type, v.type)
        if p.type == "Real":
            assert p.unit == unit_of(v), (p.name, p.unit, unit_of(v))
            assert math.isfinite(float(p.value))
    # Every unit used is defined in the file with the model description's exponents.
    fmu_units = {u.name: u for u in md.unitDefinitions}
    file_units = {u.get("name"): u.find("ssc:BaseUnit", NS) for u in root.iterfind("ssv:Units/ssc:Unit", NS)}
    # (a Real without a unit, like solver.absTol, uses no unit definition)
    used = {p.unit for p in parameter_set.parameters if p.type == "Real" and p.unit is not None}
    assert used == set(file_units)
    for name, base in file_units.items():
        expected = fmu_units[name].baseUnit
        for e in BASE:
            assert int(base.get(e, 0)) == int(getattr(expected, e) or 0), (name, e)


def test_section4_file_holds_the_fmu_defaults(md):
    """The paper's section-4 set is the FMU's default drive, but for the
    contact damping ramp: the set spells out the paper's 1 mm, the FMU's
    default is the automatic ramp (0); and for the SDE's damper: the paper's
    acts along the gap only (belt.shearDampingFactor 0), the FMU's default
    across it too (1); and for the contact points: the paper's centre contact
    (contact.points 1), the FMU's default 4 points along each body; and for
    the span damping: none in the paper's model (belt.transverseDamping 0),
    25 1/s by default."""
    variables = {v.name: v for v in md.modelVariables}
    parameter_set = read_ssv(str(ROOT / "parameters/kubas2014-section4.ssv"))
    for p in parameter_set.parameters:
        start = variables[p.name].start
        if p.name == "contact.pMax":
            assert float(p.value) == 1e-3 and float(start) == 0.0
        elif p.name == "belt.shearDampingFactor":
            assert float(p.value) == 0.0 and float(start) == 1.0
        elif p.name == "contact.points":
            assert int(p.value) == 1 and int(start) == 4
        elif p.name == "belt.transverseDamping":
            assert float(p.value) == 0.0 and float(start) == 25.0
        elif p.type == "Real":
            assert float(p.value) == float(start), p.name
        else:
            assert p.value.lower() == str(start).lower(), p.name


@pytest.mark.parametrize("path", SETS, ids=lambda p: p.stem)
def test_applied_through_fmpy(path):
    ex = ssv_example()
    start = ex.start_values(path)
    n = start["nPulleys"]
    outputs = [f"pulley[{j}].omega" for j in range(1, n + 1)] + \
              [f"span[{k}].tension" for k in range(1, n + 1)] + ["belt.minTension"]
    stop = 0.005
    res = ex.simulate(path, stop_time=stop, output_interval=1e-3, output=outputs, fmu=FMU)
    assert res["time"][-1] == pytest.approx(stop)
    for name in outputs:
        assert np.all(np.isfinite(res[name])), name
    # Speed-driven pulleys follow their ramp; the belt stays in tension.
    for j in range(1, n + 1):
        if start.get(f"pulley[{j}].speedDriven"):
            ramp = start[f"pulley[{j}].omegaRamp"] * min(stop / start[f"pulley[{j}].rampTime"], 1)
            assert res[f"pulley[{j}].omega"][-1] == pytest.approx(ramp, rel=1e-12)
    assert np.all(res["belt.minTension"] > 0)
    # At a few ms the spans are still near the preload.
    preload = start["belt.preload"]
    for k in range(1, n + 1):
        assert np.all(np.abs(res[f"span[{k}].tension"] - preload) < 0.2 * preload), k


SSD = """<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription"
    version="1.0" name="AccessoryDrive">
  <ssd:System name="engineBay">
    <ssd:Elements>
      <ssd:Component name="beltDrive" type="application/x-fmu-sharedlibrary"
          source="resources/BeltDrive.fmu">
        <ssd:ParameterBindings>
          <ssd:ParameterBinding source="resources/{ssv}"/>
        </ssd:ParameterBindings>
      </ssd:Component>
    </ssd:Elements>
  </ssd:System>
</ssd:SystemStructureDescription>
"""


@pytest.mark.parametrize("path", SETS, ids=lambda p: p.stem)
def test_bound_in_an_ssp(path, tmp_path):
    """The README's SSP recipe: the FMU and an .ssv as resources of an .ssp,
    bound to the component without a prefix (the .ssv names are the FMU's
    variable names). FMPy's SSP reader validates the .ssd against the SSP 1.0
    schema and resolves the binding."""
    import zipfile
    from fmpy.ssp.ssd import read_ssd

    ssp = tmp_path / "BeltDrive.ssp"
    with zipfile.ZipFile(ssp, "w") as z:
        z.writestr("SystemStructure.ssd", SSD.format(ssv=path.name))
        z.write(FMU, "resources/BeltDrive.fmu")
        z.write(path, f"resources/{path.name}")
    component = read_ssd(str(ssp)).system.elements[0]
    (binding,) = component.parameterBindings
    assert binding.prefix in (None, "")
    (values,) = binding.parameterValues
    assert [p.name for p in values.parameters] == [p.name for p in read_ssv(str(path)).parameters]
