//! Adaptive step-size control shared by the integrators ([`crate::solver::rkf45`],
//! [`crate::solver::rosenbrock`]): the ODE interface, counters, failures, and the
//! driver that steps to exactly a target time, carries the step size across
//! calls, and restores the state when a call fails.

use crate::solver::knobs::TUNING;

/// An ODE y' = f(t, y) with a discrete update after each accepted step.
pub trait OdeSystem {
    /// Scratch of an evaluation of the right-hand side, owned by the
    /// caller of the integrator (`()` if the system needs none).
    type Workspace;
    /// Length of the state vector.
    fn dim(&self) -> usize;
    /// A workspace for [`Self::rhs`].
    fn workspace(&self) -> Self::Workspace;
    /// dy = f(t, y), with scratch `ws`.
    fn rhs(&self, ws: &mut Self::Workspace, t: f64, y: &[f64], dy: &mut [f64]);
    /// The first `controlled_dim` components enter the error norm; the rest
    /// are quadratures that feed nothing back (all by default).
    fn controlled_dim(&self) -> usize {
        self.dim()
    }
    /// Called with the new state after every accepted step; true if it
    /// changed the state.
    fn after_step(&self, _y: &mut [f64]) -> bool {
        false
    }
    /// The first time after `t` at which f has a kink in time (the end of
    /// an input's ramp); infinity if none. A step that would pass the
    /// call's end time with such a kink inside is clipped to the end time
    /// instead ([`advance_past`]): the interpolant over it would cross the
    /// kink.
    fn next_breakpoint(&self, _t: f64) -> f64 {
        f64::INFINITY
    }
}

/// Counters, cumulative over the life of the integrator.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected trial steps.
    pub rejected: u64,
    /// Evaluations of the right-hand side.
    pub rhs_evals: u64,
    /// Size of the last accepted step [s].
    pub last_step: f64,
}

#[derive(Clone, Debug, PartialEq)]
/// Why an integration call failed (the state is then restored).
pub enum StepFailure {
    /// More than the call's step budget ([`step_budget`]) was needed.
    TooManySteps {
        /// Time reached [s].
        t: f64,
        /// Steps taken in the call.
        steps: u64,
    },
    /// The step size fell below the resolution of t.
    StepTooSmall {
        /// Time reached [s].
        t: f64,
        /// The step size [s].
        h: f64,
    },
    /// The right-hand side produced NaN or infinity at every trial step.
    NonFinite {
        /// Time reached [s].
        t: f64,
    },
}

impl StepFailure {
    /// The parameter that bounds what failed, if one does (the step-count
    /// guard).
    pub fn parameter(&self) -> Option<crate::model::param_id::Param> {
        match self {
            Self::TooManySteps { .. } => Some(crate::model::param_id::Param::SolverMaxSteps),
            _ => None,
        }
    }
}

impl std::fmt::Display for StepFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::TooManySteps { t, steps } => write!(
                f,
                "integrator step-count guard hit at t = {t} s after {steps} steps, \
                 the most a call over this interval may take"
            ),
            Self::StepTooSmall { t, h } => {
                write!(f, "integrator step size fell to {h:e} s at t = {t} s")
            }
            Self::NonFinite { t } => write!(f, "the state became non-finite at t = {t} s"),
        }
    }
}

/// Step size, counters and work guard of an integrator.
#[derive(Clone, Debug, PartialEq)]
pub struct StepControl {
    /// Step size proposed for the next step.
    pub h: f64,
    /// Most accepted steps per [`GUARD_INTERVAL`] of a call's interval
    /// ([`step_budget`]).
    pub max_steps: u64,
    /// Counters.
    pub stats: Stats,
    /// State at the start of the current call.
    backup: Vec<f64>,
    /// Start (time, state, step size) of the step that may pass the
    /// target time ([`advance_past`]), taken before its first trial; the
    /// time is NaN after a failed call.
    pub straddle_t: f64,
    /// The step size at that start.
    pub straddle_h: f64,
    /// The state at that start.
    pub straddle_y: Vec<f64>,
}

impl StepControl {
    /// Step control for `dim` states, first step `h0`, at most `max_steps` steps per call.
    pub fn new(dim: usize, h0: f64, max_steps: u64) -> Self {
        Self {
            h: h0,
            max_steps,
            stats: Stats::default(),
            backup: vec![0.0; dim],
            straddle_t: f64::NAN,
            straddle_h: f64::NAN,
            straddle_y: vec![0.0; dim],
        }
    }
}

/// An embedded pair as the driver sees it.
pub trait EmbeddedMethod<S: OdeSystem + ?Sized> {
    /// Step size, counters and work guard.
    fn control(&mut self) -> &mut StepControl;
    /// One trial step of size `h` from (t, y); keeps the candidate state and
    /// returns the scaled error norm (non-finite when the step failed).
    fn trial(&mut self, sys: &S, ws: &mut S::Workspace, t: f64, y: &[f64], h: f64) -> f64;
    /// Copies the candidate of the last trial into `y`.
    fn take_step(&mut self, y: &mut [f64]);
    /// The system changed the state after the step was taken
    /// ([`OdeSystem::after_step`]): what the method kept of it is stale.
    fn state_changed(&mut self) {}
    /// Factor on h for scaled error `err` (rejected or accepted).
    fn step_factor(&self, err: f64) -> f64;
    /// A step was accepted; returns the factor to apply (hook for methods
    /// that keep a factorization).
    fn accepted(&mut self, factor: f64) -> f64 {
        factor
    }
    /// A trial was rejected (error too large or not finite).
    fn rejected(&mut self) {}
    /// The call failed and the state was restored.
    fn failed(&mut self) {}
    /// A call of the driver starts (the methods' own `advance` do this
    /// too).
    fn call_start(&mut self) {}
    /// A step from time `t` that may pass the target time is about to be
    /// tried ([`advance_past`]): keep what a retake of it clipped to the
    /// target depends on beyond (t, y) and the step size (see
    /// [`Self::rewind`]).
    fn checkpoint(&mut self, _t: f64) {}
    /// Returns to the checkpoint taken at `t`, so a step from there
    /// proceeds as it would have if it had been clipped to its target from
    /// the start; false (and the method's kept data forgotten, so the
    /// retake is still a correct step) if that checkpoint is gone.
    fn rewind(&mut self, _t: f64) -> bool {
        false
    }
    /// f(t, y) at the start of the last accepted step, while no trial has
    /// been taken since (for dense output).
    fn start_derivative(&self) -> Option<&[f64]> {
        None
    }
    /// f(t, y) at the end of the last accepted step (the next step's first
    /// stage), if the method has it.
    fn end_derivative(&self, _t: f64) -> Option<&[f64]> {
        None
    }
}

/// The interval the step-count guard is stated per: a call over H may take
/// `max_steps` steps per `GUARD_INTERVAL` of H (at least `max_steps`).
pub const GUARD_INTERVAL: f64 = 1e-3;

/// The accepted steps a call over `interval` seconds may take:
/// `max_steps` · max(1, interval / [`GUARD_INTERVAL`]), saturating. The guard
/// scales with the interval, so a long communication step completes; what it
/// stops is a call whose mean step has collapsed below `GUARD_INTERVAL /
/// max_steps` (10 ns at the FMU's default `solver.maxSteps`, docs/numerics.md).
pub fn step_budget(max_steps: u64, interval: f64) -> u64 {
    // an interval of one GUARD_INTERVAL computed as a difference of two
    // times may exceed it in the last bits: that is still one
    let intervals = (interval / GUARD_INTERVAL * (1.0 - 1e-9)).ceil();
    if intervals.is_nan() || intervals <= 1.0 {
        return max_steps;
    }
    // float-to-int `as` saturates at u64::MAX
    max_steps.saturating_mul(intervals as u64)
}

/// Integrates `y` from `*t` to exactly `t_end` with `method`. On failure `y`,
/// `*t` and the carried step size are restored to their values at the call
/// (the counters keep the work done).
pub fn advance<S, M>(
    method: &mut M,
    sys: &S,
    ws: &mut S::Workspace,
    t: &mut f64,
    y: &mut [f64],
    t_end: f64,
) -> Result<(), StepFailure>
where
    S: OdeSystem + ?Sized,
    M: EmbeddedMethod<S>,
{
    advance_observed(method, sys, ws, t, y, t_end, &mut |_: &M, _: Trial| {})
}

/// One trial step as an observer of [`advance_observed`] sees it: the
/// step's start (time, state), its size and scaled error norm (accepted
/// when at most 1). The method still holds the trial's stages, so the
/// observer can ask it for the error's components.
#[derive(Clone, Copy, Debug)]
pub struct Trial<'a> {
    /// Start time of the trial step [s].
    pub t: f64,
    /// State at the start.
    pub y: &'a [f64],
    /// Step size tried [s].
    pub h: f64,
    /// Scaled error norm (accepted when at most 1; not finite when the step failed).
    pub err: f64,
}

/// [`advance`] with `observe` called after every trial step, before it is
/// taken or rejected: diagnostics (`examples/step_profile.rs`). The plain
/// [`advance`] is this with an observer that does nothing, compiled away.
pub fn advance_observed<S, M, O>(
    method: &mut M,
    sys: &S,
    ws: &mut S::Workspace,
    t: &mut f64,
    y: &mut [f64],
    t_end: f64,
    observe: &mut O,
) -> Result<(), StepFailure>
where
    S: OdeSystem + ?Sized,
    M: EmbeddedMethod<S>,
    O: FnMut(&M, Trial) + ?Sized,
{
    landed(advance_landing(
        method, sys, ws, t, y, t_end, false, observe,
    ))
}

/// Where a call of [`advance_past`] ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Landing {
    /// Exactly on the target time.
    OnTarget,
    /// Past it: the last step started before the target (at
    /// `StepControl::straddle_t`, from `StepControl::straddle_y`) and ended
    /// after it.
    Past,
}

fn landed(r: Result<Landing, StepFailure>) -> Result<(), StepFailure> {
    r.map(|_| ())
}

/// Like [`advance_observed`], but the last step is not clipped to land on
/// `t_end`: the integration ends at the first accepted step's end at or
/// past `t_end` (a step within 1e-12 of it relative is still clipped to it,
/// and so is a step with a kink of f in time inside,
/// [`OdeSystem::next_breakpoint`]).
/// The step that may pass `t_end` is checkpointed first
/// ([`EmbeddedMethod::checkpoint`]; its start in `StepControl::straddle_*`)
/// so that it can be retaken clipped ([`retake_clipped`]).
pub fn advance_past<S, M, O>(
    method: &mut M,
    sys: &S,
    ws: &mut S::Workspace,
    t: &mut f64,
    y: &mut [f64],
    t_end: f64,
    observe: &mut O,
) -> Result<Landing, StepFailure>
where
    S: OdeSystem + ?Sized,
    M: EmbeddedMethod<S>,
    O: FnMut(&M, Trial) + ?Sized,
{
    advance_landing(method, sys, ws, t, y, t_end, true, observe)
}

/// Retakes the last step of an [`advance_past`] call that passed its
/// target, clipped to `t_target` (inside that step): from its start
/// (`*t`, `y`, set by the caller to the `StepControl::straddle_*` of that
/// call) with the step size `h` it had there, the method back at its
/// checkpoint ([`EmbeddedMethod::rewind`]), the integration runs to
/// exactly `t_target` as [`advance`] would have from there. False in the
/// result if the checkpoint was gone (the retake is then a correct step
/// from a fresh start, not the same bits).
#[allow(clippy::too_many_arguments)]
pub fn retake_clipped<S, M, O>(
    method: &mut M,
    sys: &S,
    ws: &mut S::Workspace,
    t: &mut f64,
    y: &mut [f64],
    h: f64,
    t_target: f64,
    observe: &mut O,
) -> Result<bool, StepFailure>
where
    S: OdeSystem + ?Sized,
    M: EmbeddedMethod<S>,
    O: FnMut(&M, Trial) + ?Sized,
{
    method.control().h = h;
    let exact = method.rewind(*t);
    advance_observed(method, sys, ws, t, y, t_target, observe).map(|()| exact)
}

#[allow(clippy::too_many_arguments)]
fn advance_landing<S, M, O>(
    method: &mut M,
    sys: &S,
    ws: &mut S::Workspace,
    t: &mut f64,
    y: &mut [f64],
    t_end: f64,
    pass: bool,
    observe: &mut O,
) -> Result<Landing, StepFailure>
where
    S: OdeSystem + ?Sized,
    M: EmbeddedMethod<S>,
    O: FnMut(&M, Trial) + ?Sized,
{
    let t_start = *t;
    method.call_start();
    let c = method.control();
    c.backup.copy_from_slice(y);
    let (h_start, last_step) = (c.h, c.stats.last_step);
    let result = advance_inner(method, sys, ws, t, y, t_end, pass, observe);
    if result.is_err() {
        let c = method.control();
        c.straddle_t = f64::NAN;
        y.copy_from_slice(&c.backup);
        *t = t_start;
        c.h = h_start;
        c.stats.last_step = last_step;
        method.failed();
    }
    result
}

#[allow(clippy::too_many_arguments)]
fn advance_inner<S, M, O>(
    method: &mut M,
    sys: &S,
    ws: &mut S::Workspace,
    t: &mut f64,
    y: &mut [f64],
    t_end: f64,
    pass: bool,
    observe: &mut O,
) -> Result<Landing, StepFailure>
where
    S: OdeSystem + ?Sized,
    M: EmbeddedMethod<S>,
    O: FnMut(&M, Trial) + ?Sized,
{
    let mut steps = 0u64;
    let mut non_finite = 0u32;
    let budget = step_budget(method.control().max_steps, t_end - *t);
    let mut landing = Landing::OnTarget;
    let mut checkpointed = f64::NAN;
    while *t < t_end {
        let c = method.control();
        if steps >= budget {
            return Err(StepFailure::TooManySteps { t: *t, steps });
        }
        let remaining = t_end - *t;
        // Clip the last step to land on t_end (also when only slightly
        // shorter); passing it, only when it ends within the same 1e-12.
        let mut last = if pass {
            (c.h - remaining).abs() <= remaining * 1e-12
        } else {
            c.h >= remaining * (1.0 - 1e-12)
        };
        let mut h = if last { remaining } else { c.h };
        let mut straddle = pass && !last && h > remaining;
        if straddle && sys.next_breakpoint(*t) <= *t + h {
            (h, last, straddle) = (remaining, true, false);
        }
        if straddle && checkpointed != *t {
            checkpointed = *t;
            c.straddle_t = *t;
            c.straddle_h = h;
            c.straddle_y.copy_from_slice(y);
            method.checkpoint(*t);
        }
        let h_min = TUNING.min_step_eps * f64::EPSILON * t.abs().max(t_end.abs()).max(1e-3);
        if h < h_min && !last {
            return Err(StepFailure::StepTooSmall { t: *t, h });
        }
        let err = method.trial(sys, ws, *t, y, h);
        observe(
            &*method,
            Trial {
                t: *t,
                y: &*y,
                h,
                err,
            },
        );
        if !err.is_finite() {
            non_finite += 1;
            method.control().stats.rejected += 1;
            method.rejected();
            if non_finite > TUNING.non_finite_retries {
                return Err(StepFailure::NonFinite { t: *t });
            }
            method.control().h = h * TUNING.non_finite_step_factor;
            continue;
        }
        non_finite = 0;
        let factor = method.step_factor(err);
        if err <= 1.0 {
            method.take_step(y);
            if sys.after_step(y) {
                method.state_changed();
            }
            *t = if last { t_end } else { *t + h };
            landing = if straddle {
                Landing::Past
            } else {
                Landing::OnTarget
            };
            steps += 1;
            let factor = method.accepted(factor);
            let c = method.control();
            c.stats.steps += 1;
            c.stats.last_step = h;
            // A clipped last step does not shrink the carried step size.
            c.h = if last {
                c.h.max(h * factor)
            } else {
                h * factor
            };
        } else {
            method.control().stats.rejected += 1;
            method.rejected();
            method.control().h = h * factor;
        }
    }
    Ok(landing)
}
