//! Steady running (docs/modes.md, "Steady running"): the periodic running
//! state and its Floquet modes over one body passage.
//!
//! A running discrete belt is not at an equilibrium: its bodies travel
//! through the spans and wraps, and the state repeats, shifted by one body,
//! after the body-passing period P = l / v (a relative periodic orbit,
//! S y(t + P) = y(t), S the one-body index shift). The linearisation about
//! it is periodic.
//!
//! 1. **Trajectory.** The analysis runs its own copy of the drive, by the
//!    method `solver.method` selects at the tolerances [`ORBIT_REL_TOL`],
//!    [`ORBIT_ABS_TOL`] (the set's if tighter): at the run's relTol 1e-4 the
//!    integration error alone leaves S y(P) - y(0) at a few 1e-2. The stiff
//!    method runs without its energy check: its rejections make the step
//!    sequence, and so the flow map, jump with the state.
//! 2. **Periodic orbit** ([`settle`]). The run-up leaves lightly damped
//!    vibrations (span modes, the pulleys' rotation) that decay over
//!    seconds. Each period is timed by a Poincaré section: it ends when the
//!    body that takes a reference body's place (on the crank's wrap)
//!    reaches the line from the pulley centre through where that body was,
//!    so P is the orbit's own (the belt speed on the spans at one instant
//!    moves with their vibrations: by 4 % on the accessory drive after its
//!    run-up, which left the defect at 0.1). The states y_j = S^j y(t_j)
//!    at [`SETTLE_PERIODS`]
//!    successive periods are combined by reduced rank extrapolation (the
//!    weights, summing to 1, that make the combined period-to-period
//!    differences least; exact for a linear map with fewer slow modes than
//!    periods), the drive restarted from the combination, up to
//!    [`SETTLE_CYCLES`] times until the defect is below [`ORBIT_TOL`]. It
//!    needs no monodromy: a Newton step from the monodromy's eigenvectors
//!    diverged (they are far from orthogonal, and the bodies' angles, spins
//!    and creep jump at the wrap ends).
//! 3. **Monodromy.** The variational equations Phi' = J(t) Phi over one P
//!    from the periodic state, in `substeps` steps of Alexander's two-stage
//!    SDIRK method (second order, L-stable: [`SDIRK_GAMMA`]) with the
//!    analytic Jacobian at each stage's instant (sparse LU of I - g h J per
//!    stage), with the model's discrete creep reset (a body that touches
//!    no pulley has z = 0, whatever its perturbation: its row of Phi is
//!    zeroed), composed with S: M = S Phi(P). Second order, the damping
//!    ratios converge with the substeps (a first-order theta method (0.6)
//!    leaves them moving by a factor 2 between 64 and 192 substeps);
//!    L-stable, the bodies' fast pitching modes (omega h >> 1) are damped
//!    out within the period instead of keeping multipliers of modulus ~1.
//! 4. **Modes.** The eigenvalues mu of M: the per-substep factor mu^(1/N),
//!    its branch (whole turns within P) the one nearest the eigenvector's
//!    own frequency (its velocities against its displacements), mapped
//!    back through the method's amplification R(z) = (1 + (1 - 2g) z) /
//!    (1 - g z)^2, z = h lambda, which removes its numerical damping and
//!    phase error (exactly for a constant Jacobian; to the variation of J
//!    within one substep otherwise).

use super::adapter::{self, Linearisation, BODY_STATES};
use super::degenerate::{localise, Candidate};
use super::{classify, regions, Mode, Modes, Options};
use crate::drive::Window;
use crate::model::params::MAX_PULLEYS;
use crate::Drive;
use faer::linalg::solvers::{Eigen, Solve};
use faer::sparse::linalg::solvers::Lu;
use faer::sparse::{SparseColMat, Triplet};
use faer::{c64, Mat};
use std::f64::consts::TAU;

/// Substeps per body-passing period by default: 128. On the accessory
/// drive at idle 64 substeps missed its unstable span mode (184 Hz,
/// zeta -0.018 at 128 and 256 substeps and in the time domain; docs/modes.md).
pub const FLOQUET_SUBSTEPS: usize = 128;

/// The running state the analysis linearised about.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Orbit {
    /// Body-passing period P [s].
    pub period: f64,
    /// How far the trajectory is from periodic: the largest residual of
    /// S y(P) - y(0) over the bodies' positions and velocities and the free
    /// pulleys', decouplers' and arms' states, each in units of its scale
    /// (body length, belt speed, 2 pi / n rad and 2 pi / n times the
    /// fastest pulley speed): of the first period of each extrapolation of
    /// [`settle`], then of the period analysed (the last).
    pub defects: Vec<f64>,
    /// Tension of the middle element of every free span averaged over the
    /// analysed period (trapezoidal rule over its substeps) [N], span k
    /// from pulley k to pulley k+1: the tension ripples with the bodies'
    /// passage, so one instant is not the span's steady tension.
    pub span_tension: Vec<f64>,
    /// Mean speed of the belt bodies, averaged over the period like the
    /// tensions [m/s].
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

/// Body-passing period of the running belt at one instant [s] and the
/// direction of travel along the body index (+1: body i takes the place of
/// body i + 1): the bodies on the free spans, where each body covers the
/// distance to its neighbour in one period (on a wrap the chord between
/// centres is shorter than the arc they travel), with their speed along
/// that chord (a span's transverse vibration does not count). An estimate:
/// the analysis times the periods by a Poincaré section. Infinite at rest.
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
            let len = d[0].hypot(d[1]);
            dist += len;
            speed += (v[0] * d[0] + v[1] * d[1]).abs() / len;
        }
    }
    (dist / speed, dir.signum())
}

/// Sparse `scale * J + diag * I` from the dense row-major Jacobian (the
/// Jacobian of the chain is banded, plus the pulleys' rows and columns).
pub(super) fn sparse(
    lin: &Linearisation,
    scale: f64,
    diag: f64,
) -> Result<SparseColMat<usize, f64>, String> {
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

/// The variational equations integrated over one period along the drive's
/// trajectory (the drive advances by the period).
struct Monodromy {
    lin0: Linearisation,
    /// Phi(P), unshifted.
    phi: Mat<f64>,
    /// Span tensions and belt speed averaged over the period ([`Orbit`]).
    span_tension: Vec<f64>,
    belt_speed: f64,
}

/// The monodromy over one `period` from the drive's state now, its
/// Jacobians with arm j's pivot friction replaced by a damper
/// `equivalent[j]` where given ([`adapter::linearise_with`]).
fn monodromy(
    drive: &mut Drive,
    period: f64,
    substeps: usize,
    equivalent: &[Option<f64>; MAX_PULLEYS],
) -> Result<Monodromy, String> {
    let lin0 = adapter::linearise_with(drive, equivalent);
    let dim = lin0.dim;
    let t0 = drive.time();
    let h = period / substeps as f64;
    let g = SDIRK_GAMMA;
    // LU of I - g h J at the drive's state now (sparse: the chain's
    // Jacobian is banded, plus the pulleys' rows and columns)
    let step_matrix = |drive: &Drive| {
        let lin = adapter::linearise_with(drive, equivalent);
        let lu = sparse(&lin, -g * h, 1.0)?
            .sp_lu()
            .map_err(|e| format!("the variational step matrix is singular: {e:?}"))?;
        Ok::<_, String>((lin, lu))
    };
    let mut phi = Mat::<f64>::identity(dim, dim);
    // trapezoidal means over the period: half weight at both ends
    let (mut tension, mut speed) = adapter::span_tensions_and_speed(drive);
    tension.iter_mut().for_each(|t| *t *= 0.5);
    speed *= 0.5;
    for s in 1..=substeps {
        // the stages' Jacobians, at t + g h and t + h
        adapter::run_to(drive, t0 + (s as f64 - 1.0 + g) * h)?;
        let (_, lu1) = step_matrix(drive)?;
        adapter::run_to(drive, t0 + s as f64 * h)?;
        let (lin, lu2) = step_matrix(drive)?;
        sdirk_step(&mut phi, &lu1, &lu2);
        if !phi.as_ref().is_all_finite() {
            return Err("the variational equations diverged".into());
        }
        // The model resets the creep of a body that touches no pulley
        // after every step (`BeltSystem::after_step`): its perturbation too.
        for i in 0..lin.n {
            if lin.contact_of(i).is_none() {
                let r = lin.body(i, 6);
                for c in 0..dim {
                    phi[(r, c)] = 0.0;
                }
            }
        }
        let (t, v) = adapter::span_tensions_and_speed(drive);
        let w = if s == substeps { 0.5 } else { 1.0 };
        tension.iter_mut().zip(&t).for_each(|(a, b)| *a += w * b);
        speed += w * v;
    }
    let n = substeps as f64;
    tension.iter_mut().for_each(|t| *t /= n);
    Ok(Monodromy {
        lin0,
        phi,
        span_tension: tension,
        belt_speed: speed / n,
    })
}

/// One step of Alexander's two-stage SDIRK method ([`SDIRK_GAMMA`]) for
/// the linear x' = J(t) x, on the columns of `x`: (I - g h J1) Y1 = x, then
/// (I - g h J2) Y2 = x + (1 - g)/g (Y1 - x), and x(t + h) = Y2 (the method
/// is stiffly accurate). `lu1`, `lu2`: the factored I - g h J at t + g h
/// and at t + h.
pub(super) fn sdirk_step(x: &mut Mat<f64>, lu1: &Lu<usize, f64>, lu2: &Lu<usize, f64>) {
    let b = (1.0 - SDIRK_GAMMA) / SDIRK_GAMMA;
    let mut y1 = x.clone();
    lu1.solve_in_place(y1.as_mut());
    for c in 0..x.ncols() {
        for r in 0..x.nrows() {
            x[(r, c)] = (1.0 - b) * x[(r, c)] + b * y1[(r, c)];
        }
    }
    lu2.solve_in_place(x.as_mut());
}

/// g = 1 - 1/sqrt(2) of Alexander's two-stage SDIRK method that integrates
/// the variational equations (second order, L-stable, stiffly accurate:
/// R(z) = (1 + (1 - 2g) z) / (1 - g z)^2 tends to 0 as z grows, so the
/// bodies' fast pitching modes die out within the period).
pub const SDIRK_GAMMA: f64 = 1.0 - std::f64::consts::FRAC_1_SQRT_2;

/// z = h lambda with R(z) = m, R(z) = (1 + (1 - 2g) z) / (1 - g z)^2 the
/// SDIRK2 amplification: the root that tends to 0 as m tends to 1.
fn sdirk_inverse(m: c64) -> Option<c64> {
    let g = SDIRK_GAMMA;
    // m g^2 z^2 - (2 m g + 1 - 2 g) z + (m - 1) = 0
    let a = m * (g * g);
    let b = -(m * (2.0 * g) + (1.0 - 2.0 * g));
    let c = m - 1.0;
    let disc = (b * b - a * c * 4.0).sqrt();
    // q = -(b + sign disc)/2 with the sign that avoids cancellation
    let q = if (b.conj() * disc).re >= 0.0 {
        (b + disc) * -0.5
    } else {
        (b - disc) * -0.5
    };
    if q.norm() == 0.0 {
        return None;
    }
    // the small root c / q
    Some(c / q)
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

/// Relative tolerance of the analysis' own runs (the settling and the
/// period of the variational equations), by the method `solver.method`
/// selects (or the set's tolerance if tighter).
pub const ORBIT_REL_TOL: f64 = 1e-6;

/// The orbit counts as periodic when its defect ([`Orbit::defects`]) is
/// below this (the settling stops there).
pub const ORBIT_TOL: f64 = 1e-3;

/// Periods combined per extrapolation in [`settle`].
pub const SETTLE_PERIODS: usize = 30;

/// Most extrapolations in [`settle`].
pub const SETTLE_CYCLES: usize = 6;

/// Absolute tolerance of those runs.
pub const ORBIT_ABS_TOL: f64 = 1e-8;

/// A copy of `run` (parameters, time, state, inputs, arms' free angles) that
/// integrates by the same method at the analysis' tolerances
/// ([`ORBIT_REL_TOL`], [`ORBIT_ABS_TOL`]); the stiff method without its
/// energy check ([`Drive::set_energy_check`]): at relTol 1e-6 the error norm
/// alone is accurate, and the settling's extrapolation needs a flow map
/// smooth in the state, which the check's rejections make jump.
fn orbit_drive(run: &Drive) -> Result<Drive, String> {
    let mut p = run.params().clone();
    p.solver.rel_tol = p.solver.rel_tol.min(ORBIT_REL_TOL);
    p.solver.abs_tol = p.solver.abs_tol.min(ORBIT_ABS_TOL);
    let mut drive =
        Drive::mounted(&p, run.time()).map_err(|e| crate::fmu::names::render_error(&e))?;
    drive.set_energy_check(false);
    if !drive.set_arm_free_angles(&run.arm_free_angles()) {
        return Err("the tensioner arms' free angles do not fit".into());
    }
    let window = Window {
        start: run.time(),
        omega_change: [0.0; MAX_PULLEYS],
    };
    let data = drive.integrator_data();
    let (h, stats) = (p.solver.initial_step, drive.stats());
    if drive.restore(
        run.time(),
        run.state(),
        window,
        *run.inputs(),
        h,
        stats,
        &data,
    ) {
        Ok(drive)
    } else {
        Err("the state does not fit the drive".into())
    }
}

/// The Poincaré section that times each period: the line from a pulley
/// centre through the body in the middle of that pulley's wrap at the start.
/// A period ends when the body taking that body's place crosses the line, so
/// the period is the orbit's own, not an estimate from one instant (the
/// belt speed on the spans moves with their vibrations, by 4 % on the
/// accessory drive after its run-up).
#[derive(Clone, Copy, Debug)]
struct Section {
    centre: [f64; 2],
    angle: f64,
    /// +1 if the bodies cross it counterclockwise about `centre`.
    sense: f64,
    /// The body on the line at the start.
    body: usize,
    /// Index step to the body that takes a body's place after one period.
    step: usize,
}

impl Section {
    /// On the wrap of the first speed-driven pulley (the crank, whose
    /// surface moves steadily), else of the first pulley with a wrap.
    fn new(lin: &Linearisation, dir: f64) -> Option<Self> {
        let n = lin.n;
        let np = lin.pulleys.len();
        let order = (0..np)
            .filter(|&j| lin.pulleys[j].speed_driven)
            .chain((0..np).filter(|&j| !lin.pulleys[j].speed_driven));
        for j in order {
            let on = |i: usize| lin.contact_of(i % n) == Some(j);
            // the first body of the wrap's run, then its middle
            let Some(first) = (0..n).find(|&i| on(i) && !on(i + n - 1)) else {
                continue;
            };
            let len = (0..n).take_while(|&k| on(first + k)).count();
            let body = (first + len / 2) % n;
            let centre = lin.pulleys[j].centre;
            let (x, y) = (lin.y[lin.body(body, 0)], lin.y[lin.body(body, 1)]);
            let (vx, vy) = (lin.y[lin.body(body, 3)], lin.y[lin.body(body, 4)]);
            let (rx, ry) = (x - centre[0], y - centre[1]);
            let cross = rx * vy - ry * vx;
            if cross == 0.0 {
                continue;
            }
            return Some(Self {
                centre,
                angle: ry.atan2(rx),
                sense: cross.signum(),
                body,
                step: if dir > 0.0 { n - 1 } else { 1 },
            });
        }
        None
    }

    /// Angle of `body` past the line in its direction of travel [rad].
    fn past(&self, y: &[f64], body: usize) -> f64 {
        let o = BODY_STATES * body;
        let a = (y[o + 1] - self.centre[1]).atan2(y[o] - self.centre[0]);
        self.sense * angle_diff(a, self.angle)
    }

    /// Runs the drive until the body that takes `body`'s place crosses the
    /// line (`guess`: the period expected); returns that body.
    fn next(&self, drive: &mut Drive, body: usize, guess: f64) -> Result<usize, String> {
        let next = (body + self.step) % drive.system().n_bodies();
        let t0 = drive.time();
        adapter::run_to(drive, t0 + 0.8 * guess)?;
        if self.past(drive.state(), next) >= 0.0 {
            return Err("the belt ran more than one body pitch in 0.8 periods".into());
        }
        let h = guess / 32.0;
        loop {
            let before = drive.clone();
            let ga = self.past(before.state(), next);
            adapter::run_to(drive, before.time() + h)?;
            let gb = self.past(drive.state(), next);
            if gb >= 0.0 {
                // the crossing by the secant, twice (the body moves smoothly
                // with its pulley: the second lands within ~1e-10 P)
                let rate = (gb - ga) / h;
                let mut t = before.time() - ga / rate;
                for _ in 0..2 {
                    *drive = before.clone();
                    adapter::run_to(drive, t)?;
                    t -= self.past(drive.state(), next) / rate;
                    if t <= before.time() {
                        break;
                    }
                }
                return Ok(next);
            }
            if drive.time() > t0 + 1.5 * guess {
                return Err("no body crossed the period's section within 1.5 periods".into());
            }
        }
    }
}

/// Runs the drive over one period (to the section) and returns S y(P) on
/// the periodic states (the bodies' angles unwrapped against y(0)), y(0) on
/// the others, and the body now on the section.
fn one_period(
    drive: &mut Drive,
    lin: &Linearisation,
    section: &Section,
    body: usize,
    guess: f64,
    to: &[usize],
) -> Result<(Vec<f64>, usize), String> {
    let y0 = drive.state().to_vec();
    let next = section.next(drive, body, guess)?;
    let r = residual(lin, to, &y0, drive.state());
    Ok((y0.iter().zip(&r).map(|(a, b)| a + b).collect(), next))
}

/// Brings the drive onto its periodic running state by reduced rank
/// extrapolation (module doc, step 2): at most `cycles` times, `k` periods
/// run and the combination of the period-sampled states (shifted, weights
/// summing to 1) whose period-to-period differences are least taken as the
/// new state; stops when a cycle's first period is periodic within
/// [`ORBIT_TOL`]. Returns the defect of each cycle's first period.
pub fn settle(drive: &mut Drive, cycles: usize, k: usize) -> Result<Vec<f64>, String> {
    let mut defects = Vec::new();
    for _ in 0..cycles {
        let lin = adapter::linearise(drive);
        let (mut period, dir) = passing_period(&lin);
        if !period.is_finite() || period >= 1.0 || period <= 0.0 {
            return Err("the belt is not running (under one body passing per second)".into());
        }
        let to = shift_map(&lin, dir);
        let section = Section::new(&lin, dir).ok_or("no belt body touches a pulley")?;
        let mut body = section.body;
        let scale = scales(&lin);
        let periodic = lin.periodic_states();
        // x_0 = y(t0), x_j = S^j y(t0 + j P) in the labelling of x_0
        let mut xs: Vec<Vec<f64>> = vec![drive.state().to_vec()];
        let mut perm: Vec<usize> = (0..lin.dim).collect(); // S^j as a map
        for _ in 0..k {
            let lin_now = adapter::linearise(drive);
            let t = drive.time();
            let (end, next) = one_period(drive, &lin_now, &section, body, period, &to)?;
            (body, period) = (next, drive.time() - t);
            // `end` is S y(t + P) in the labelling of y(t); map to x_0's
            let mut x = vec![0.0; lin.dim];
            for (r, &v) in end.iter().enumerate() {
                x[perm[r]] = v;
            }
            perm = perm.iter().map(|&p| to[p]).collect();
            // the bodies' angles continuous from one sample to the next
            let prev = &xs[xs.len() - 1];
            for i in 0..lin.n {
                let a = lin.body(i, 2);
                x[a] = prev[a] + angle_diff(x[a], prev[a]);
            }
            xs.push(x);
        }
        let d0: Vec<f64> = xs[1].iter().zip(&xs[0]).map(|(a, b)| a - b).collect();
        defects.push(scaled_max(&d0, &scale));
        if defects[defects.len() - 1] < ORBIT_TOL {
            break;
        }
        // differences u_j = x_{j+1} - x_j on the smooth states, scaled
        let rows: Vec<usize> = periodic
            .iter()
            .copied()
            .filter(|&st| scale[st] > 0.0)
            .collect();
        let u = Mat::<f64>::from_fn(rows.len(), k, |i, j| {
            let st = rows[i];
            (xs[j + 1][st] - xs[j][st]) / scale[st]
        });
        // min |U g| with sum g = 1: g = c / sum c, (U^T U) c = 1, by SVD
        let svd = u.thin_svd().map_err(|e| format!("svd: {e:?}"))?;
        let sv = svd.S().column_vector();
        let smax = (0..sv.nrows()).map(|i| sv[i]).fold(0.0, f64::max);
        let mut c = vec![0.0; k];
        for q in 0..sv.nrows() {
            if sv[q] > 1e-10 * smax {
                let w: f64 = (0..k).map(|j| svd.V()[(j, q)]).sum::<f64>() / (sv[q] * sv[q]);
                for (j, cj) in c.iter_mut().enumerate() {
                    *cj += svd.V()[(j, q)] * w;
                }
            }
        }
        let total: f64 = c.iter().sum();
        let g: Vec<f64> = c.iter().map(|x| x / total).collect();
        // the extrapolated state in x_0's labelling, then in the drive's
        // (its slot st is slot perm[st] of x_0's)
        let mut s = xs[k].clone();
        for &st in &periodic {
            s[st] = (0..k).map(|j| g[j] * xs[j][st]).sum();
        }
        let mut y = drive.state().to_vec();
        for &st in &periodic {
            y[st] = if st < BODY_STATES * lin.n && st % BODY_STATES == 2 {
                y[st] + angle_diff(s[perm[st]], y[st])
            } else {
                s[perm[st]]
            };
        }
        let cap = drive.params().friction.creep_max * 1.5;
        let lin_now = adapter::linearise(drive);
        for i in 0..lin.n {
            let z = lin.body(i, 6);
            y[z] = if lin_now.contact_of(i).is_some() {
                y[z].clamp(-cap, cap)
            } else {
                0.0
            };
        }
        adapter::set_state(drive, &y)?;
    }
    Ok(defects)
}

/// Floquet analysis of steady running (module doc) from the running state
/// of `run` (not advanced: the analysis integrates its own copy). The
/// result's `orbit` reports the period and how far the analysed trajectory
/// is from periodic (not an error: check `Orbit::defect`).
///
/// Errors: a drive at rest (no period), a failed run, a failed eigen-solve.
pub fn floquet(run: &Drive, opts: &Options, substeps: usize) -> Result<Modes, String> {
    let (drive, defects) = settled(run)?;
    floquet_settled(&drive, defects, opts, substeps)
}

/// [`floquet`] of the drive `p` run from rest to time `at` (the modes
/// tool's steady running: [`super::params::at_crank_speed`] gives `at`),
/// with [`FLOQUET_SUBSTEPS`].
pub fn after_run_up(p: &crate::DriveParams, at: f64, opts: &Options) -> Result<Modes, String> {
    let mut drive = adapter::build(p)?;
    adapter::run_to(&mut drive, at)?;
    floquet(&drive, opts, FLOQUET_SUBSTEPS)
}

/// A copy of the running drive `run` at the analysis' tolerances, settled
/// onto its periodic running state ([`settle`]), and the settling's
/// defects: the state [`floquet`] linearises about (e.g. to follow the
/// drive from there in the time domain).
pub fn settled(run: &Drive) -> Result<(Drive, Vec<f64>), String> {
    let mut drive = orbit_drive(run)?;
    let defects = settle(&mut drive, SETTLE_CYCLES, SETTLE_PERIODS)?;
    Ok((drive, defects))
}

/// The Floquet analysis (steps 3 and 4) from a drive already settled onto
/// its orbit by [`settle`] (not advanced), `defects` its settling's. The
/// pivot friction of tensioner arms is replaced by its describing function
/// at `opts.arm_amplitude` ([`super::describe_arms`]; each iteration one
/// monodromy about the same orbit, whose trajectory keeps the friction as
/// it is).
pub fn floquet_settled(
    settled: &Drive,
    defects: Vec<f64>,
    opts: &Options,
    substeps: usize,
) -> Result<Modes, String> {
    let substeps = substeps.max(1);
    let drive = settled;
    let lin = adapter::linearise(drive);
    let (guess, dir) = passing_period(&lin);
    if !guess.is_finite() || guess >= 1.0 || guess <= 0.0 {
        return Err("the belt is not running (under one body passing per second)".into());
    }
    // the period of the orbit: to the section, on a copy
    let section = Section::new(&lin, dir).ok_or("no belt body touches a pulley")?;
    let mut probe = drive.clone();
    section.next(&mut probe, section.body, guess)?;
    let period = probe.time() - drive.time();
    let to = shift_map(&lin, dir);
    let y0 = drive.state().to_vec();
    let t0 = drive.time();
    let scale = scales(&lin);
    // a frictional tensioner arm: the monodromy with its friction replaced
    // by the describing function, iterated on the arm mode's frequency
    super::describe_arms(
        drive,
        opts,
        RUNNING_ARM_FREQUENCY_TOL,
        RUNNING_ARM_ITERATIONS,
        |equivalent| {
            let run = &mut drive.clone();
            let mono = monodromy(run, period, substeps, equivalent)?;
            let mut defects = defects.clone();
            defects.push(scaled_max(&residual(&lin, &to, &y0, run.state()), &scale));
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
            out.arm_taps = super::tap::running(&m, &lin, period);
            out.orbit = Some(Orbit {
                period,
                defects,
                span_tension: mono.span_tension.clone(),
                belt_speed: mono.belt_speed,
                time: t0,
            });
            Ok(out)
        },
    )
}

/// The describing-function iteration of a running drive stops when the
/// arm modes' frequencies change by less than 1e-3 (relative): each
/// iteration costs a monodromy and its eigen-solve, and the Floquet
/// frequencies themselves move by about that much between 128 and 256
/// substeps (docs/modes.md, "Convergence in the substeps").
pub const RUNNING_ARM_FREQUENCY_TOL: f64 = 1e-3;

/// At most this many describing-function iterations of a running drive
/// (each a monodromy and its eigen-solve): where the arm shares its mode
/// with the spans, the mode swinging it most can change from one
/// iteration to the next, and the iteration then stops here, reported
/// not converged.
pub const RUNNING_ARM_ITERATIONS: usize = 6;

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
    let mut out = Modes {
        reduced_dim: dim,
        body_rate: 1.0 / period,
        ..Modes::default()
    };
    let regions = regions(lin0);
    let (s, u) = (evd.S(), evd.U());
    let mut vec = vec![c64::new(0.0, 0.0); dim];
    let mut cands = Vec::new();
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
        // The branch (whole turns within P) nearest the eigenvector's own
        // frequency: its velocities against its displacements, lambda ~
        // (x^H x') / (x^H x) over the bodies, the free pulleys, the
        // tensioner arms and the decouplers' twist (whose rate is the
        // rotor's speed less the pulley's).
        let (mut xx, mut xv) = (0.0, c64::new(0.0, 0.0));
        let mut pair = |x: c64, v: c64| {
            xx += x.norm_sqr();
            xv += x.conj() * v;
        };
        for i in 0..n {
            pair(vec[lin0.body(i, 0)], vec[lin0.body(i, 3)]);
            pair(vec[lin0.body(i, 1)], vec[lin0.body(i, 4)]);
        }
        for (j, p) in lin0.pulleys.iter().enumerate() {
            let (a, w) = lin0.pulley(j);
            if !p.speed_driven {
                pair(vec[a], vec[w]);
            }
            if p.arm.is_some() {
                let arm = lin0.states.arm(j);
                pair(vec[arm.angle], vec[arm.rate]);
            }
            if p.decoupler.is_some() {
                let d = lin0.states.decoupler(j);
                let pulley_speed = if p.speed_driven {
                    c64::new(0.0, 0.0)
                } else {
                    vec[w]
                };
                pair(vec[d.twist], vec[d.rotor_speed] - pulley_speed);
            }
        }
        let f_own = (xv.im / xx) / TAU;
        let turns = ((f_own * period) - arg / TAU).round();
        // per-substep factor, then back through the SDIRK method's
        // amplification R(z) (module doc)
        let per_step = c64::from_polar(
            r.powf(1.0 / substeps as f64),
            (arg + TAU * turns) / substeps as f64,
        );
        let Some(z) = sdirk_inverse(per_step) else {
            out.overdamped += 1;
            continue;
        };
        let lambda = z / h;
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
        // the eigenvector as a state perturbation, its largest component 1
        let big = vec
            .iter()
            .copied()
            .max_by(|a, b| a.norm().total_cmp(&b.norm()))
            .unwrap_or(c64::new(1.0, 0.0));
        let shape: Vec<c64> = vec.iter().map(|&x| x / big).collect();
        // Described without the bodies' spin: the L-stable method has
        // damped the artificial pitching modes away (they end as
        // overdamped or above the frequency limit), and
        // in a running belt a slow mode's spin perturbation is dominated by
        // the bodies at the wrap ends, whose spin jumps between 0 and v/r
        // there, so a small shift of the entry point carries a large spin
        // energy that is not pitching.
        for i in 0..n {
            vec[lin0.body(i, 5)] = c64::new(0.0, 0.0);
        }
        cands.push(Candidate {
            lambda,
            vec: vec.clone(),
            shape,
        });
    }
    cands.sort_by(|a, b| a.lambda.norm().total_cmp(&b.lambda.norm()));
    out.split_pairs = localise(lin0, &regions, &mut cands, false);
    for c in cands {
        let mag = c.lambda.norm();
        let (part, share) = classify(lin0, &regions, &c.vec, false);
        let shares = super::shares(lin0, &regions, &c.vec, false);
        out.modes.push(Mode {
            frequency_hz: mag / TAU,
            damping_ratio: -c.lambda.re / mag,
            damped_hz: c.lambda.im.abs() / TAU,
            part,
            share,
            shares,
            shape: c.shape,
        });
    }
    out.modes
        .sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The amplification's inverse returns z for R(z), over the range of
    /// h lambda the analysis meets (slow modes, |z| << 1, to the pitching
    /// modes beyond the frequency limit), lightly damped and growing.
    #[test]
    fn sdirk_amplification_inverts() {
        let g = SDIRK_GAMMA;
        let r = |z: c64| {
            (c64::new(1.0, 0.0) + z * (1.0 - 2.0 * g))
                / ((c64::new(1.0, 0.0) - z * g) * (c64::new(1.0, 0.0) - z * g))
        };
        for &(re, im) in &[
            (-1e-5, 2e-3),
            (1e-4, 0.05),
            (-0.02, 0.4),
            (-0.1, 1.0),
            (0.0, 1.5),
        ] {
            let z = c64::new(re, im);
            let back = sdirk_inverse(r(z)).expect("a root");
            assert!((back - z).norm() < 1e-9 * (1.0 + z.norm()), "{z} -> {back}");
        }
        // second order: R(z) = e^z + O(z^3)
        let z = c64::new(-1e-3, 1e-2);
        assert!((r(z) - z.exp()).norm() < 1e-6);
    }
}
