//! Linearly implicit Rosenbrock-W integrator ROS34PW2 (Rang & Angermann,
//! BIT 45, 2005): 4 stages, order 3 with an embedded order-2 solution,
//! L-stable and stiffly accurate. The stiff alternative to [`crate::solver::rkf45`].
//!
//! Why a W-method: its order conditions hold for *any* matrix in place of the
//! exact Jacobian, so the Jacobian can be kept over several steps, the
//! dissipated-energy accumulator can be left out of it, and the explicit time
//! dependence of the inputs needs no df/dt term, all without losing order.
//! Each stage solves (I - h gamma J) x = b with the system's own structured
//! solver (for the belt: O(n), see [`crate::solver::iteration_matrix`]).
//!
//! Stages are written in the transformed variables of Hairer & Wanner
//! (Solving ODEs II, IV.7): with Gamma = (gamma_ij),
//! `(I/(h gamma) - J) U_i = f(t + alpha_i h, y + sum a_ij U_j) + sum (c_ij / h) U_j`,
//! `y1 = y + sum m_i U_i`, where a = A Gamma^-1, C = diag(1/gamma) - Gamma^-1,
//! m = b Gamma^-1; the coefficients are transformed once, at compile time
//! (`tableau.rs`). The interface a system implements for it is
//! [`crate::solver::stiff_system`].

use crate::model::simd::{self, Isa};
use crate::solver::knobs::TUNING;
use crate::solver::step_control::{EmbeddedMethod, StepControl, StepFailure, Trial};

pub use crate::solver::stiff_system::{EnergyBalance, StiffSystem};
pub use tableau::GAMMA;
use tableau::{S, T};

mod tableau;

#[cfg(test)]
mod tests;

/// How long a Jacobian is kept by default: it is re-evaluated after this
/// many accepted steps, after a rejected step, and after a restore.
pub const JACOBIAN_MAX_AGE: u32 = TUNING.jacobian_max_age;

/// Step-size increases below this factor are not taken, so the factored
/// iteration matrix (which depends on h) can be reused.
const KEEP_STEP_BELOW: f64 = TUNING.keep_step_below;

#[derive(Clone, Debug, PartialEq)]
/// The ROS34PW2 integrator: tolerances, step control, kept Jacobian and work vectors.
pub struct Rosenbrock<Sys: StiffSystem> {
    /// Relative error tolerance.
    pub rel_tol: f64,
    /// Absolute error tolerance.
    pub abs_tol: f64,
    /// Step size, counters and work guard.
    pub control: StepControl,
    /// Accepted steps a Jacobian is used for (1 = a fresh one every step).
    pub jacobian_max_age: u32,
    /// Whether a trial step is also checked on its energy residual (with
    /// the no-growth rule after a rejection); true by default. Off, the step
    /// control is the error norm's alone, whose step sequence is smooth in
    /// the state: for runs at tolerances where the norm alone is accurate
    /// and that need a smooth flow map (the modal analysis' own runs).
    pub energy_check: bool,
    /// Jacobian evaluations and factorizations (cumulative).
    pub jacobians: u64,
    /// Factorizations of the iteration matrix (cumulative).
    pub factorizations: u64,
    jac: Sys::Jacobian,
    mat: Sys::Matrix,
    /// Accepted steps since the Jacobian was evaluated; None = no valid Jacobian.
    jac_age: Option<u32>,
    /// The `c = h gamma` of the current factorization, if any.
    factored_c: Option<f64>,
    u: [Vec<f64>; S],
    f: Vec<f64>,
    /// f(t, y) at the start of the next trial step, the first stage's
    /// (alpha_0 = 0, a_0j = 0), if known: the time it was taken at.
    f_start: Vec<f64>,
    f_start_at: Option<f64>,
    /// f at the last trial step's end (time, state): the next step's first
    /// stage if the trial is accepted (first same as last).
    f_end: Vec<f64>,
    f_end_at: Option<f64>,
    stage: Vec<f64>,
    mask: Vec<f64>,
    controlled: usize,
    /// The energy balance at the start of the next trial step, if known:
    /// taken with `f_start`, valid while it is.
    balance: Option<EnergyBalance>,
    /// The energy balance of the last trial step's end state.
    trial_balance: Option<EnergyBalance>,
    /// Trial steps rejected for their energy residual alone (cumulative).
    pub energy_rejections: u64,
    /// The last trial step was rejected: the next accepted one does not
    /// grow the step (Hairer & Wanner II, IV.8: facmax = 1 after a
    /// rejection).
    no_grow: bool,
    /// What a retake of the step that may pass the communication point,
    /// clipped to it, needs ([`EmbeddedMethod::rewind`]).
    checkpoint: Checkpoint<Sys::Jacobian>,
}

/// The stiff method at the start of a step that may pass the communication
/// point: its time (NaN if none), the Jacobian's age and the no-growth
/// flag there; the kept Jacobian is parked here (swapped, not copied) if a
/// rejected trial from that start would replace it.
#[derive(Clone, Debug, PartialEq)]
struct Checkpoint<J> {
    t: f64,
    jac_age: Option<u32>,
    no_grow: bool,
    /// Trials from the checkpoint's start are still running.
    open: bool,
    /// `jac` holds the Jacobian of the checkpoint.
    parked: bool,
    jac: J,
}

impl<Sys: StiffSystem> Rosenbrock<Sys> {
    /// An integrator for `sys`, first step `h0`, at most `max_steps` steps per call.
    pub fn new(sys: &Sys, rel_tol: f64, abs_tol: f64, h0: f64, max_steps: u64) -> Self {
        let dim = sys.dim();
        let mut mask = vec![1.0; dim];
        sys.error_mask(rel_tol, &mut mask);
        let controlled = mask.iter().filter(|&&m| m != 0.0).count().max(1);
        Self {
            mask,
            controlled,
            rel_tol,
            abs_tol,
            control: StepControl::new(dim, h0, max_steps),
            jacobian_max_age: JACOBIAN_MAX_AGE,
            energy_check: true,
            jacobians: 0,
            factorizations: 0,
            jac: sys.new_jacobian(),
            mat: sys.new_matrix(),
            jac_age: None,
            factored_c: None,
            u: std::array::from_fn(|_| vec![0.0; dim]),
            f: vec![0.0; dim],
            f_start: vec![0.0; dim],
            f_start_at: None,
            f_end: vec![0.0; dim],
            f_end_at: None,
            stage: vec![0.0; dim],
            balance: None,
            trial_balance: None,
            energy_rejections: 0,
            no_grow: false,
            checkpoint: Checkpoint {
                t: f64::NAN,
                jac_age: None,
                no_grow: false,
                open: false,
                parked: false,
                jac: sys.new_jacobian(),
            },
        }
    }

    /// Forgets the Jacobian and factorization (after the state was replaced),
    /// and what [`Self::state_changed`] forgets.
    pub fn invalidate(&mut self) {
        self.state_changed();
        self.jac_age = None;
        self.factored_c = None;
    }

    /// Forgets the right-hand side and energy balance kept from the last
    /// step's end: call it whenever the state or the system's inputs are
    /// changed between calls of [`Self::advance`] at the same time (a
    /// change of the time is noticed: they are kept for one time).
    pub fn state_changed(&mut self) {
        self.balance = None;
        self.f_start_at = None;
    }

    /// What must be saved besides state, step size and counters for a
    /// restored run to continue bit-identically: Jacobian evaluations and
    /// factorizations, the first stage kept from the last step's end (its
    /// time, the right-hand side and the energy balance; evaluated again,
    /// they would be the same bits, but the count of right-hand sides
    /// would not), the kept Jacobian, its age, and the factored `c`.
    /// `point`: what the right-hand side depends on (time, state, inputs);
    /// the first stage is restored only at the same point (a caller may
    /// restore the data with another state, keeping the Jacobian).
    pub fn save(&self, sys: &Sys, point: &[f64], out: &mut Vec<f64>) {
        out.push(self.jacobians as f64);
        out.push(self.factorizations as f64);
        match (self.f_start_at, self.balance) {
            (None, _) => out.push(0.0),
            (Some(t), balance) => {
                out.push(if balance.is_some() { 2.0 } else { 1.0 });
                out.push(t);
                out.extend_from_slice(&fingerprint(point));
                out.extend_from_slice(&self.f_start);
                if let Some(b) = balance {
                    out.extend_from_slice(&[b.balance, b.scale, b.magnitude]);
                }
            }
        }
        match self.jac_age {
            None => out.push(-1.0),
            Some(age) => {
                out.push(f64::from(age));
                out.push(self.factored_c.unwrap_or(-1.0));
                sys.save_jacobian(&self.jac, out);
            }
        }
    }

    /// The checkpoint of the step that may pass the communication point
    /// (its time, NaN if none; the Jacobian's age there, -1 for none; the
    /// no-growth flag; and the Jacobian parked there, if any), for a saved
    /// state.
    pub fn save_checkpoint(&self, sys: &Sys, out: &mut Vec<f64>) {
        let ck = &self.checkpoint;
        out.push(ck.t);
        out.push(ck.jac_age.map_or(-1.0, f64::from));
        out.push(f64::from(u8::from(ck.no_grow)));
        out.push(f64::from(u8::from(ck.parked)));
        if ck.parked {
            sys.save_jacobian(&ck.jac, out);
        }
    }

    /// Reads what [`save_checkpoint`](Self::save_checkpoint) wrote; false
    /// if it does not fit.
    pub fn load_checkpoint(&mut self, sys: &Sys, src: &[f64]) -> bool {
        let [t, age, no_grow, parked, jac @ ..] = src else {
            return false;
        };
        let flag = |x: f64| (x == 0.0 || x == 1.0).then_some(x == 1.0);
        let (Some(no_grow), Some(parked)) = (flag(*no_grow), flag(*parked)) else {
            return false;
        };
        let jac_age = match *age {
            -1.0 => None,
            a if a >= 0.0 && a.fract() == 0.0 && a <= f64::from(u32::MAX) => Some(a as u32),
            _ => return false,
        };
        if parked {
            if !sys.load_jacobian(&mut self.checkpoint.jac, jac) {
                return false;
            }
        } else if !jac.is_empty() {
            return false;
        }
        let ck = &mut self.checkpoint;
        (ck.t, ck.jac_age, ck.no_grow, ck.open, ck.parked) = (*t, jac_age, no_grow, false, parked);
        true
    }

    /// Reads what [`save`](Self::save) wrote; false (and a fresh Jacobian
    /// at the next step) if it does not fit this system.
    pub fn load(&mut self, sys: &Sys, point: &[f64], src: &[f64]) -> bool {
        self.invalidate();
        let [jacobians, factorizations, kept, rest @ ..] = src else {
            return false;
        };
        let count = |x: f64| (x >= 0.0 && x.fract() == 0.0 && x < 9e15).then_some(x as u64);
        let (Some(jacobians), Some(factorizations)) = (count(*jacobians), count(*factorizations))
        else {
            return false;
        };
        // the kept first stage: none (0), its time and right-hand side (1),
        // and its energy balance (2)
        let dim = self.f_start.len();
        let (kept, rest) = match (count(*kept), rest) {
            (Some(0), rest) => (None, rest),
            (Some(k @ (1 | 2)), [t, hi, lo, rest @ ..])
                if rest.len() > dim + 3 * (k as usize - 1) =>
            {
                let (data, rest) = rest.split_at(dim + 3 * (k as usize - 1));
                let here = [*hi, *lo] == fingerprint(point);
                (here.then_some((*t, data)), rest)
            }
            _ => return false,
        };
        let [age, rest @ ..] = rest else {
            return false;
        };
        self.jacobians = jacobians;
        self.factorizations = factorizations;
        if *age >= 0.0 {
            let Some(age) = count(*age).and_then(|a| u32::try_from(a).ok()) else {
                return false;
            };
            let [c, jac @ ..] = rest else {
                return false;
            };
            if !sys.load_jacobian(&mut self.jac, jac) {
                return false;
            }
            self.jac_age = Some(age);
            if *c > 0.0 && sys.factor(&self.jac, *c, &mut self.mat) {
                self.factored_c = Some(*c);
            }
        } else if !rest.is_empty() {
            return false;
        }
        if let Some((t, data)) = kept {
            let (f, balance) = data.split_at(dim);
            self.f_start.copy_from_slice(f);
            self.f_start_at = Some(t);
            self.balance = match *balance {
                [balance, scale, magnitude] => Some(EnergyBalance {
                    balance,
                    scale,
                    magnitude,
                }),
                _ => None,
            };
        }
        true
    }

    /// One trial step of size h from (t, y): the new state goes to
    /// `self.stage`; returns the weighted RMS error norm (infinite if the
    /// iteration matrix is singular). The vector loops run in an AVX2 build
    /// where the CPU has it (no FMA: the same results to the last bit).
    fn trial(&mut self, sys: &Sys, ws: &mut Sys::Workspace, t: f64, y: &[f64], h: f64) -> f64 {
        self.trial_with(Isa::detected().min(Isa::Avx2), sys, ws, t, y, h)
    }

    /// [`Self::trial`] with its own vector loops built for `isa`, each its
    /// own kernel between the system's (which dispatch themselves).
    fn trial_with(
        &mut self,
        isa: Isa,
        sys: &Sys,
        ws: &mut Sys::Workspace,
        t: f64,
        y: &[f64],
        h: f64,
    ) -> f64 {
        if self.jac_age.is_none() {
            sys.jacobian(t, y, &mut self.jac);
            self.jacobians += 1;
            self.jac_age = Some(0);
            self.factored_c = None;
        }
        sys.step_rows(t, &mut self.jac);
        let c = h * GAMMA;
        if self.factored_c != Some(c) {
            self.factorizations += 1;
            if !sys.factor(&self.jac, c, &mut self.mat) {
                self.factored_c = None;
                return f64::INFINITY;
            }
            self.factored_c = Some(c);
        }
        // the first stage, f(t, y): kept from the previous step's end (or
        // from a rejected trial from the same start), else evaluated here,
        // with the energy balance in the same pass when the check wants it
        if self.f_start_at != Some(t) {
            self.balance = if self.energy_check {
                sys.rhs_balance(ws, t, y, &mut self.f_start)
            } else {
                sys.rhs(ws, t, y, &mut self.f_start);
                None
            };
            self.f_start_at = Some(t);
            self.control.stats.rhs_evals += 1;
        }
        {
            let ui = &mut self.u[0];
            simd::dispatch_with(
                isa,
                (&mut ui[..], &self.f_start[..]),
                #[inline(always)]
                move |(ui, f)| {
                    combine(ui, f, |f| c * f, &terms(&[][..], |_| 0.0));
                },
            );
            sys.solve(&self.jac, &mut self.mat, ui);
        }
        for i in 1..S {
            // stage state y + sum a_ij U_j
            let (done, rest) = self.u.split_at_mut(i);
            simd::dispatch_with(
                isa,
                (&mut self.stage[..], &*done),
                #[inline(always)]
                move |(stage, done)| {
                    combine(stage, y, |y| y, &terms(done, |j| T.a[i][j]));
                },
            );
            sys.rhs(ws, t + T.alpha[i] * h, &self.stage, &mut self.f);
            self.control.stats.rhs_evals += 1;
            // right-hand side of (I - c J) U_i = c (f + sum c_ij/h U_j)
            let ui = &mut rest[0];
            simd::dispatch_with(
                isa,
                (&mut ui[..], &self.f[..], &*done),
                #[inline(always)]
                move |(ui, f, done)| {
                    combine(ui, f, |f| c * f, &terms(done, |j| c * T.c[i][j] / h));
                },
            );
            sys.solve(&self.jac, &mut self.mat, ui);
        }
        // y1 = y + sum m_i U_i, error sum e_i U_i (stage increments s0..s3),
        // weighted RMS norm
        let [u0, u1, u2, u3] = &self.u;
        let (abs_tol, rel_tol) = (self.abs_tol, self.rel_tol);
        let sum = simd::dispatch_with(
            isa,
            (&mut self.stage[..], &self.mask[..], u0, u1, u2, u3),
            #[inline(always)]
            move |(stage, mask, u0, u1, u2, u3)| {
                let mut sum = 0.0;
                for (((((y1, &y0), &m), s0), s1), (s2, s3)) in stage
                    .iter_mut()
                    .zip(y)
                    .zip(mask)
                    .zip(u0)
                    .zip(u1)
                    .zip(u2.iter().zip(u3))
                {
                    let new = y0 + (T.m[0] * s0 + T.m[1] * s1 + T.m[2] * s2 + T.m[3] * s3);
                    let err = T.e[0] * s0 + T.e[1] * s1 + T.e[2] * s2 + T.e[3] * s3;
                    let w = abs_tol + rel_tol * y0.abs().max(new.abs());
                    let e = m * err / w;
                    sum += e * e;
                    *y1 = new;
                }
                sum
            },
        );
        let err = (sum / self.controlled as f64).sqrt();
        self.trial_balance = None;
        self.f_end_at = None;
        if err > 1.0 || err.is_nan() {
            // rejected anyway (or not finite): the end state's right-hand
            // side and energy are not needed
            return err;
        }
        // f at the end state: the next step's first stage if this one is
        // accepted (t + h is the time the step driver moves to), with the
        // energy balance from the same evaluation when checked
        let t_end = t + h;
        self.f_end_at = Some(t_end);
        self.control.stats.rhs_evals += 1;
        if !self.energy_check {
            sys.rhs(ws, t_end, &self.stage, &mut self.f_end);
            return err;
        }
        let Some(end) = sys.rhs_balance(ws, t_end, &self.stage, &mut self.f_end) else {
            return err;
        };
        let energy = self.energy_error(sys, y, end);
        if energy > 1.0 {
            self.energy_rejections += 1;
        }
        err.max(energy)
    }

    /// The trial step's energy residual r (the change of the energy
    /// balance from `y` to the step's end state in `self.stage`) against
    /// its tolerance relTol E_b (E_b the system's energy scale at the
    /// step's start; for the belt its own stored energy), as an error of
    /// the embedded estimate's order: (|r| / (relTol E_b))^(3/4). r is the
    /// local error of the order-3 solution's energy, O(h^4), the embedded
    /// estimate O(h^3): the power 3/4 makes the step factor
    /// err^(-1/3) the one that brings r to its tolerance, and 1 still
    /// means "at tolerance". `end`: the balance of the end state.
    fn energy_error(&mut self, sys: &Sys, y: &[f64], end: EnergyBalance) -> f64 {
        // the start's balance is taken with its right-hand side; it is
        // missing only where that was taken with the check off
        let start = match self.balance {
            Some(b) => b,
            None => {
                let b = sys.energy_balance(y).unwrap_or(end);
                self.balance = Some(b);
                b
            }
        };
        self.trial_balance = Some(end);
        self.energy_ratio(start, end)
    }

    /// The energy error of a step from balance `start` to `end`
    /// ([`Self::energy_error`]).
    fn energy_ratio(&self, start: EnergyBalance, end: EnergyBalance) -> f64 {
        let r = end.balance - start.balance;
        // the balance's round-off: a few ulps of the terms it sums
        let roundoff =
            TUNING.energy_roundoff_ulps * f64::EPSILON * start.magnitude.max(end.magnitude);
        let tol = TUNING.energy_tolerance * self.rel_tol * start.scale + roundoff;
        if r.abs() <= roundoff {
            return 0.0;
        }
        (r.abs() / tol).powf(3.0 / TUNING.energy_error_order)
    }

    /// Integrates `y` from `*t` to exactly `t_end`. On failure `y` and `*t`
    /// are restored to their values at the call.
    pub fn advance(
        &mut self,
        sys: &Sys,
        ws: &mut Sys::Workspace,
        t: &mut f64,
        y: &mut [f64],
        t_end: f64,
    ) -> Result<(), StepFailure> {
        self.advance_observed(sys, ws, t, y, t_end, &mut |_: &Self, _: Trial| {})
    }

    /// [`Self::advance`] with `observe` told of every trial step
    /// ([`crate::solver::step_control::advance_observed`]; diagnostics).
    pub fn advance_observed(
        &mut self,
        sys: &Sys,
        ws: &mut Sys::Workspace,
        t: &mut f64,
        y: &mut [f64],
        t_end: f64,
        observe: &mut dyn FnMut(&Self, Trial),
    ) -> Result<(), StepFailure> {
        // every advance ends on an accepted step; the first stage and
        // balance kept from its end are used if the time is still theirs
        // (a caller that changed the state calls `state_changed`)
        self.no_grow = false;
        crate::solver::step_control::advance_observed(self, sys, ws, t, y, t_end, observe)
    }

    /// Diagnostics of the last trial step from `y` (an observer's
    /// [`Trial`]): writes each component's weighted error `mask e_i / w_i`
    /// to `out` (the error norm is their RMS over the controlled
    /// components) and the trial's end state to `end`, and returns the
    /// step's energy error (0 where it was not taken: the check off, or the
    /// step rejected on its error norm first). Not on the integration's
    /// path: it repeats the trial's last loop.
    pub fn error_components(&self, y: &[f64], out: &mut [f64], end: &mut [f64]) -> f64 {
        let [u0, u1, u2, u3] = &self.u;
        end.copy_from_slice(&self.stage);
        for (i, o) in out.iter_mut().enumerate() {
            let (s0, s1, s2, s3) = (u0[i], u1[i], u2[i], u3[i]);
            let new = y[i] + (T.m[0] * s0 + T.m[1] * s1 + T.m[2] * s2 + T.m[3] * s3);
            let err = T.e[0] * s0 + T.e[1] * s1 + T.e[2] * s2 + T.e[3] * s3;
            let w = self.abs_tol + self.rel_tol * y[i].abs().max(new.abs());
            *o = self.mask[i] * err / w;
        }
        match (self.balance, self.trial_balance) {
            (Some(start), Some(end)) if self.energy_check => self.energy_ratio(start, end),
            _ => 0.0,
        }
    }
}

/// A 64-bit fingerprint (FNV-1a over the bits) of the numbers `point`, as
/// two exact integers.
fn fingerprint(point: &[f64]) -> [f64; 2] {
    let h = point.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, x| {
        (h ^ x.to_bits()).wrapping_mul(0x0000_0100_0000_01b3)
    });
    [(h >> 32) as f64, (h & 0xffff_ffff) as f64]
}

/// The earlier stages `done` with their coefficients `coef(j)`, zero
/// coefficients of the tableau left out: at most S - 1 terms, `len` used.
#[inline(always)]
fn terms<'a>(done: &'a [Vec<f64>], coef: impl Fn(usize) -> f64) -> Terms<'a> {
    let mut t = Terms {
        a: [0.0; S - 1],
        x: [&[]; S - 1],
        len: 0,
    };
    for (j, x) in done.iter().enumerate() {
        let a = coef(j);
        if a != 0.0 {
            t.a[t.len] = a;
            t.x[t.len] = x;
            t.len += 1;
        }
    }
    t
}

/// Coefficients and vectors of a stage combination.
struct Terms<'a> {
    a: [f64; S - 1],
    x: [&'a [f64]; S - 1],
    len: usize,
}

/// `out = first(base) + a_0 x_0 + a_1 x_1 + ...`, summed left to right in
/// one pass over the vectors (the same numbers as a copy followed by one
/// `out += a_j x_j` pass per term, without re-reading `out`).
#[inline(always)]
fn combine(out: &mut [f64], base: &[f64], first: impl Fn(f64) -> f64, t: &Terms) {
    let n = out.len();
    let (base, [x0, x1, x2]) = (
        &base[..n],
        t.x.map(|x| if x.is_empty() { x } else { &x[..n] }),
    );
    let [a0, a1, a2] = t.a;
    match t.len {
        0 => {
            for (o, &b) in out.iter_mut().zip(base) {
                *o = first(b);
            }
        }
        1 => {
            for ((o, &b), &x0) in out.iter_mut().zip(base).zip(x0) {
                *o = first(b) + a0 * x0;
            }
        }
        2 => {
            for (((o, &b), &x0), &x1) in out.iter_mut().zip(base).zip(x0).zip(x1) {
                *o = first(b) + a0 * x0 + a1 * x1;
            }
        }
        _ => {
            for ((((o, &b), &x0), &x1), &x2) in out.iter_mut().zip(base).zip(x0).zip(x1).zip(x2) {
                *o = first(b) + a0 * x0 + a1 * x1 + a2 * x2;
            }
        }
    }
}

impl<Sys: StiffSystem> EmbeddedMethod<Sys> for Rosenbrock<Sys> {
    fn control(&mut self) -> &mut StepControl {
        &mut self.control
    }

    fn trial(&mut self, sys: &Sys, ws: &mut Sys::Workspace, t: f64, y: &[f64], h: f64) -> f64 {
        Rosenbrock::trial(self, sys, ws, t, y, h)
    }

    fn take_step(&mut self, y: &mut [f64]) {
        y.copy_from_slice(&self.stage);
        std::mem::swap(&mut self.f_start, &mut self.f_end);
        self.f_start_at = self.f_end_at;
        self.balance = self.trial_balance;
    }

    fn state_changed(&mut self) {
        Rosenbrock::state_changed(self);
    }

    /// Embedded order 2: the error scales as h^3.
    fn step_factor(&self, err: f64) -> f64 {
        let t = &TUNING;
        if err == 0.0 {
            t.rosenbrock_factor_max
        } else {
            (t.rosenbrock_safety * err.powf(-1.0 / 3.0))
                .clamp(t.rosenbrock_factor_min, t.rosenbrock_factor_max)
        }
    }

    /// Small increases are skipped to keep the factorization; the Jacobian
    /// ages by one step.
    fn accepted(&mut self, factor: f64) -> f64 {
        self.checkpoint.open = false;
        let factor = if self.no_grow {
            factor.min(1.0)
        } else {
            factor
        };
        self.no_grow = false;
        let age = self.jac_age.map_or(0, |a| a + 1);
        self.jac_age = (age < self.jacobian_max_age).then_some(age);
        if (1.0..KEEP_STEP_BELOW).contains(&factor) {
            1.0
        } else {
            factor
        }
    }

    fn rejected(&mut self) {
        let ck = &mut self.checkpoint;
        if ck.open && !ck.parked && self.jac_age.is_some() {
            // the next trial evaluates a fresh Jacobian into `jac`: park
            // the checkpoint's first
            std::mem::swap(&mut self.jac, &mut ck.jac);
            ck.parked = true;
        }
        self.jac_age = None;
        self.no_grow = self.energy_check;
    }

    fn failed(&mut self) {
        self.invalidate();
        self.checkpoint.t = f64::NAN;
    }

    fn call_start(&mut self) {
        self.no_grow = false;
    }

    fn checkpoint(&mut self, t: f64) {
        let ck = &mut self.checkpoint;
        ck.t = t;
        ck.jac_age = self.jac_age;
        ck.no_grow = self.no_grow;
        ck.open = true;
        ck.parked = false;
    }

    /// Back to the checkpoint's Jacobian, its age and no-growth flag; the
    /// first stage is evaluated again (the same bits) and the matrix
    /// factored again.
    fn rewind(&mut self, t: f64) -> bool {
        self.state_changed();
        self.factored_c = None;
        let ck = &mut self.checkpoint;
        if ck.t != t {
            self.jac_age = None;
            return false;
        }
        if ck.parked {
            std::mem::swap(&mut self.jac, &mut ck.jac);
            ck.parked = false;
        }
        ck.open = true;
        self.jac_age = ck.jac_age;
        self.no_grow = ck.no_grow;
        true
    }

    /// The first stage of the last accepted step (swapped into `f_end` by
    /// [`Self::take_step`]), until the next trial.
    fn start_derivative(&self) -> Option<&[f64]> {
        Some(&self.f_end)
    }

    /// The next step's first stage, if kept for time `t`.
    fn end_derivative(&self, t: f64) -> Option<&[f64]> {
        (self.f_start_at == Some(t)).then_some(&self.f_start[..])
    }
}
