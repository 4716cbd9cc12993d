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
//! m = b Gamma^-1; the coefficients are transformed once, at compile time of
//! the tableau below.

use crate::model::simd::{self, Isa};
use crate::solver::knobs::TUNING;
use crate::solver::step_control::{EmbeddedMethod, OdeSystem, StepControl, StepFailure, Trial};

/// An ODE whose Jacobian (or an approximation of it) can be formed and whose
/// iteration matrix `I - c J` can be factored and solved.
pub trait StiffSystem: OdeSystem {
    /// The Jacobian's storage.
    type Jacobian: Clone + std::fmt::Debug + PartialEq;
    /// The factored iteration matrix's storage.
    type Matrix: Clone + std::fmt::Debug + PartialEq;
    /// Storage for a Jacobian.
    fn new_jacobian(&self) -> Self::Jacobian;
    /// Storage for an iteration matrix.
    fn new_matrix(&self) -> Self::Matrix;
    /// Evaluates the Jacobian at (t, y).
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut Self::Jacobian);
    /// Sets the entries of a kept Jacobian that depend on the time alone
    /// (the inputs) to their values at the start `t` of the step about to
    /// be tried; called before every trial step. Entries outside the
    /// factored matrix only (rows nothing depends on): the factorization
    /// stays valid.
    fn step_rows(&self, _t: f64, _jac: &mut Self::Jacobian) {}
    /// Factors `I - c J`; false if it is singular.
    fn factor(&self, jac: &Self::Jacobian, c: f64, m: &mut Self::Matrix) -> bool;
    /// Overwrites `b` with the solution x of `(I - c J) x = b`.
    fn solve(&self, jac: &Self::Jacobian, m: &mut Self::Matrix, b: &mut [f64]);
    /// Which components enter the error norm (1) and which not (0): those
    /// that only carry the fast modes the method is meant to damp; weights
    /// in between may depend on the relative tolerance `rel_tol`.
    fn error_mask(&self, _rel_tol: f64, mask: &mut [f64]) {
        mask.fill(1.0);
    }
    /// The energy balance of state `y`, if the system books its energy:
    /// the input work less the dissipated and the stored energy, constant
    /// along the exact flow (see [`EnergyBalance`]).
    fn energy_balance(&self, _y: &[f64]) -> Option<EnergyBalance> {
        None
    }
    /// dy = f(t, y) and the energy balance of `y` ([`Self::energy_balance`])
    /// from one evaluation; `dy` must be the right-hand side's to the last
    /// bit. By default the right-hand side, then the balance.
    fn rhs_balance(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
    ) -> Option<EnergyBalance> {
        self.rhs(ws, t, y, dy);
        self.energy_balance(y)
    }
    /// Appends the Jacobian's numbers to `out` / reads them back (false if
    /// they do not fit), for saved states.
    fn save_jacobian(&self, jac: &Self::Jacobian, out: &mut Vec<f64>);
    /// Reads what `save_jacobian` wrote; false if it does not fit.
    fn load_jacobian(&self, jac: &mut Self::Jacobian, src: &[f64]) -> bool;
}

/// A state's energy balance (see [`StiffSystem::energy_balance`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyBalance {
    /// Input work less dissipated energy less stored energy [J]: its change
    /// over a step is the step's energy residual, zero for the exact flow.
    pub balance: f64,
    /// The energy the residual is measured against [J]: a step's residual
    /// is at tolerance when it is relTol times this (for the belt: the
    /// belt's own stored energy, [`crate::model::system::StoredEnergy::belt`]).
    pub scale: f64,
    /// The size of the terms the balance sums [J], for its round-off.
    pub magnitude: f64,
}

const S: usize = 4;
/// ROS34PW2 in the notation of Rang & Angermann (2005), Table 2.
const GAMMA: f64 = 4.358_665_215_084_59e-1;
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
struct Transformed {
    a: [[f64; S]; S],
    c: [[f64; S]; S],
    m: [f64; S],
    e: [f64; S],
    alpha: [f64; S],
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

const T: Transformed = transformed();

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
        self.jac_age = None;
        self.no_grow = self.energy_check;
    }

    fn failed(&mut self) {
        self.invalidate();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Small dense test systems: the Jacobian is a dense matrix, the
    /// iteration matrix solved by Gaussian elimination.
    #[derive(Clone)]
    struct Dense<F: Fn(f64, &[f64], &mut [f64]) + Clone> {
        n: usize,
        f: F,
        /// Jacobian used by the method: exact (finite differences), or zero
        /// (the W-method then degenerates to an explicit Runge-Kutta method).
        exact: bool,
    }

    impl<F: Fn(f64, &[f64], &mut [f64]) + Clone> OdeSystem for Dense<F> {
        type Workspace = ();
        fn dim(&self) -> usize {
            self.n
        }
        fn workspace(&self) {}
        fn rhs(&self, _: &mut (), t: f64, y: &[f64], dy: &mut [f64]) {
            (self.f)(t, y, dy)
        }
    }

    impl<F: Fn(f64, &[f64], &mut [f64]) + Clone> StiffSystem for Dense<F> {
        type Jacobian = Vec<f64>;
        type Matrix = Vec<f64>;
        fn new_jacobian(&self) -> Vec<f64> {
            vec![0.0; self.n * self.n]
        }
        fn new_matrix(&self) -> Vec<f64> {
            vec![0.0; self.n * self.n]
        }
        fn jacobian(&self, t: f64, y: &[f64], jac: &mut Vec<f64>) {
            jac.iter_mut().for_each(|v| *v = 0.0);
            if !self.exact {
                return;
            }
            let n = self.n;
            let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
            for j in 0..n {
                let mut yp = y.to_vec();
                let e = 1e-7 * y[j].abs().max(1.0);
                yp[j] += e;
                (self.f)(t, &yp, &mut a);
                yp[j] -= 2.0 * e;
                (self.f)(t, &yp, &mut b);
                for i in 0..n {
                    jac[i * n + j] = (a[i] - b[i]) / (2.0 * e);
                }
            }
        }
        fn factor(&self, jac: &Vec<f64>, c: f64, m: &mut Vec<f64>) -> bool {
            let n = self.n;
            for i in 0..n {
                for j in 0..n {
                    m[i * n + j] = f64::from(u8::from(i == j)) - c * jac[i * n + j];
                }
            }
            true
        }
        fn save_jacobian(&self, jac: &Vec<f64>, out: &mut Vec<f64>) {
            out.extend_from_slice(jac);
        }
        fn load_jacobian(&self, jac: &mut Vec<f64>, src: &[f64]) -> bool {
            jac.copy_from_slice(src);
            true
        }
        fn solve(&self, _jac: &Vec<f64>, m: &mut Vec<f64>, b: &mut [f64]) {
            let x = crate::solver::iteration_matrix::tests::dense_solve(m.clone(), b.to_vec());
            b.copy_from_slice(&x);
        }
    }

    /// Error at t = 1 of fixed steps h on y' = -y + sin(t) y^2-ish smooth
    /// nonlinear non-autonomous problem, against a fine reference.
    fn fixed_step_error(exact: bool, h: f64) -> f64 {
        let f = |t: f64, y: &[f64], dy: &mut [f64]| {
            dy[0] = y[1];
            dy[1] = -y[0] - 0.5 * y[1] * y[1] + (2.0 * t).cos();
        };
        let run = |h: f64| {
            let sys = Dense { n: 2, f, exact };
            // tolerance so loose that every step is accepted: fixed steps
            let mut ros = Rosenbrock::new(&sys, 1e3, 1e3, h, 1_000_000);
            let mut y = vec![1.0, 0.0];
            let mut t = 0.0;
            let steps = (1.0 / h).round() as usize;
            for k in 1..=steps {
                ros.control.h = h;
                ros.advance(&sys, &mut (), &mut t, &mut y, k as f64 * h)
                    .unwrap();
            }
            y
        };
        let reference = run(1e-4);
        let y = run(h);
        (y[0] - reference[0]).abs() + (y[1] - reference[1]).abs()
    }

    #[test]
    fn order_three_with_exact_or_zero_jacobian() {
        // The W-method property: order 3 whatever matrix stands for J.
        for exact in [true, false] {
            let (e1, e2) = (fixed_step_error(exact, 0.02), fixed_step_error(exact, 0.01));
            let order = (e1 / e2).log2();
            assert!(
                (2.7..3.4).contains(&order),
                "exact J = {exact}: observed order {order} ({e1:e}, {e2:e})"
            );
        }
    }

    #[test]
    fn stiff_problem_with_large_steps() {
        // Prothero-Robinson: y' = -1e6 (y - cos t) - sin t, y = cos t.
        let f = |t: f64, y: &[f64], dy: &mut [f64]| {
            dy[0] = -1e6 * (y[0] - t.cos()) - t.sin();
        };
        let sys = Dense {
            n: 1,
            f,
            exact: true,
        };
        let mut ros = Rosenbrock::new(&sys, 1e-6, 1e-8, 1e-3, 100_000);
        let mut y = vec![1.0];
        let mut t = 0.0;
        ros.advance(&sys, &mut (), &mut t, &mut y, 2.0).unwrap();
        assert_eq!(t, 2.0);
        assert!((y[0] - 2f64.cos()).abs() < 1e-6, "{}", y[0]);
        // An explicit method would need ~1e6 steps (stability h < 2.8e-6).
        assert!(ros.control.stats.steps < 2000, "{:?}", ros.control.stats);
    }

    #[test]
    fn tolerance_controls_error_and_failure_restores() {
        let f = |_t: f64, y: &[f64], dy: &mut [f64]| {
            dy[0] = y[1];
            dy[1] = -y[0];
        };
        let sys = Dense {
            n: 2,
            f,
            exact: true,
        };
        let mut prev = f64::INFINITY;
        for tol in [1e-4, 1e-6, 1e-8] {
            let mut ros = Rosenbrock::new(&sys, tol, tol, 1e-3, 1_000_000);
            let mut y = vec![1.0, 0.0];
            let mut t = 0.0;
            for k in 1..=100 {
                ros.advance(&sys, &mut (), &mut t, &mut y, k as f64 * 0.1)
                    .unwrap();
                assert_eq!(t, k as f64 * 0.1);
            }
            let err = (y[0] - 10f64.cos()).abs() + (y[1] + 10f64.sin()).abs();
            assert!(err < 1000.0 * tol && err < prev, "tol {tol}: {err}");
            prev = err;
        }
        let mut ros = Rosenbrock::new(&sys, 1e-12, 1e-12, 1e-3, 3);
        let mut y = vec![1.0, 0.0];
        let mut t = 0.25;
        assert!(ros.advance(&sys, &mut (), &mut t, &mut y, 50.0).is_err());
        assert_eq!((t, y), (0.25, vec![1.0, 0.0]));
    }

    /// x'' = -x with its energy balance -(x^2 + v^2)/2 (no input, no
    /// dissipation) and both states left out of the error norm, so that
    /// the energy check alone controls the step (`check`: the balance is
    /// given; otherwise the system books no energy).
    #[derive(Clone)]
    struct Oscillator {
        check: bool,
    }

    impl OdeSystem for Oscillator {
        type Workspace = ();
        fn dim(&self) -> usize {
            2
        }
        fn workspace(&self) {}
        fn rhs(&self, _: &mut (), _t: f64, y: &[f64], dy: &mut [f64]) {
            dy[0] = y[1];
            dy[1] = -y[0];
        }
    }

    impl StiffSystem for Oscillator {
        type Jacobian = [f64; 4];
        type Matrix = [f64; 4];
        fn new_jacobian(&self) -> [f64; 4] {
            [0.0; 4]
        }
        fn new_matrix(&self) -> [f64; 4] {
            [0.0; 4]
        }
        fn jacobian(&self, _t: f64, _y: &[f64], jac: &mut [f64; 4]) {
            *jac = [0.0, 1.0, -1.0, 0.0];
        }
        fn factor(&self, jac: &[f64; 4], c: f64, m: &mut [f64; 4]) -> bool {
            *m = [1.0 - c * jac[0], -c * jac[1], -c * jac[2], 1.0 - c * jac[3]];
            true
        }
        fn solve(&self, _jac: &[f64; 4], m: &mut [f64; 4], b: &mut [f64]) {
            let det = m[0] * m[3] - m[1] * m[2];
            let (b0, b1) = (b[0], b[1]);
            b[0] = (m[3] * b0 - m[1] * b1) / det;
            b[1] = (m[0] * b1 - m[2] * b0) / det;
        }
        fn error_mask(&self, _rel_tol: f64, mask: &mut [f64]) {
            mask.fill(0.0);
        }
        fn energy_balance(&self, y: &[f64]) -> Option<EnergyBalance> {
            let e = 0.5 * (y[0] * y[0] + y[1] * y[1]);
            self.check.then_some(EnergyBalance {
                balance: -e,
                scale: e,
                magnitude: e,
            })
        }
        fn save_jacobian(&self, jac: &[f64; 4], out: &mut Vec<f64>) {
            out.extend_from_slice(jac);
        }
        fn load_jacobian(&self, jac: &mut [f64; 4], src: &[f64]) -> bool {
            jac.copy_from_slice(src);
            true
        }
    }

    /// The energy check holds each step's energy residual to relTol times
    /// the stored energy: over ten periods of an oscillator whose states are
    /// left out of the error norm the energy drifts by at most relTol per
    /// step (measured 6.5e-7 per step at relTol 1e-6, 1056 steps). Without
    /// the check nothing limits the steps and the L-stable method's
    /// numerical damping takes most of the energy.
    #[test]
    fn energy_check_bounds_the_energy_residual_per_step() {
        // `check`: the system books its energy; `switch`: the integrator's
        // energy check is on
        let run_with = |check: bool, switch: bool| {
            let sys = Oscillator { check };
            let mut ros = Rosenbrock::new(&sys, 1e-6, 1e-6, 1e-3, 1_000_000);
            ros.energy_check = switch;
            let (mut t, mut y) = (0.0, vec![1.0, 0.0]);
            let t_end = 20.0 * std::f64::consts::PI;
            ros.advance(&sys, &mut (), &mut t, &mut y, t_end).unwrap();
            let drift = 1.0 - (y[0] * y[0] + y[1] * y[1]);
            (drift, ros.control.stats.steps, ros.energy_rejections)
        };
        let run = |check: bool| run_with(check, true);
        let (drift, steps, rejections) = run(true);
        assert!(
            drift.abs() <= 1e-6 * steps as f64,
            "with the check: drift {drift:e} over {steps} steps ({rejections} rejected on energy)"
        );
        let (unchecked, unchecked_steps, _) = run(false);
        assert!(
            unchecked > 0.5 && unchecked_steps < steps / 10,
            "without the check: drift {unchecked:e} over {unchecked_steps} steps"
        );
        // the switch off: the error norm's step control alone, step for step
        assert_eq!(run_with(true, false), (unchecked, unchecked_steps, 0));
    }

    /// The observer sees every trial with the error norm the step control
    /// used: the RMS of the components it is given, and the energy error
    /// where that was larger (the oscillator's states are out of the norm,
    /// so with the check on the energy error alone sets the step).
    #[test]
    fn observer_sees_every_trial_and_its_error_components() {
        let f = |t: f64, y: &[f64], dy: &mut [f64]| {
            dy[0] = y[1];
            dy[1] = -y[0] - 0.5 * y[1] * y[1] + (2.0 * t).cos();
        };
        let sys = Dense {
            n: 2,
            f,
            exact: true,
        };
        let mut ros = Rosenbrock::new(&sys, 1e-8, 1e-8, 0.5, 1_000_000);
        let (mut y, mut t) = (vec![1.0, 0.0], 0.0);
        let (mut trials, mut max_gap) = (0u64, 0.0f64);
        let (mut comps, mut end) = (vec![0.0; 2], vec![0.0; 2]);
        ros.advance_observed(&sys, &mut (), &mut t, &mut y, 1.0, &mut |m, tr| {
            trials += 1;
            assert_eq!(m.error_components(tr.y, &mut comps, &mut end), 0.0);
            let rms = ((comps[0] * comps[0] + comps[1] * comps[1]) / 2.0).sqrt();
            max_gap = max_gap.max((rms - tr.err).abs() / tr.err.max(1e-300));
        })
        .unwrap();
        let s = ros.control.stats;
        assert!(s.rejected > 0, "the first step (0.5 s) is rejected: {s:?}");
        assert_eq!(trials, s.steps + s.rejected);
        assert!(max_gap < 1e-12, "{max_gap:e}");
        assert_eq!(end, y, "the last trial's end state is the result");

        let sys = Oscillator { check: true };
        let mut ros = Rosenbrock::new(&sys, 1e-6, 1e-6, 1e-3, 1_000_000);
        let (mut y, mut t) = (vec![1.0, 0.0], 0.0);
        let mut energy_set = 0u64;
        ros.advance_observed(&sys, &mut (), &mut t, &mut y, 1.0, &mut |m, tr| {
            let e = m.error_components(tr.y, &mut comps, &mut end);
            assert_eq!(comps, [0.0, 0.0], "masked out of the norm");
            if tr.err <= 1.0 {
                assert_eq!(e, tr.err);
                energy_set += 1;
            }
        })
        .unwrap();
        assert_eq!(energy_set, ros.control.stats.steps);
    }

    /// The AVX2 build of a trial step gives the baseline's state and error
    /// norm to the last bit (no FMA).
    #[test]
    fn avx2_build_matches_baseline_to_the_bit() {
        if !Isa::Avx2.available() {
            return;
        }
        let f = |t: f64, y: &[f64], dy: &mut [f64]| {
            for (k, d) in dy.iter_mut().enumerate() {
                let (a, b) = (y[k], y[(k + 1) % y.len()]);
                *d = -(k as f64 + 1.0) * a + 0.3 * b * b + (t * (k as f64 + 2.0)).sin();
            }
        };
        let sys = Dense {
            n: 11,
            f,
            exact: true,
        };
        let y: Vec<f64> = (0..11).map(|k| (k as f64 * 0.37).cos()).collect();
        let mut base = Rosenbrock::new(&sys, 1e-6, 1e-8, 1e-3, 100);
        let mut wide = base.clone();
        let e_base = base.trial_with(Isa::Baseline, &sys, &mut (), 0.1, &y, 0.05);
        let e_wide = wide.trial_with(Isa::Avx2, &sys, &mut (), 0.1, &y, 0.05);
        assert!(e_base > 0.0 && e_base.is_finite());
        assert_eq!(e_base.to_bits(), e_wide.to_bits());
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&base.stage), bits(&wide.stage));
        assert_ne!(base.stage, y);
    }
}
