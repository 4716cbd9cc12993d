"""ModelStructure/Outputs declares, for every output, the inputs it depends on
directly (`dependencies`): a master coupling the FMU needs it to avoid
artificial algebraic loops, so a missing dependency would make it read a stale
output. Checked against the FMU itself: after some steps, each input is
changed on its own without a doStep, and every output that changes must list
that input. Run on drives that exercise different dependencies: the default
5PK drive (both pulleys torque-driven), the same with pulley 1 speed-driven,
and the 4-pulley accessory drive (crank speed-driven, a back-side idler), with
probe bodies in contact with a pulley so that the contact outputs are live.
"""
import numpy as np
import pytest
from fmpy.fmi2 import FMU2Slave
from fmpy.ssp.ssd import read_ssv

from conftest import ROOT


def parse(value, ty):
    if ty == "Integer":
        return int(value)
    if ty == "Boolean":
        return value in (True, "true", "1", 1)
    return float(value)


def accessory_drive():
    ps = read_ssv(str(ROOT / "parameters/accessory-drive-4.ssv"))
    return {p.name: parse(p.value, p.type) for p in ps.parameters}


DRIVES = {
    "default, probe on pulley 1": {"probe.body": 1},
    "pulley 1 speed-driven": {"pulley[1].speedDriven": True, "pulley[1].torqueRamp": 0.0,
                              "pulley[1].omegaRamp": -20.0, "pulley[1].rampTime": 0.01,
                              "probe.body": 1},
    "accessory drive": accessory_drive,
    "accessory drive, pulley 2 speed-driven": lambda: {
        **accessory_drive(), "pulley[2].speedDriven": True, "pulley[2].omegaRamp": 30.0},
}


def observed_dependencies(md, unzipdir, start):
    by_name = {v.name: v for v in md.modelVariables}
    outputs = [v for v in md.modelVariables if v.causality == "output"]
    inputs = [v for v in md.modelVariables if v.causality == "input"]
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir,
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="deps")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    for name, value in start.items():
        v = by_name[name]
        {"Real": fmu.setReal, "Integer": fmu.setInteger, "Boolean": fmu.setBoolean}[v.type](
            [v.valueReference], [value])
    fmu.exitInitializationMode()
    for n in range(20):
        fmu.doStep(n * 1e-3, 1e-3)
    state = fmu.getFMUstate()
    vrs = [v.valueReference for v in outputs]
    base = np.array(fmu.getReal(vrs))
    seen = {}
    for inp in inputs:
        fmu.setFMUstate(state)
        old = fmu.getReal([inp.valueReference])[0]
        fmu.setReal([inp.valueReference], [old + 3.0])
        changed = np.array(fmu.getReal(vrs)) != base
        for v in np.array(outputs)[changed]:
            seen.setdefault(v.name, set()).add(inp.name)
    fmu.freeFMUstate(state)
    fmu.terminate()
    fmu.freeInstance()
    return seen


def declared_dependencies(md):
    outputs = {v.name: v for v in md.modelVariables if v.causality == "output"}
    assert len(md.outputs) == len(outputs)
    declared = {}
    for unknown in md.outputs:
        # FMPy reads `dependencies` into a list of variables; None means the
        # attribute is missing ("depends on all inputs"), which we never want.
        assert unknown.dependencies is not None, f"{unknown.variable.name}: no dependencies"
        declared[unknown.variable.name] = {d.name for d in unknown.dependencies}
    return declared


def test_every_output_declares_its_direct_dependencies(md):
    declared = declared_dependencies(md)
    by_name = {v.name: v for v in md.modelVariables}
    for name, deps in declared.items():
        for d in deps:
            assert by_name[d].causality == "input", f"{name} depends on non-input {d}"
    # State outputs depend on no input directly.
    for name in ["span[1].tension", "pulley[1].angle", "probe.sdeForce", "energy.input",
                 "belt.maxTension", "solver.steps"]:
        assert declared[name] == set(), name
    # The counters are discrete.
    for name in ["solver.steps", "solver.rejectedSteps", "solver.rhsEvaluations"]:
        assert by_name[name].variability == "discrete", name


@pytest.mark.parametrize("drive", list(DRIVES))
def test_declared_dependencies_cover_the_observed_ones(md, unzipdir, drive):
    start = DRIVES[drive]
    start = start() if callable(start) else start
    seen = observed_dependencies(md, unzipdir, start)
    declared = declared_dependencies(md)
    # The check can fail: on every drive some output reacts to some input.
    assert seen, "no output reacted to any input: the probe is broken"
    missing = {o: sorted(i - declared[o]) for o, i in seen.items() if i - declared[o]}
    assert missing == {}, f"outputs changing with undeclared inputs: {missing}"
