//! A simulated belt drive: parameters, mounted layout, state, integrator.
//! This is the whole interface the FMI adapter uses.
//!
//! * `integrator`: the drive's ODE for the integrators, and its
//!   [`Integrator`];
//! * `mounting`: equilibrium relaxation, arms' free angles, probe body,
//!   warnings;
//! * `mesh_check`: the warnings that the mesh is too coarse for the spans;
//! * `outputs`: [`Outputs`] and how they are recorded.

mod integrator;
pub(crate) mod mesh_check;
mod mounting;
mod outputs;

pub use integrator::Integrator;
pub use outputs::{Outputs, ProbeOutputs, PulleyOutputs};

use mounting::{auto_probe, mount_arms, relax_into_equilibrium, warnings};

use crate::interval::{IntervalAccumulator, StartStates, INTERVAL_DATA};
use crate::model::layout::Layout;
use crate::model::param_id::Message;
use crate::model::params::{DriveParams, ParamError, MAX_PULLEYS, PROBE_AUTO};
use crate::model::state::{self, BodyIndex};
use crate::model::system::{BeltSystem, Inputs, Workspace, BODY_DOF, IMPULSES};
use crate::solver::step_control::{Landing, Stats, StepFailure};

/// The integrator's own time and state when it has stepped past the
/// communication point ([`Drive::advance`]): its last step, from
/// (`t_a`, `y_a`) to (`t_b`, `y_b`), holds the drive's time, and the
/// drive's state there is that step's cubic Hermite interpolant.
#[derive(Clone, Debug, PartialEq)]
struct Ahead {
    /// The integrator is past the drive's time (else `t_b`, `y_b` are
    /// scratch).
    active: bool,
    t_a: f64,
    /// The step size the step from `t_a` was tried with first.
    h_a: f64,
    y_a: Vec<f64>,
    /// f(t_a, y_a), f(t_b, y_b).
    f_a: Vec<f64>,
    t_b: f64,
    y_b: Vec<f64>,
    f_b: Vec<f64>,
    /// Belt bodies (they come first in the state).
    n_bodies: usize,
}

impl Ahead {
    fn new(dim: usize, n_bodies: usize) -> Self {
        Self {
            active: false,
            t_a: f64::NAN,
            h_a: f64::NAN,
            y_a: vec![0.0; dim],
            f_a: vec![0.0; dim],
            t_b: f64::NAN,
            y_b: vec![0.0; dim],
            f_b: vec![0.0; dim],
            n_bodies,
        }
    }

    /// Whether the step past gives `y` (the controlled coordinates) at
    /// time `t`, to the bit.
    fn leads_to(&self, t: f64, y: &[f64]) -> bool {
        let mut at = self.y_b.clone();
        self.interpolate(t, &mut at);
        at[..y.len()]
            .iter()
            .zip(y)
            .all(|(a, b)| a.to_bits() == b.to_bits())
    }

    /// The state at time `t` in [t_a, t_b]: the step's cubic Hermite
    /// interpolant (Hairer, Norsett & Wanner I, II.6: third order, through
    /// both ends with their slopes) for every state but the belt bodies'
    /// velocities, spins and creep displacements. Their slopes (the body
    /// accelerations, the creep rates) carry the belt's stiff modes, which
    /// the stiff method damps within a step: h f is then far larger than
    /// the change over the step, and the cubic through them swings by
    /// thousands of tolerances. A body's velocity and spin are the time
    /// derivative of its position's and angle's interpolant instead (so the
    /// bodies move as they are shown to move), its creep is interpolated
    /// linearly. Measured against the step retaken clipped and against a
    /// tight reference from the step's start (`examples/dense_output.rs`):
    /// the belt torques and span tensions at the point are as accurate as
    /// the clipped step's on the accessory drive, and within 0.3 % of the
    /// belt torque on the 5PK drive.
    fn interpolate(&self, t: f64, out: &mut [f64]) {
        let h = self.t_b - self.t_a;
        let s = (t - self.t_a) / h;
        // y = y_a + s d + c_d d + c_a f_a + c_b f_b, d = y_b - y_a
        let (c_d, c_a, c_b) = (
            s * (s - 1.0) * (1.0 - 2.0 * s),
            s * (s - 1.0) * (s - 1.0) * h,
            s * s * (s - 1.0) * h,
        );
        // its time derivative: d / h (1 + c_d') + c_a' / h f_a + c_b' / h f_b
        let (e_d, e_a, e_b) = (
            6.0 * s * (1.0 - s) / h,
            (s - 1.0) * (3.0 * s - 1.0),
            s * (3.0 * s - 2.0),
        );
        // the bodies, one pass over their contiguous states
        let nb = BODY_DOF * self.n_bodies;
        let idx = BodyIndex::of(0);
        let ends = self.y_a[..nb]
            .chunks_exact(BODY_DOF)
            .zip(self.y_b[..nb].chunks_exact(BODY_DOF));
        let slopes = self.f_a[..nb]
            .chunks_exact(BODY_DOF)
            .zip(self.f_b[..nb].chunks_exact(BODY_DOF));
        for ((o, (ya, yb)), (fa, fb)) in out[..nb].chunks_exact_mut(BODY_DOF).zip(ends).zip(slopes)
        {
            let o: &mut [f64; BODY_DOF] = o.try_into().expect("a body's states");
            let [ya, yb, fa, fb]: [&[f64; BODY_DOF]; 4] =
                [ya, yb, fa, fb].map(|x| x.try_into().expect("a body's states"));
            for (q, v) in idx.coordinates().into_iter().zip(idx.rates()) {
                let d = yb[q] - ya[q];
                o[q] = ya[q] + s * d + c_d * d + c_a * fa[q] + c_b * fb[q];
                o[v] = e_d * d + e_a * fa[q] + e_b * fb[q];
            }
            let z = idx.creep;
            o[z] = ya[z] + s * (yb[z] - ya[z]);
        }
        // the pulleys, decouplers, arms, impulses and energies
        for (i, o) in out.iter_mut().enumerate().skip(nb) {
            let (ya, yb) = (self.y_a[i], self.y_b[i]);
            let d = yb - ya;
            *o = ya + s * d + c_d * d + c_a * self.f_a[i] + c_b * self.f_b[i];
        }
    }
}

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
    /// Where the interval keeps its start state (`IntervalAccumulator::continue_at`).
    interval_starts: StartStates,
    /// The integrator's step past the drive's time, if it took one.
    ahead: Ahead,
    /// Whether [`Drive::advance`] may step past its target time.
    look_ahead: bool,
    /// The inputs changed at the drive's time: the next call of
    /// [`Drive::advance`] clips its last step (they may change again).
    clip_next: bool,
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
            let mut body = state::body_mut(&mut y, i);
            body.set_position([b.x, b.y]);
            body.set_angle(b.phi);
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
            interval_starts: [vec![0.0; dim], vec![0.0; dim]],
            ahead: Ahead::new(dim, params.belt.n_bodies),
            look_ahead: true,
            clip_next: false,
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
    ///
    /// Inputs with the values held (to the bit, no rate before or after)
    /// leave a step the integrator took past the current time valid; any
    /// other change drops that step ([`Self::drop_step_past`]: the
    /// integration continues from the state shown at the current time, so
    /// nothing read now changes) and clips the next call's last step.
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
        if same && self.ahead.active {
            return;
        }
        if !same {
            self.drop_step_past();
            self.clip_next = true;
        }
        let mut before = [0.0; MAX_PULLEYS];
        for (j, w) in before.iter_mut().enumerate().take(self.sys.np) {
            *w = self.sys.prescribed_speed(j, self.t).0;
        }
        self.sys.inputs = inputs;
        // a speed-driven pulley whose prescription at this time changed
        // jumps to it (one that kept it keeps its state, the state shown)
        for (j, w_before) in before.iter().enumerate().take(self.sys.np) {
            if self.sys.pulleys[j].speed_driven {
                let w = self.sys.prescribed_speed(j, self.t).0;
                if w.to_bits() != w_before.to_bits() {
                    let o = self.sys.state_layout().pulley(j).speed;
                    same = false;
                    self.interval
                        .invalidate(&self.sys, &self.interval_starts, &self.y);
                    self.y[o] = w;
                }
            }
        }
        if !same {
            self.integrator.state_changed();
        }
    }

    /// Advances the drive to exactly `t_end`; the mean outputs then
    /// average over this call ([`Window`]). On failure the drive stays at
    /// its last good state (the time, state and window of the call).
    ///
    /// The integrator steps past `t_end` unless the inputs changed at the
    /// drive's time (or [`Self::set_look_ahead`] is off): its last step
    /// ends at or after `t_end`, the drive's state at `t_end` is that
    /// step's cubic Hermite interpolant, and the next call continues from
    /// the step's end, so that the steps do not depend on the calls' end
    /// times. The interval outputs take the interpolated ends of the
    /// partial steps; the impulses are interpolated like every state.
    pub fn advance(&mut self, t_end: f64) -> Result<(), StepFailure> {
        let q = self.sys.controlled_dim();
        let dim = self.y.len();
        let mut impulses = [0.0; IMPULSES * MAX_PULLEYS];
        let kept = &mut impulses[..dim - q];
        kept.copy_from_slice(&self.y[q..]);
        // the impulses count from the window's start: the integrator's are
        // moved by their (interpolated) values there
        let mut kept_ahead = [[0.0; IMPULSES * MAX_PULLEYS]; 2];
        let a = &mut self.ahead;
        if a.active {
            kept_ahead[0][..dim - q].copy_from_slice(&a.y_a[q..]);
            kept_ahead[1][..dim - q].copy_from_slice(&a.y_b[q..]);
            for k in q..dim {
                a.y_a[k] -= self.y[k];
                a.y_b[k] -= self.y[k];
            }
        }
        self.y[q..].fill(0.0);
        let mut omega = [0.0; MAX_PULLEYS];
        for (j, w) in omega.iter_mut().enumerate().take(self.sys.np) {
            *w = self.sys.pulley_speed(j, self.t, &self.y);
        }
        let start = self.t;
        let before = self.interval.clone();
        self.interval
            .continue_at(&self.sys, self.t, &self.y, &mut self.interval_starts);
        let a = &mut self.ahead;
        // a target within the step taken past: no step
        let within = a.active && t_end <= a.t_b;
        let result = if within {
            Ok(Landing::Past)
        } else {
            if !a.active {
                a.t_b = self.t;
                a.y_b.copy_from_slice(&self.y);
            }
            let (sys, interval) = (&self.sys, &mut self.interval);
            let step_start = &mut |t, y: &[f64]| interval.step_end(sys, t, y);
            if self.look_ahead && !self.clip_next {
                self.integrator.advance_past(
                    sys,
                    &mut self.ws,
                    &mut a.t_b,
                    &mut a.y_b,
                    t_end,
                    step_start,
                )
            } else {
                self.integrator
                    .advance(sys, &mut self.ws, &mut a.t_b, &mut a.y_b, t_end, step_start)
                    .map(|()| Landing::OnTarget)
            }
        };
        let landing = match result {
            Ok(l) => l,
            Err(e) => {
                let a = &mut self.ahead;
                if a.active {
                    a.y_a[q..].copy_from_slice(&kept_ahead[0][..dim - q]);
                    a.y_b[q..].copy_from_slice(&kept_ahead[1][..dim - q]);
                }
                self.y[q..].copy_from_slice(kept);
                self.interval = before;
                return Err(e);
            }
        };
        let a = &mut self.ahead;
        match landing {
            Landing::OnTarget => {
                self.y.copy_from_slice(&a.y_b);
                a.active = false;
            }
            Landing::Past => {
                if !within {
                    let c = self.integrator.control();
                    a.t_a = c.straddle_t;
                    a.h_a = c.straddle_h;
                    a.y_a.copy_from_slice(&c.straddle_y);
                    let (f_a, f_b) = self.integrator.step_derivatives(a.t_b);
                    a.f_a
                        .copy_from_slice(f_a.expect("both methods keep the first stage"));
                    match f_b {
                        Some(f) => a.f_b.copy_from_slice(f),
                        None => {
                            use crate::solver::step_control::OdeSystem;
                            OdeSystem::rhs(&self.sys, &mut self.ws, a.t_b, &a.y_b, &mut a.f_b);
                        }
                    }
                    a.active = true;
                }
                a.interpolate(t_end, &mut self.y);
            }
        }
        self.t = t_end;
        self.clip_next = false;
        self.interval.point_end(&self.sys, self.t, &self.y);
        self.window.start = start;
        for (j, w) in omega.iter().enumerate().take(self.sys.np) {
            self.window.omega_change[j] = self.sys.pulley_speed(j, self.t, &self.y) - w;
        }
        Ok(())
    }

    /// Forgets the step the integrator took past the drive's time, if it
    /// took one: the next call integrates from the drive's state, the
    /// step's interpolant at the drive's time, which is what the outputs
    /// at this time showed (a master that changes an input after reading
    /// the outputs sees no output change that the input does not cause).
    pub fn drop_step_past(&mut self) {
        if self.ahead.active {
            self.ahead.active = false;
            self.integrator.state_changed();
        }
    }

    /// What a drive that clips its steps would show at the drive's time
    /// (diagnostics: `examples/dense_output.rs`): if the integrator
    /// stepped past it, the step it took past is taken again from its
    /// start, clipped to the drive's time (with the method as it was at
    /// that start, the same bits as a call that clipped it in the first
    /// place), and the drive's state becomes that step's end (its impulses,
    /// the last window's, are kept). Should the retake fail, the integrator
    /// continues from the interpolated state.
    pub fn materialise(&mut self) {
        let a = &mut self.ahead;
        if !a.active {
            return;
        }
        a.active = false;
        let mut t = a.t_a;
        a.y_b.copy_from_slice(&a.y_a);
        let q = self.sys.controlled_dim();
        match self.integrator.retake_clipped(
            &self.sys,
            &mut self.ws,
            &mut t,
            &mut a.y_b,
            a.h_a,
            self.t,
        ) {
            Ok(_) => {
                self.interval
                    .invalidate(&self.sys, &self.interval_starts, &self.y);
                self.y[..q].copy_from_slice(&a.y_b[..q]);
            }
            Err(_) => self.integrator.state_changed(),
        }
    }

    /// Whether [`Self::advance`] may step past its target time (on by
    /// default); switching it off drops a step taken past
    /// ([`Self::drop_step_past`]).
    pub fn set_look_ahead(&mut self, on: bool) {
        if !on {
            self.drop_step_past();
        }
        self.look_ahead = on;
    }

    /// The start (time, state) of the integrator's step past the drive's
    /// time, if it took one (diagnostics: `examples/dense_output.rs`).
    pub fn step_past(&self) -> Option<(f64, &[f64])> {
        self.ahead
            .active
            .then_some((self.ahead.t_a, &self.ahead.y_a[..]))
    }

    /// The integrator's own time: the drive's, or the end of the step it
    /// took past it.
    pub fn integrator_time(&self) -> f64 {
        if self.ahead.active {
            self.ahead.t_b
        } else {
            self.t
        }
    }

    /// The window the mean outputs average over.
    pub fn window(&self) -> Window {
        self.window
    }

    /// Whether the window is empty (before the first step): the means are
    /// then the instantaneous values.
    pub fn window_empty(&self) -> bool {
        self.t <= self.window.start
    }

    /// What the right-hand side depends on: time, state and inputs (the
    /// stiff method keeps its first stage in the integrator data for this
    /// point only).
    fn point(&self) -> Vec<f64> {
        let i = &self.sys.inputs;
        let mut p = vec![self.integrator_time(), i.t0];
        p.extend_from_slice(if self.ahead.active {
            &self.ahead.y_b
        } else {
            &self.y
        });
        for a in [i.torque, i.torque_rate, i.omega_ref, i.omega_ref_rate] {
            p.extend_from_slice(&a);
        }
        p
    }

    /// Integrator data for a saved state, see [`restore`](Self::restore).
    /// First the look-ahead: whether the next call clips, whether the
    /// integrator is past the drive's time, and if so its step past it
    /// (start time, step size, end time, the method's checkpoint after its
    /// length, then y_a, f_a, y_b, f_b).
    pub fn integrator_data(&self) -> Vec<f64> {
        let a = &self.ahead;
        let flag = |b: bool| f64::from(u8::from(b));
        let mut out = vec![flag(self.clip_next), flag(a.active)];
        if a.active {
            out.extend_from_slice(&[a.t_a, a.h_a, a.t_b]);
            let mut ck = Vec::new();
            self.integrator.save_checkpoint(&self.sys, &mut ck);
            out.push(ck.len() as f64);
            out.extend_from_slice(&ck);
            for v in [&a.y_a, &a.f_a, &a.y_b, &a.f_b] {
                out.extend_from_slice(v);
            }
        }
        out.extend(self.integrator.save(&self.sys, &self.point()));
        let belt_min = self
            .interval
            .belt_min_tension(&self.sys, &self.interval_starts, &self.y);
        self.interval.save(&mut out, belt_min);
        out
    }

    /// Reads the look-ahead [`integrator_data`](Self::integrator_data)
    /// starts with; the rest of the data, or None if it does not fit.
    fn load_ahead<'a>(&mut self, data: &'a [f64]) -> Option<&'a [f64]> {
        let flag = |x: f64| (x == 0.0 || x == 1.0).then_some(x == 1.0);
        let [clip, active, rest @ ..] = data else {
            return None;
        };
        self.clip_next = flag(*clip)?;
        if !flag(*active)? {
            self.ahead.active = false;
            return Some(rest);
        }
        let [t_a, h_a, t_b, n, rest @ ..] = rest else {
            return None;
        };
        let times_ok = t_a.is_finite() && t_b.is_finite() && *t_a <= self.t && self.t <= *t_b;
        if !(times_ok && h_a.is_finite() && *h_a > 0.0) || n.fract() != 0.0 || *n < 0.0 {
            return None;
        }
        let n = *n as usize;
        let dim = self.y.len();
        if rest.len() < n + 4 * dim {
            return None;
        }
        let (ck, rest) = rest.split_at(n);
        if !self.integrator.load_checkpoint(&self.sys, ck) {
            return None;
        }
        let (v, rest) = rest.split_at(4 * dim);
        if !v.iter().all(|x| x.is_finite()) {
            return None;
        }
        let a = &mut self.ahead;
        for (dst, src) in [&mut a.y_a, &mut a.f_a, &mut a.y_b, &mut a.f_b]
            .into_iter()
            .zip(v.chunks_exact(dim))
        {
            dst.copy_from_slice(src);
        }
        (a.t_a, a.h_a, a.t_b, a.active) = (*t_a, *h_a, *t_b, true);
        Some(rest)
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
        let Some(integrator_data) = self.load_ahead(integrator_data) else {
            return false;
        };
        // a state other than the one the saved step past leads to (a
        // perturbed copy): the step past is dropped, the next call steps
        // from `y`
        if self.ahead.active && !self.ahead.leads_to(t, &self.y[..self.sys.controlled_dim()]) {
            self.ahead.active = false;
        }
        self.integrator
            .restore(&self.sys, &self.point(), h, stats, integrator_data)
    }

    /// Replaces the state at the current time (a perturbed initial
    /// condition, a tap on a span): a step the integrator took past the
    /// current time is dropped, and the next call steps from `y` with the
    /// step size kept. False (nothing changed) if `y` does not fit the
    /// drive or is not finite.
    pub fn set_state(&mut self, y: &[f64]) -> bool {
        if y.len() != self.y.len() || !y.iter().all(|v| v.is_finite()) {
            return false;
        }
        self.ahead.active = false;
        self.interval
            .invalidate(&self.sys, &self.interval_starts, &self.y);
        self.y.copy_from_slice(y);
        self.integrator.state_changed();
        true
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
    /// Angles other than the current ones act like changed inputs: a step
    /// taken past the drive's time is dropped ([`Self::drop_step_past`])
    /// and the next call's last step is clipped.
    pub fn set_arm_free_angles(&mut self, angles: &[f64]) -> bool {
        if angles.len() != self.sys.state_layout().n_arms() || !angles.iter().all(|a| a.is_finite())
        {
            return false;
        }
        let current = self.arm_free_angles();
        if current
            .iter()
            .zip(angles)
            .any(|(a, b)| a.to_bits() != b.to_bits())
        {
            self.drop_step_past();
            self.clip_next = true;
        }
        let arms = self.sys.pulleys[..self.sys.np]
            .iter_mut()
            .filter_map(|p| p.arm.as_mut());
        for (arm, &a) in arms.zip(angles) {
            arm.free_angle = a;
        }
        // the spring torques the interval outputs sampled have changed
        self.interval
            .invalidate(&self.sys, &self.interval_starts, &self.y);
        self.integrator.state_changed();
        true
    }

    /// Step size the integrator will try next.
    pub fn next_step_size(&self) -> f64 {
        self.integrator.step_size()
    }
}
