//! The drive's ODE as the integrators see it (`OdeSystem`, `StiffSystem`)
//! and the integrator a drive runs ([`Integrator`]).

use crate::model::elements::friction::Law;
use crate::model::params::{DriveParams, Method};
use crate::model::state::BodyIndex;
use crate::model::system::{BeltSystem, NoRecord, Workspace};
use crate::solver::iteration_matrix::IterationMatrix;
use crate::solver::jacobian::Jacobian;
use crate::solver::knobs::TUNING;
use crate::solver::rkf45::Rkf45;
use crate::solver::rosenbrock::{EnergyBalance, Rosenbrock, StiffSystem};
use crate::solver::step_control::{
    self, EmbeddedMethod, Landing, OdeSystem, Stats, StepControl, StepFailure, Trial,
};

impl OdeSystem for BeltSystem {
    type Workspace = Workspace;
    fn dim(&self) -> usize {
        BeltSystem::dim(self)
    }
    fn workspace(&self) -> Workspace {
        Workspace::new()
    }
    #[inline]
    fn rhs(&self, ws: &mut Workspace, t: f64, y: &[f64], dy: &mut [f64]) {
        BeltSystem::rhs(self, ws, t, y, dy, &mut NoRecord);
    }
    fn controlled_dim(&self) -> usize {
        BeltSystem::controlled_dim(self)
    }
    fn after_step(&self, y: &mut [f64]) -> bool {
        BeltSystem::after_step(self, y)
    }
    fn next_breakpoint(&self, t: f64) -> f64 {
        BeltSystem::next_breakpoint(self, t)
    }
}

impl StiffSystem for BeltSystem {
    type Jacobian = Jacobian;
    type Matrix = IterationMatrix;
    fn new_jacobian(&self) -> Jacobian {
        Jacobian::new(self)
    }
    fn new_matrix(&self) -> IterationMatrix {
        IterationMatrix::new(self)
    }
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut Jacobian) {
        BeltSystem::jacobian(self, t, y, jac);
    }
    /// The input energy's row: the prescribed speeds and applied torques at
    /// the step's start, so that over a step at constant inputs the input
    /// energy grows by exactly their work on the drive-torque impulses and
    /// pulley angles (a Jacobian kept from before a ramp's end or an input
    /// change would book it with the old speed or torque).
    fn step_rows(&self, t: f64, jac: &mut Jacobian) {
        jac.set_power_row(self, t);
    }
    fn factor(&self, jac: &Jacobian, c: f64, m: &mut IterationMatrix) -> bool {
        m.factor(self, jac, c)
    }
    fn solve(&self, jac: &Jacobian, m: &mut IterationMatrix, b: &mut [f64]) {
        m.solve(self, jac, b);
    }
    /// The input work less the dissipated and the stored energy, measured
    /// against the belt's own stored energy (its bodies' kinetic energy and
    /// the elastic energy of its SDEs, contacts and creep springs).
    fn energy_balance(&self, y: &[f64]) -> Option<EnergyBalance> {
        Some(BeltSystem::energy_balance(self, y))
    }
    /// The right-hand side with the stored energy taken in the same pass
    /// over the bodies ([`BeltSystem::rhs_energy`]).
    fn rhs_balance(
        &self,
        ws: &mut Workspace,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
    ) -> Option<EnergyBalance> {
        let e = BeltSystem::rhs_energy(self, ws, t, y, dy);
        Some(self.balance_of(y, e))
    }
    fn save_jacobian(&self, jac: &Jacobian, out: &mut Vec<f64>) {
        jac.save(out);
    }
    fn load_jacobian(&self, jac: &mut Jacobian, src: &[f64]) -> bool {
        jac.load(src)
    }
    /// Body angles and spins carry only the damped artificial modes: weight
    /// 1e-3 (not left out altogether, so a step that goes unstable in them is
    /// still rejected). The body velocities' weight depends on whether the
    /// friction law follows the sliding velocity
    /// (`SolverTuning::velocity_error_weight`); the tensioner arms' rates
    /// take the same.
    fn error_mask(&self, rel_tol: f64, mask: &mut [f64]) {
        const ANGLES: f64 = TUNING.weight_angles;
        mask.fill(1.0);
        let velocities =
            TUNING.velocity_error_weight(self.friction.follows_sliding_velocity(), rel_tol);
        for i in 0..self.n {
            let b = BodyIndex::of(i);
            mask[b.angle] = ANGLES;
            mask[b.spin] = ANGLES;
            mask[b.vx] = velocities;
            mask[b.vy] = velocities;
        }
        // a tensioner arm's rate: like the bodies' velocities, it carries
        // the arm's response to the body-passing ripple; the arm's angle
        // and its pivot friction's deflection (whose presliding law the
        // friction follows, not the rate) keep weight 1
        for j in 0..self.np {
            if self.pulleys[j].arm.is_some() {
                mask[self.state_layout.arm(j).rate] = velocities;
            }
        }
        // the impulses are outputs only
        mask[self.controlled_dim()..].fill(0.0);
    }
}

/// The integrator of a drive, chosen by [`SolverParams::method`](crate::model::params::SolverParams::method).
#[derive(Clone, Debug, PartialEq)]
#[allow(clippy::large_enum_variant)] // one per drive: its size does not matter
pub enum Integrator {
    /// Runge-Kutta-Fehlberg 4(5) ([`Method::Rkf45`]).
    Rkf45(Rkf45),
    /// The stiff Rosenbrock-W method ([`Method::Rosenbrock`]).
    Rosenbrock(Rosenbrock<BeltSystem>),
}

impl Integrator {
    pub(super) fn new(sys: &BeltSystem, params: &DriveParams) -> Self {
        let s = &params.solver;
        match s.method {
            Method::Rkf45 => Self::Rkf45(Rkf45::new(
                sys.dim(),
                s.rel_tol,
                s.abs_tol,
                s.initial_step,
                s.max_steps,
            )),
            Method::Rosenbrock => Self::Rosenbrock(Rosenbrock::new(
                sys,
                s.rel_tol,
                s.abs_tol,
                s.initial_step,
                s.max_steps,
            )),
        }
    }

    /// Integrates to `t_end`; `step_start` is told the time and state at the
    /// start of every accepted step (the end of the one before).
    pub(super) fn advance(
        &mut self,
        sys: &BeltSystem,
        ws: &mut Workspace,
        t: &mut f64,
        y: &mut [f64],
        t_end: f64,
        step_start: &mut dyn FnMut(f64, &[f64]),
    ) -> Result<(), StepFailure> {
        match self {
            Self::Rkf45(i) => i.advance_observed(sys, ws, t, y, t_end, &mut observer(step_start)),
            Self::Rosenbrock(i) => {
                i.advance_observed(sys, ws, t, y, t_end, &mut observer(step_start))
            }
        }
    }

    /// Integrates from `*t` to the first accepted step's end at or past
    /// `t_end` ([`step_control::advance_past`]); `step_start` as in
    /// [`Self::advance`].
    pub(super) fn advance_past(
        &mut self,
        sys: &BeltSystem,
        ws: &mut Workspace,
        t: &mut f64,
        y: &mut [f64],
        t_end: f64,
        step_start: &mut dyn FnMut(f64, &[f64]),
    ) -> Result<Landing, StepFailure> {
        match self {
            Self::Rkf45(i) => {
                step_control::advance_past(i, sys, ws, t, y, t_end, &mut observer(step_start))
            }
            Self::Rosenbrock(i) => {
                step_control::advance_past(i, sys, ws, t, y, t_end, &mut observer(step_start))
            }
        }
    }

    /// Retakes the step that passed a communication point clipped to
    /// `t_target` ([`step_control::retake_clipped`]) from (`*t`, `y`), its
    /// start, with the step size `h` it had there. Ok(false): the
    /// method's checkpoint was gone, the retake started afresh.
    pub(super) fn retake_clipped(
        &mut self,
        sys: &BeltSystem,
        ws: &mut Workspace,
        t: &mut f64,
        y: &mut [f64],
        h: f64,
        t_target: f64,
    ) -> Result<bool, StepFailure> {
        match self {
            Self::Rkf45(i) => {
                step_control::retake_clipped(i, sys, ws, t, y, h, t_target, &mut |_: &_, _| {})
            }
            Self::Rosenbrock(i) => {
                step_control::retake_clipped(i, sys, ws, t, y, h, t_target, &mut |_: &_, _| {})
            }
        }
    }

    /// f at the start of the last accepted step (until the next trial) and
    /// at its end `t_end`, where the method has them.
    pub(super) fn step_derivatives(&self, t_end: f64) -> (Option<&[f64]>, Option<&[f64]>) {
        match self {
            Self::Rkf45(i) => (
                EmbeddedMethod::<BeltSystem>::start_derivative(i),
                EmbeddedMethod::<BeltSystem>::end_derivative(i, t_end),
            ),
            Self::Rosenbrock(i) => (i.start_derivative(), i.end_derivative(t_end)),
        }
    }

    /// The state or the inputs were changed between steps: the stiff
    /// method's kept first stage and energy balance are stale.
    pub(super) fn state_changed(&mut self) {
        if let Self::Rosenbrock(i) = self {
            i.state_changed();
        }
    }

    /// Step size, counters and work guard.
    pub fn control(&self) -> &StepControl {
        match self {
            Self::Rkf45(i) => &i.control,
            Self::Rosenbrock(i) => &i.control,
        }
    }

    pub(super) fn control_mut(&mut self) -> &mut StepControl {
        match self {
            Self::Rkf45(i) => &mut i.control,
            Self::Rosenbrock(i) => &mut i.control,
        }
    }

    /// Counters of the work done (cumulative).
    pub fn stats(&self) -> Stats {
        self.control().stats
    }

    /// Step size proposed for the next step.
    pub fn step_size(&self) -> f64 {
        self.control().h
    }

    /// Integrator data beyond step size and counters that a saved state
    /// must carry (the stiff method's kept Jacobian, RKF45's step-size
    /// controller memory).
    pub(super) fn save(&self, sys: &BeltSystem, point: &[f64]) -> Vec<f64> {
        let mut out = Vec::new();
        match self {
            Self::Rkf45(i) => i.save(&mut out),
            Self::Rosenbrock(i) => i.save(sys, point, &mut out),
        }
        out
    }

    /// The method's checkpoint of the step taken past the communication
    /// point, for a saved state.
    pub(super) fn save_checkpoint(&self, sys: &BeltSystem, out: &mut Vec<f64>) {
        match self {
            Self::Rkf45(i) => i.save_checkpoint(out),
            Self::Rosenbrock(i) => i.save_checkpoint(sys, out),
        }
    }

    /// Reads what [`save_checkpoint`](Self::save_checkpoint) wrote.
    pub(super) fn load_checkpoint(&mut self, sys: &BeltSystem, src: &[f64]) -> bool {
        match self {
            Self::Rkf45(i) => i.load_checkpoint(src),
            Self::Rosenbrock(i) => i.load_checkpoint(sys, src),
        }
    }

    /// Restores step size, counters and what [`save`](Self::save) wrote.
    pub(super) fn restore(
        &mut self,
        sys: &BeltSystem,
        point: &[f64],
        h: f64,
        stats: Stats,
        extra: &[f64],
    ) -> bool {
        let c = self.control_mut();
        c.h = h;
        c.stats = stats;
        match self {
            Self::Rkf45(i) => i.load(extra),
            Self::Rosenbrock(i) => i.load(sys, point, extra),
        }
    }
}

/// An observer of the trials that tells `step_start` the time and state at
/// the start of every accepted trial (error norm at most 1).
fn observer<M>(step_start: &mut dyn FnMut(f64, &[f64])) -> impl FnMut(&M, Trial) + '_ {
    move |_, tr: Trial| {
        if tr.err <= 1.0 {
            step_start(tr.t, tr.y);
        }
    }
}
