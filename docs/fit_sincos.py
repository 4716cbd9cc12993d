"""Coefficients of the sin/cos polynomials in src/model/trig.rs.

Minimax fits on [0, pi/4] by Lawson's iteration (weighted least squares whose
weights grow where the error is largest) in 50-digit arithmetic (mpmath):
sin r = r + r^3 S(r^2), relative error; cos r = 1 - r^2/2 + r^4 C(r^2),
absolute error. Prints the coefficients (lowest power first) and the largest
error of the double-precision Horner evaluation the Rust code does.

Run: python3 docs/fit_sincos.py   (needs mpmath and numpy; ~10 s)
"""

import mpmath as mp
import numpy as np

mp.mp.dps = 50
R = mp.pi / 4


def fit(target, powers, npts=200, iters=15):
    """Minimax-like coefficients c_j of sum c_j x^p_j * scale(x) ~ target(x)."""
    xs = [R * (1 - mp.cos(mp.pi * (i + 0.5) / npts)) / 2 for i in range(npts)]
    w = [mp.mpf(1)] * len(xs)
    for _ in range(iters):
        a = mp.matrix(len(xs), len(powers))
        b = mp.matrix(len(xs), 1)
        for i, x in enumerate(xs):
            t, scale = target(x)
            sw = mp.sqrt(w[i])
            for j, p in enumerate(powers):
                a[i, j] = sw * x**p * scale
            b[i] = sw * t
        c = mp.lu_solve(a.T * a, a.T * b)
        errs = []
        for x in xs:
            t, scale = target(x)
            errs.append(abs(t - sum(c[j] * x**p * scale for j, p in enumerate(powers))))
        tot = sum(wi * e for wi, e in zip(w, errs))
        w = [wi * e / tot for wi, e in zip(w, errs)]
    return [float(c[j]) for j in range(len(powers))]


def horner(cs, r2):
    p = cs[-1]
    for c in reversed(cs[:-1]):
        p = c + r2 * p
    return p


def main():
    # relative error of sin: (sin r - r) / sin r against r^p / sin r
    cs = fit(lambda x: ((mp.sin(x) - x) / mp.sin(x), 1 / mp.sin(x)), [3, 5, 7, 9, 11, 13])
    cc = fit(lambda x: (mp.cos(x) - (1 - x * x / 2), 1), [4, 6, 8, 10, 12])
    rs = np.linspace(1e-6, float(R), 20001)
    es = max(
        abs((r + r * r * r * horner(cs, r * r)) - float(mp.sin(r))) / float(mp.sin(r))
        for r in map(float, rs)
    )
    ec = max(
        abs(((1.0 - 0.5 * r * r) + (r * r) ** 2 * horner(cc, r * r)) - float(mp.cos(r)))
        for r in map(float, rs)
    )
    print("sin S:", [repr(c) for c in cs], f"max rel. error {es:.2e} ({es / 2**-53:.1f} half-ulp)")
    print("cos C:", [repr(c) for c in cc], f"max abs. error {ec:.2e} ({ec / 2**-53:.1f} half-ulp)")


if __name__ == "__main__":
    main()
