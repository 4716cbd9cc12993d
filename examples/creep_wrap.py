"""The steady creep of a continuous belt on the wraps of a drive
(docs/validation.md, "Why a coarse mesh slips more"): the reduced model that
accounts for the discrete belt's slip against the mesh.

    .venv/bin/python examples/creep_wrap.py [5pk|2to1 [T1 T2]]   # the continuum and its sensitivities
    .venv/bin/python examples/creep_wrap.py PROFILE [start_deg[,start_deg...]]  # check a wrap_profile run

A continuous belt (EA, mass m' per length) on a pulley of radius r with the
FMU's `creep` friction law (docs/model.md, "Friction": mu = mu_s S(z /
Delta_max) with its Kelvin-Voigt damper in the elastic range, softening to
mu_k over Delta_max..1.5 Delta_max, held at 1.5 Delta_max), in steady running.
Along the arc x in the belt's direction of travel a belt element carries its
creep displacement z (the travel of the pulley surface relative to the belt
since the element arrived; z > 0: the belt lags the surface) and its tension T:

    dz/dx = v_T / v = (1 + eps0) / (1 + T / EA) - 1,   dT/dx = -mu(z) (T - m' v^2) / r,

eps0 = omega r / v0 - 1 the strain at which the belt would stick (v0 = the
unstretched belt's flux speed, the same on every pulley). For given tensions
in and out, eps0 is shot so that T reaches the outgoing span's tension at the
end of the arc; the speed loss of pulley j against pulley 1 is
1 - (1 + eps0_j) / (1 + eps0_1). The only thing the mesh can change in this
model is the state (T, z) in which the belt enters the arc: z = 0 is a belt
that arrives unstrained.

With a PROFILE (the output of `cargo run --profile ci --example wrap_profile
-- 5pk|2to1|accessory N BIN [points]`, whose header gives the belt's and the
pulleys' constants) the model starts each wrap from the simulated state (mean
SDE tension and mean creep of the contacts) in the bin at `start_deg` of
travel from the arrival (default: the first bin; one value per wrap in the
profile's order, or one for all), integrates to the tangent point where the
belt leaves, and compares the speed losses with the simulated ones.
"""

import math
import sys

from scipy.optimize import brentq

# The paper's 5PK belt and pulleys (DriveParams::kubas_section4, the creep
# law's defaults): EA [N], Delta_max [m], mu_s, mu_k, the creep damper's tau [s].
EA, DMAX, MU_S, MU_K, TAU = 1.52e5, 1e-4, 1.05, 1.0, 3e-4
# Centrifugal force m' v^2 [N]: 0.04 N on the 5PK drive, left out of the
# continuum runs; a profile's header sets it.
CENTRIFUGAL = 0.0
# The 5PK drive's radius [m], wrap angle [rad] (equal pulleys) and belt speed
# [m/s] (for the damper's v_T only).
RADIUS, WRAP, SPEED = 0.027, math.pi, 0.68
# The drives wrap_profile runs: per pulley the radius [m] and the travel
# angle [rad] from wrap_profile's origin (the bottom of pulley 1, the top of
# pulley 2) at which the belt arrives and leaves, and the belt speed. The 2:1
# drive (examples/common/two_to_one.rs: 40 and 80 mm, 0.3 m apart): the
# spans are inclined by d = asin((r2 - r1) / a) = 7.66 deg, so the small
# pulley wraps 180 - 2d deg from d to 180 - d, the large one 180 + 2d from -d.
_D = math.asin(0.04 / 0.3)
DRIVES = {
    "5pk": ([(0.027, 0.0, math.pi), (0.027, 0.0, math.pi)], 0.68),
    "2to1": ([(0.04, _D, math.pi - _D), (0.08, -_D, math.pi + _D)], 1.6),
}
STEPS_PER_RADIAN = 2000


def s_curve(u):
    return 0.5 * (3.0 * u - u**3)


def smoothstep(x):
    x = min(max(x, 0.0), 1.0)
    return x * x * (3.0 - 2.0 * x)


def mu(z, v_t, mu_s=None, mu_k=None):
    """The `creep` law (src/model/elements/friction/creep.rs), z > 0: belt lags."""
    mu_s = MU_S if mu_s is None else mu_s
    mu_k = MU_K if mu_k is None else mu_k
    u = z / DMAX
    if abs(u) <= 1.0:
        m = mu_s * (s_curve(u) + 1.5 * (1.0 - u * u) * TAU / DMAX * v_t)
        return max(-mu_s, min(mu_s, m))
    return math.copysign(mu_s + (mu_k - mu_s) * smoothstep(2.0 * (abs(u) - 1.0)), u)


def march(eps0, t_in, z_in, arc, r=RADIUS, mus=None):
    """(T, z) at the end of an arc of length `arc` entered in state (t_in, z_in)
    by a belt whose stick strain is eps0 (midpoint rule, z held at its cap);
    `mus` = (mu_s, mu_k) of the pulley."""
    mus = mus or (MU_S, MU_K)
    cap = 1.5 * DMAX
    n = max(200, int(STEPS_PER_RADIAN * arc / r))
    h = arc / n
    t, z = t_in, z_in

    def rate(t, z):
        dz = (1.0 + eps0) / (1.0 + t / EA) - 1.0
        if (z >= cap and dz > 0.0) or (z <= -cap and dz < 0.0):
            dz = 0.0
        return -mu(z, SPEED * dz, *mus) * (t - CENTRIFUGAL) / r, dz

    for _ in range(n):
        a = rate(t, z)
        b = rate(t + 0.5 * h * a[0], z + 0.5 * h * a[1])
        t += h * b[0]
        z = min(cap, max(-cap, z + h * b[1]))
    return t, z


def stick_strain(t_in, t_out, z_in=0.0, arc=RADIUS * WRAP, r=RADIUS, mus=None):
    """eps0 of a wrap of radius r entered at tension t_in with creep z_in and left at t_out."""
    return brentq(lambda e: march(e, t_in, z_in, arc, r, mus)[0] - t_out, -0.05, 0.05, xtol=1e-13)


def speed_loss(e_driver, e_driven):
    return 1.0 - (1.0 + e_driven) / (1.0 + e_driver)


def continuum(drive, t1, t2):
    """Slip of a belt that enters both wraps unstrained, against rigid-adhesion
    creep theory, and its sensitivity to the creep a belt brings onto each wrap
    (pulley 1 drives; t1, t2 the tight and slack span tensions)."""
    global SPEED
    pulleys, SPEED = DRIVES[drive]
    (r1, a1, b1), (r2, a2, b2) = pulleys
    arc1, arc2 = r1 * (b1 - a1), r2 * (b2 - a2)
    e1, e2 = stick_strain(t1, t2, 0.0, arc1, r1), stick_strain(t2, t1, 0.0, arc2, r2)
    base = speed_loss(e1, e2)
    lam = [math.sqrt(EA * DMAX / (1.5 * MU_S * t / r)) for t, r in ((t1, r1), (t2, r2))]
    print(f"{drive}: span tensions {t1:.1f} / {t2:.1f} N, EA {EA:.3g} N, Delta_max {DMAX * 1e3:.2g} mm, "
          f"mu_s {MU_S}, r {r1 * 1e3:.0f} / {r2 * 1e3:.0f} mm")
    print(f"creep length sqrt(EA Delta_max / (1.5 mu_s T / r)): {lam[0] * 1e3:.1f} mm on the "
          f"driver's entry, {lam[1] * 1e3:.1f} mm on the driven pulley's (wraps {arc1 * 1e3:.0f} / "
          f"{arc2 * 1e3:.0f} mm)")
    print(f"rigid-adhesion creep theory (T1 - T2) / (EA + T1): {100 * (t1 - t2) / (EA + t1):.4f} %")
    print(f"elastic creep, belt entering unstrained:           {100 * base:.4f} %")
    dz = 1e-6
    d1 = speed_loss(stick_strain(t1, t2, dz, arc1, r1), e2) - base
    d2 = speed_loss(e1, stick_strain(t2, t1, dz, arc2, r2)) - base
    print(f"per um of creep brought onto the wrap (belt lagging the surface): driver {100 * d1:+.4f}, "
          f"driven {100 * d2:+.4f} points of slip")


def read_profile(path):
    """A wrap_profile run: the speed losses against pulley 1, and per wrap its
    pulley, radius, wrap angle, (mu_s, mu_k) and {travel deg: (tension, z [m]
    or None off the wrap)}; sets the belt's constants from its header."""
    global EA, DMAX, TAU, SPEED, CENTRIFUGAL
    losses, wraps = None, []
    for line in open(path):
        if "speed loss" in line:
            losses = [float(v) / 100.0 for v in line.split("[%]")[1].split("/")]
        elif line.startswith("belt EA"):
            f = line.replace(",", " ").split()
            EA, DMAX, TAU, SPEED = float(f[2]), float(f[5]), float(f[8]), float(f[12])
            CENTRIFUGAL = float(f[15]) * SPEED**2
        elif line.startswith("pulley "):
            f = line.replace("(", " ").replace(",", " ").replace(";", " ").split()
            wraps.append({"pulley": int(f[1]), "radius": float(f[3]), "wrap": math.radians(float(f[6])),
                          "mus": (float(f[9]), float(f[11])), "bins": {}})
        elif "|" in line and wraps:
            a, b = line.split("|")
            deg, ten = (float(v) for v in a.split())
            _, _, z, _, count = (float(v) for v in b.split())
            wraps[-1]["bins"][deg] = (ten, z * 1e-6 if count > 0.0 else None)
    return losses, wraps


def check(path, start=None):
    """Each wrap from the simulated state at `start` degrees of travel (one value
    per wrap, or one for all; default the first bin) to the tangent point where
    the belt leaves, into the span's simulated tension; then the same with each
    wrap in turn started from the arriving span's tension and no creep (what its
    landing does to the slip)."""
    losses, wraps = read_profile(path)
    runs = []
    for m, w in enumerate(wraps):
        bins, r, wrap = w["bins"], w["radius"], w["wrap"]
        inside = sorted(d for d in bins if bins[d][1] is not None and d < math.degrees(wrap))
        deg = inside[0] if start is None else min(inside, key=lambda d: abs(d - start[m % len(start)]))
        t_in, z_in = bins[deg]
        # the spans: the mean SDE tension off the wrap over the 40 deg
        # before the arrival and after the tangent point where it leaves
        before = [bins[d][0] for d in bins if bins[d][1] is None and d > 320.0]
        after = [bins[d][0] for d in bins if bins[d][1] is None and 0 < d - math.degrees(wrap) < 40.0]
        t_span, t_out = sum(before) / len(before), sum(after) / len(after)
        arc = r * (wrap - math.radians(deg))
        landed = stick_strain(t_in, t_out, z_in, arc, r, w["mus"])
        unstrained = stick_strain(t_span, t_out, 0.0, arc, r, w["mus"])
        runs.append((w["pulley"], landed, unstrained))
        print(f"pulley {w['pulley']}: from {deg:.1f} deg, T {t_in:.1f} N ({t_in - t_span:+.1f} N against the "
              f"arriving span), z {z_in * 1e6:+.2f} um (+: lagging), leaving into {t_out:.1f} N")

    def losses_of(eps):
        return [speed_loss(eps[1], eps[j]) for j in sorted(eps) if j != 1]

    model = losses_of({j: e for j, e, _ in runs})
    print(f"{path}: speed loss against pulley 1, simulated "
          + " / ".join(f"{100 * v:.4f}" for v in losses) + " %, reduced model "
          + " / ".join(f"{100 * v:.4f}" for v in model) + " %")
    for j, _, _ in runs:
        alone = losses_of({k: (u if k == j else e) for k, e, u in runs})
        print(f"  pulley {j}'s landing moves the losses by "
              + " / ".join(f"{100 * (a - b):+.4f}" for a, b in zip(model, alone)) + " points")


if __name__ == "__main__":
    if len(sys.argv) == 1 or sys.argv[1] in DRIVES:
        drive = sys.argv[1] if len(sys.argv) > 1 else "5pk"
        # default tensions: the 1200-body 5PK run and the 480-body 2:1 run
        # (wrap_profile, means over 0.5-0.8 s)
        t = [float(v) for v in sys.argv[2:4]] or {"5pk": [839.6, 284.1], "2to1": [712.7, 338.8]}[drive]
        continuum(drive, *t)
    else:
        check(sys.argv[1], [float(v) for v in sys.argv[2].split(",")] if len(sys.argv) > 2 else None)
