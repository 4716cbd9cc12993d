"""examples/creep_wrap.py, the reduced model of docs/validation.md ("Why a coarse
mesh slips more"), against the closed forms it must reduce to (no FMU needed)."""

import importlib.util
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture()
def cw():
    spec = importlib.util.spec_from_file_location("creep_wrap", ROOT / "examples/creep_wrap.py")
    m = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(m)
    return m


def slip(cw, t1, t2):
    return cw.speed_loss(cw.stick_strain(t1, t2), cw.stick_strain(t2, t1))


def test_stiff_creep_spring_gives_rigid_adhesion_creep_theory(cw):
    """With Delta_max -> 0 the creep spring is rigid: the belt sticks where the
    wrap needs no friction and slides at mu_k elsewhere, so the slip is creep
    theory's (T1 - T2) / (EA + T1) (Euler-Eytelwein capstan with stretch).
    Delta_max = 1e-6 m puts the creep length at 1.8 mm, 2 % of the wrap, and
    the model meets the closed form to 3e-10 of it; 0.5 % is the bound that
    Delta_max = 3e-5 m (creep length 10 mm) already fails (+0.9 %)."""
    cw.DMAX = 1e-6
    t1, t2 = 839.6, 284.1
    theory = (t1 - t2) / (cw.EA + t1)
    assert slip(cw, t1, t2) == pytest.approx(theory, rel=5e-3)


def test_elastic_creep_slips_more_than_creep_theory(cw):
    """At the paper's Delta_max = 0.1 mm the creep length (18-30 mm) is a fair
    part of the 85 mm wrap and there is no adhesion arc: the slip exceeds
    creep theory's, and a belt brought onto the drive pulley lagging the
    surface (the continuous belt's entry) slips less, on the driven pulley
    more (docs/validation.md: -0.0056 and +0.0039 points per um)."""
    t1, t2 = 839.6, 284.1
    theory = (t1 - t2) / (cw.EA + t1)
    e1, e2 = cw.stick_strain(t1, t2), cw.stick_strain(t2, t1)
    base = cw.speed_loss(e1, e2)
    assert base > 1.05 * theory
    lag = 1e-6
    assert cw.speed_loss(cw.stick_strain(t1, t2, lag), e2) < base
    assert cw.speed_loss(e1, cw.stick_strain(t2, t1, lag)) > base
