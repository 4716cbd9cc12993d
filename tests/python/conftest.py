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
