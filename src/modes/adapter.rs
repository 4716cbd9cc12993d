//! The one place the modal analysis touches the physics core: build a drive,
//! run it, and read its state, its state layout and its dense Jacobian.
//! Everything else in `modes` works on the [`Linearisation`] this returns.

use crate::model::elements::Arm;
use crate::model::params::MAX_PULLEYS;
use crate::model::state::{self, StateLayout};
use crate::model::system::BODY_DOF;
use crate::solver::jacobian::Jacobian;
use crate::{Drive, DriveParams};

/// Values per body in the state (x, y, phi, vx, vy, omega, z).
pub const BODY_STATES: usize = BODY_DOF;

/// A pulley as the analysis needs it.
#[derive(Clone, Debug, PartialEq)]
pub struct PulleyInfo {
    /// Centre [m].
    pub centre: [f64; 2],
    /// Radius [m].
    pub radius: f64,
    /// Moment of inertia [kg m^2].
    pub inertia: f64,
    /// Follows a prescribed speed (its angle and speed are no degrees of freedom).
    pub speed_driven: bool,
    /// Speed at the linearisation point [rad/s].
    pub omega: f64,
    /// Angle between neighbouring body centres on its wrap [rad] (0 without wrap).
    pub pitch_angle: f64,
    /// +1 wrapped inside the loop, -1 back-side idler.
    pub side: f64,
    /// The model's friction lever: the pulley's surface speed is omega
    /// times it (`PulleyConst::lever`, read from the model, not recomputed).
    pub lever: f64,
    /// Tensioner arm: index of its angle (the rate follows) and its moment
    /// of inertia about the pivot [kg m^2].
    pub arm: Option<(usize, f64)>,
    /// Decoupler: index of its twist (the rotor speed follows) and the
    /// rotor's moment of inertia [kg m^2].
    pub decoupler: Option<(usize, f64)>,
}

/// The drive's state and Jacobian at one instant, with the state layout.
#[derive(Clone, Debug, PartialEq)]
pub struct Linearisation {
    /// Time of the linearisation [s].
    pub time: f64,
    /// State vector, `dim` values.
    pub y: Vec<f64>,
    /// d(dy/dt)/dy, row-major `dim x dim`.
    pub jacobian: Vec<f64>,
    /// Length of the state vector.
    pub dim: usize,
    /// Number of belt bodies.
    pub n: usize,
    /// Body mass [kg] and moment of inertia [kg m^2].
    pub mass: f64,
    /// Moment of inertia [kg m^2].
    pub inertia: f64,
    /// Natural body length [m].
    pub body_length: f64,
    /// The pulleys, in pulley order.
    pub pulleys: Vec<PulleyInfo>,
    /// Free spans (pulley it leaves, pulley it reaches, length [m]), loop order.
    pub spans: Vec<(usize, usize, f64)>,
    /// The pulley each body touches (the model's contact test), if any.
    pub contact: Vec<Option<usize>>,
    /// Where each state sits in `y` (and in the Jacobian's rows).
    pub states: StateLayout,
}

impl Linearisation {
    /// Index of body `i`'s state `k` (0..7: x, y, phi, vx, vy, omega, z).
    pub fn body(&self, i: usize, k: usize) -> usize {
        state::body_index(i, state::BodyComponent::at(k))
    }
    /// Indices of pulley `j`'s angle and speed.
    pub fn pulley(&self, j: usize) -> (usize, usize) {
        let p = self.states.pulley(j);
        (p.angle, p.speed)
    }
    /// Index of the first of the two energy accumulators (no dynamics).
    pub fn energy(&self) -> usize {
        self.states.energy().work_in
    }
    /// Indices of the states that repeat in steady running (shifted by one
    /// body for the belt): every body's, the free pulleys' speeds, the
    /// decouplers' and the arms'. Left out: the pulley angles (nothing
    /// depends on them), the prescribed speeds, the energy accumulators and
    /// the impulses (quadratures).
    pub fn periodic_states(&self) -> Vec<usize> {
        let mut out: Vec<usize> = (0..self.states.bodies_len()).collect();
        for (j, p) in self.pulleys.iter().enumerate() {
            if !p.speed_driven {
                out.push(self.pulley(j).1);
            }
        }
        for (j, p) in self.pulleys.iter().enumerate() {
            if p.decoupler.is_some() {
                let d = self.states.decoupler(j);
                out.extend([d.twist, d.rotor_speed]);
            }
            if p.arm.is_some() {
                let a = self.states.arm(j);
                out.extend([a.angle, a.rate]);
            }
        }
        out
    }

    /// The pulley body `i` touches, if any: the model's own contact test
    /// (`BeltSystem::touching`, with the pulley where its arm has moved it).
    pub fn contact_of(&self, i: usize) -> Option<usize> {
        self.contact[i]
    }
}

/// Validates the parameters, lays the belt out and settles it into static
/// equilibrium (the mounted static state). The error names the parameter.
pub fn build(params: &DriveParams) -> Result<Drive, String> {
    Drive::new(params, 0.0).map_err(|e| crate::fmu::names::render_error(&e))
}

/// Integrates the drive to time `t`, in calls of at most 1 ms (as an
/// importer's 1 ms communication steps do).
pub fn run_to(drive: &mut Drive, t: f64) -> Result<(), String> {
    const CHUNK: f64 = 1e-3;
    while drive.time() < t {
        let next = (drive.time() + CHUNK).min(t);
        drive
            .advance(next)
            .map_err(|e| format!("the run to t = {t} s failed: {e:?}"))?;
    }
    Ok(())
}

/// State, layout and analytic Jacobian of the drive now.
pub fn linearise(drive: &Drive) -> Linearisation {
    linearise_with(drive, &[None; MAX_PULLEYS])
}

/// The pivot friction of every tensioner arm at the drive's state now:
/// its torque scale M_f = M_c + mu_h r_f |F_hub| [N m] (0 without an
/// arm), for the describing function ([`Arm::friction_describing`]).
pub fn arm_friction(drive: &Drive) -> [f64; MAX_PULLEYS] {
    let mut out = [0.0; MAX_PULLEYS];
    let o = drive.clone().outputs();
    for (j, pc) in drive.system().pulleys().iter().enumerate() {
        if let Some(arm) = &pc.arm {
            out[j] = arm.friction_torque(o.pulleys[j].hub_force);
        }
    }
    out
}

/// The equivalent viscous damping [N m s/rad] of the pivot friction of
/// the arm carrying pulley `j` (0-based) at the drive's state now, for an
/// arm swinging with angle amplitude `amplitude` [rad] at `omega` [rad/s]
/// ([`Arm::friction_describing`]); 0 without an arm.
pub fn arm_describing(drive: &Drive, j: usize, amplitude: f64, omega: f64) -> f64 {
    let hub = drive.clone().outputs().pulleys[j].hub_force;
    drive.system().pulleys()[j]
        .arm
        .as_ref()
        .map_or(0.0, |a: &Arm| {
            a.friction_describing(a.friction_torque(hub), amplitude, omega)
        })
}

/// [`linearise`] with the pivot friction of arm j (constant and hub-load)
/// replaced, where `equivalent[j]` is given, by a viscous damper of that
/// rate [N m s/rad] (the describing function of the friction at an
/// amplitude of the arm's swing, `modes::describing`): the Jacobian is
/// taken with the arm's friction off (its presliding stiffness gone, the
/// deflection left standing, a zero eigenvalue apart from the rest) and
/// -c / I_arm added to the arm's
/// acceleration by its rate. Nothing else depends on the pivot friction.
pub fn linearise_with(drive: &Drive, equivalent: &[Option<f64>; MAX_PULLEYS]) -> Linearisation {
    let sys = drive.system();
    let y = drive.state().to_vec();
    let t = drive.time();
    let frictionless;
    let jac_sys = if equivalent.iter().any(Option::is_some) {
        let mut s = sys.clone();
        for (pc, c) in s.pulleys.iter_mut().zip(equivalent) {
            if let (Some(arm), Some(_)) = (pc.arm.as_mut(), c) {
                arm.friction = 0.0;
                arm.hub_friction = 0.0;
            }
        }
        frictionless = s;
        &frictionless
    } else {
        sys
    };
    let mut jac = Jacobian::new(jac_sys);
    jac_sys.jacobian(t, &y, &mut jac);
    let mut dense = jac.to_dense(jac_sys);
    let dim = sys.dim();
    for (j, (pc, c)) in sys.pulleys().iter().zip(equivalent).enumerate() {
        if let (Some(arm), Some(c)) = (&pc.arm, c) {
            let r = sys.state_layout().arm(j).rate;
            dense[r * dim + r] -= c / arm.inertia;
        }
    }
    let layout = drive.layout();
    let pulleys = drive
        .params()
        .pulleys
        .iter()
        .enumerate()
        .map(|(j, p)| {
            let wrap = layout.wrap_of(j);
            let pc = &sys.pulleys()[j];
            let states = sys.state_layout();
            PulleyInfo {
                centre: sys.pulley_centre(j, &y).0,
                radius: p.radius,
                inertia: p.inertia,
                speed_driven: p.speed_driven,
                omega: sys.pulley_speed(j, t, &y),
                pitch_angle: wrap.map_or(0.0, |w| w.pitch_angle),
                side: wrap.map_or(1.0, |w| w.side),
                lever: pc.lever,
                arm: pc.arm.map(|a| (states.arm(j).angle, a.inertia)),
                decoupler: pc
                    .decoupler
                    .map(|_| (states.decoupler(j).twist, pc.rotor_inertia)),
            }
        })
        .collect();
    let centres: Vec<[f64; 2]> = (0..drive.params().pulleys.len())
        .map(|j| sys.pulley_centre(j, &y).0)
        .collect();
    let contact = (0..sys.n_bodies())
        .map(|i| sys.touching(i, &y, &centres))
        .collect();
    Linearisation {
        time: t,
        contact,
        jacobian: dense,
        states: *sys.state_layout(),
        dim: sys.dim(),
        n: sys.n_bodies(),
        mass: sys.mass(),
        inertia: sys.inertia(),
        body_length: layout.body_length,
        pulleys,
        spans: layout
            .spans
            .iter()
            .map(|s| (s.from, s.to, s.length))
            .collect(),
        y,
    }
}

/// Current state (read-only), e.g. for a time-domain cross-check.
pub fn state(drive: &Drive) -> &[f64] {
    drive.state()
}

/// Replaces the drive's state at its current time (a perturbed initial
/// condition for a free-vibration run).
pub fn set_state(drive: &mut Drive, y: &[f64]) -> Result<(), String> {
    if drive.set_state(y) {
        Ok(())
    } else {
        Err(format!(
            "state of length {} does not fit the drive ({}) or is not finite",
            y.len(),
            drive.state().len()
        ))
    }
}

/// Tension of the middle element of every free span (span k from pulley k
/// to pulley k+1) [N], and the mean speed of the belt bodies [m/s].
pub fn span_tensions_and_speed(drive: &mut Drive) -> (Vec<f64>, f64) {
    let np = drive.params().pulleys.len();
    let o = drive.outputs();
    let y = drive.state();
    let n = drive.system().n_bodies();
    let v = state::bodies(y, n)
        .map(|b| b.velocity()[0].hypot(b.velocity()[1]))
        .sum::<f64>()
        / n as f64;
    (o.span_tension[..np].to_vec(), v)
}
