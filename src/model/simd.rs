//! CPU-feature dispatch, in one place: the instruction set is detected once
//! ([`Isa::detected`]) and a kernel runs compiled for it through
//! [`dispatch`] (or [`dispatch_wide`]). This module holds the only
//! `#[target_feature]` functions and the only `unsafe` calls of them, and
//! the x86-64 shuffles that move bodies between the state's layout and the
//! right-hand side's columns.
//!
//! Kernels are leaves: a dispatched kernel calls no other dispatched
//! kernel (the integrators dispatch their vector loops between the calls of
//! the right-hand side, which dispatches itself). Every build performs the
//! same operations (no FMA: it would change rounding), so the results agree
//! to the last bit whatever the CPU (tested per kernel).

use std::sync::OnceLock;

/// An instruction set a kernel is compiled for, narrowest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Isa {
    /// The binary's baseline (SSE2 on x86-64).
    Baseline,
    /// AVX2 (4 doubles per vector).
    Avx2,
    /// AVX-512F (8 doubles per vector).
    Avx512,
}

impl Isa {
    /// The widest instruction set this CPU has, detected on the first call.
    #[inline]
    pub fn detected() -> Self {
        static ISA: OnceLock<Isa> = OnceLock::new();
        *ISA.get_or_init(|| {
            #[cfg(target_arch = "x86_64")]
            {
                if std::arch::is_x86_feature_detected!("avx512f") {
                    return Isa::Avx512;
                }
                if std::arch::is_x86_feature_detected!("avx2") {
                    return Isa::Avx2;
                }
            }
            Isa::Baseline
        })
    }

    /// True if this CPU can run code built for `self`.
    #[inline]
    pub fn available(self) -> bool {
        self <= Self::detected()
    }
}

/// Runs `f` compiled for `isa` (the baseline if the CPU lacks it). For the
/// compiler to build `f`'s body for `isa`, pass a closure marked
/// `#[inline(always)]` whose callees are `#[inline(always)]` too. `f` must
/// not use the AVX shuffles of this module (see [`dispatch_wide`]).
#[inline(always)]
pub fn dispatch<T>(isa: Isa, f: impl FnOnce() -> T) -> T {
    dispatch_with(
        isa,
        (),
        #[inline(always)]
        |()| f(),
    )
}

/// As [`dispatch`], with the kernel's data passed in `args` rather than
/// captured: a closure that captures a `&mut` reaches its data through one
/// more pointer, which can cost the optimiser its view of the data (the
/// factorization measured 2 % more instructions that way).
#[inline(always)]
pub fn dispatch_with<A, T>(isa: Isa, args: A, f: impl FnOnce(A) -> T) -> T {
    match isa {
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 if isa.available() => {
            // SAFETY: the CPU has AVX-512F (checked above).
            unsafe { avx512(args, f) }
        }
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 if isa.available() => {
            // SAFETY: the CPU has AVX2 (checked above).
            unsafe { avx2(args, f) }
        }
        _ => f(args),
    }
}

/// Runs a kernel of two forms on `args`: `narrow` for the baseline (also
/// when the CPU lacks `isa`), `wide` compiled for AVX2 or AVX-512 (it may
/// use the AVX shuffles of this module: [`gather`], [`scatter`] with
/// `WIDE`). Both forms are closures marked `#[inline(always)]` that take
/// their data through `args`, so that they can borrow the same data.
#[inline(always)]
pub fn dispatch_wide<A, T>(
    isa: Isa,
    args: A,
    narrow: impl FnOnce(A) -> T,
    wide: impl FnOnce(A) -> T,
) -> T {
    match isa {
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 if isa.available() => {
            // SAFETY: the CPU has AVX-512F (checked above).
            unsafe { avx512(args, wide) }
        }
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 if isa.available() => {
            // SAFETY: the CPU has AVX2 (checked above).
            unsafe { avx2(args, wide) }
        }
        _ => narrow(args),
    }
}

/// # Safety
/// The CPU has AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn avx2<A, T>(args: A, f: impl FnOnce(A) -> T) -> T {
    f(args)
}

/// # Safety
/// The CPU has AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn avx512<A, T>(args: A, f: impl FnOnce(A) -> T) -> T {
    f(args)
}

/// Values per body in the state vector (`system::BODY_DOF`).
const DOF: usize = 7;

/// Copies `count` consecutive bodies of `src` (`[x, y, phi, vx, vy, omega,
/// z]` each) into the seven columns `cols` at index `d` onwards. Pure data
/// movement: with `WIDE` (only inside a [`dispatch_wide`] wide kernel) four
/// bodies at a time by AVX transposes, then two at a time by SSE2 shuffles
/// on x86-64, element by element elsewhere.
#[inline(always)]
pub(crate) fn gather<const WIDE: bool, const N: usize>(
    cols: [&mut [f64; N]; DOF],
    d: usize,
    src: &[f64],
) {
    let count = src.len() / DOF;
    assert!(d + count <= N && src.len() == count * DOF);
    let [xs, ys, phis, vxs, vys, ws, zs] = cols;
    let mut k = 0;
    #[cfg(target_arch = "x86_64")]
    if WIDE {
        use std::arch::x86_64::{_mm256_loadu_pd, _mm256_storeu_pd};
        while k + 4 <= count {
            // SAFETY: WIDE is set only in the wide kernels of
            // `dispatch_wide`, which run on CPUs with AVX; bodies k..k + 4
            // lie in `src`, columns d + k..d + k + 4 in the arrays
            // (asserted above).
            unsafe {
                let s = src.as_ptr().add(DOF * k);
                let rows = |o: usize| -> [_; 4] {
                    std::array::from_fn(|b| _mm256_loadu_pd(s.add(DOF * b + o)))
                };
                let [x, y, phi, _] = transpose4(rows(0));
                let [vx, vy, w, z] = transpose4(rows(3));
                let at = d + k;
                _mm256_storeu_pd(xs.as_mut_ptr().add(at), x);
                _mm256_storeu_pd(ys.as_mut_ptr().add(at), y);
                _mm256_storeu_pd(phis.as_mut_ptr().add(at), phi);
                _mm256_storeu_pd(vxs.as_mut_ptr().add(at), vx);
                _mm256_storeu_pd(vys.as_mut_ptr().add(at), vy);
                _mm256_storeu_pd(ws.as_mut_ptr().add(at), w);
                _mm256_storeu_pd(zs.as_mut_ptr().add(at), z);
            }
            k += 4;
        }
    }
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_loadu_pd, _mm_shuffle_pd, _mm_storeu_pd};
        while k + 2 <= count {
            let at = d + k;
            // SAFETY: bodies k and k + 1 lie in `src` and columns at,
            // at + 1 in the arrays (both asserted above); SSE2 is part of
            // the x86-64 baseline.
            unsafe {
                let s = src.as_ptr().add(DOF * k);
                // l = (a0 a1) (a2 a3) (a4 a5) (a6 b0) (b1 b2) (b3 b4) (b5 b6)
                let l: [_; DOF] = std::array::from_fn(|i| _mm_loadu_pd(s.add(2 * i)));
                _mm_storeu_pd(xs.as_mut_ptr().add(at), _mm_shuffle_pd(l[0], l[3], 0b10));
                _mm_storeu_pd(ys.as_mut_ptr().add(at), _mm_shuffle_pd(l[0], l[4], 0b01));
                _mm_storeu_pd(phis.as_mut_ptr().add(at), _mm_shuffle_pd(l[1], l[4], 0b10));
                _mm_storeu_pd(vxs.as_mut_ptr().add(at), _mm_shuffle_pd(l[1], l[5], 0b01));
                _mm_storeu_pd(vys.as_mut_ptr().add(at), _mm_shuffle_pd(l[2], l[5], 0b10));
                _mm_storeu_pd(ws.as_mut_ptr().add(at), _mm_shuffle_pd(l[2], l[6], 0b01));
                _mm_storeu_pd(zs.as_mut_ptr().add(at), _mm_shuffle_pd(l[3], l[6], 0b10));
            }
            k += 2;
        }
    }
    for (k, s) in (k..count).zip(src[DOF * k..].chunks_exact(DOF)) {
        let at = d + k;
        xs[at] = s[0];
        ys[at] = s[1];
        phis[at] = s[2];
        vxs[at] = s[3];
        vys[at] = s[4];
        ws[at] = s[5];
        zs[at] = s[6];
    }
}

/// Writes the first `dst.len() / 7` values of the seven columns `cols`
/// into `dst` as bodies of seven values each, the inverse of [`gather`]:
/// with `WIDE` four bodies at a time, then two, then one.
#[inline(always)]
pub(crate) fn scatter<const WIDE: bool>(cols: [&[f64]; DOF], dst: &mut [f64]) {
    let count = dst.len() / DOF;
    assert!(dst.len() == count * DOF && cols.iter().all(|c| c.len() >= count));
    let mut k = 0;
    #[cfg(target_arch = "x86_64")]
    if WIDE {
        use std::arch::x86_64::{_mm256_loadu_pd, _mm256_storeu_pd};
        while k + 4 <= count {
            // SAFETY: WIDE is set only in the wide kernels of
            // `dispatch_wide` (CPUs with AVX); every column holds at least
            // `count` values and bodies k..k + 4 lie in `dst` (asserted
            // above). Two 4 x 4 transposes, of columns 0-3 and 3-6, stored
            // at offsets 0 and 3 of each body (value 3 twice).
            unsafe {
                let col = |i: usize| _mm256_loadu_pd(cols[i].as_ptr().add(k));
                let lo = transpose4([col(0), col(1), col(2), col(3)]);
                let hi = transpose4([col(3), col(4), col(5), col(6)]);
                let o = dst.as_mut_ptr().add(DOF * k);
                for b in 0..4 {
                    _mm256_storeu_pd(o.add(DOF * b), lo[b]);
                    _mm256_storeu_pd(o.add(DOF * b + 3), hi[b]);
                }
            }
            k += 4;
        }
    }
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{
            _mm_loadu_pd, _mm_shuffle_pd, _mm_storeu_pd, _mm_unpackhi_pd, _mm_unpacklo_pd,
        };
        while k + 2 <= count {
            // SAFETY: every column holds at least `count` values (asserted
            // above) and bodies k, k + 1 lie in `dst`; SSE2 is baseline.
            unsafe {
                // c[i] = (a_i b_i)
                let c: [_; DOF] = std::array::from_fn(|i| _mm_loadu_pd(cols[i].as_ptr().add(k)));
                let o = dst.as_mut_ptr().add(DOF * k);
                _mm_storeu_pd(o, _mm_unpacklo_pd(c[0], c[1]));
                _mm_storeu_pd(o.add(2), _mm_unpacklo_pd(c[2], c[3]));
                _mm_storeu_pd(o.add(4), _mm_unpacklo_pd(c[4], c[5]));
                _mm_storeu_pd(o.add(6), _mm_shuffle_pd(c[6], c[0], 0b10));
                _mm_storeu_pd(o.add(8), _mm_unpackhi_pd(c[1], c[2]));
                _mm_storeu_pd(o.add(10), _mm_unpackhi_pd(c[3], c[4]));
                _mm_storeu_pd(o.add(12), _mm_unpackhi_pd(c[5], c[6]));
            }
            k += 2;
        }
    }
    for (k, d) in (k..count).zip(dst[DOF * k..].chunks_exact_mut(DOF)) {
        for (v, col) in d.iter_mut().zip(cols) {
            *v = col[k];
        }
    }
}

/// 4 x 4 transpose: rows (r_i0, r_i1, r_i2, r_i3) to columns.
///
/// # Safety
/// The CPU has AVX.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn transpose4(r: [std::arch::x86_64::__m256d; 4]) -> [std::arch::x86_64::__m256d; 4] {
    use std::arch::x86_64::{_mm256_permute2f128_pd, _mm256_unpackhi_pd, _mm256_unpacklo_pd};
    // SAFETY: the caller guarantees AVX.
    unsafe {
        let t0 = _mm256_unpacklo_pd(r[0], r[1]); // r00 r10 r02 r12
        let t1 = _mm256_unpackhi_pd(r[0], r[1]); // r01 r11 r03 r13
        let t2 = _mm256_unpacklo_pd(r[2], r[3]);
        let t3 = _mm256_unpackhi_pd(r[2], r[3]);
        [
            _mm256_permute2f128_pd(t0, t2, 0x20),
            _mm256_permute2f128_pd(t1, t3, 0x20),
            _mm256_permute2f128_pd(t0, t2, 0x31),
            _mm256_permute2f128_pd(t1, t3, 0x31),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// gather and scatter are inverse, and every build moves the same
    /// values (counts of 0..=9 bodies cover the 4-, 2- and 1-body paths).
    #[test]
    fn gather_scatter_round_trip_in_every_build() {
        for count in 0..=9 {
            let src: Vec<f64> = (0..DOF * count).map(|k| k as f64 * 1.5 - 3.0).collect();
            for isa in [Isa::Baseline, Isa::Avx2, Isa::Avx512] {
                let mut cols = [[f64::NAN; 12]; DOF];
                let mut back = vec![0.0; src.len()];
                dispatch_wide(
                    isa,
                    (&mut cols, src.as_slice()),
                    #[inline(always)]
                    |([a, b, c, d, e, f, g], src)| {
                        gather::<false, 12>([a, b, c, d, e, f, g], 2, src)
                    },
                    #[inline(always)]
                    |([a, b, c, d, e, f, g], src)| {
                        gather::<true, 12>([a, b, c, d, e, f, g], 2, src)
                    },
                );
                for k in 0..count {
                    for i in 0..DOF {
                        assert_eq!(cols[i][2 + k], src[DOF * k + i], "{isa:?} {count}");
                    }
                }
                let view: [&[f64]; DOF] = std::array::from_fn(|i| &cols[i][2..]);
                dispatch_wide(
                    isa,
                    (view, back.as_mut_slice()),
                    #[inline(always)]
                    |(view, back)| scatter::<false>(view, back),
                    #[inline(always)]
                    |(view, back)| scatter::<true>(view, back),
                );
                assert_eq!(back, src, "{isa:?} {count}");
            }
        }
    }

    #[test]
    fn detection_is_consistent() {
        let isa = Isa::detected();
        assert!(isa.available() && Isa::Baseline.available());
        assert_eq!(isa, Isa::detected());
    }
}
