//! Every internal knob of the solvers in one place, with its value and why.
//!
//! The user-facing choices (method, tolerances, first step, step guard) are
//! [`SolverParams`](crate::model::params::SolverParams), set through the FMU's
//! `solver.*` variables. The values here are fixed: they were chosen on the
//! paper's drives and are documented in docs/model.md ("Integrators"). A
//! change to any of them changes results; rerun the accuracy benchmarks
//! (`cargo bench --bench belt -- accuracy`, `cargo bench --bench stiff`).
//! The model's own regularisations sit with their elements (the SDE's at a
//! zero gap: `elements::sde::REGULARISATION`, the clutch band:
//! `elements::decoupler::CLUTCH_BAND`), the mounting's relaxation knobs with
//! the mounting (`drive/mounting.rs`, `MOUNTING`).

/// The solvers' fixed knobs. [`TUNING`] holds the values in use.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverTuning {
    /// Error weight of the body angles and spins. They carry only the damped
    /// artificial modes: 1e-3, not 0, so that a step that goes unstable in
    /// them is still rejected.
    pub weight_angles: f64,
    /// Error weight of the body velocities with the creep law: they carry
    /// the artificial modes and the creep velocities that set the slip
    /// (1e-3 let the 5PK slip drift 5 % from RKF45's, 1e-2 0.3 %, for 28 %
    /// more steps). With `kubas2014` the velocities keep weight 1: friction
    /// follows the sliding velocity itself.
    pub weight_creep_velocities: f64,
    /// ... but the body velocities are never controlled more loosely than
    /// this relative tolerance (their weight is at least relTol / this):
    /// the creep velocities that set the slip are ~1e-3 of the belt speed,
    /// and at relTol 1e-3 with weight 1e-2 (10 % of the speed) the stiff
    /// method's steps lost the creep arcs (5PK drive: slip 0.94 % instead of
    /// 0.48 %, span tensions 5-18 % high); with this bound its speeds,
    /// tensions and slip stay within 0.3 %, 0.3 % and 2 % of RKF45's.
    pub creep_velocity_max_rel_tol: f64,
    /// RKF45 step factor after a rejected step: the elementary controller
    /// safety * err^(-1/5) with safety 0.9 (Hairer & Wanner), at most 1.
    pub rkf45_safety: f64,
    /// RKF45 PI controller over accepted steps, h_new = h * (target /
    /// err_n)^beta1 * (err_{n-1} / target)^beta2 (Gustafsson 1991; Hairer &
    /// Wanner II, IV.2, eq. 2.43c, with the safety written as the error level
    /// the controller steers to). The error estimate is O(h^5) (k = 5);
    /// beta1 = 1/k, beta2 = 0 is the elementary controller. beta1 = 0.7/k,
    /// beta2 = 0.4/k are Gustafsson's values: they keep the step-size
    /// sequence smooth where the step is held at the explicit method's
    /// stability limit (the bodies' fast modes), which the elementary
    /// controller overshoots every few steps (0.15-0.26 rejections per
    /// accepted step on the paper's drives; docs/benchmarks.md, "RKF45
    /// step-size control").
    pub rkf45_beta1: f64,
    /// See `rkf45_beta1`.
    pub rkf45_beta2: f64,
    /// Error level the PI controller steers to: 0.5. Measured on the 5PK
    /// drive (0-0.4 s, relTol 1e-4) over 0.3-0.9: a lower target takes
    /// smaller steps than the stability limit allows (0.3: 11 % more steps
    /// than the elementary controller), a higher one overshoots that limit
    /// again (0.9: as many rejections as the elementary controller); 0.5 took
    /// the fewest right-hand-side evaluations.
    pub rkf45_target_error: f64,
    /// Step factor limits [min, max] = [0.2, 5] (Hairer & Wanner's DOPRI5
    /// uses [0.2, 10]; 5 keeps the first steps after a shock cautious). After
    /// a rejection the next accepted step does not grow the step.
    pub rkf45_factor_min: f64,
    /// See `rkf45_factor_min`.
    pub rkf45_factor_max: f64,
    /// Rosenbrock (ROS34PW2) step factor: safety 0.9 on err^(-1/3) of its
    /// order-3 embedded estimate, limited to [0.2, 4].
    pub rosenbrock_safety: f64,
    /// See `rosenbrock_safety`.
    pub rosenbrock_factor_min: f64,
    /// See `rosenbrock_safety`.
    pub rosenbrock_factor_max: f64,
    /// Floor on the RKF45 PI controller's remembered error: an exact step
    /// (err = 0) must not make its `(err_{n-1} / target)^beta2` term blow
    /// up.
    pub rkf45_error_floor: f64,
    /// A trial step whose error is not finite (a force overflowed) is
    /// retried with the step times this factor ...
    pub non_finite_step_factor: f64,
    /// ... at most this many times in a row before the step fails.
    pub non_finite_retries: u32,
    /// Smallest step, in units of machine epsilon times the time (at least
    /// 1e-3 s): below it the step cannot move the time and the advance
    /// fails rather than loop.
    pub min_step_eps: f64,
    /// Step-size increases below this factor are not taken, so that the
    /// factored iteration matrix (which depends on h) can be reused.
    pub keep_step_below: f64,
    /// The stiff method's energy check (docs/model.md, "Integrators"): a
    /// trial step is also rejected when its energy residual r, the change
    /// over the step of the input work less the dissipated and the stored
    /// energy (zero for the exact flow), exceeds this times relTol times the
    /// belt's own stored energy E_b (its bodies' kinetic energy and the
    /// elastic energy of its SDEs, contacts and creep springs, at the
    /// step's start): 1, the energy's own relative tolerance. The error
    /// norm's components cannot see this error: it is a bias of ~0.5 % of
    /// the belt forces in every step, coherent over all bodies, far below
    /// each body's tolerance, which fed the belt's fast motion with energy
    /// on fast, lightly loaded drives (60-body drive of tests/defaults.rs:
    /// -1.54 W of a 0.5 W belt loss; speeds 0.67 % off). E_b, not the
    /// pulleys' energy (an engine's inertia) nor the frame's gravity
    /// potential, nor the transmitted power times h (that bound, relTol of
    /// the power, asks the method to resolve the contact and pitching
    /// modes it damps: steps near RKF45's).
    pub energy_tolerance: f64,
    /// Order in h of the energy residual of a step: 4, the local error of
    /// the order-3 solution's energy (measured on the 60-body drive from a
    /// running state: r falls 16-fold per halving of h below 0.1 ms). The
    /// residual enters the error norm as (|r| / tol)^(3 / this), so that
    /// the controller's exponent -1/3 for the order-2 embedded estimate
    /// brings it to its tolerance.
    pub energy_error_order: f64,
    /// Round-off of the energy balance, in machine epsilons of the largest
    /// term it sums (input work, dissipated, kinetic and potential energy):
    /// a residual below it is taken as zero, and it floors the tolerance
    /// (a belt at rest with no stored energy).
    pub energy_roundoff_ulps: f64,
    /// Accepted steps a Jacobian is kept for (it is also re-evaluated after a
    /// rejected step and after a restore): 1, a fresh Jacobian every step.
    /// Kept for 2 steps, the second step's energy error is about five times
    /// the first's at the same step size (docs/benchmarks.md), and on the
    /// accessory drives the energy check rejected 35-45 % of the trials
    /// (`cargo run --profile ci --example step_profile`); with a fresh one,
    /// 0.4-1.7 % (0-0.5 % on the tensioner set),
    /// and 1.7-2.1 times fewer trials for about as many Jacobians and fewer
    /// factorizations.
    pub jacobian_max_age: u32,
}

impl SolverTuning {
    /// Weight of the body velocities in the stiff method's error norm at
    /// relative tolerance `rel_tol`, for a friction law that follows the
    /// sliding velocity itself (`friction::Law::follows_sliding_velocity`)
    /// or not. The paper's law: 1, friction follows the sliding velocity,
    /// and a step that jumps across the stick band |v_T| < dv lands on the
    /// sliding branch, whose linearisation has no friction slope. The creep
    /// law: the body velocities carry the damped artificial modes, but also
    /// the creep velocities that set the slip: weight
    /// `weight_creep_velocities` (1e-2; 1e-3 let the 5PK slip drift 5 % from
    /// RKF45's, 1e-2 0.3 %, for 28 % more steps; docs/model.md), and never
    /// looser than a relative tolerance of `creep_velocity_max_rel_tol` on
    /// them: at relTol 1e-3 a weight of 1e-2 let the steps lose the creep
    /// arcs.
    pub fn velocity_error_weight(&self, follows_sliding_velocity: bool, rel_tol: f64) -> f64 {
        if follows_sliding_velocity {
            1.0
        } else {
            self.weight_creep_velocities
                .max(rel_tol / self.creep_velocity_max_rel_tol)
                .min(1.0)
        }
    }
}

/// The values in use.
pub const TUNING: SolverTuning = SolverTuning {
    weight_angles: 1e-3,
    weight_creep_velocities: 1e-2,
    creep_velocity_max_rel_tol: 1e-2,
    rkf45_safety: 0.9,
    rkf45_beta1: 0.7 / 5.0,
    rkf45_beta2: 0.4 / 5.0,
    rkf45_target_error: 0.5,
    rkf45_factor_min: 0.2,
    rkf45_factor_max: 5.0,
    rkf45_error_floor: 1e-4,
    non_finite_step_factor: 0.25,
    non_finite_retries: 40,
    min_step_eps: 16.0,
    rosenbrock_safety: 0.9,
    rosenbrock_factor_min: 0.2,
    rosenbrock_factor_max: 4.0,
    keep_step_below: 1.25,
    energy_tolerance: 1.0,
    energy_error_order: 4.0,
    energy_roundoff_ulps: 1e3,
    jacobian_max_age: 1,
};
