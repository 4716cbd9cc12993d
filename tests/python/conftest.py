import functools
import importlib.util
import pathlib
import shutil
import tempfile

import pytest
from fmpy import extract, read_model_description

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU = ROOT / "dist" / "BeltDrive.fmu"


@pytest.fixture(scope="session")
def fmu_path():
    if not FMU.exists():
        pytest.fail(f"{FMU} missing: run `cargo xtask fmu` first")
    return str(FMU)


@pytest.fixture(scope="session")
def md(fmu_path):
    return read_model_description(fmu_path)


@pytest.fixture(scope="session")
def unzipdir(fmu_path):
    d = extract(fmu_path, unzipdir=tempfile.mkdtemp(prefix="beltdrive-"))
    yield d
    shutil.rmtree(d, ignore_errors=True)


@functools.cache
def ssv_example():
    """examples/simulate_ssv.py as a module: the .ssv reader and runner the
    users run, so the tests read the parameter sets the same way."""
    spec = importlib.util.spec_from_file_location("simulate_ssv", ROOT / "examples/simulate_ssv.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def runs_of_both_methods(ssv, outputs, stop_time=0.8):
    """The parameter set's start values, and its run through FMPy with RKF45
    (solver.method 1) and with the stiff method (2), 1 ms communication
    step: {method: result}."""
    from fmpy import simulate_fmu
    start = ssv_example().start_values(ssv)
    out = {method: simulate_fmu(str(FMU), stop_time=stop_time, output_interval=1e-3,
                                start_values=dict(start, **{"solver.method": method}),
                                output=outputs)
           for method in (1, 2)}
    return start, out


def window(res, name, t0=0.6):
    """The output `name` from t0 on."""
    return res[name][res["time"] >= t0]
