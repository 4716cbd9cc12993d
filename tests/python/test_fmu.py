"""BeltDrive.fmu through its real C ABI with FMPy."""
import ctypes

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
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
    for v in md.modelVariables:
        assert v.description, v.name
        if v.type == "Real":
            # every Real is typed; dimensionless types (factors, counts) carry no unit
            assert v.declaredType is not None, v.name


def test_simulate_default_drive_short(fmu_path):
    res = simulate_fmu(fmu_path, stop_time=0.01, output_interval=1e-3,
                       output=["pulley[1].omega", "span[1].tension", "span[2].tension"])
    assert np.all(np.isfinite(res["pulley[1].omega"]))
    # The drive torque ramps to -15 N m: pulley 1 turns clockwise.
    assert res["pulley[1].omega"][-1] < 0
    assert 400 < res["span[1].tension"][0] < 700


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
    steps = [1e-4, 3e-4, 2e-4, 5e-4, 1e-4] * 8  # 0.0096 s, variable
    a = Harness(md, unzipdir, "inside")
    b = Harness(md, unzipdir, "outside")
    inside = run_coupled(a, steps, external_load=False)
    outside = run_coupled(b, steps, external_load=True)
    # The external load is held over each step (zero-order hold of -d*omega):
    # the speeds agree to the change of omega within a step (<< 1 rad/s here).
    assert np.max(np.abs(inside - outside)) < 0.05
    assert abs(inside[-1, 0]) > 0.01


def test_get_set_state_bit_identical(h):
    h.init(SHORT)
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

    # serialize into a new instance
    h.fmu.setFMUstate(state)
    data = h.fmu.serializeFMUstate(state)
    h.fmu.freeFMUstate(state)
    h2 = Harness(h.md, h.fmu.unzipDirectory, "copy")
    h2.init(SHORT)
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
        ("nPulleys", 7, "nPulleys"),
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


def test_nan_input_keeps_last_good_state(h):
    h.init(SHORT)
    h.fmu.doStep(0.0, 1e-3)
    before = h.get("pulley[1].omega")
    n = len(h.log)
    with pytest.raises(FMICallException):
        h.fmu.setReal([h.vr["pulley[1].torque"]], [float("nan")])
    assert len(h.log) > n
    assert h.get("pulley[1].omega") == before  # last good state kept
    h.fmu.reset()  # usable again after reset
    h.init(SHORT)
    h.fmu.doStep(0.0, 1e-3)


def test_input_and_output_derivatives(h):
    h.init(SHORT)
    vr_t = h.vr["pulley[2].torque"]
    h.fmu.setRealInputDerivatives([vr_t], [1], [10.0])
    h.fmu.doStep(0.0, 1e-3)
    # the input ramped to 10 N m/s * 1 ms at the end of the step
    assert h.fmu.getReal([vr_t])[0] == pytest.approx(0.01)
    (alpha,) = h.fmu.getRealOutputDerivatives([h.vr["pulley[1].omega"]], [1])
    (alpha_out,) = h.get("pulley[1].alpha")
    assert alpha == alpha_out
