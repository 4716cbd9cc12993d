//! A simulated belt drive: parameters, mounted layout, state, integrator.
//! This is the whole interface the FMI adapter uses.

use crate::interval::{IntervalAccumulator, IntervalOutputs, INTERVAL_DATA};
use crate::model::elements::contact::{smoothstep, AUTO_P_MAX_PER_PENETRATION};
use crate::model::elements::friction::Law;
use crate::model::layout::Layout;
use crate::model::param_id::{msg, Message, Param, Part};
use crate::model::params::{DriveParams, Method, ParamError, MAX_PULLEYS, PROBE_AUTO};
use crate::model::system::{
    BeltSystem, Inputs, NoRecord, Recorder, Relaxation, Workspace, BODY_DOF, IMPULSES,
};
use crate::solver::iteration_matrix::IterationMatrix;
use crate::solver::jacobian::Jacobian;
use crate::solver::knobs::TUNING;
use crate::solver::rkf45::Rkf45;
use crate::solver::rosenbrock::{EnergyBalance, Rosenbrock, StiffSystem};
use crate::solver::step_control::{OdeSystem, Stats, StepControl, StepFailure, Trial};

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
    /// (`SolverTuning::velocity_error_weight`).
    fn error_mask(&self, rel_tol: f64, mask: &mut [f64]) {
        const ANGLES: f64 = TUNING.weight_angles;
        mask.fill(1.0);
        let velocities =
            TUNING.velocity_error_weight(self.friction.follows_sliding_velocity(), rel_tol);
        for body in mask[..BODY_DOF * self.n].chunks_exact_mut(BODY_DOF) {
            body[2] = ANGLES;
            body[5] = ANGLES;
            body[3] = velocities;
            body[4] = velocities;
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
    fn new(sys: &BeltSystem, params: &DriveParams) -> Self {
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
    fn advance(
        &mut self,
        sys: &BeltSystem,
        ws: &mut Workspace,
        t: &mut f64,
        y: &mut [f64],
        t_end: f64,
        step_start: &mut dyn FnMut(f64, &[f64]),
    ) -> Result<(), StepFailure> {
        // a trial is accepted when its error norm is at most 1
        match self {
            Self::Rkf45(i) => i.advance_observed(sys, ws, t, y, t_end, &mut |_, tr: Trial| {
                if tr.err <= 1.0 {
                    step_start(tr.t, tr.y);
                }
            }),
            Self::Rosenbrock(i) => i.advance_observed(sys, ws, t, y, t_end, &mut |_, tr: Trial| {
                if tr.err <= 1.0 {
                    step_start(tr.t, tr.y);
                }
            }),
        }
    }

    /// The state or the inputs were changed between steps: the stiff
    /// method's kept first stage and energy balance are stale.
    fn state_changed(&mut self) {
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

    fn control_mut(&mut self) -> &mut StepControl {
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
    fn save(&self, sys: &BeltSystem, point: &[f64]) -> Vec<f64> {
        let mut out = Vec::new();
        match self {
            Self::Rkf45(i) => i.save(&mut out),
            Self::Rosenbrock(i) => i.save(sys, point, &mut out),
        }
        out
    }

    /// Restores step size, counters and what [`save`](Self::save) wrote.
    fn restore(
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

/// Per-pulley outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PulleyOutputs {
    /// Angle of rotation [rad].
    pub angle: f64,
    /// Angular speed [rad/s].
    pub omega: f64,
    /// Angular acceleration [rad/s^2].
    pub alpha: f64,
    /// Torque the belt exerts on the pulley [N m].
    pub belt_torque: f64,
    /// Torque a speed drive supplies (0 for torque-driven pulleys) [N m].
    pub drive_torque: f64,
    /// Force of the belt on the hub [N].
    pub hub_force: [f64; 2],
    /// Means over the last communication step (see [`Window`]): belt torque
    /// and drive torque [N m], force on the hub [N], acceleration [rad/s2].
    pub mean_belt_torque: f64,
    /// Mean drive torque [N m].
    pub mean_drive_torque: f64,
    /// Mean force on the hub [N].
    pub mean_hub_force: [f64; 2],
    /// Mean acceleration [rad/s2].
    pub mean_alpha: f64,
    /// 1 - v_j / v_1: surface speed loss relative to pulley 1.
    pub slip: f64,
    /// Wrap angle of the mounted belt on the pulley [rad].
    pub wrap_angle: f64,
    /// Speed of the rotor behind a decoupler (the pulley's speed without
    /// one) [rad/s], and the torque the decoupler's clutch transmits in its
    /// driving sense (>= 0; 0 without one) [N m].
    pub rotor_omega: f64,
    /// Torque the decoupler's clutch transmits [N m] (see `rotor_omega`).
    pub decoupler_torque: f64,
    /// Tensioner arm (zero without one): angle from the mounted position
    /// (counterclockwise positive) [rad], its rate [rad/s], the spring's
    /// torque on the arm [N m] and the spring's free angle found by the
    /// mounting [rad].
    pub arm_angle: f64,
    /// Tensioner arm's angular rate [rad/s] (see `arm_angle`).
    pub arm_omega: f64,
    /// Torque of the tensioner spring on the arm [N m].
    pub arm_spring_torque: f64,
    /// Free angle of the tensioner spring found by the mounting [rad].
    pub arm_free_angle: f64,
}

/// Forces on the probe body from each pulley (Figs. 16-18).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ProbeOutputs {
    /// Force in the translational SDE at the probe body's left end (Fig. 15).
    pub sde_force: f64,
    /// Centre of the probe body [m].
    pub position: [f64; 2],
    /// Normal contact force on the probe body from pulley j [N] (Fig. 16).
    pub normal_force: [f64; MAX_PULLEYS],
    /// Friction force on the probe body from pulley j, along the pulley's tangent [N] (Fig. 17).
    pub friction_force: [f64; MAX_PULLEYS],
    /// Relative velocity v_T of pulley j's surface and the probe body [m/s] (Fig. 18).
    pub slip_velocity: [f64; MAX_PULLEYS],
}

#[derive(Clone, Debug, Default, PartialEq)]
/// Every output of the drive at one instant.
pub struct Outputs {
    /// Per pulley, in pulley order.
    pub pulleys: [PulleyOutputs; MAX_PULLEYS],
    /// Tension of the middle SDE of the free span from pulley k to k+1.
    pub span_tension: [f64; MAX_PULLEYS],
    /// Slip across span k: 1 - v_{k+1} / v_k, surface speeds of consecutive
    /// pulleys (the last span closes the loop back to pulley 1).
    pub span_slip: [f64; MAX_PULLEYS],
    /// Transverse deflection of the belt at the fixed mid-point of span k
    /// from the straight common tangent of the mounted path [m], positive
    /// to the left of the travel from pulley k to k+1, and its rate [m/s].
    pub span_mid_deflection: [f64; MAX_PULLEYS],
    /// Rate of `span_mid_deflection` [m/s].
    pub span_mid_deflection_rate: [f64; MAX_PULLEYS],
    /// Smallest tension of any translational SDE [N].
    pub min_tension: f64,
    /// Largest tension of any translational SDE [N].
    pub max_tension: f64,
    /// Forces on and position of the probe body.
    pub probe: ProbeOutputs,
    /// Power dissipated at this instant, the rate of `energy_dissipated`
    /// [W]: loads, dampers, friction slip and the creep springs' exchange
    /// with the normal force (not signed; elements::friction).
    pub power_dissipated: f64,
    /// Power dissipated in the belt alone (>= 0): SDE dampers, contact
    /// damping and friction slip, without the creep springs' exchange.
    pub belt_power_loss: f64,
    /// Energy dissipated since the start, less what the creep springs
    /// store [J].
    pub energy_dissipated: f64,
    /// Work done by the drives and input torques since the start [J].
    pub energy_input: f64,
    /// Kinetic energy of bodies, pulleys, rotors and arms [J].
    pub kinetic_energy: f64,
    /// Elastic (SDEs, contacts, creep springs) and gravitational energy [J].
    pub potential_energy: f64,
    /// Means and extrema over the last communication step (`interval`).
    pub interval: IntervalOutputs,
}

/// Collects the outputs during one recorded force evaluation.
struct OutputRecorder<'a> {
    out: &'a mut Outputs,
    tensions: &'a mut [f64],
    probe: usize,
    span_mid: [[f64; 2]; MAX_PULLEYS],
    n_spans: usize,
    span_best: [f64; MAX_PULLEYS],
    /// Power stored in the creep springs (not dissipated).
    spring_power: f64,
}

impl Recorder for OutputRecorder<'_> {
    const ACTIVE: bool = true;
    fn sde(&mut self, k: usize, tension: f64, mid: [f64; 2]) {
        self.tensions[k] = tension;
        if k == self.probe {
            self.out.probe.sde_force = tension;
        }
        for s in 0..self.n_spans {
            let d = (mid[0] - self.span_mid[s][0]).hypot(mid[1] - self.span_mid[s][1]);
            if d < self.span_best[s] {
                self.span_best[s] = d;
                self.out.span_tension[s] = tension;
            }
        }
    }
    fn contact(&mut self, body: usize, pulley: usize, n: f64, f: f64, v_t: f64, _p: f64) {
        if body == self.probe {
            self.out.probe.normal_force[pulley] = n;
            self.out.probe.friction_force[pulley] = f;
            self.out.probe.slip_velocity[pulley] = v_t;
        }
    }
    fn hub_force(&mut self, pulley: usize, fx: f64, fy: f64) {
        self.out.pulleys[pulley].hub_force[0] += fx;
        self.out.pulleys[pulley].hub_force[1] += fy;
    }
    fn pulley(&mut self, j: usize, belt_torque: f64, drive_torque: f64, alpha: f64) {
        let p = &mut self.out.pulleys[j];
        p.belt_torque = belt_torque;
        p.drive_torque = drive_torque;
        p.alpha = alpha;
    }
    fn decoupler(&mut self, j: usize, torque: f64, rotor_omega: f64) {
        let p = &mut self.out.pulleys[j];
        p.decoupler_torque = torque;
        p.rotor_omega = rotor_omega;
    }
    fn power(&mut self, _input: f64, dissipated: f64) {
        self.out.power_dissipated = dissipated;
    }
    fn belt_loss(&mut self, p: f64) {
        self.out.belt_power_loss += p;
    }
    fn creep_spring_power(&mut self, p: f64) {
        self.spring_power += p;
    }
}

/// Settles the mounted belt into its frictionless static equilibrium with
/// the pulleys held: the layout gives every SDE the preload, but where a
/// span meets an arc the chord geometry cannot also balance the contact
/// forces exactly, and friction would lock that error in. A short damped
/// relaxation (mass-proportional damping near critical for the contact mode,
/// friction off) removes it; the belt then starts at rest with zero creep.
/// `max_steps` bounds the work in total (the solver's step-count guard, at
/// most `RELAX_MAX_STEPS`); a relaxation cut short leaves the belt as far as
/// it got.
fn relax_into_equilibrium(sys: &BeltSystem, ws: &mut Workspace, y: &mut [f64], max_steps: u64) {
    // Contact mode of one body: stiffness dN/dp at the typical penetration.
    let k_contact = sys.contact.stiffness(TUNING.relax_penetration);
    // Friction off, the pulleys (and a decoupler's rotor, a tensioner's
    // arm) held at rest.
    let relax = sys.with_relaxation(Relaxation {
        damping: 2.0 * (k_contact / sys.mass).sqrt(),
        frictionless: true,
        pulleys_held: true,
    });
    // Relax over a few axial diffusion times of the damped belt, at least
    // ten contact periods; stop early once everything is at rest.
    const CHUNKS: u64 = TUNING.relax_chunks;
    let per_chunk = (max_steps.min(RELAX_MAX_STEPS) / CHUNKS).max(1);
    let mut rk = Rkf45::new(
        y.len(),
        TUNING.relax_rel_tol,
        TUNING.relax_abs_tol,
        TUNING.relax_initial_step,
        per_chunk,
    );
    let mut t = 0.0;
    let period = std::f64::consts::TAU / (k_contact / relax.mass).sqrt();
    let chunk = 2.0 * period;
    for _ in 0..CHUNKS {
        let target = t + chunk;
        if rk.advance(&relax, ws, &mut t, y, target).is_err() {
            break;
        }
        let v_max = (0..relax.n)
            .map(|i| y[BODY_DOF * i + 3].abs().max(y[BODY_DOF * i + 4].abs()))
            .fold(0.0, f64::max);
        if t >= TUNING.relax_min_periods * period && v_max < TUNING.relax_rest_speed {
            break;
        }
    }
    for i in 0..relax.n {
        let o = BODY_DOF * i;
        y[o + 3] = 0.0;
        y[o + 4] = 0.0;
        y[o + 5] = 0.0;
        y[o + 6] = 0.0;
    }
    let e = relax.energy_offset();
    y[e] = 0.0;
    y[e + 1] = 0.0;
    y[relax.controlled_dim()..].fill(0.0);
    for p in &relax.pulleys[..relax.np] {
        if p.decoupler.is_some() {
            y[p.decoupler_offset] = 0.0;
            y[p.decoupler_offset + 1] = 0.0;
        }
        if p.arm.is_some() {
            y[p.arm_offset] = 0.0;
            y[p.arm_offset + 1] = 0.0;
        }
    }
}

/// Collects the belt's force on every pulley's hub.
struct HubRecorder([[f64; 2]; MAX_PULLEYS]);

impl Recorder for HubRecorder {
    const ACTIVE: bool = true;
    fn hub_force(&mut self, pulley: usize, fx: f64, fy: f64) {
        self.0[pulley][0] += fx;
        self.0[pulley][1] += fy;
    }
}

/// Mounting of the tensioner arms: with the belt at rest in its static
/// equilibrium (`y`, arms at their mounted positions), each arm's spring
/// gets the free angle at which its torque balances the moment of the
/// belt's hub force about the pivot, `-k (0 - alpha_free) + M_hub = 0`
/// (`elements::tensioner::Arm::free_angle_for`).
fn mount_arms(sys: &mut BeltSystem, ws: &mut Workspace, t: f64, y: &[f64]) {
    if sys.n_arms == 0 {
        return;
    }
    let mut rec = HubRecorder([[0.0; 2]; MAX_PULLEYS]);
    let mut dy = vec![0.0; y.len()];
    sys.rhs(ws, t, y, &mut dy, &mut rec);
    for (j, pc) in sys.pulleys[..sys.np].iter_mut().enumerate() {
        if let Some(arm) = pc.arm.as_mut() {
            let moment = arm.moment(y[pc.arm_offset], rec.0[j]).0;
            arm.free_angle = arm.free_angle_for(moment);
        }
    }
}

/// Step-count guard of the equilibrium relaxation.
const RELAX_MAX_STEPS: u64 = TUNING.relax_max_steps;

/// The window the mean outputs average over: the last call of
/// [`Drive::advance`] (in the FMU, the last communication step). The
/// impulses over it are states (`BeltSystem::impulse_offset`), reset at its
/// start; the pulley speeds' change over it gives the mean accelerations.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Window {
    /// Time the window starts at; equal to the drive's time before the
    /// first step (an empty window: the means are the instantaneous values).
    pub start: f64,
    /// Change of each pulley's speed over the window [rad/s] (a speed
    /// input set after the window does not count).
    pub omega_change: [f64; MAX_PULLEYS],
}

/// A belt drive ready to run.
#[derive(Clone, Debug)]
pub struct Drive {
    params: DriveParams,
    layout: Layout,
    sys: BeltSystem,
    t: f64,
    y: Vec<f64>,
    window: Window,
    integrator: Integrator,
    /// Scratch of the right-hand side.
    ws: Workspace,
    /// Scratch for recorded evaluations (outputs only).
    dy: Vec<f64>,
    tensions: Vec<f64>,
    warnings: Vec<Message>,
    /// The probe body (0-based), chosen by `auto_probe` for `PROBE_AUTO`.
    probe: usize,
    /// Means and extrema over the last call of [`Drive::advance`].
    interval: IntervalAccumulator,
}

/// The probe body [`PROBE_AUTO`] stands for: the body whose centre lies
/// nearest the middle of the free span from pulley 1 to pulley 2 in the
/// mounted belt. It starts free, in a span with a defined tension, so its
/// forces (Figs. 15-18) show a whole passage: span, pulley 2, the next span,
/// ...; and it exists for any body count.
fn auto_probe(layout: &Layout) -> usize {
    let Some(span) = layout.span_between(0, 1) else {
        return 0;
    };
    let m = span.midpoint();
    let d = |b: &crate::model::layout::BodyPose| (b.x - m[0]).hypot(b.y - m[1]);
    (0..layout.bodies.len())
        .min_by(|&a, &b| d(&layout.bodies[a]).total_cmp(&d(&layout.bodies[b])))
        .unwrap_or(0)
}

/// Damping ratio of the radial contact mode at the equilibrium penetration
/// below which a wrap counts as undamped: the belt then rattles on the
/// pulley after a shock and loses traction (docs/model.md, "Contact"; the
/// paper's 5PK drive has 0.26, its section-3 drive as printed 6e-5).
const WEAK_CONTACT_DAMPING: f64 = TUNING.weak_contact_damping;

/// Mass per length above which a belt is taken for a unit slip and warned
/// about [kg/m]: drive belts weigh about 0.01 (small flat and round belts)
/// to 2 kg/m (wide banded V-belts); a belt's g/m typed as kg/m lands at
/// 10 to 2000. Heavier belts (conveyors) still run, with the warning.
const HEAVIEST_BELT: f64 = 5.0;

/// Parameter choices that are valid but make the drive behave badly, one
/// message each, naming the parameter and the value to use instead.
fn warnings(params: &DriveParams, layout: &Layout, sys: &BeltSystem) -> Vec<Message> {
    let mut out = Vec::new();
    let mu = params.belt.mass_per_length;
    if mu > HEAVIEST_BELT {
        out.push(msg![
            Param::BeltMassPerLength,
            format!(
                " = {mu} kg/m is more than the {HEAVIEST_BELT} kg/m of the heaviest drive belts \
                 (flat, V, V-ribbed and synchronous belts weigh about 0.01 to 2 kg/m); it is in \
                 kg/m: if {mu} was meant in g/m, set {}",
                mu * 1e-3
            ),
        ]);
    }
    let c = &sys.contact;
    if c.b <= 0.0 {
        return out;
    }
    let mut wraps: Vec<_> = layout.wraps.iter().collect();
    wraps.sort_by_key(|w| w.pulley);
    for w in wraps {
        let p0 = w.penetration;
        let inv_p_max = sys.pulleys[w.pulley].inv_p_max;
        let share = smoothstep(p0 * inv_p_max);
        let zeta = c.damping_ratio(p0, sys.mass, inv_p_max);
        if zeta >= WEAK_CONTACT_DAMPING {
            continue;
        }
        if share >= 0.5 {
            out.push(msg![
                Param::ContactDamping,
                format!(
                    " = {:e} N s/m2 damps the belt's bounce on ",
                    params.contact.damping
                ),
                Part::Pulley(w.pulley),
                format!(
                    " with a damping ratio of only {zeta:.1e}, so the belt can rattle on the \
                     pulley and lose traction; a ratio of 0.1 needs "
                ),
                Param::ContactDamping,
                format!(
                    " of about {:.1e} N s/m2",
                    params.contact.damping * 0.1 / zeta
                ),
            ]);
        } else {
            // only a user's contact.pMax can be this long: the automatic
            // one puts the full damping at the penetration
            let p_max = params.contact.p_max;
            out.push(msg![
                Param::ContactPMax,
                format!(
                    " = {p_max:e} m is {:.0} times the equilibrium penetration {p0:.2e} m on ",
                    p_max / p0
                ),
                Part::Pulley(w.pulley),
                format!(": the contact damping acts there with {share:.1e} of "),
                Param::ContactDamping,
                format!(
                    " (damping ratio {zeta:.1e}), so the belt can rattle on the pulley and lose \
                     traction; set "
                ),
                Param::ContactPMax,
                format!(
                    " to 0 (automatic: {AUTO_P_MAX_PER_PENETRATION} x each pulley's penetration, \
                     here {:.1e} m)",
                    AUTO_P_MAX_PER_PENETRATION * p0
                ),
            ]);
        }
    }
    out
}

impl Drive {
    /// Validates `params`, lays out the belt, mounts it at time `t0` and
    /// relaxes it into static equilibrium.
    pub fn new(params: &DriveParams, t0: f64) -> Result<Self, ParamError> {
        let mut drive = Self::mounted(params, t0)?;
        relax_into_equilibrium(
            &drive.sys,
            &mut drive.ws,
            &mut drive.y,
            params.solver.max_steps,
        );
        mount_arms(&mut drive.sys, &mut drive.ws, drive.t, &drive.y);
        drive.interval.begin(&drive.sys, drive.t, &drive.y);
        Ok(drive)
    }

    /// The drive as laid out, without the equilibrium relaxation (for
    /// restoring a saved state, which replaces the state anyway).
    pub fn mounted(params: &DriveParams, t0: f64) -> Result<Self, ParamError> {
        params.validate()?;
        // With `belt.naturalLength` the preload is the installation tension.
        let installed = crate::model::layout::installed(params)?;
        let params: &DriveParams = &installed;
        let layout = Layout::new(params)?;
        let sys = BeltSystem::new(params, &layout);
        let dim = sys.dim();
        let mut y = vec![0.0; dim];
        for (i, b) in layout.bodies.iter().enumerate() {
            let o = BODY_DOF * i;
            y[o] = b.x;
            y[o + 1] = b.y;
            y[o + 2] = b.phi;
        }
        let integrator = Integrator::new(&sys, params);
        let warnings = warnings(params, &layout, &sys);
        let probe = if params.probe_body == PROBE_AUTO {
            auto_probe(&layout)
        } else {
            params.probe_body
        };
        let np = params.pulleys.len();
        let mids: Vec<Option<[f64; 2]>> = (0..np)
            .map(|k| layout.span_between(k, (k + 1) % np).map(|s| s.midpoint()))
            .collect();
        let interval = IntervalAccumulator::new(&mids);
        let mut drive = Self {
            params: params.clone(),
            layout,
            sys,
            t: t0,
            y,
            window: Window {
                start: t0,
                omega_change: [0.0; MAX_PULLEYS],
            },
            integrator,
            ws: Workspace::new(),
            dy: vec![0.0; dim],
            tensions: vec![0.0; params.belt.n_bodies],
            warnings,
            probe,
            interval,
        };
        drive.interval.begin(&drive.sys, t0, &drive.y);
        drive.set_inputs(Inputs {
            t0,
            ..Inputs::default()
        });
        Ok(drive)
    }

    /// Valid parameter choices that make the drive behave badly, as
    /// messages naming the parameter and a better value.
    pub fn warnings(&self) -> &[Message] {
        &self.warnings
    }

    /// The probe body (0-based): `params().probe_body`, or the one chosen
    /// for [`PROBE_AUTO`] (`auto_probe`).
    pub fn probe_body(&self) -> usize {
        self.probe
    }

    /// The parameters the drive was built from.
    pub fn params(&self) -> &DriveParams {
        &self.params
    }
    /// The mounted belt path.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }
    /// The equations of motion (constants and inputs).
    pub fn system(&self) -> &BeltSystem {
        &self.sys
    }
    /// Current time [s].
    pub fn time(&self) -> f64 {
        self.t
    }
    /// Current state vector (layout in `model`).
    pub fn state(&self) -> &[f64] {
        &self.y
    }
    /// Counters of the work done (cumulative).
    pub fn stats(&self) -> Stats {
        self.integrator.stats()
    }
    /// The integrator and its step control.
    pub fn integrator(&self) -> &Integrator {
        &self.integrator
    }
    /// Switches the stiff method's energy check on every trial step (on by
    /// default; [`Rosenbrock::energy_check`]); RKF45 has none. Off for runs at
    /// tight tolerances that need a step sequence smooth in the state (the
    /// modal analysis' settling onto a periodic orbit).
    pub fn set_energy_check(&mut self, on: bool) {
        if let Integrator::Rosenbrock(i) = &mut self.integrator {
            i.energy_check = on;
        }
    }
    /// The inputs held over the current step.
    pub fn inputs(&self) -> &Inputs {
        &self.sys.inputs
    }

    /// Sets the inputs held from now on (`inputs.t0` is set to the current
    /// time). A speed-driven pulley's speed jumps to its new prescription.
    pub fn set_inputs(&mut self, mut inputs: Inputs) {
        inputs.t0 = self.t;
        // the right-hand side stays the same to the bit where the values
        // stay and no rate is set before or after (then the time they were
        // set at does not enter it)
        let old = self.sys.inputs;
        let held = |i: &Inputs| {
            i.torque_rate == [0.0; MAX_PULLEYS] && i.omega_ref_rate == [0.0; MAX_PULLEYS]
        };
        let mut same = held(&old)
            && held(&inputs)
            && old.torque.map(f64::to_bits) == inputs.torque.map(f64::to_bits)
            && old.omega_ref.map(f64::to_bits) == inputs.omega_ref.map(f64::to_bits);
        self.sys.inputs = inputs;
        for j in 0..self.sys.np {
            if self.sys.pulleys[j].speed_driven {
                let o = self.sys.pulley_offset(j);
                let w = self.sys.prescribed_speed(j, self.t).0;
                same &= w.to_bits() == self.y[o + 1].to_bits();
                self.y[o + 1] = w;
            }
        }
        if !same {
            self.integrator.state_changed();
        }
    }

    /// Integrates to exactly `t_end`; the mean outputs then average over
    /// this call ([`Window`]). On failure the drive stays at its last good
    /// state (the time, state and window of the call).
    pub fn advance(&mut self, t_end: f64) -> Result<(), StepFailure> {
        let q = self.sys.controlled_dim();
        let mut impulses = [0.0; IMPULSES * MAX_PULLEYS];
        let kept = &mut impulses[..self.y.len() - q];
        kept.copy_from_slice(&self.y[q..]);
        self.y[q..].fill(0.0);
        let mut omega = [0.0; MAX_PULLEYS];
        for (j, w) in omega.iter_mut().enumerate().take(self.sys.np) {
            *w = self.sys.pulley_speed(j, self.t, &self.y);
        }
        let start = self.t;
        let before = self.interval.clone();
        self.interval.begin(&self.sys, self.t, &self.y);
        let (sys, interval) = (&self.sys, &mut self.interval);
        let result = self.integrator.advance(
            sys,
            &mut self.ws,
            &mut self.t,
            &mut self.y,
            t_end,
            &mut |t, y| interval.step_end(sys, t, y),
        );
        if result.is_err() {
            self.y[q..].copy_from_slice(kept);
            self.interval = before;
            return result;
        }
        self.interval.step_end(&self.sys, self.t, &self.y);
        self.window.start = start;
        for (j, w) in omega.iter().enumerate().take(self.sys.np) {
            self.window.omega_change[j] = self.sys.pulley_speed(j, self.t, &self.y) - w;
        }
        result
    }

    /// The window the mean outputs average over.
    pub fn window(&self) -> Window {
        self.window
    }

    /// All outputs at the current state.
    pub fn outputs(&mut self) -> Outputs {
        let mut out = Outputs::default();
        let np = self.sys.np;
        let mut span_mid = [[0.0; 2]; MAX_PULLEYS];
        for (k, mid) in span_mid.iter_mut().enumerate().take(np) {
            if let Some(s) = self.layout.span_between(k, (k + 1) % np) {
                *mid = s.midpoint();
            }
        }
        {
            let mut rec = OutputRecorder {
                out: &mut out,
                tensions: &mut self.tensions,
                probe: self.probe,
                span_mid,
                n_spans: np,
                span_best: [f64::INFINITY; MAX_PULLEYS],
                spring_power: 0.0,
            };
            self.sys
                .rhs(&mut self.ws, self.t, &self.y, &mut self.dy, &mut rec);
            // the friction power stored in the creep springs is not lost
            rec.out.power_dissipated -= rec.spring_power;
        }
        out.min_tension = self.tensions.iter().copied().fold(f64::INFINITY, f64::min);
        out.max_tension = self
            .tensions
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        let p = self.probe;
        out.probe.position = [self.y[BODY_DOF * p], self.y[BODY_DOF * p + 1]];
        let surface = |j: usize| {
            let w = self.sys.pulley_speed(j, self.t, &self.y);
            let side = self.layout.wrap_of(j).map_or(1.0, |w| w.side);
            side * w * self.sys.pulleys[j].radius
        };
        let v1 = surface(0);
        for j in 0..np {
            let o = self.sys.pulley_offset(j);
            let po = &mut out.pulleys[j];
            po.angle = self.y[o];
            po.omega = self.sys.pulley_speed(j, self.t, &self.y);
            if self.sys.pulleys[j].decoupler.is_none() {
                po.rotor_omega = po.omega;
            }
            if let Some(arm) = &self.sys.pulleys[j].arm {
                let o = self.sys.pulleys[j].arm_offset;
                po.arm_angle = self.y[o];
                po.arm_omega = self.y[o + 1];
                po.arm_spring_torque = arm.spring_torque(self.y[o]);
                po.arm_free_angle = arm.free_angle;
            }
            po.slip = if v1 != 0.0 {
                1.0 - surface(j) / v1
            } else {
                0.0
            };
            po.wrap_angle = self.layout.wrap_of(j).map_or(0.0, |w| w.angle);
            // means over the window: impulse / duration, exact for both
            // integrators; the instantaneous values of an empty window
            let span = self.t - self.window.start;
            if span > 0.0 {
                let q = self.sys.impulse_offset(j);
                po.mean_belt_torque = self.y[q] / span;
                po.mean_drive_torque = self.y[q + 1] / span;
                po.mean_hub_force = [self.y[q + 2] / span, self.y[q + 3] / span];
                po.mean_alpha = self.window.omega_change[j] / span;
            } else {
                po.mean_belt_torque = po.belt_torque;
                po.mean_drive_torque = po.drive_torque;
                po.mean_hub_force = po.hub_force;
                po.mean_alpha = po.alpha;
            }
            let v = surface(j);
            out.span_slip[j] = if v != 0.0 {
                1.0 - surface((j + 1) % np) / v
            } else {
                0.0
            };
        }
        for k in 0..np {
            if let Some((d, rate)) = self.mid_deflection(k) {
                out.span_mid_deflection[k] = d;
                out.span_mid_deflection_rate[k] = rate;
            }
        }
        let e = self.sys.energy_offset();
        out.energy_input = self.y[e];
        // the state integrates the friction work; what the creep springs
        // still store is not dissipated (it is in the potential energy)
        out.energy_dissipated = self.y[e + 1] - self.sys.creep_spring_energy(&self.y);
        let (kin, pot) = self.sys.energies(&self.y);
        out.kinetic_energy = kin;
        out.potential_energy = pot;
        out.interval = self.interval.outputs();
        out
    }

    /// Deflection and its rate at the fixed mid-point of the free span from
    /// pulley k to k+1 (`Outputs::span_mid_deflection`). The belt's line is
    /// the polygon through the body centres (straight in a straight span);
    /// where it crosses the normal to the reference line through its
    /// mid-point, the crossing's distance from the reference line is the
    /// deflection; its rate is the exact time derivative of that distance
    /// (the crossing point moves along the polygon). The reference line is
    /// the one the mounted span's body centres lie on without gravity, the
    /// line through the span's end points where the belt leaves the pulleys
    /// (`Layout::lines`: outside the pulleys' common tangent at the body
    /// centres' radius by the chordal offset l^2 / (8 rho) of the bodies on
    /// the arcs, so the same sag reads the same on a span above and below
    /// the pulleys). Of the two strands of the loop that cross the normal,
    /// the nearer one is the span's. None if the span has no free length.
    fn mid_deflection(&self, k: usize) -> Option<(f64, f64)> {
        let np = self.sys.np;
        let next = (k + 1) % np;
        let span = self.layout.line_between(k, next)?;
        let (a, b) = if span.from == k {
            (span.start, span.end)
        } else {
            (span.end, span.start)
        };
        let (lx, ly) = (b[0] - a[0], b[1] - a[1]);
        let len = lx.hypot(ly);
        if len <= 0.0 {
            return None;
        }
        let (tx, ty) = (lx / len, ly / len);
        let (nx, ny) = (-ty, tx);
        let m = span.midpoint();
        let n = self.sys.n;
        let local = |i: usize| {
            let o = BODY_DOF * i;
            let (rx, ry) = (self.y[o] - m[0], self.y[o + 1] - m[1]);
            let (vx, vy) = (self.y[o + 3], self.y[o + 4]);
            // along, across, and their rates
            (
                rx * tx + ry * ty,
                rx * nx + ry * ny,
                vx * tx + vy * ty,
                vx * nx + vy * ny,
            )
        };
        let mut best: Option<(f64, f64)> = None;
        let mut prev = local(n - 1);
        for i in 0..n {
            let cur = local(i);
            let (s0, d0, ds0, dd0) = prev;
            let (s1, d1, ds1, dd1) = cur;
            prev = cur;
            if (s0 <= 0.0) == (s1 <= 0.0) {
                continue;
            }
            let den = s0 - s1;
            let lam = s0 / den;
            let d = d0 + lam * (d1 - d0);
            if best.is_some_and(|(bd, _)| bd.abs() <= d.abs()) {
                continue;
            }
            let lam_rate = (s0 * ds1 - s1 * ds0) / (den * den);
            let rate = dd0 + lam_rate * (d1 - d0) + lam * (dd1 - dd0);
            best = Some((d, rate));
        }
        best
    }

    /// What the right-hand side depends on: time, state and inputs (the
    /// stiff method keeps its first stage in the integrator data for this
    /// point only).
    fn point(&self) -> Vec<f64> {
        let i = &self.sys.inputs;
        let mut p = vec![self.t, i.t0];
        p.extend_from_slice(&self.y);
        for a in [i.torque, i.torque_rate, i.omega_ref, i.omega_ref_rate] {
            p.extend_from_slice(&a);
        }
        p
    }

    /// Integrator data for a saved state, see [`restore`](Self::restore).
    pub fn integrator_data(&self) -> Vec<f64> {
        let mut out = self.integrator.save(&self.sys, &self.point());
        self.interval.save(&mut out);
        out
    }

    /// Replaces time, state, window, inputs and integrator data (restoring
    /// a snapshot of the same parameters; `integrator_data` as returned by
    /// [`integrator_data`](Self::integrator_data)). False if they do not fit.
    #[allow(clippy::too_many_arguments)]
    pub fn restore(
        &mut self,
        t: f64,
        y: &[f64],
        window: Window,
        inputs: Inputs,
        h: f64,
        stats: Stats,
        integrator_data: &[f64],
    ) -> bool {
        if y.len() != self.y.len() || window.start.is_nan() || window.start > t {
            return false;
        }
        let Some(split) = integrator_data.len().checked_sub(INTERVAL_DATA) else {
            return false;
        };
        let (integrator_data, interval) = integrator_data.split_at(split);
        if !self.interval.load(interval, self.sys.n) {
            return false;
        }
        self.t = t;
        self.window = window;
        self.y.copy_from_slice(y);
        self.sys.inputs = inputs;
        self.integrator
            .restore(&self.sys, &self.point(), h, stats, integrator_data)
    }

    /// Free angles of the tensioner arms' springs found by the mounting, in
    /// pulley order (empty without arms); part of a saved state.
    pub fn arm_free_angles(&self) -> Vec<f64> {
        self.sys.pulleys[..self.sys.np]
            .iter()
            .filter_map(|p| p.arm.map(|a| a.free_angle))
            .collect()
    }

    /// Restores what [`arm_free_angles`](Self::arm_free_angles) returned;
    /// false (nothing changed) if the count does not fit or one is not finite.
    pub fn set_arm_free_angles(&mut self, angles: &[f64]) -> bool {
        if angles.len() != self.sys.n_arms || !angles.iter().all(|a| a.is_finite()) {
            return false;
        }
        let arms = self.sys.pulleys[..self.sys.np]
            .iter_mut()
            .filter_map(|p| p.arm.as_mut());
        for (arm, &a) in arms.zip(angles) {
            arm.free_angle = a;
        }
        self.integrator.state_changed();
        true
    }

    /// Step size the integrator will try next.
    pub fn next_step_size(&self) -> f64 {
        self.integrator.step_size()
    }
}
