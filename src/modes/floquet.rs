//! Steady running (docs/modes.md, "Steady running"): the periodic running
//! state and its Floquet modes over one body passage.
//!
//! A running discrete belt is not at an equilibrium: its bodies travel
//! through the spans and wraps, and the state repeats, shifted by one body,
//! after the body-passing period P = l / v (a relative periodic orbit,
//! S y(t + P) = y(t), S the one-body index shift). The linearisation about
//! it is periodic.
//!
//! 1. **Monodromy.** The variational equations Phi' = J(t) Phi over one P
//!    along the drive's own trajectory (by the drive's own integrator): the
//!    analytic Jacobian at `substeps` + 1 instants, the theta method
//!    ([`FLOQUET_THETA`]) between them (sparse LU of I - theta h J per
//!    substep), the model's discrete creep reset (a body that touches no
//!    pulley has z = 0, whatever its perturbation: its row of Phi is
//!    zeroed), composed with S: M = S Phi(P).
//! 2. **How periodic the trajectory is.** The run-up leaves lightly damped
//!    vibrations (span modes, the pulleys' rotation), so the trajectory is
//!    periodic only approximately; [`Orbit::defects`] reports the residual
//!    S y(P) - y(0).
//! 3. **Modes.** The eigenvalues mu of M: the per-substep factor mu^(1/N) (the branch counted by
//!    following each mode's phase v^H Phi(t) v through 8 instants,
//!    unambiguous below 4/P) is mapped back through the theta method's
//!    amplification (1 + (1 - theta) z) / (1 - theta z), z = h lambda,
//!    which removes its numerical damping and phase error (exactly for a
//!    constant Jacobian; to the variation of J within one substep
//!    otherwise).

use super::adapter::{self, Linearisation, BODY_STATES};
use super::{classify, regions, Mode, Modes, Options};
use crate::belt::Drive;
use faer::linalg::solvers::{Eigen, Solve};
use faer::sparse::linalg::matmul::sparse_dense_matmul;
use faer::sparse::{SparseColMat, Triplet};
use faer::{c64, Accum, Mat, Par};
use std::f64::consts::TAU;

/// Implicitness of the theta method that integrates the variational
/// equations: 0.6. At 1/2 (the trapezoidal rule) the bodies' fast
/// artificial modes (pitching at ~1e5 rad/s, omega h >> 1) keep
/// multipliers of modulus ~1 at arbitrary angles and mix into the
/// eigenvectors of the slow modes; at 0.6 each step damps them by 2/3
/// (1e-11 over 64 steps). The numerical damping this gives the slow modes
/// is removed again when the multipliers are mapped back (module doc).
pub const FLOQUET_THETA: f64 = 0.6;

/// Substeps per body-passing period by default.
pub const FLOQUET_SUBSTEPS: usize = 64;

/// The running state the analysis linearised about.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Orbit {
    /// Body-passing period P [s].
    pub period: f64,
    /// How far the trajectory is from periodic: the largest residual of
    /// S y(P) - y(0) over the bodies' positions and velocities and the free
    /// pulleys', decouplers' and arms' states, each in units of its scale
    /// (body length, belt speed, 2 pi / n rad and 2 pi / n times the
    /// fastest pulley speed), of each period integrated.
    pub defects: Vec<f64>,
    /// Tension of the middle element of every free span at the start of
    /// the analysed period [N], span k from pulley k to pulley k+1.
    pub span_tension: Vec<f64>,
    /// Mean speed of the belt bodies at the start [m/s].
    pub belt_speed: f64,
    /// Time at the start of the analysed period [s].
    pub time: f64,
}

impl Orbit {
    /// Defect of the analysed period (the last of [`Self::defects`]).
    pub fn defect(&self) -> f64 {
        self.defects.last().copied().unwrap_or(f64::NAN)
    }
}

/// Body-passing period of the running belt [s] and the direction of travel
/// along the body index (+1: body i takes the place of body i + 1): the
/// bodies on the free spans, where each body covers the distance to its
/// neighbour in one period (on a wrap the chord between centres is shorter
/// than the arc they travel). Infinite at rest.
pub fn passing_period(lin: &Linearisation) -> (f64, f64) {
    let n = lin.n;
    let (mut dist, mut speed, mut dir) = (0.0, 0.0, 0.0);
    let contact: Vec<Option<usize>> = (0..n).map(|i| lin.contact_of(i)).collect();
    let all_free = contact.iter().all(Option::is_none);
    for i in 0..n {
        let k = (i + 1) % n;
        let d = [
            lin.y[lin.body(k, 0)] - lin.y[lin.body(i, 0)],
            lin.y[lin.body(k, 1)] - lin.y[lin.body(i, 1)],
        ];
        let v = [lin.y[lin.body(i, 3)], lin.y[lin.body(i, 4)]];
        dir += v[0] * d[0] + v[1] * d[1];
        if all_free || (contact[i].is_none() && contact[k].is_none()) {
            dist += d[0].hypot(d[1]);
            speed += v[0].hypot(v[1]);
        }
    }
    (dist / speed, dir.signum())
}

/// Sparse `scale * J + diag * I` from the dense row-major Jacobian (the
/// Jacobian of the chain is banded, plus the pulleys' rows and columns).
fn sparse(lin: &Linearisation, scale: f64, diag: f64) -> Result<SparseColMat<usize, f64>, String> {
    let dim = lin.dim;
    let mut entries = Vec::new();
    for r in 0..dim {
        for c in 0..dim {
            let v = scale * lin.jacobian[r * dim + c] + if r == c { diag } else { 0.0 };
            if v != 0.0 {
                entries.push(Triplet::new(r, c, v));
            }
        }
    }
    SparseColMat::try_new_from_triplets(dim, dim, &entries)
        .map_err(|e| format!("sparse Jacobian: {e:?}"))
}

const SAMPLES: usize = 8;

/// The variational equations integrated over one period along the drive's
/// trajectory (the drive advances by the period).
struct Monodromy {
    lin0: Linearisation,
    /// Phi(P), unshifted.
    phi: Mat<f64>,
    /// Phi at 1/8, 2/8, ... 7/8 of the period.
    samples: Vec<Mat<f64>>,
}

fn monodromy(drive: &mut Drive, period: f64, substeps: usize) -> Result<Monodromy, String> {
    let lin0 = adapter::linearise(drive);
    let dim = lin0.dim;
    let t0 = drive.time();
    let h = period / substeps as f64;
    let theta = FLOQUET_THETA;
    let mut phi = Mat::<f64>::identity(dim, dim);
    // (1 - theta) h J_k, sparse
    let mut explicit = sparse(&lin0, (1.0 - theta) * h, 0.0)?;
    let mut samples: Vec<Mat<f64>> = Vec::with_capacity(SAMPLES - 1);
    for s in 1..=substeps {
        adapter::run_to(drive, t0 + s as f64 * h)?;
        let lin = adapter::linearise(drive);
        // (I - theta h J_{k+1}) Phi_{k+1} = (I + (1 - theta) h J_k) Phi_k
        let mut rhs = phi.clone();
        sparse_dense_matmul(
            rhs.as_mut(),
            Accum::Add,
            explicit.as_ref(),
            phi.as_ref(),
            1.0,
            Par::Seq,
        );
        let lu = sparse(&lin, -theta * h, 1.0)?
            .sp_lu()
            .map_err(|e| format!("the variational step matrix is singular: {e:?}"))?;
        lu.solve_in_place(rhs.as_mut());
        if !rhs.as_ref().is_all_finite() {
            return Err("the variational equations diverged".into());
        }
        // The model resets the creep of a body that touches no pulley
        // after every step (`BeltSystem::after_step`): its perturbation too.
        for i in 0..lin.n {
            if lin.contact_of(i).is_none() {
                let r = lin.body(i, 6);
                for c in 0..dim {
                    rhs[(r, c)] = 0.0;
                }
            }
        }
        phi = rhs;
        explicit = sparse(&lin, (1.0 - theta) * h, 0.0)?;
        if s % (substeps / SAMPLES) == 0 && s < substeps {
            samples.push(phi.clone());
        }
    }
    Ok(Monodromy { lin0, phi, samples })
}

/// Where each state goes under the one-body shift S: the body in slot i
/// now sits where the body in slot i + dir sat at the start.
fn shift_map(lin: &Linearisation, dir: f64) -> Vec<usize> {
    let n = lin.n;
    let step = if dir > 0.0 { 1 } else { n - 1 };
    (0..lin.dim)
        .map(|r| {
            if r < BODY_STATES * n {
                let (i, k) = (r / BODY_STATES, r % BODY_STATES);
                lin.body((i + step) % n, k)
            } else {
                r
            }
        })
        .collect()
}

/// The angle a - b in (-pi, pi].
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    if d > std::f64::consts::PI {
        d - TAU
    } else {
        d
    }
}

/// Scale of every state in [`Orbit::defect`] (0: not counted).
fn scales(lin: &Linearisation) -> Vec<f64> {
    let n = lin.n as f64;
    let speed = (0..lin.n)
        .map(|i| lin.y[lin.body(i, 3)].hypot(lin.y[lin.body(i, 4)]))
        .sum::<f64>()
        / n;
    let dphi = TAU / n;
    let w_max = lin
        .pulleys
        .iter()
        .map(|p| p.omega.abs())
        .fold(1.0, f64::max);
    let mut s = vec![0.0; lin.dim];
    for i in 0..lin.n {
        for k in [0, 1] {
            s[lin.body(i, k)] = lin.body_length;
            s[lin.body(i, k + 3)] = speed.max(1e-3);
        }
    }
    for (j, p) in lin.pulleys.iter().enumerate() {
        if !p.speed_driven {
            s[lin.pulley(j).1] = w_max * dphi;
        }
        for (o, _) in p.arm.iter().chain(p.decoupler.iter()) {
            s[*o] = dphi;
            s[o + 1] = w_max * dphi;
        }
    }
    s
}

/// Residual of periodicity S y_end - y0 on the states that repeat
/// ([`Linearisation::periodic_states`]), zero on the others.
fn residual(lin: &Linearisation, to: &[usize], y0: &[f64], end: &[f64]) -> Vec<f64> {
    let mut ys = vec![0.0; end.len()];
    for (r, &x) in end.iter().enumerate() {
        ys[to[r]] = x;
    }
    let mut out = vec![0.0; y0.len()];
    for r in lin.periodic_states() {
        out[r] = if r < BODY_STATES * lin.n && r % BODY_STATES == 2 {
            angle_diff(ys[r], y0[r])
        } else {
            ys[r] - y0[r]
        };
    }
    out
}

fn scaled_max(x: &[f64], scale: &[f64]) -> f64 {
    x.iter()
        .zip(scale)
        .filter(|(_, &s)| s > 0.0)
        .map(|(x, s)| (x / s).abs())
        .fold(0.0, f64::max)
}

/// Floquet analysis of steady running (module doc, steps 1 and 3) about
/// the drive's trajectory over one period from its current state (the
/// drive advances by the period). The result's `orbit` reports the period
/// and how far the trajectory is from periodic.
///
/// Errors: a drive at rest (no period), a failed run, a failed eigen-solve.
pub fn floquet(drive: &mut Drive, opts: &Options, substeps: usize) -> Result<Modes, String> {
    let substeps = substeps.div_ceil(SAMPLES).max(1) * SAMPLES;
    let lin = adapter::linearise(drive);
    let (period, dir) = passing_period(&lin);
    if !period.is_finite() || period >= 1.0 || period <= 0.0 {
        return Err("the belt is not running (under one body passing per second)".into());
    }
    let to = shift_map(&lin, dir);
    let y0 = drive.state().to_vec();
    let t0 = drive.time();
    let (span_tension, belt_speed) = adapter::span_tensions_and_speed(drive);
    let mono = monodromy(drive, period, substeps)?;
    let r = residual(&lin, &to, &y0, drive.state());
    let defect = scaled_max(&r, &scales(&lin));
    let dim = lin.dim;
    let mut m = Mat::<f64>::zeros(dim, dim);
    for rr in 0..dim {
        for c in 0..dim {
            m[(to[rr], c)] = mono.phi[(rr, c)];
        }
    }
    let evd = Eigen::new_from_real(m.as_ref())
        .map_err(|e| format!("eigen-decomposition failed: {e:?}"))?;
    let mut out = floquet_modes(&mono, &evd, period, substeps, opts)?;
    out.orbit = Some(Orbit {
        period,
        defects: vec![defect],
        span_tension,
        belt_speed,
        time: t0,
    });
    Ok(out)
}

/// Modes from the monodromy matrix (module doc, step 3).
fn floquet_modes(
    mono: &Monodromy,
    evd: &Eigen<f64>,
    period: f64,
    substeps: usize,
    opts: &Options,
) -> Result<Modes, String> {
    let lin0 = &mono.lin0;
    let (dim, n) = (lin0.dim, lin0.n);
    let w_zero = TAU * opts.zero_frequency_hz;
    let h = period / substeps as f64;
    let theta = FLOQUET_THETA;
    let mut out = Modes {
        reduced_dim: dim,
        body_rate: 1.0 / period,
        ..Modes::default()
    };
    let regions = regions(lin0);
    let (s, u) = (evd.S(), evd.U());
    // v^H Phi(t) v at every sampled instant for the eigenvectors v that
    // can be modes: one of each conjugate pair, |mu| above 1e-8 (a motion
    // that decays by 1e-8 within one body passage is counted as overdamped).
    let candidates: Vec<usize> = (0..dim)
        .filter(|&k| s[k].im > 0.0 && s[k].re.hypot(s[k].im) > 1e-8)
        .collect();
    let (ure, uim) = (
        Mat::<f64>::from_fn(dim, candidates.len(), |r, c| u[(r, candidates[c])].re),
        Mat::<f64>::from_fn(dim, candidates.len(), |r, c| u[(r, candidates[c])].im),
    );
    let mut phase: Vec<Vec<c64>> = vec![Vec::new(); dim];
    for ph in &mono.samples {
        let (yre, yim) = (ph * &ure, ph * &uim);
        for (c, &k) in candidates.iter().enumerate() {
            let mut p = c64::new(0.0, 0.0);
            for r in 0..dim {
                p += u[(r, k)].conj() * c64::new(yre[(r, c)], yim[(r, c)]);
            }
            phase[k].push(p);
        }
    }
    let mut vec = vec![c64::new(0.0, 0.0); dim];
    for k in 0..dim {
        let mu = s[k];
        let (r, arg) = (mu.re.hypot(mu.im), mu.im.atan2(mu.re));
        if arg < 0.0 {
            continue; // the conjugate of a pair counted below
        }
        let sigma = r.ln() / period;
        if arg == 0.0 || !sigma.is_finite() || r <= 1e-8 {
            if sigma.is_finite() && sigma.abs() < w_zero {
                out.zero_modes += 1;
            } else {
                out.overdamped += 1;
            }
            continue;
        }
        for (row, x) in vec.iter_mut().enumerate() {
            *x = u[(row, k)];
        }
        // Phase of v^H Phi(t) v through the period, ending at mu |v|^2.
        let norm2: f64 = vec.iter().map(|x| x.norm_sqr()).sum();
        let mut prev = c64::new(norm2, 0.0);
        let mut turned = 0.0;
        for &p in phase[k].iter().chain(std::iter::once(&(mu * norm2))) {
            turned += (p * prev.conj()).arg();
            prev = p;
        }
        let turns = ((turned - arg) / TAU).round();
        // per-substep factor, then back through the theta method's
        // amplification g(z) = (1 + (1 - theta) z) / (1 - theta z)
        let per_step = c64::from_polar(
            r.powf(1.0 / substeps as f64),
            (arg + TAU * turns) / substeps as f64,
        );
        let den = c64::new(1.0 - theta, 0.0) + per_step * theta;
        if den.norm() < 1e-12 {
            out.overdamped += 1;
            continue;
        }
        let lambda = (per_step - 1.0) / den / h;
        let mag = lambda.norm();
        if mag < w_zero {
            out.zero_modes += 1;
            continue;
        }
        if lambda.im.abs() < 1e-9 * mag {
            out.overdamped += 1;
            continue;
        }
        if mag / TAU > opts.max_frequency_hz {
            out.above_limit += 1;
            continue;
        }
        // Described without the bodies' spin: the theta method has damped
        // the artificial pitching modes away (they end as overdamped), and
        // in a running belt a slow mode's spin perturbation is dominated by
        // the bodies at the wrap ends, whose spin jumps between 0 and v/r
        // there, so a small shift of the entry point carries a large spin
        // energy that is not pitching.
        for i in 0..n {
            vec[lin0.body(i, 5)] = c64::new(0.0, 0.0);
        }
        let (part, share) = classify(lin0, &regions, &vec, false);
        out.modes.push(Mode {
            frequency_hz: mag / TAU,
            damping_ratio: -lambda.re / mag,
            damped_hz: lambda.im.abs() / TAU,
            part,
            share,
        });
    }
    out.modes
        .sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
    Ok(out)
}
