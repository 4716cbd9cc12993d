//! Equations of motion of belt bodies and pulleys (eq. 20-24) with contact
//! (eq. 4-11) and friction (eq. 12-19): the right-hand side of the ODE.
//!
//! The state vector's layout (bodies first, then pulleys, energies,
//! decouplers, arms, impulses) is `model::state`'s [`StateLayout`].
//!
//! Here the constants ([`BeltSystem`], built once from the parameters,
//! with its [`StateLayout`]), [`Inputs`], [`Recorder`] and [`Relaxation`]; in the files
//! beside it:
//! * `rhs.rs`: the right-hand side, block by block in four steps (body
//!   ends, SDEs, contact, accelerations), then pulleys and tensioner arms;
//! * `workspace.rs`: its scratch, the structure-of-arrays `Block` (owned
//!   through a [`Workspace`]), and the bit-exact column sums;
//! * `contact_kernels.rs`: contact and friction over a run of bodies, at
//!   the centre and along the body (the vectorised loops);
//! * `energy.rs`: the stored energy ([`StoredEnergy`]) and the energy
//!   balance;
//! * `creep.rs`: the creep reset after every accepted step.

mod contact_kernels;
mod creep;
mod energy;
mod rhs;
mod workspace;

pub use energy::StoredEnergy;
pub use workspace::{Workspace, BLOCK};

use crate::model::elements::contact::{self, ContactLaw};
use crate::model::elements::decoupler::DecouplerParams;
use crate::model::elements::friction::Friction;
use crate::model::elements::groove::friction_factor;
pub use crate::model::elements::pulley::PulleyConst;
use crate::model::elements::sde::{AxialSde, TorsionalSde};
use crate::model::elements::tensioner::Arm;
use crate::model::elements::transverse::TransverseDamper;
use crate::model::layout::Layout;
use crate::model::params::{DriveParams, MAX_PULLEYS};
pub use crate::model::state::StateLayout;

/// Values per body in the state vector.
pub const BODY_DOF: usize = 7;

/// Impulse states per pulley: belt torque, drive torque, hub force x, y.
pub const IMPULSES: usize = 4;

/// Inputs held over a communication step: value at `t0` plus a rate (FMI
/// input derivatives), so inputs ramp linearly within the step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Inputs {
    /// Time the inputs were set [s].
    pub t0: f64,
    /// Torque input per pulley at `t0` [N m].
    pub torque: [f64; MAX_PULLEYS],
    /// Rate of the torque input [N m/s].
    pub torque_rate: [f64; MAX_PULLEYS],
    /// Speed reference per speed-driven pulley at `t0` [rad/s].
    pub omega_ref: [f64; MAX_PULLEYS],
    /// Rate of the speed reference [rad/s^2].
    pub omega_ref_rate: [f64; MAX_PULLEYS],
}

/// Observer of the force evaluation, used for outputs. The hot path uses
/// [`NoRecord`], whose calls compile away.
pub trait Recorder {
    /// False for [`NoRecord`]: the recording code then compiles away.
    const ACTIVE: bool;
    /// Translational SDE `k` (between body k-1 and body k): its tension and
    /// the midpoint of the gap it spans.
    fn sde(&mut self, _k: usize, _tension: f64, _mid: [f64; 2]) {}
    /// Contact of `body` with `pulley`: normal force, signed friction force
    /// along the pulley tangent, relative velocity v_T, penetration.
    fn contact(&mut self, _body: usize, _pulley: usize, _n: f64, _f: f64, _v_t: f64, _p: f64) {}
    /// Force the belt exerts on a pulley's hub.
    fn hub_force(&mut self, _pulley: usize, _fx: f64, _fy: f64) {}
    /// Per pulley: torque of the belt, torque a speed drive must supply, acceleration.
    fn pulley(&mut self, _pulley: usize, _belt_torque: f64, _drive_torque: f64, _alpha: f64) {}
    /// Per decoupler pulley: the torque its clutch transmits (>= 0, in the
    /// clutch's driving sense) and the rotor's speed.
    fn decoupler(&mut self, _pulley: usize, _torque: f64, _rotor_omega: f64) {}
    /// Power put in by drives and inputs, and power dissipated [W].
    fn power(&mut self, _input: f64, _dissipated: f64) {}
    /// A share of the power dissipated in the belt (SDE dampers, contact
    /// damping, friction slip without the creep springs); the shares of
    /// one evaluation add up to the belt's loss.
    fn belt_loss(&mut self, _p: f64) {}
    /// A contact's power stored in its creep spring (elements::friction):
    /// the part of `power`'s dissipated power that is not lost.
    fn creep_spring_power(&mut self, _p: f64) {}
}

/// The recorder of the hot path: records nothing.
pub struct NoRecord;
impl Recorder for NoRecord {
    const ACTIVE: bool = false;
}

/// What the right-hand side changes while the mounted belt is relaxed into
/// static equilibrium (`Drive::new`); all off ([`Relaxation::NONE`]) while
/// the drive runs. The drive's physical constants stay as they are.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Relaxation {
    /// Mass-proportional damping of the bodies' translation and rotation
    /// [1/s].
    pub damping: f64,
    /// Friction between belt and pulleys switched off (the creep
    /// displacement still follows its rate law).
    pub frictionless: bool,
    /// Every pulley, decoupler rotor and tensioner arm held at rest: inputs
    /// and built-in ramps are ignored and every pulley is treated as
    /// speed-driven; the arms stay where they were placed.
    pub pulleys_held: bool,
}

impl Relaxation {
    /// The running drive: nothing changed.
    pub const NONE: Self = Self {
        damping: 0.0,
        frictionless: false,
        pulleys_held: false,
    };
}

/// The belt drive as an ODE system: the constants of every body, SDE,
/// contact and pulley, and the inputs held over the current step. The
/// scratch of an evaluation is a [`Workspace`] the caller owns.
#[derive(Clone, Debug, PartialEq)]
pub struct BeltSystem {
    /// Belt bodies n.
    pub(crate) n: usize,
    /// Pulleys.
    pub(crate) np: usize,
    /// Where each state sits in the state vector.
    pub(crate) state_layout: StateLayout,
    pub(crate) pulleys: [PulleyConst; MAX_PULLEYS],
    /// Half the body length l/2 [m].
    pub(crate) half_length: f64,
    /// Body mass m and moment of inertia I (eq. 2), with their inverses.
    pub(crate) mass: f64,
    pub(crate) inv_mass: f64,
    pub(crate) inertia: f64,
    pub(crate) inv_inertia: f64,
    /// Translational SDE between neighbouring bodies (EA/l, B/l).
    pub(crate) axial: AxialSde,
    /// Torsional SDE between neighbouring bodies (EI/l, damping).
    pub(crate) bend: TorsionalSde,
    /// Damping of each body's motion across its axis (span damping).
    pub(crate) transverse: TransverseDamper,
    /// Gravitational acceleration [m/s^2] (acts in -y).
    pub(crate) gravity: f64,
    pub(crate) contact: ContactLaw,
    pub(crate) friction: Friction,
    /// Friction factor of every body (1 outside the modified zone).
    pub(crate) zone_factor: Vec<f64>,
    /// The equilibrium relaxation's settings ([`Relaxation::NONE`] when
    /// running).
    pub(crate) relaxation: Relaxation,
    pub(crate) inputs: Inputs,
    /// Contact points along each body (`contact.points`,
    /// [`contact::quadrature`]; 1 = the body centre, the paper's contact).
    pub(crate) points: usize,
}

pub(crate) use crate::model::trig::wrap_angle;

impl BeltSystem {
    /// The system of validated `params` on the mounted `layout`.
    pub fn new(params: &DriveParams, layout: &Layout) -> Self {
        let l = layout.body_length;
        let b = &params.belt;
        let mass = b.mass_per_length * l;
        let inertia = mass * l * l / 12.0; // eq. 2
        let n = b.n_bodies;
        let np = params.pulleys.len();
        let hardware: Vec<(bool, bool)> = params
            .pulleys
            .iter()
            .map(|p| (p.decoupler.is_some(), p.arm.is_some()))
            .collect();
        let mut pulleys = [PulleyConst::NONE; MAX_PULLEYS];
        for (j, (pc, p)) in pulleys.iter_mut().zip(&params.pulleys).enumerate() {
            let radii = contact::point_radii(p.radius, l, params.contact.points);
            *pc = PulleyConst {
                cx: p.x,
                cy: p.y,
                radius: p.radius,
                radius2: p.radius * p.radius,
                // the chordal effect of the straight bodies (elements::contact)
                lever: contact::chordal_lever(
                    p.radius,
                    layout.wrap_of(j).map_or(0.0, |w| w.penetration),
                    l,
                ),
                levers: contact::point_levers(
                    p.radius,
                    layout.wrap_of(j).map_or(0.0, |w| w.penetration),
                    l,
                    params.contact.points,
                ),
                radii,
                reach: radii.iter().fold(0.0, |a: f64, &b| a.max(b)) + 0.5 * l,
                inv_inertia: 1.0 / p.inertia,
                inertia: p.inertia,
                // the groove's wedge effect (elements::groove)
                mu_s: p.mu_static * friction_factor(p.groove_angle, p.back_side),
                mu_k: p.mu_kinetic * friction_factor(p.groove_angle, p.back_side),
                // the damping ramp: the user's contact.pMax, or from the
                // wrap's equilibrium penetration (elements::contact)
                inv_p_max: 1.0
                    / contact::auto_p_max(
                        params.contact.p_max,
                        layout.wrap_of(j).map_or(0.0, |w| w.penetration),
                    ),
                speed_driven: p.speed_driven,
                load_damping: p.load_damping,
                torque_ramp: p.torque_ramp,
                omega_ramp: p.omega_ramp,
                ramp_time: p.ramp_time,
                decoupler: p.decoupler.as_ref().map(DecouplerParams::law),
                rotor_inertia: p.decoupler.map_or(0.0, |d| d.rotor_inertia),
                rotor_inv_inertia: p.decoupler.map_or(0.0, |d| 1.0 / d.rotor_inertia),
                arm: p.arm.as_ref().map(|a| {
                    let mut arm = Arm::new(a, [p.x, p.y]);
                    // the pivot friction's presliding under the installed
                    // hub force 2 T0 sin(wrap / 2)
                    let wrap = layout.wrap_of(j).map_or(0.0, |w| w.angle);
                    arm.mount_friction(2.0 * params.belt.preload * (0.5 * wrap).sin());
                    arm
                }),
            };
        }
        let f = &params.friction;
        let mut zone_factor = vec![1.0; n];
        for k in 0..f.zone_bodies {
            zone_factor[(f.zone_start + k) % n] = f.zone_factor;
        }
        let c = &params.contact;
        Self {
            n,
            np,
            state_layout: StateLayout::new(n, &hardware),
            pulleys,
            half_length: 0.5 * l,
            mass,
            inv_mass: 1.0 / mass,
            inertia,
            inv_inertia: 1.0 / inertia,
            axial: AxialSde {
                k: b.ea / l,
                b: b.axial_damping / l,
                bt: b.shear_damping_factor * b.axial_damping / l,
                eps2: AxialSde::regularisation_eps2(l),
            },
            bend: TorsionalSde {
                k: b.bending_stiffness / l,
                b: b.bending_damping / l,
            },
            transverse: TransverseDamper {
                rate: b.transverse_damping,
            },
            gravity: params.gravity,
            contact: ContactLaw {
                c1: c.c1 * l,
                c2: c.c2 * l,
                b: c.damping * l,
            },
            friction: Friction::new(f.law, f.dv, f.creep_max, f.creep_damping_time),
            zone_factor,
            relaxation: Relaxation::NONE,
            inputs: Inputs::default(),
            points: params.contact.points,
        }
    }

    /// Length of the state vector.
    pub fn dim(&self) -> usize {
        self.state_layout.dim()
    }

    /// States whose error the integrators control: all but the impulses at
    /// the end, which feed nothing back.
    pub fn controlled_dim(&self) -> usize {
        self.state_layout.controlled_len()
    }

    /// Where each state sits in the state vector.
    #[inline(always)]
    pub fn state_layout(&self) -> &StateLayout {
        &self.state_layout
    }

    /// Centre of pulley j in state `y` and its velocity: the fixed centre,
    /// or the end of its tensioner arm, `c(alpha)` and `c'(alpha) alpha'`.
    #[inline]
    pub fn pulley_centre(&self, j: usize, y: &[f64]) -> ([f64; 2], [f64; 2]) {
        let pc = &self.pulleys[j];
        match &pc.arm {
            None => ([pc.cx, pc.cy], [0.0, 0.0]),
            Some(arm) => {
                let o = self.state_layout.arm(j);
                let (a, w) = (y[o.angle], y[o.rate]);
                let (c, dc) = arm.centre(a);
                (c, [dc[0] * w, dc[1] * w])
            }
        }
    }

    /// Number of belt bodies n.
    pub fn n_bodies(&self) -> usize {
        self.n
    }

    /// Number of pulleys.
    pub fn n_pulleys(&self) -> usize {
        self.np
    }

    /// Number of pulleys with a one-way decoupler.
    pub fn n_decouplers(&self) -> usize {
        self.state_layout.n_decouplers()
    }

    /// The pulleys' constants, in pulley order.
    pub fn pulleys(&self) -> &[PulleyConst] {
        &self.pulleys[..self.np]
    }

    /// Half the body length l/2 [m].
    pub fn half_length(&self) -> f64 {
        self.half_length
    }

    /// Mass of one body [kg].
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// Moment of inertia of one body about its centre (eq. 2) [kg m^2].
    pub fn inertia(&self) -> f64 {
        self.inertia
    }

    /// Gravitational acceleration [m/s^2], acting in -y.
    pub fn gravity(&self) -> f64 {
        self.gravity
    }

    /// The translational SDE between neighbouring bodies.
    pub fn axial(&self) -> AxialSde {
        self.axial
    }

    /// The torsional SDE between neighbouring bodies.
    pub fn bend(&self) -> TorsionalSde {
        self.bend
    }

    /// The transverse (span) damping of every body.
    pub fn transverse(&self) -> TransverseDamper {
        self.transverse
    }

    /// The normal-force law of every contact.
    pub fn contact(&self) -> ContactLaw {
        self.contact
    }

    /// Contact points along each body (`contact.points`).
    pub fn contact_points(&self) -> usize {
        self.points
    }

    /// The friction law of every contact.
    pub fn friction(&self) -> Friction {
        self.friction
    }

    /// Friction factor of each body (1 outside the modified zone).
    pub fn zone_factor(&self) -> &[f64] {
        &self.zone_factor
    }

    /// The inputs held over the current step.
    pub fn inputs(&self) -> &Inputs {
        &self.inputs
    }

    /// The equilibrium relaxation's settings in effect.
    pub fn relaxation(&self) -> Relaxation {
        self.relaxation
    }

    /// The same drive with the relaxation settings `r` (its constants
    /// unchanged).
    pub fn with_relaxation(&self, r: Relaxation) -> Self {
        Self {
            relaxation: r,
            ..self.clone()
        }
    }

    /// Pulley j as the equations see it: during the relaxation without
    /// friction and held at rest (speed-driven) as its settings say.
    #[inline(always)]
    pub(crate) fn pulley_in_effect(&self, j: usize) -> PulleyConst {
        let mut pc = self.pulleys[j];
        let r = &self.relaxation;
        if r.frictionless {
            pc.mu_s = 0.0;
            pc.mu_k = 0.0;
        }
        if r.pulleys_held {
            pc.speed_driven = true;
        }
        pc
    }

    /// All pulleys as [`Self::pulley_in_effect`] gives them: the system's
    /// own array while running, else `buf` filled (left empty while running:
    /// filling it on every call cost the right-hand side 1.7 % of its
    /// instructions).
    #[inline(always)]
    pub(crate) fn pulleys_in_effect<'a>(
        &'a self,
        buf: &'a mut Option<[PulleyConst; MAX_PULLEYS]>,
    ) -> &'a [PulleyConst; MAX_PULLEYS] {
        if self.relaxation == Relaxation::NONE {
            return &self.pulleys;
        }
        let buf = buf.insert([PulleyConst::NONE; MAX_PULLEYS]);
        for (j, pc) in buf.iter_mut().enumerate().take(self.np) {
            *pc = self.pulley_in_effect(j);
        }
        buf
    }

    /// Torque input plus built-in ramp on pulley j at time t (0 while the
    /// relaxation holds the pulleys).
    #[inline]
    pub fn applied_torque(&self, j: usize, t: f64) -> f64 {
        if self.relaxation.pulleys_held {
            return 0.0;
        }
        let p = &self.pulleys[j];
        let inp = &self.inputs;
        inp.torque[j] + inp.torque_rate[j] * (t - inp.t0) + p.ramp(p.torque_ramp, t)
    }

    /// The first time after `t` at which a pulley's ramp (applied torque or
    /// prescribed speed) starts or ends: the right-hand side has a kink
    /// there. Infinity if none is to come.
    pub fn next_breakpoint(&self, t: f64) -> f64 {
        if self.relaxation.pulleys_held {
            return f64::INFINITY;
        }
        let mut next = f64::INFINITY;
        for p in &self.pulleys[..self.np] {
            if p.torque_ramp == 0.0 && p.omega_ramp == 0.0 {
                continue;
            }
            for kink in [0.0, p.ramp_time] {
                if kink > t {
                    next = next.min(kink);
                }
            }
        }
        next
    }

    /// Prescribed speed of a speed-driven pulley j at time t, and its rate
    /// (0 while the relaxation holds the pulleys).
    #[inline]
    pub fn prescribed_speed(&self, j: usize, t: f64) -> (f64, f64) {
        if self.relaxation.pulleys_held {
            return (0.0, 0.0);
        }
        let p = &self.pulleys[j];
        let inp = &self.inputs;
        let w = inp.omega_ref[j] + inp.omega_ref_rate[j] * (t - inp.t0) + p.ramp(p.omega_ramp, t);
        let dw = inp.omega_ref_rate[j] + p.ramp_rate(p.omega_ramp, t);
        (w, dw)
    }

    /// Angular speed of pulley j used by the contact: the state for
    /// torque-driven pulleys, the prescription for speed-driven ones.
    #[inline]
    pub fn pulley_speed(&self, j: usize, t: f64, y: &[f64]) -> f64 {
        if self.pulleys[j].speed_driven || self.relaxation.pulleys_held {
            self.prescribed_speed(j, t).0
        } else {
            y[self.state_layout.pulley(j).speed]
        }
    }
}
