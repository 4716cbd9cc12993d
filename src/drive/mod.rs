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

use crate::interval::{IntervalAccumulator, INTERVAL_DATA};
use crate::model::layout::Layout;
use crate::model::param_id::Message;
use crate::model::params::{DriveParams, ParamError, MAX_PULLEYS, PROBE_AUTO};
use crate::model::state;
use crate::model::system::{BeltSystem, Inputs, Workspace, IMPULSES};
use crate::solver::step_control::{Stats, StepFailure};

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
                let o = self.sys.state_layout().pulley(j).speed;
                let w = self.sys.prescribed_speed(j, self.t).0;
                same &= w.to_bits() == self.y[o].to_bits();
                self.y[o] = w;
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
        if angles.len() != self.sys.state_layout().n_arms() || !angles.iter().all(|a| a.is_finite())
        {
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
