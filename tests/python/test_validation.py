"""The validation report's script in its --quick mode (short horizons, few
bodies), so `validation/validate.py` cannot rot: it must run through the
built FMU, write every plot and table, and give numbers that obey the laws
the full report checks (torque balance, capstan limit, refusal of a too
coarse mesh, the section-3 vibration near its closed-form frequency)."""
import json
import math
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "validation"))

import validate  # noqa: E402

PLOTS = ["s3_driven_speed.png", "s4_fig14_speeds.png", "s4_fig15_sde_force.png",
         "s4_fig16_18_contact.png", "panel_creep_capstan.png", "convergence.png"]


@pytest.fixture(scope="module")
def report(fmu_path, tmp_path_factory):
    out = tmp_path_factory.mktemp("validation")
    # kubas2014 at dv = 0.1 (section 4) and 0.01 m/s (section 3) keeps the
    # smoke run cheap; a private cache so the test really simulates.
    validate.CACHE = out / "cache"
    an = validate.main(["--quick", "--out", str(out), "--dv", "0.1", "--dv-s3", "0.01", "--jobs", "2"])
    return out, an


def test_files_written(report):
    out, _ = report
    for name in PLOTS + ["results.json", "tables.md"]:
        assert (out / name).stat().st_size > 1000 or name == "tables.md", name
    tables = (out / "tables.md").read_text()
    for block in ("## s3", "## s4", "## panel", "## mesh", "## tol", "## dv"):
        assert block in tables
    json.loads((out / "results.json").read_text())


def test_section3_numbers(report):
    _, an = report
    s3 = an["s3"]
    kub = s3["laws"]["kubas2014"]
    # Before the load step the free driven pulley follows the prescribed -10 rad/s.
    assert abs(kub["pre"]["omega2"] / validate.S3_OMEGA - 1) < 0.03
    # The torsional vibration after the step is the driven pulley against the
    # spans: between the closed forms with and without belt inertia, +-25 %.
    f = kub["freq_hz"]
    lo = s3["omega_n_belt_mass"] / (2 * math.pi)
    hi = s3["omega_n_massless"] / (2 * math.pi)
    assert 0.75 * lo < f < 1.25 * hi, (f, lo, hi)


def test_panel_torque_balance_and_capstan(report):
    _, an = report
    pan = an["panel"]
    assert pan["points"]
    for p in pan["points"]:
        # Steady state: the belt's torque on the driven pulley is the load.
        if p["ratio"] < 0.9 * pan["capstan"]:
            assert abs(p["torque"] - p["load_torque"]) < 0.05 * p["load_torque"] + 0.05, p
        # Capstan: the tension ratio cannot exceed e^(mu theta).
        assert p["ratio"] < 1.02 * pan["capstan"], p


def test_mesh_refusal_and_sane_steady_values(report):
    _, an = report
    rows = {r["n"]: r for r in an["mesh"]["rows"]}
    assert "belt.nBodies" in rows[60]["error"]
    r = rows[100]
    assert "error" not in r
    assert r["omega1"] < 0 and r["omega2"] < 0
    assert 0 < r["slack"] < r["tight"]
    for row in an["tol"]["rows"] + an["dv"]["rows"]:
        assert "error" not in row, row
        assert math.isfinite(row["slip"]) and row["steps"] > 0


def test_dv_integrator_crosscheck(report):
    """kubas2014: the stiff method over the check window gives RKF45's
    speeds and span forces (docs/model.md: body velocities stay in its
    error norm for this law)."""
    _, an = report
    check = {r["method"]: r for r in an["dv"]["rows"] if r["window"] == [0.04, 0.06]}
    assert set(check) == {1, 2}, an["dv"]["rows"]
    rk, ros = check[1], check[2]
    for k in ("omega1", "omega2"):
        assert abs(ros[k] / rk[k] - 1) < 2e-3, (k, rk[k], ros[k])
    for k in ("tight", "slack"):
        assert abs(ros[k] / rk[k] - 1) < 1e-2, (k, rk[k], ros[k])
    assert ros["steps"] < rk["steps"]


def test_time_limit_keeps_a_partial_run(fmu_path, tmp_path):
    """A run that reaches --time-limit is stopped and reported with the time
    it reached, not thrown away."""
    validate.TIME_LIMIT = 0.0
    try:
        c = validate.case("limited", validate.s4_params(100), validate.HEADLINE, 0.5, 1e-3)
    finally:
        validate.TIME_LIMIT = None
    r = validate._simulate(c)
    assert "error" not in r
    reached = validate.short_of(r, 0.5)
    assert reached is not None and 0 < reached < 0.5, reached


def test_section3_parameters_match_the_shipped_set():
    """validate.py's section-3 drive is the shipped parameter set
    (parameters/kubas2014-section3.ssv, which tests/parameter_sets.rs ties
    to DriveParams::kubas_section3()) wherever both set a variable."""
    from fmpy.ssp.ssd import read_ssv

    ssv = {p.name: p for p in read_ssv(str(ROOT / "parameters" / "kubas2014-section3.ssv")).parameters}
    ours = validate.s3_params(60)
    common = sorted(set(ours) & set(ssv))
    assert "contact.pMax" in common and len(common) > 15, common
    for name in common:
        p = ssv[name]
        value = {"Real": float, "Integer": int}.get(p.type, lambda v: str(v).lower() == "true")(p.value)
        assert math.isclose(float(ours[name]), float(value), rel_tol=1e-9), (name, ours[name], p.value)
