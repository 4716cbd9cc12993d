//! Degenerate pairs split into span-localised modes before labelling.
//!
//! Two identical spans have (nearly) equal natural frequencies; the
//! eigen-solver then returns any two independent combinations of the two
//! spans' modes, typically the in-phase and the opposite-phase one, each with
//! half its energy in either span, and the label (the part with the most
//! energy) names the same span twice. Within such a pair every combination is
//! a mode (to the pair's tiny frequency split), so the pair is replaced by
//! the two combinations that put the most and the least kinetic energy into
//! one span: the generalised eigenvectors of the 2x2 Hermitian pencil
//! (E_span, E_total) of the energy forms restricted to the pair, which are
//! orthogonal in the total energy. Only pairs of span modes are split: both
//! modes must have more than half their energy in the spans' transverse
//! motion, and the localised combination must put more than half its energy
//! into one span (close pairs of other modes, e.g. slow modes of a drive
//! running near an instability, are not span modes and keep their labels).
//! Pairs whose modes are already localised are left as the solver gave them.

use super::adapter::Linearisation;
use super::{energies, Part, Region};
use faer::c64;

/// Eigenvalues closer than this, relative to their magnitude, form a
/// degenerate pair. Identical spans meet through the pulleys and the wrapped
/// belt only, which splits their transverse modes by far less (see the test
/// in `tests/modes.rs`); distinct spans a few per cent apart in length stay
/// apart.
pub const DEGENERATE_TOLERANCE: f64 = 2e-3;

/// A localised combination replaces the pair only if it puts at least this
/// much more of its energy into one span than the better of the two modes
/// the solver gave.
const GAIN: f64 = 0.05;

/// An eigenpair before labelling: the continuous-time eigenvalue, the
/// eigenvector the energies are taken of, and a shape vector to combine
/// alike (the Floquet analysis' state perturbation; may be empty).
#[derive(Clone, Debug)]
pub struct Candidate {
    /// Eigenvalue (upper half plane).
    pub lambda: c64,
    /// Eigenvector for the energies.
    pub vec: Vec<c64>,
    /// Shape combined with the same coefficients (may be empty).
    pub shape: Vec<c64>,
}

type H2 = [[c64; 2]; 2];

/// Kinetic energy per span (transverse and longitudinal) and in total.
fn span_energies(
    lin: &Linearisation,
    regions: &[Region],
    v: &[c64],
    local: bool,
) -> (Vec<f64>, f64) {
    let mut spans = vec![0.0; lin.pulleys.len().max(1)];
    let mut total = 0.0;
    for (part, e) in energies(lin, regions, v, local) {
        total += e;
        if let Part::SpanTransverse(k) | Part::SpanLongitudinal(k) = part {
            spans[k - 1] += e;
        }
    }
    (spans, total)
}

/// The share of a mode's kinetic energy in the spans' transverse motion.
fn transverse_share(lin: &Linearisation, regions: &[Region], v: &[c64], local: bool) -> f64 {
    let (mut transverse, mut total) = (0.0, 0.0);
    for (part, e) in energies(lin, regions, v, local) {
        total += e;
        if let Part::SpanTransverse(_) = part {
            transverse += e;
        }
    }
    if total > 0.0 {
        transverse / total
    } else {
        0.0
    }
}

fn combine(a: &[c64], b: &[c64], x: [c64; 2]) -> Vec<c64> {
    a.iter()
        .zip(b)
        .map(|(&p, &q)| p * x[0] + q * x[1])
        .collect()
}

/// The 2x2 Hermitian matrices of the span energy forms and of the total on
/// span{v1, v2}, by polarisation: Q(x + y) - Q(x - y) = 4 Re(x^H A y),
/// Q(x + i y) - Q(x - i y) = -4 Im(x^H A y).
fn forms(
    lin: &Linearisation,
    regions: &[Region],
    v1: &[c64],
    v2: &[c64],
    local: bool,
) -> (Vec<H2>, H2) {
    let one = c64::new(1.0, 0.0);
    let i = c64::new(0.0, 1.0);
    let q = |x: [c64; 2]| span_energies(lin, regions, &combine(v1, v2, x), local);
    let (s11, t11) = q([one, c64::new(0.0, 0.0)]);
    let (s22, t22) = q([c64::new(0.0, 0.0), one]);
    let (sp, tp) = q([one, one]);
    let (sm, tm) = q([one, -one]);
    let (sip, tip) = q([one, i]);
    let (sim, tim) = q([one, -i]);
    let h = |a11: f64, a22: f64, p: f64, m: f64, ip: f64, im: f64| -> H2 {
        let a12 = c64::new(0.25 * (p - m), -0.25 * (ip - im));
        [[c64::new(a11, 0.0), a12], [a12.conj(), c64::new(a22, 0.0)]]
    };
    let spans = (0..s11.len())
        .map(|k| h(s11[k], s22[k], sp[k], sm[k], sip[k], sim[k]))
        .collect();
    (spans, h(t11, t22, tp, tm, tip, tim))
}

/// Generalised eigenvectors of the Hermitian pencil (a, t), t positive
/// definite: (largest eigenvalue, its vector, the other vector).
fn pencil(a: &H2, t: &H2) -> Option<(f64, [c64; 2], [c64; 2])> {
    // t = L L^H
    let l11 = t[0][0].re.sqrt();
    let l21 = t[1][0] / l11;
    let l22 = (t[1][1].re - l21.norm_sqr()).sqrt();
    if !(l11 > 0.0 && l22 > 0.0) {
        return None;
    }
    // L^-1 = [[1/l11, 0], [-l21/(l11 l22), 1/l22]]
    let zero = c64::new(0.0, 0.0);
    let li = [
        [c64::new(1.0 / l11, 0.0), zero],
        [-l21 / (l11 * l22), c64::new(1.0 / l22, 0.0)],
    ];
    let mul = |x: &H2, y: &H2| -> H2 {
        let mut r = [[zero; 2]; 2];
        for (i, row) in r.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = x[i][0] * y[0][j] + x[i][1] * y[1][j];
            }
        }
        r
    };
    let lih = [
        [li[0][0].conj(), li[1][0].conj()],
        [li[0][1].conj(), li[1][1].conj()],
    ];
    let b = mul(&mul(&li, a), &lih);
    let (b11, b22, b12) = (b[0][0].re, b[1][1].re, b[0][1]);
    let mean = 0.5 * (b11 + b22);
    let rad = (0.25 * (b11 - b22).powi(2) + b12.norm_sqr()).sqrt();
    let top = mean + rad;
    let y1 = if b12.norm() > 1e-14 * (b11.abs() + b22.abs()) {
        [b12, c64::new(top - b11, 0.0)]
    } else if b11 >= b22 {
        [c64::new(1.0, 0.0), zero]
    } else {
        [zero, c64::new(1.0, 0.0)]
    };
    let y2 = [-y1[1].conj(), y1[0].conj()];
    // x = L^-H y
    let back = |y: [c64; 2]| {
        [
            lih[0][0] * y[0] + lih[0][1] * y[1],
            lih[1][0] * y[0] + lih[1][1] * y[1],
        ]
    };
    Some((top, back(y1), back(y2)))
}

/// The eigenvalue of a combination x of the pair: the pair's eigenvalues
/// weighted by the energy each contributes.
fn weighted(l1: c64, l2: c64, x: [c64; 2], t: &H2) -> c64 {
    let (w1, w2) = (x[0].norm_sqr() * t[0][0].re, x[1].norm_sqr() * t[1][1].re);
    (l1 * w1 + l2 * w2) / (w1 + w2)
}

/// Splits degenerate pairs of `cands` (sorted by |lambda|) into
/// span-localised modes, in place. `local`: the body velocities are in body
/// frames (as for [`energies`]). Returns how many pairs were split.
pub fn localise(
    lin: &Linearisation,
    regions: &[Region],
    cands: &mut [Candidate],
    local: bool,
) -> usize {
    let mut split = 0;
    let mut i = 0;
    while i + 1 < cands.len() {
        let (l1, l2) = (cands[i].lambda, cands[i + 1].lambda);
        if (l1 - l2).norm() > DEGENERATE_TOLERANCE * l1.norm() {
            i += 1;
            continue;
        }
        let (v1, v2) = (&cands[i].vec, &cands[i + 1].vec);
        if transverse_share(lin, regions, v1, local).min(transverse_share(lin, regions, v2, local))
            <= 0.5
        {
            i += 1;
            continue;
        }
        let (spans, t) = forms(lin, regions, v1, v2, local);
        let share = |k: usize, j: usize| spans[k][j][j].re / t[j][j].re;
        let before = (0..spans.len())
            .flat_map(|k| [share(k, 0), share(k, 1)])
            .fold(0.0, f64::max);
        let best = spans
            .iter()
            .filter_map(|a| pencil(a, &t))
            .max_by(|a, b| a.0.total_cmp(&b.0));
        let Some((top, x1, x2)) = best else {
            i += 1;
            continue;
        };
        if top <= 0.5 || top < before + GAIN {
            i += 1;
            continue;
        }
        let (a, b) = (cands[i].clone(), cands[i + 1].clone());
        for (c, x) in cands[i..i + 2].iter_mut().zip([x1, x2]) {
            c.lambda = weighted(l1, l2, x, &t);
            c.vec = combine(&a.vec, &b.vec, x);
            if !a.shape.is_empty() {
                let s = combine(&a.shape, &b.shape, x);
                let big = s
                    .iter()
                    .copied()
                    .max_by(|p, q| p.norm().total_cmp(&q.norm()))
                    .unwrap_or(c64::new(1.0, 0.0));
                c.shape = s.iter().map(|&z| z / big).collect();
            }
        }
        split += 1;
        i += 2;
    }
    split
}
