//! The ROS34PW2 tableau (Rang & Angermann 2005, Table 2) and its
//! coefficients in the transformed variables of Hairer & Wanner (Solving
//! ODEs II, IV.7), computed at compile time.

pub(super) const S: usize = 4;
/// ROS34PW2 in the notation of Rang & Angermann (2005), Table 2; gamma is
/// also the diagonal of the iteration matrix, I - h gamma J.
pub const GAMMA: f64 = 4.358_665_215_084_59e-1;
const ALPHA: [[f64; S]; S] = [
    [0.0; 4],
    [8.717_330_430_169_18e-1, 0.0, 0.0, 0.0],
    [
        8.445_706_001_536_942e-1,
        -1.129_906_423_648_418_5e-1,
        0.0,
        0.0,
    ],
    [0.0, 0.0, 1.0, 0.0],
];
const GAMMA_IJ: [[f64; S]; S] = [
    [GAMMA, 0.0, 0.0, 0.0],
    [-8.717_330_430_169_18e-1, GAMMA, 0.0, 0.0],
    [
        -9.033_805_701_304_408e-1,
        5.418_067_238_809_532_6e-2,
        GAMMA,
        0.0,
    ],
    [
        2.421_238_070_609_534_6e-1,
        -1.223_250_583_904_514_7,
        5.452_602_553_351_021e-1,
        GAMMA,
    ],
];
const B: [f64; S] = [
    2.421_238_070_609_534_6e-1,
    -1.223_250_583_904_514_7,
    1.545_260_255_335_102,
    GAMMA,
];
const B_HAT: [f64; S] = [
    3.781_090_314_581_937e-1,
    -9.604_229_221_242_318e-2,
    0.5,
    2.179_332_607_542_295e-1,
];

/// Coefficients in transformed variables: (a, c, m, m - m_hat, alpha_i).
pub(super) struct Transformed {
    pub(super) a: [[f64; S]; S],
    pub(super) c: [[f64; S]; S],
    pub(super) m: [f64; S],
    pub(super) e: [f64; S],
    pub(super) alpha: [f64; S],
}

/// Inverse of the lower-triangular Gamma by forward substitution.
const fn gamma_inverse() -> [[f64; S]; S] {
    let mut inv = [[0.0; S]; S];
    let mut col = 0;
    while col < S {
        let mut i = col;
        while i < S {
            let mut s = if i == col { 1.0 } else { 0.0 };
            let mut k = col;
            while k < i {
                s -= GAMMA_IJ[i][k] * inv[k][col];
                k += 1;
            }
            inv[i][col] = s / GAMMA_IJ[i][i];
            i += 1;
        }
        col += 1;
    }
    inv
}

const fn transformed() -> Transformed {
    let gi = gamma_inverse();
    let mut t = Transformed {
        a: [[0.0; S]; S],
        c: [[0.0; S]; S],
        m: [0.0; S],
        e: [0.0; S],
        alpha: [0.0; S],
    };
    let mut i = 0;
    while i < S {
        let mut j = 0;
        while j < S {
            let mut a = 0.0;
            let mut k = 0;
            while k < S {
                a += ALPHA[i][k] * gi[k][j];
                k += 1;
            }
            t.a[i][j] = a;
            t.c[i][j] = if i == j { 1.0 / GAMMA } else { 0.0 } - gi[i][j];
            t.m[i] += B[j] * gi[j][i];
            t.e[i] += (B[j] - B_HAT[j]) * gi[j][i];
            t.alpha[i] += ALPHA[i][j];
            j += 1;
        }
        i += 1;
    }
    t
}

pub(super) const T: Transformed = transformed();
