//! The drive's outputs: per pulley, at the probe body, the spans, energies
//! and powers; from the state, or from a recorded force evaluation.

use super::Drive;
use crate::interval::IntervalOutputs;
use crate::model::params::MAX_PULLEYS;
use crate::model::state;
use crate::model::system::Recorder;

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

impl Drive {
    /// All outputs at the current state: [`Self::state_outputs`] and
    /// [`Self::add_evaluated_outputs`].
    pub fn outputs(&mut self) -> Outputs {
        let mut out = self.state_outputs();
        self.add_evaluated_outputs(&mut out);
        out
    }

    /// The outputs read from the state and the geometry alone, with no
    /// evaluation of the forces: pulley angles, speeds, slips, wrap angles,
    /// rotor speeds, the arms' angles, rates and spring torques, the means
    /// over a non-empty window (impulses over its duration), the span
    /// slips, the probe's position, the input energy and the interval
    /// outputs but the belt's smallest tension (NaN here). Every other
    /// field is zero; so are the means of an empty window (they are the
    /// instantaneous forces).
    pub fn state_outputs(&self) -> Outputs {
        let mut out = Outputs::default();
        let np = self.sys.np;
        let p = self.probe;
        out.probe.position = state::body(&self.y, p).position();
        let surface = |j: usize| {
            let w = self.sys.pulley_speed(j, self.t, &self.y);
            let side = self.layout.wrap_of(j).map_or(1.0, |w| w.side);
            side * w * self.sys.pulleys[j].radius
        };
        let v1 = surface(0);
        let states = self.sys.state_layout();
        for j in 0..np {
            let po = &mut out.pulleys[j];
            po.angle = self.y[states.pulley(j).angle];
            po.omega = self.sys.pulley_speed(j, self.t, &self.y);
            po.rotor_omega = if self.sys.pulleys[j].decoupler.is_some() {
                self.y[states.decoupler(j).rotor_speed]
            } else {
                po.omega
            };
            if let Some(arm) = &self.sys.pulleys[j].arm {
                let o = states.arm(j);
                po.arm_angle = self.y[o.angle];
                po.arm_omega = self.y[o.rate];
                po.arm_spring_torque = arm.spring_torque(self.y[o.angle]);
                po.arm_free_angle = arm.free_angle;
            }
            po.slip = if v1 != 0.0 {
                1.0 - surface(j) / v1
            } else {
                0.0
            };
            po.wrap_angle = self.layout.wrap_of(j).map_or(0.0, |w| w.angle);
            // means over the window: impulse / duration, exact for both
            // integrators
            if !self.window_empty() {
                let span = self.t - self.window.start;
                let q = states.impulses(j);
                po.mean_belt_torque = self.y[q.belt_torque] / span;
                po.mean_drive_torque = self.y[q.drive_torque] / span;
                po.mean_hub_force = q.hub_force.map(|k| self.y[k] / span);
                po.mean_alpha = self.window.omega_change[j] / span;
            }
            let v = surface(j);
            out.span_slip[j] = if v != 0.0 {
                1.0 - surface((j + 1) % np) / v
            } else {
                0.0
            };
        }
        out.energy_input = self.y[states.energy().work_in];
        out.interval = self.interval.outputs();
        // taken only when read: Self::add_evaluated_outputs
        out.interval.belt_min_tension = f64::NAN;
        out
    }

    /// Adds to `out` (from [`Self::state_outputs`]) the outputs that take
    /// a pass over the belt: one recorded evaluation of the forces and the
    /// energy sums (torques, accelerations, hub forces, tensions, the
    /// probe's forces, powers, energies, and the means of an empty window,
    /// the instantaneous values), the mid-span deflections (a search along
    /// the belt per span) and the belt's smallest tension over the
    /// interval (a pass over the belt at its ends).
    pub fn add_evaluated_outputs(&mut self, out: &mut Outputs) {
        let np = self.sys.np;
        self.interval
            .settle(&self.sys, &self.interval_starts, &self.y);
        out.interval.belt_min_tension = self.interval.outputs().belt_min_tension;
        let mut span_mid = [[0.0; 2]; MAX_PULLEYS];
        for (k, mid) in span_mid.iter_mut().enumerate().take(np) {
            if let Some(s) = self.layout.span_between(k, (k + 1) % np) {
                *mid = s.midpoint();
            }
        }
        {
            let mut rec = OutputRecorder {
                out: &mut *out,
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
        if self.window_empty() {
            for po in &mut out.pulleys[..np] {
                po.mean_belt_torque = po.belt_torque;
                po.mean_drive_torque = po.drive_torque;
                po.mean_hub_force = po.hub_force;
                po.mean_alpha = po.alpha;
            }
        }
        let e = self.sys.state_layout().energy();
        // the state integrates the friction work; what the creep springs
        // still store is not dissipated (it is in the potential energy)
        out.energy_dissipated = self.y[e.dissipated] - self.sys.creep_spring_energy(&self.y);
        let (kin, pot) = self.sys.energies(&self.y);
        out.kinetic_energy = kin;
        out.potential_energy = pot;
        for k in 0..np {
            if let Some((d, rate)) = self.mid_deflection(k) {
                out.span_mid_deflection[k] = d;
                out.span_mid_deflection_rate[k] = rate;
            }
        }
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
            let b = state::body(&self.y, i);
            let ([x, y], [vx, vy]) = (b.position(), b.velocity());
            let (rx, ry) = (x - m[0], y - m[1]);
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
}
