"""BeltDrive.fmu through its real C ABI with FMPy."""
import ctypes

import numpy as np
import pytest
from fmpy import dump, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2LastSuccessfulTime,
    fmi2Terminated,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
)
from fmpy.validation import validate_fmu

SHORT = {"belt.nBodies": 100, "probe.body": 1}  # enough to resolve the 27 mm pulleys


class Harness:
    """An FMU2Slave with a capturing logger."""

    def __init__(self, md, unzipdir, name="belt", guid=None):
        self.md = md
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.var = {v.name: v for v in md.modelVariables}
        self.log = []
        self.fmu = FMU2Slave(guid=guid or md.guid, unzipDirectory=unzipdir,
                             modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        libc = ctypes.CDLL(None)
        libc.calloc.restype = ctypes.c_void_p
        libc.calloc.argtypes = [ctypes.c_size_t, ctypes.c_size_t]
        libc.free.argtypes = [ctypes.c_void_p]

        def logger(env, instance, status, category, message):
            self.log.append((status, category.decode() if category else "", message.decode()))

        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(logger)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(lambda n, s: libc.calloc(n, s))
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(lambda p: libc.free(p))
        self._cb = cb  # keep the ctypes callbacks alive
        self.fmu.instantiate(callbacks=cb, loggingOn=True)

    def set(self, **values):
        for name, value in values.items():
            name = name.replace("__", ".")
            self.set_named(name, value)

    def set_named(self, name, value):
        v = self.var[name]
        if v.type == "Real":
            self.fmu.setReal([v.valueReference], [float(value)])
        elif v.type == "Integer":
            self.fmu.setInteger([v.valueReference], [int(value)])
        else:
            self.fmu.setBoolean([v.valueReference], [bool(value)])

    def get(self, *names):
        return [self.fmu.getReal([self.vr[n]])[0] for n in names]

    def init(self, params=None, start=0.0):
        for name, value in (params or {}).items():
            self.set_named(name, value)
        self.fmu.setupExperiment(startTime=start)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()

    def logged(self, text):
        return any(text in m for _, _, m in self.log)


@pytest.fixture
def h(md, unzipdir):
    harness = Harness(md, unzipdir)
    yield harness
    try:
        harness.fmu.freeInstance()
    except Exception:
        pass


def test_validate(fmu_path):
    assert validate_fmu(fmu_path) == []


def test_every_variable_documented(md):
    """Spec: every variable has a description; every Real a unit (its own or
    its declared type's; dimensionless quantities use unit "1"), except a
    quantity whose description says it has "no single unit" and why (the
    absolute tolerance, compared with every state in that state's unit)."""
    undocumented = [v.name for v in md.modelVariables if not v.description]
    assert undocumented == []

    def unit(v):
        return v.unit or (v.declaredType.unit if v.declaredType is not None else None)

    unitless = sorted({
        v.declaredType.name if v.declaredType is not None else v.name
        for v in md.modelVariables
        if v.type == "Real" and not unit(v) and "no single unit" not in v.description
    })
    assert unitless == [], f"Real variables/types without a unit: {unitless}"
    defined = {u.name for u in md.unitDefinitions}
    for v in md.modelVariables:
        if v.type == "Real" and unit(v):
            assert unit(v) in defined, (v.name, unit(v))


def test_dump_and_model_description(fmu_path, md, capsys):
    dump(fmu_path)
    text = capsys.readouterr().out
    assert "BeltDrive" in text and "pulley[1].omega" in text
    cs = md.coSimulation
    assert cs.modelIdentifier == "BeltDrive"
    assert cs.canHandleVariableCommunicationStepSize and cs.canInterpolateInputs
    assert cs.maxOutputDerivativeOrder == 1
    assert cs.canGetAndSetFMUstate and cs.canSerializeFMUstate
    assert not cs.canBeInstantiatedOnlyOncePerProcess
    de = md.defaultExperiment
    assert (float(de.startTime), float(de.stopTime), float(de.stepSize), float(de.tolerance)) == (
        0.0, 2.0, 1e-3, 1e-4)
    outputs = {v.name for v in md.modelVariables if v.causality == "output"}
    assert {v.variable.name for v in md.outputs} == outputs
    for name in ["pulley[1].omega", "pulley[2].slip", "span[1].tension", "span[2].tension",
                 "belt.minTension", "belt.maxTension", "probe.sdeForce", "solver.steps"]:
        assert name in outputs, name


def test_stiff_method_same_answers_fewer_steps(fmu_path):
    # The default drive over 0.1 s of its torque ramp with both integrators:
    # same pulley speeds and span tensions, a fraction of the steps.
    outs = ["pulley[1].omega", "pulley[2].omega", "span[1].tension", "span[2].tension",
            "solver.steps"]
    res = {m: simulate_fmu(fmu_path, stop_time=0.1, output_interval=1e-2, output=outs,
                           start_values={"solver.method": m})
           for m in (1, 2)}
    for name in outs[:2]:
        np.testing.assert_allclose(res[2][name], res[1][name], rtol=5e-3, atol=2e-3)
    for name in outs[2:4]:  # pitching vibration of a few N is damped by the stiff method
        np.testing.assert_allclose(res[2][name], res[1][name], rtol=0, atol=5.0)
    assert res[2]["solver.steps"][-1] * 10 < res[1]["solver.steps"][-1]


def test_simulate_default_drive_short(fmu_path, md):
    # no parameters set: the paper's section-4 drive, all outputs recorded
    res = simulate_fmu(fmu_path, stop_time=0.02, output_interval=1e-3)
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    assert set(outputs) <= set(res.dtype.names)
    bad = [n for n in outputs if not np.all(np.isfinite(res[n]))]
    assert bad == []
    # The drive torque ramps to -15 N m: pulley 1 turns clockwise.
    assert res["pulley[1].omega"][-1] < 0
    assert res["pulley[2].omega"][-1] < 0
    assert 400 < res["span[1].tension"][0] < 700
    assert res["span[1].tension"][-1] > res["span[2].tension"][-1]  # span 1 tight
    # Slip across consecutive pulleys, from surface speeds v_j = r_j omega_j:
    # span 1 runs from pulley 1 to 2, span 2 closes the loop from 2 to 1.
    r = 0.027
    v1, v2 = r * res["pulley[1].omega"][-1], r * res["pulley[2].omega"][-1]
    assert res["span[1].slip"][-1] == pytest.approx(1 - v2 / v1, rel=1e-9, abs=1e-12)
    assert res["span[2].slip"][-1] == pytest.approx(1 - v1 / v2, rel=1e-9, abs=1e-12)
    assert res["span[1].slip"][-1] == pytest.approx(res["pulley[2].slip"][-1], rel=1e-9, abs=1e-12)
    assert np.all(res["span[3].slip"] == 0.0)  # no third pulley


def run_coupled(h, steps, external_load):
    """Python computes the load torque from the returned speed each step."""
    d = 15.0 / (8 * np.pi)
    params = dict(SHORT)
    if external_load:
        params["pulley[2].loadDamping"] = 0.0
    h.init(params)
    t = 0.0
    out = []
    for dt in steps:
        if external_load:
            (w2,) = h.get("pulley[2].omega")
            h.set_named("pulley[2].torque", -d * w2)
        h.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=dt)
        t += dt
        out.append(h.get("pulley[1].omega", "pulley[2].omega"))
    return np.array(out)


def test_coupled_load_with_variable_steps(md, unzipdir):
    """Python closes the load loop (torque = -d*omega from the returned speed,
    held over each step) with variable steps; the FMU's built-in loadDamping
    is the reference. The zero-order hold makes the coupled result first-order
    in the communication step: halving every step must roughly halve the
    deviation, while the built-in run does not depend on the step at all."""
    steps = [1e-4, 3e-4, 2e-4, 5e-4, 1e-4] * 8  # 0.0096 s, variable
    half = [dt / 2 for dt in steps for _ in (0, 1)]

    def pair(seq, tag):
        inside = run_coupled(Harness(md, unzipdir, "inside" + tag), seq, external_load=False)
        outside = run_coupled(Harness(md, unzipdir, "outside" + tag), seq, external_load=True)
        return inside, outside

    inside, outside = pair(steps, "")
    inside_h, outside_h = pair(half, "/2")
    inside_h, outside_h = inside_h[1::2], outside_h[1::2]  # the coarse points
    assert abs(inside[-1, 0]) > 0.1  # the drive is turning
    # built-in load: independent of the communication grid up to the
    # integrator's error, a fraction of relTol = 1e-4 (measured 2e-6 of the
    # largest speed); the coupled runs below differ by ~8 %
    assert np.max(np.abs(inside - inside_h)) < 1e-5 * np.max(np.abs(inside))
    err = np.max(np.abs(inside - outside))
    err_h = np.max(np.abs(inside_h - outside_h))
    assert err < 0.12 * np.max(np.abs(inside))  # ~8 % at steps up to 0.5 ms
    assert 0.3 < err_h / err < 0.7, (err, err_h)  # first order in the step


@pytest.mark.parametrize("method", [1, 2])  # RKF45; stiff method with its kept Jacobian
def test_get_set_state_bit_identical(h, method):
    params = {**SHORT, "solver.method": method}
    h.init(params)
    t = 0.0
    for _ in range(5):
        h.fmu.doStep(t, 1e-3)
        t += 1e-3
    state = h.fmu.getFMUstate()
    names = ["pulley[1].omega", "pulley[2].omega", "span[1].tension", "probe.sdeForce"]
    first = []
    for k in range(3):
        h.fmu.doStep(t + k * 1e-3, 1e-3)
        first.append(h.get(*names))
    h.fmu.setFMUstate(state)
    again = []
    for k in range(3):
        h.fmu.doStep(t + k * 1e-3, 1e-3)
        again.append(h.get(*names))
    assert first == again  # bit-identical

    # serialize, deserialize into the same instance
    data = h.fmu.serializeFMUstate(state)
    h.fmu.freeFMUstate(state)
    back = h.fmu.deSerializeFMUstate(data)
    h.fmu.setFMUstate(back)
    h.fmu.freeFMUstate(back)
    same = []
    for k in range(3):
        h.fmu.doStep(t + k * 1e-3, 1e-3)
        same.append(h.get(*names))
    assert same == first

    # ... and into a new instance
    h2 = Harness(h.md, h.fmu.unzipDirectory, "copy")
    h2.init(params)
    st2 = h2.fmu.deSerializeFMUstate(data)
    h2.fmu.setFMUstate(st2)
    copy = []
    for k in range(3):
        h2.fmu.doStep(t + k * 1e-3, 1e-3)
        copy.append(h2.get(*names))
    assert copy == first
    # corrupted bytes are refused
    bad = bytearray(data)
    bad[len(bad) // 2] ^= 0xFF
    with pytest.raises(FMICallException):
        h2.fmu.deSerializeFMUstate(bytes(bad))
    with pytest.raises(FMICallException):
        h2.fmu.deSerializeFMUstate(bytes(data[: len(data) // 3]))
    h2.fmu.freeInstance()


def test_reset_equals_fresh(md, unzipdir):
    a = Harness(md, unzipdir, "a")
    a.init(SHORT)
    a.fmu.doStep(0.0, 2e-3)
    a.fmu.reset()
    a.init(SHORT)
    a.fmu.doStep(0.0, 2e-3)
    b = Harness(md, unzipdir, "b")
    b.init(SHORT)
    b.fmu.doStep(0.0, 2e-3)
    names = ["pulley[1].omega", "span[1].tension"]
    assert a.get(*names) == b.get(*names)


def test_two_instances_independent(md, unzipdir):
    p1 = dict(SHORT, **{"belt.preload": 400.0})
    p2 = dict(SHORT, **{"belt.preload": 600.0})
    alone = []
    for p in (p1, p2):
        x = Harness(md, unzipdir, "alone")
        x.init(p)
        for k in range(4):
            x.fmu.doStep(k * 5e-4, 5e-4)
        alone.append(x.get("span[1].tension", "pulley[1].omega"))
        x.fmu.freeInstance()
    a, b = Harness(md, unzipdir, "a"), Harness(md, unzipdir, "b")
    a.init(p1)
    b.init(p2)
    for k in range(4):
        a.fmu.doStep(k * 5e-4, 5e-4)
        b.fmu.doStep(k * 5e-4, 5e-4)
    assert a.get("span[1].tension", "pulley[1].omega") == alone[0]
    assert b.get("span[1].tension", "pulley[1].omega") == alone[1]


def expect_error(h, call, text=None):
    n = len(h.log)
    with pytest.raises(FMICallException):
        call()
    assert len(h.log) > n, "no log line for the refused call"
    if text:
        assert any(text in m for _, _, m in h.log[n:]), h.log[n:]


@pytest.mark.parametrize("case", ["step_before_init", "set_output", "unknown_vr",
                                  "fixed_after_init", "wrong_time", "null_array"])
def test_misuse_is_refused_with_a_log_line(md, unzipdir, case):
    # fmi2Error puts an FMI 2.0 instance into its error state: one instance per rule.
    h = Harness(md, unzipdir, case)
    if case == "step_before_init":
        expect_error(h, lambda: h.fmu.doStep(0.0, 1e-3))
    elif case == "set_output":
        expect_error(h, lambda: h.fmu.setReal([h.vr["pulley[1].omega"]], [1.0]))
    elif case == "unknown_vr":
        expect_error(h, lambda: h.fmu.getReal([999999]))
    elif case == "null_array":
        vr = (ctypes.c_uint * 1)(h.vr["belt.preload"])
        status = h.fmu.fmi2GetReal.__wrapped__(h.fmu.component, vr, 1, None) \
            if hasattr(h.fmu.fmi2GetReal, "__wrapped__") else \
            h.fmu._functions["fmi2GetReal"](h.fmu.component, vr, 1, None)
        assert status == 3 and h.log
    else:
        h.init(SHORT)
        if case == "fixed_after_init":
            expect_error(h, lambda: h.fmu.setReal([h.vr["belt.preload"]], [100.0]))
        else:
            expect_error(h, lambda: h.fmu.doStep(0.5, 1e-3))
    h.fmu.freeInstance()


def test_bad_parameter_names_variable_and_range(md, unzipdir):
    for name, value, text in [
        ("pulley[1].radius", -1.0, "pulley[1].radius"),
        ("nPulleys", 9, "nPulleys"),
        ("pulley[2].muKinetic", 2.0, "pulley[2].muKinetic"),
        ("belt.nBodies", 20, "belt.nBodies"),
    ]:
        x = Harness(md, unzipdir, "bad")
        x.set_named(name, value)
        if name == "belt.nBodies":
            x.set_named("probe.body", 1)
        x.fmu.setupExperiment(startTime=0.0)
        x.fmu.enterInitializationMode()
        n = len(x.log)
        with pytest.raises(FMICallException):
            x.fmu.exitInitializationMode()
        assert any(text in m for _, _, m in x.log[n:]), (name, x.log[n:])
        x.fmu.freeInstance()


def test_wrong_guid_refused(md, unzipdir):
    with pytest.raises(Exception):
        Harness(md, unzipdir, "wrong", guid="{00000000-0000-0000-0000-000000000000}")


def test_nan_input_refused_last_good_state_kept(h):
    h.init(SHORT)
    h.fmu.doStep(0.0, 1e-3)
    before = h.get("pulley[1].omega", "span[1].tension")
    n = len(h.log)
    with pytest.raises(FMICallException) as refused:
        # refused either at fmi2SetReal or, at the latest, by the next step
        h.fmu.setReal([h.vr["pulley[1].torque"]], [float("nan")])
        h.fmu.doStep(1e-3, 1e-3)
    assert refused.value.status in (2, 3)  # fmi2Discard or fmi2Error
    assert len(h.log) > n, "no log line for the NaN input"
    assert h.get("pulley[1].omega", "span[1].tension") == before  # last good state kept
    if refused.value.status == 2:
        # fmi2Discard: the instance reports how far it got
        assert h.fmu.getRealStatus(fmi2LastSuccessfulTime) == 1e-3
    else:
        # fmi2Error: FMI 2.0 allows no fmi2GetXXXStatus in the error state,
        # only getters, reset and free; the refusal must be consistent.
        with pytest.raises(FMICallException):
            h.fmu.getRealStatus(fmi2LastSuccessfulTime)
    h.fmu.reset()  # usable again after reset
    h.init(SHORT)
    h.fmu.doStep(0.0, 1e-3)


def test_discarded_step_reports_last_successful_time(md, unzipdir):
    """A step the FMU cannot finish (here: the solver.maxSteps guard) returns
    fmi2Discard; fmi2GetRealStatus(fmi2LastSuccessfulTime) gives the last
    good communication point and the outputs stay there."""
    h = Harness(md, unzipdir, "discard")
    h.init(dict(SHORT, **{"solver.maxSteps": 30}))
    h.fmu.doStep(0.0, 1e-5)
    h.fmu.doStep(1e-5, 1e-5)
    (steps,) = h.get("solver.steps")
    assert steps < 30
    physical = ["pulley[1].omega", "pulley[2].omega", "span[1].tension", "probe.x"]
    before = h.get(*physical)
    n = len(h.log)
    with pytest.raises(FMICallException) as refused:
        h.fmu.doStep(2e-5, 0.05)  # needs far more than 30 steps per ms (1500)
    assert refused.value.status == 2  # fmi2Discard
    assert any("solver.maxSteps" in m for _, _, m in h.log[n:]), h.log[n:]
    assert h.fmu.getRealStatus(fmi2LastSuccessfulTime) == 2e-5
    # fmi2DoStep is not allowed after a discard: the instance asks to stop
    assert h.fmu.getBooleanStatus(fmi2Terminated)
    # (the solver.* counters may include the discarded attempt's work)
    assert h.get(*physical) == before
    h.fmu.terminate()
    h.fmu.freeInstance()


def test_fmpy_ends_a_discarded_run_at_the_last_successful_time(fmu_path):
    """FMPy's simulate_fmu asks fmi2Terminated after fmi2Discard: the FMU says
    yes, so the run ends cleanly at the last successful communication point
    with the results so far (instead of retrying the step, which fmi2DoStep
    refuses in the step-failed state)."""
    res = simulate_fmu(fmu_path, stop_time=0.05, output_interval=1e-3,
                       start_values={"solver.maxSteps": 30},
                       output=["pulley[2].omega"])
    assert res["time"][0] == 0.0
    assert res["time"][-1] < 0.05  # stopped early, no exception
    assert np.all(np.isfinite(res["pulley[2].omega"]))


def test_communication_points_exact(h):
    """Variable steps land exactly on the communication points: the FMU's
    time is the importer's sum, and a step from a different time is refused."""
    h.init(SHORT)
    t = 0.0
    for dt in [1e-4, 3e-4, 1.7e-4, 2.9e-4, 1e-4, 5.3e-4]:
        h.fmu.doStep(t, dt)
        t += dt
        assert h.fmu.getRealStatus(fmi2LastSuccessfulTime) == t
    n = len(h.log)
    with pytest.raises(FMICallException):
        h.fmu.doStep(t + 1e-3, 1e-4)
    assert len(h.log) > n


def test_input_and_output_derivatives(h):
    h.init(SHORT)
    vr_t = h.vr["pulley[2].torque"]
    h.fmu.setRealInputDerivatives([vr_t], [1], [10.0])
    h.fmu.doStep(0.0, 1e-3)
    # the input ramped to 10 N m/s * 1 ms at the end of the step
    assert h.fmu.getReal([vr_t])[0] == pytest.approx(0.01)
    vrs = [h.vr["pulley[1].omega"], h.vr["pulley[2].omega"]]
    alphas = list(h.fmu.getRealOutputDerivatives(vrs, [1, 1]))
    assert alphas == h.get("pulley[1].alpha", "pulley[2].alpha")
    assert all(np.isfinite(alphas)) and alphas[0] != 0.0
    # order 2 is beyond maxOutputDerivativeOrder = 1
    with pytest.raises(FMICallException):
        h.fmu.getRealOutputDerivatives(vrs[:1], [2])
