//! Branch-free sine, cosine and angle wrap for the right-hand side's
//! vectorised loops (the body angles of eq. 20-23).
//!
//! `sin_cos` reduces the angle by multiples of pi/2 (three-part Cody-Waite
//! constants, exact products for |q| < 2^20, i.e. |x| < 1.6e6 rad) and
//! evaluates minimax polynomials of sin and cos on |r| <= pi/4 (degree 13
//! and 12). The quadrant
//! is applied with bit operations, so a loop over many angles has no
//! branches and no calls and the compiler vectorises it. Agreement with the
//! C library: within 2 ulp of 1 (tested below).

/// 1.5 * 2^52: adding it rounds a double of magnitude < 2^51 to an integer
/// (to nearest, ties to even), which then sits in the low mantissa bits.
const ROUND_MAGIC: f64 = 6_755_399_441_055_744.0;
const TWO_OVER_PI: f64 = std::f64::consts::FRAC_2_PI;
/// pi/2 = P1 + P2 + P3; P1 and P2 have 33 significant bits.
const P1: f64 = 1.570_796_326_734_125_6;
const P2: f64 = 6.077_100_506_303_966e-11;
const P3: f64 = 2.022_266_248_795_950_6e-21;

/// sin(x) and cos(x) for |x| < 1.6e6 (accuracy degrades slowly beyond).
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    let qf = x * TWO_OVER_PI + ROUND_MAGIC;
    let q = qf.to_bits().wrapping_sub(ROUND_MAGIC.to_bits());
    let k = qf - ROUND_MAGIC;
    let r = ((x - k * P1) - k * P2) - k * P3;
    let r2 = r * r;
    // Minimax polynomials on |r| <= pi/4 (docs/fit_sincos.py: Lawson-weighted
    // least squares in 50-digit arithmetic): sin r = r + r^3 S(r^2) with S of
    // degree 5 (within 1 ulp), cos r = 1 - r^2/2 + r^4 C(r^2) with C of
    // degree 4 (within 2 ulp); one and two terms shorter than the Taylor
    // series of the same accuracy.
    let ps = 1.589_623_727_834_754_3e-10;
    let ps = -2.505_074_789_655_876_4e-8 + r2 * ps;
    let ps = 2.755_731_362_232_731_4e-6 + r2 * ps;
    let ps = -1.984_126_982_959_258_5e-4 + r2 * ps;
    let ps = 8.333_333_333_322_123e-3 + r2 * ps;
    let ps = -0.166_666_666_666_666_3 + r2 * ps;
    let s = r + r * r2 * ps;
    let pc = 2.064_773_693_622_93e-9;
    let pc = -2.755_556_711_169_524e-7 + r2 * pc;
    let pc = 2.480_158_097_152_706_3e-5 + r2 * pc;
    let pc = -1.388_888_887_827_387_1e-3 + r2 * pc;
    let pc = 4.166_666_666_660_225e-2 + r2 * pc;
    let c = (1.0 - 0.5 * r2) + (r2 * r2) * pc;
    // quadrant q mod 4: (s, c), (c, -s), (-s, -c), (-c, s)
    let swap = q & 1 != 0;
    let (s0, c0) = if swap { (c, s) } else { (s, c) };
    let sin = f64::from_bits(s0.to_bits() ^ ((q & 2) << 62));
    let cos = f64::from_bits(c0.to_bits() ^ ((q.wrapping_add(1) & 2) << 62));
    (sin, cos)
}

/// `x.round()` (half away from zero) without a library call: branch-free,
/// vectorisable, identical results for every finite x.
#[inline(always)]
pub fn round(x: f64) -> f64 {
    let a = x.abs();
    // to nearest, ties to even (exact for a < 2^52) ...
    let t = (a + 4_503_599_627_370_496.0) - 4_503_599_627_370_496.0;
    // ... then ties away from zero
    let t = if t - a == -0.5 { t + 1.0 } else { t };
    let t = if a < 4_503_599_627_370_496.0 { t } else { a };
    t.copysign(x)
}

/// Angle wrapped to [-pi, pi]: the same value as `a - TAU * (a / TAU).round()`.
#[inline(always)]
pub fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::TAU;
    a - TAU * round(a * (1.0 / TAU))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(x: f64) {
        let (s, c) = sin_cos(x);
        let (s0, c0) = x.sin_cos();
        let tol = 2.0 * f64::EPSILON;
        assert!(
            (s - s0).abs() <= tol && (c - c0).abs() <= tol,
            "x = {x:e}: ({s:e}, {c:e}) vs libm ({s0:e}, {c0:e})"
        );
    }

    #[test]
    fn sin_cos_matches_libm() {
        use std::f64::consts::FRAC_PI_4;
        // quadrant boundaries and their neighbours
        for k in -400..=400 {
            let b = k as f64 * FRAC_PI_4;
            for x in [b, b.next_up(), b.next_down(), b + 1e-9, b - 1e-9] {
                check(x);
            }
        }
        // dense sweep and large angles (belt bodies after many turns)
        let mut x = -20.0;
        while x < 20.0 {
            check(x);
            x += 0.000_37;
        }
        let mut seed = 1u64;
        for _ in 0..200_000 {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
            check((u - 0.5) * 2e5);
            check((u - 0.5) * 2e-3);
        }
        check(0.0);
        check(-0.0);
        check(1e-300);
    }

    #[test]
    fn round_and_wrap_match_std() {
        let mut cases = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            -1.5,
            2.5,
            -2.5,
            0.49999999999999994,
            1e15 + 0.5,
            4503599627370495.5,
            4503599627370496.0,
            9007199254740993.0,
            -7.5e300,
            1e-310,
        ];
        for k in -100..100 {
            let b = k as f64 * 0.25;
            cases.extend([b, b.next_up(), b.next_down()]);
        }
        for x in cases {
            assert_eq!(round(x).to_bits(), x.round().to_bits(), "round({x:e})");
        }
        use std::f64::consts::{PI, TAU};
        for a in [0.0, 1.0, -3.0, PI, -PI, 3.2, -3.2, 7.0, 1e4, -1e4 - 0.3] {
            let r = a - TAU * (a * (1.0 / TAU)).round();
            assert_eq!(wrap_angle(a).to_bits(), r.to_bits(), "wrap_angle({a})");
        }
    }
}
