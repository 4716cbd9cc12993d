"""The steady creep of a continuous belt on the wraps of the paper's 5PK drive
(docs/validation.md, "Why a coarse mesh slips more"): the reduced model that
accounts for the discrete belt's slip against the mesh.

    .venv/bin/python examples/creep_wrap.py [5pk|2to1 [T1 T2]]   # the continuum and its sensitivities
    .venv/bin/python examples/creep_wrap.py PROFILE [start_deg[,start_deg]]  # check a wrap_profile run

A continuous belt (EA, no mass: 0.04 N of centrifugal force at 0.7 m/s) on a
pulley of radius r with the FMU's `creep` friction law (docs/model.md,
"Friction": mu = mu_s S(z / Delta_max) with its Kelvin-Voigt damper in the
elastic range, softening to mu_k over Delta_max..1.5 Delta_max, held at
1.5 Delta_max), in steady running. Along the arc x in the belt's direction of
travel a belt element carries its creep displacement z (the travel of the
pulley surface relative to the belt since the element arrived; z > 0: the belt
lags the surface) and its tension T:

    dz/dx = v_T / v = (1 + eps0) / (1 + T / EA) - 1,   dT/dx = -mu(z) T / r,

eps0 = omega r / v0 - 1 the strain at which the belt would stick (v0 = the
unstretched belt's flux speed, the same on every pulley). For given tensions
in and out, eps0 is shot so that T reaches the outgoing span's tension at the
end of the arc; the speed loss of the driven pulley is 1 - (1 + eps0_driven) /
(1 + eps0_driver). The only thing the mesh can change in this model is the
state (T, z) in which the belt enters the arc: z0 = 0 is a belt that arrives
unstrained.

With a PROFILE (the output of `cargo run --profile ci --example wrap_profile
-- 5pk|2to1 N BIN [points]`) the model starts each wrap from the simulated
state (mean SDE tension and mean creep of the contacts) in the bin at
`start_deg` (default: the first bin inside the wrap; two values: one per
pulley) of travel, integrates to
the tangent point where the belt leaves, and compares the speed loss with the
simulated one.
"""

import math
import sys

from scipy.optimize import brentq

# The paper's 5PK belt and pulleys (DriveParams::kubas_section4, the creep
# law's defaults): EA [N], Delta_max [m], mu_s, mu_k, the creep damper's tau [s].
EA, DMAX, MU_S, MU_K, TAU = 1.52e5, 1e-4, 1.05, 1.0, 3e-4
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


def mu(z, v_t):
    """The `creep` law (src/belt/elements/friction/creep.rs), z > 0: belt lags."""
    u = z / DMAX
    if abs(u) <= 1.0:
        m = MU_S * (s_curve(u) + 1.5 * (1.0 - u * u) * TAU / DMAX * v_t)
        return max(-MU_S, min(MU_S, m))
    return math.copysign(MU_S + (MU_K - MU_S) * smoothstep(2.0 * (abs(u) - 1.0)), u)


def march(eps0, t_in, z_in, arc, r=RADIUS):
    """(T, z) at the end of an arc of length `arc` entered in state (t_in, z_in)
    by a belt whose stick strain is eps0 (midpoint rule, z held at its cap)."""
    cap = 1.5 * DMAX
    n = max(200, int(STEPS_PER_RADIAN * arc / r))
    h = arc / n
    t, z = t_in, z_in

    def rate(t, z):
        dz = (1.0 + eps0) / (1.0 + t / EA) - 1.0
        if (z >= cap and dz > 0.0) or (z <= -cap and dz < 0.0):
            dz = 0.0
        return -mu(z, SPEED * dz) * t / r, dz

    for _ in range(n):
        a = rate(t, z)
        b = rate(t + 0.5 * h * a[0], z + 0.5 * h * a[1])
        t += h * b[0]
        z = min(cap, max(-cap, z + h * b[1]))
    return t, z


def stick_strain(t_in, t_out, z_in=0.0, arc=RADIUS * WRAP, r=RADIUS):
    """eps0 of a wrap of radius r entered at tension t_in with creep z_in and left at t_out."""
    return brentq(lambda e: march(e, t_in, z_in, arc, r)[0] - t_out, -0.05, 0.05, xtol=1e-13)


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
    """Drive, speed loss and per pulley {travel deg: (tension, z [m] or None off
    the wrap)} of a wrap_profile run."""
    loss, wraps, j, drive = None, [{}, {}], -1, None
    for line in open(path):
        if drive is None:
            drive = line.split(",")[0]
        if "speed loss" in line:
            loss = float(line.split("speed loss")[1].split("%")[0]) / 100.0
        elif line.startswith("pulley "):
            j += 1
        elif "|" in line and j >= 0:
            a, b = line.split("|")
            deg, ten = (float(v) for v in a.split())
            n, _, z, _, count = (float(v) for v in b.split())
            # the profile's z > 0 is the body faster than the surface on
            # these clockwise pulleys: the belt leading, the opposite of this
            # model's sign
            wraps[j][deg] = (ten, -z * 1e-6 if count > 0.0 else None)
    return drive, loss, wraps


def check(path, start=None):
    global SPEED
    drive, loss, wraps = read_profile(path)
    pulleys, SPEED = DRIVES[drive]
    eps = []
    for j, w in enumerate(wraps):
        r, arrive, leave = pulleys[j]
        inside = sorted(d for d in w if w[d][1] is not None and math.radians(d) > arrive and d < 270.0)
        deg = inside[0] if start is None else min(inside, key=lambda d: abs(d - start[j % len(start)]))
        t_in, z_in = w[deg]
        # the span it leaves into: the mean SDE tension off the wrap over the
        # 40 deg after the tangent point where the belt leaves
        off = [w[d][0] for d in w if w[d][1] is None and 0 < d - math.degrees(leave) < 40.0]
        t_out = sum(off) / len(off)
        arc = r * (leave - math.radians(deg))
        eps.append(stick_strain(t_in, t_out, z_in, arc, r))
        print(f"pulley {j + 1}: from {deg:.1f} deg, T {t_in:.1f} N, z {z_in * 1e6:+.2f} um (+: lagging)")
    print(f"{path}: speed loss simulated {100 * loss:.4f} %, reduced model {100 * speed_loss(*eps):.4f} %")


if __name__ == "__main__":
    if len(sys.argv) == 1 or sys.argv[1] in DRIVES:
        drive = sys.argv[1] if len(sys.argv) > 1 else "5pk"
        # default tensions: the 1200-body 5PK run and the 480-body 2:1 run
        # (wrap_profile, means over 0.5-0.8 s)
        t = [float(v) for v in sys.argv[2:4]] or {"5pk": [839.6, 284.1], "2to1": [712.7, 338.8]}[drive]
        continuum(drive, *t)
    else:
        check(sys.argv[1], [float(v) for v in sys.argv[2].split(",")] if len(sys.argv) > 2 else None)
