//! Products of small fixed-size matrices, inlined.
//!
//! nalgebra's `*` on its fixed-size matrices sums each entry in a call per
//! column (`gemm` over `axcpy`) that the compiler leaves out of line: on
//! the accessory drive (`parameters/accessory-drive-4.ssv`, 800 rpm, stiff
//! method) 57 % of the instructions went to those calls from the iteration
//! matrix' bordered factorization and the contact partials. [`mm`] sums
//! each entry in the same order, so it gives the same bits.

use nalgebra::SMatrix;

/// The product `a b`, each entry summed as nalgebra's `gemm` sums it:
/// a_r0 b_0j + a_r1 b_1j + ..., left to right, no fused multiply-add (the
/// same bits as `a * b`), inlined into the caller's loop.
#[inline(always)]
pub fn mm<const R: usize, const K: usize, const C: usize>(
    a: &SMatrix<f64, R, K>,
    b: &SMatrix<f64, K, C>,
) -> SMatrix<f64, R, C> {
    let mut out = SMatrix::<f64, R, C>::zeros();
    for j in 0..C {
        for r in 0..R {
            let mut s = a[(r, 0)] * b[(0, j)];
            for k in 1..K {
                s += a[(r, k)] * b[(k, j)];
            }
            out[(r, j)] = s;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::mm;
    use nalgebra::{Matrix2x3, Matrix3, RowVector2, SMatrix, Vector2};

    /// The same bits as nalgebra's product, on entries whose sums round.
    #[test]
    fn same_bits_as_nalgebra() {
        let x = |k: usize| ((k as f64) * 0.731).sin() * 10f64.powi((k % 7) as i32 - 3);
        let a = Matrix3::from_fn(|r, c| x(3 * r + c));
        let b = SMatrix::<f64, 3, 7>::from_fn(|r, c| x(40 + 7 * r + c));
        assert_eq!(mm(&a, &b), a * b);
        let f = SMatrix::<f64, 7, 3>::from_fn(|r, c| x(90 + 3 * r + c));
        assert_eq!(mm(&f, &b), f * b);
        let u = Vector2::new(x(5), x(6));
        let v = RowVector2::new(x(7), x(8));
        assert_eq!(mm(&u, &v), u * v);
        let j = Matrix2x3::from_fn(|r, c| x(120 + 3 * r + c));
        assert_eq!(mm(&v, &j), v * j);
    }
}
