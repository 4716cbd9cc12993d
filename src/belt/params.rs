//! Parameters of a belt drive, their defaults (the paper's section-4 drive)
//! and their validation.
//!
//! Belt properties are given as continuum quantities (EA, axial damping,
//! bending stiffness, contact stiffness per unit length) and mapped onto the
//! discrete spring-damper elements (SDEs) with the body length l, so a finer
//! mesh models the same belt. See `docs/model.md`, "Parameters".

use super::elements::groove::MIN_GROOVE_ANGLE;
use super::param_id::{msg, Message, Param, Part, Plain, Spelling};

/// Number of pulley slots: the largest pulley count the model description
/// declares.
pub const MAX_PULLEYS: usize = declared_max(Param::PulleyCount);

/// The declared maximum of a count parameter, at compile time.
const fn declared_max(p: Param) -> usize {
    match p.declared().max {
        Some(m) => m as usize,
        None => panic!("the model description declares no maximum"),
    }
}

/// The belt-pulley friction law (section 2.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrictionLaw {
    /// Eq. 12-19 as printed: velocity-regularised Coulomb friction with a
    /// creep term; stiff for small `dv`.
    Kubas2014,
    /// Elastic-plastic creep law (ref. [11]): friction grows with the
    /// integrated creep displacement, slides at mu_k.
    Creep,
}

/// Which integrator advances the state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Runge-Kutta-Fehlberg 4(5), the paper's method.
    Rkf45,
    /// Linearly implicit Rosenbrock-W method ROS34PW2 (stiff, L-stable).
    Rosenbrock,
}

#[derive(Clone, Debug, PartialEq)]
/// Parameters of one pulley.
pub struct PulleyParams {
    /// Centre [m].
    pub x: f64,
    /// Centre y [m].
    pub y: f64,
    /// Radius [m].
    pub radius: f64,
    /// Moment of inertia about the axis [kg m^2].
    pub inertia: f64,
    /// Static friction coefficient with the belt.
    pub mu_static: f64,
    /// Kinetic friction coefficient with the belt (<= `mu_static`).
    pub mu_kinetic: f64,
    /// The belt's back touches this pulley (an idler outside the loop).
    pub back_side: bool,
    /// Included angle 2 beta of the V-ribbed groove [rad], 0 = flat: the
    /// ribs carry friction with mu / sin(beta); the belt's back on a
    /// back-side idler stays flat (`elements::groove`).
    pub groove_angle: f64,
    /// A one-way decoupler sits between the hub (which the belt drives) and
    /// a rotor; the load torque, input torque and load damping act on the
    /// rotor (`elements::decoupler`).
    pub decoupler: bool,
    /// Decoupler spring [N m/rad] and damper [N m s/rad] (> 0).
    pub decoupler_stiffness: f64,
    /// Decoupler damper [N m s/rad] (> 0).
    pub decoupler_damping: f64,
    /// The clutch drives the rotor clockwise (negative omega) instead of
    /// counterclockwise.
    pub decoupler_clockwise: bool,
    /// Rotor moment of inertia [kg m^2].
    pub rotor_inertia: f64,
    /// The pulley sits on an automatic tensioner arm pivoting about
    /// `arm_pivot` instead of on a fixed centre; `x`, `y` is its mounted
    /// centre (`elements::tensioner`).
    pub tensioner: bool,
    /// Pivot of the tensioner arm [m].
    pub arm_pivot: [f64; 2],
    /// Moment of inertia of arm and pulley about the pivot [kg m^2].
    pub arm_inertia: f64,
    /// Arm spring [N m/rad], viscous damper [N m s/rad] and Coulomb
    /// friction torque of the pivot [N m].
    pub arm_stiffness: f64,
    /// Arm damper [N m s/rad].
    pub arm_damping: f64,
    /// Coulomb friction torque of the arm's pivot [N m].
    pub arm_friction: f64,
    /// The pulley follows a prescribed speed instead of eq. 24.
    pub speed_driven: bool,
    /// Resistance torque -load_damping * omega [N m s/rad] (Fig. 13).
    pub load_damping: f64,
    /// Built-in torque profile: ramps linearly from 0 to `torque_ramp`
    /// over `ramp_time`, then holds (Fig. 12). Added to the torque input.
    pub torque_ramp: f64,
    /// Built-in speed profile for speed-driven pulleys, added to omegaRef.
    pub omega_ramp: f64,
    /// Duration of the built-in ramps [s].
    pub ramp_time: f64,
}

impl PulleyParams {
    /// A pulley of the paper's section-4 drive at (x, y).
    pub fn paper_5pk(x: f64, y: f64) -> Self {
        Self {
            x,
            y,
            radius: 0.027,
            inertia: 2.4e-4,
            mu_static: 1.05,
            mu_kinetic: 1.0,
            back_side: false,
            groove_angle: 0.0,
            decoupler: false,
            decoupler_stiffness: 10.0,
            decoupler_damping: 0.02,
            decoupler_clockwise: false,
            rotor_inertia: 3e-3,
            tensioner: false,
            arm_pivot: [0.0, 0.0],
            arm_inertia: 1e-3,
            arm_stiffness: 40.0,
            arm_damping: 0.0,
            arm_friction: 0.0,
            speed_driven: false,
            load_damping: 0.0,
            torque_ramp: 0.0,
            omega_ramp: 0.0,
            ramp_time: 0.3,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
/// Parameters of the belt (continuum quantities).
pub struct BeltParams {
    /// Number of rigid bodies the belt is divided into.
    pub n_bodies: usize,
    /// Static tension at assembly [N].
    pub preload: f64,
    /// Axial stiffness [N]; each translational SDE gets EA / l.
    pub ea: f64,
    /// Axial damping [N s] (force per unit strain rate); each SDE gets value / l.
    pub axial_damping: f64,
    /// Bending stiffness EI [N m^2]; each torsional SDE gets EI / l.
    pub bending_stiffness: f64,
    /// Bending damping [N m^2 s]; each torsional SDE gets value / l.
    pub bending_damping: f64,
    /// [kg/m]
    pub mass_per_length: f64,
}

#[derive(Clone, Debug, PartialEq)]
/// Parameters of the belt-pulley contact (eq. 9-11).
pub struct ContactParams {
    /// Quadratic penalty stiffness per unit belt length [N/m^3] (eq. 9: c1 = value * l).
    pub c1: f64,
    /// Linear penalty stiffness per unit belt length [N/m^2] (eq. 9: c2 = value * l).
    pub c2: f64,
    /// Contact damping per unit belt length [N s/m^2] (eq. 9: b = value * l).
    pub damping: f64,
    /// Penetration of full damping, eq. 10-11 [m]; 0 = automatic, per
    /// pulley from its equilibrium penetration (`elements::contact::auto_p_max`).
    pub p_max: f64,
    /// Contact points along each body: the penalty law per unit length
    /// integrated by this many Gauss-Legendre points (1 = the body centre,
    /// the paper's contact; `elements::contact::quadrature`).
    pub points: usize,
}

#[derive(Clone, Debug, PartialEq)]
/// Parameters of the belt-pulley friction (section 2.2).
pub struct FrictionParams {
    /// Which friction law.
    pub law: FrictionLaw,
    /// Transition velocity of the kubas2014 law [m/s].
    pub dv: f64,
    /// Creep displacement of fully developed static friction [m].
    pub creep_max: f64,
    /// Relaxation time of the creep law's spring [s]: its damper is this
    /// time the spring's slope (Kelvin-Voigt, docs/model.md "Friction").
    pub creep_damping_time: f64,
    /// Friction factor over a belt zone (oil contamination, section 5).
    pub zone_factor: f64,
    /// First body of the zone (0-based) and its length in bodies.
    pub zone_start: usize,
    /// Bodies in the modified-friction zone (0 = none).
    pub zone_bodies: usize,
}

/// The paper's friction in both its cases: mu1 over Delta_max = 0.1 mm,
/// dv = 1e-5 m/s for `kubas2014`; the `creep` law is the default.
impl Default for FrictionParams {
    fn default() -> Self {
        Self {
            law: FrictionLaw::Creep,
            dv: 1e-5,
            creep_max: 1e-4,
            creep_damping_time: CREEP_DAMPING_TIME,
            zone_factor: 1.0,
            zone_start: 0,
            zone_bodies: 0,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
/// The integrator and its user-facing settings.
pub struct SolverParams {
    /// Which integrator.
    pub method: Method,
    /// Relative error tolerance.
    pub rel_tol: f64,
    /// Absolute error tolerance (in each state's SI unit).
    pub abs_tol: f64,
    /// First trial step size [s].
    pub initial_step: f64,
    /// Step-count guard per `advance` call.
    pub max_steps: u64,
}

/// RKF45 at rtol 1e-4; the work guard is generous for library runs over
/// long horizons (the FMU sets 1e5 per fmi2DoStep, docs/model.md).
impl Default for SolverParams {
    fn default() -> Self {
        Self {
            method: Method::Rkf45,
            rel_tol: 1e-4,
            abs_tol: 1e-6,
            initial_step: 1e-7,
            max_steps: 100_000_000,
        }
    }
}

/// Everything that defines a drive.
#[derive(Clone, Debug, PartialEq)]
pub struct DriveParams {
    /// Pulleys in belt order around the loop (`n_pulleys` of them are used).
    pub pulleys: Vec<PulleyParams>,
    /// The belt.
    pub belt: BeltParams,
    /// The contact law.
    pub contact: ContactParams,
    /// The friction law.
    pub friction: FrictionParams,
    /// The integrator.
    pub solver: SolverParams,
    /// [m/s^2], acting in -y.
    pub gravity: f64,
    /// Body (0-based) whose forces the probe outputs report, or
    /// [`PROBE_AUTO`]: the body nearest the middle of the free span from
    /// pulley 1 to pulley 2 in the mounted belt (`Drive::probe_body`).
    pub probe_body: usize,
}

/// `probe_body` value that lets the drive choose the probe body (the FMU's
/// `probe.body` = 0): any body count is then valid.
pub const PROBE_AUTO: usize = usize::MAX;

/// Body length of the paper's section-4 mesh (1.2 m belt, 150 bodies), used
/// to turn its per-element figures into per-length belt properties.
const PAPER4_BODY_LENGTH: f64 = 0.008;
/// Default relaxation time of the creep law's spring [s] (not in the paper;
/// chosen and justified in docs/model.md, "Friction").
pub const CREEP_DAMPING_TIME: f64 = 3e-4;
/// Same for section 3 (0.2530*2 + 2*pi*0.08125 m belt, 60 bodies).
const PAPER3_BODY_LENGTH: f64 = (2.0 * 0.253 + 2.0 * std::f64::consts::PI * 0.08125) / 60.0;

/// The FMU's default drive: the paper's section-4 drive with the contact
/// damping ramp chosen automatically per pulley (`contact.pMax` = 0; the
/// paper's 1 mm leaves the radial contact mode of most belts undamped,
/// docs/model.md "Contact").
impl Default for DriveParams {
    fn default() -> Self {
        let mut p = Self::kubas_section4();
        p.contact.p_max = 0.0;
        p
    }
}

impl DriveParams {
    /// The paper's section-4 drive: 5PK poly-V belt, two 27 mm pulleys
    /// 0.515 m apart, 150 bodies, 550 N preload, -15 N m drive torque ramped
    /// over 0.3 s on pulley 1, resistance 15 N m at 8*pi rad/s on pulley 2.
    pub fn kubas_section4() -> Self {
        let l = PAPER4_BODY_LENGTH;
        let mut p1 = PulleyParams::paper_5pk(0.0, 0.0);
        p1.torque_ramp = -15.0;
        let mut p2 = PulleyParams::paper_5pk(0.515, 0.0);
        p2.load_damping = 15.0 / (8.0 * std::f64::consts::PI);
        Self {
            pulleys: vec![p1, p2],
            belt: BeltParams {
                n_bodies: 150,
                preload: 550.0,
                ea: 1.52e5,
                axial_damping: 20.5 * l,
                bending_stiffness: 0.026 * l,
                bending_damping: 0.0,
                mass_per_length: 0.096,
            },
            contact: ContactParams {
                c1: 3.0256e9 / l,
                c2: 6.5e5 / l,
                damping: 300.0 / l,
                p_max: 1e-3,
                points: 1,
            },
            friction: FrictionParams::default(),
            solver: SolverParams::default(),
            gravity: 9.81,
            probe_body: PROBE_AUTO,
        }
    }

    /// The paper's section-3 verification drive (after Cepon & Boltezar
    /// [12]): 60 bodies, two 81.25 mm pulleys (I = 0.02 kg m^2) 0.253 m
    /// apart, mu_s = mu_k = 0.8; c_tra = 1e4 read as EA, the other per-SDE
    /// and per-contact figures converted to the per-length parameters with
    /// the body length l (docs/model.md, "Parameters"). p_max = 1e-5 m
    /// instead of the paper's 1 mm, which is 160 times the 6 um penetration
    /// and would switch the contact damping off (docs/model.md, "Contact").
    ///
    /// Figs. 8 and 9 are not in the text, so the drive course and the load
    /// are readings: pulley 1 is speed-driven, ramped to -10 rad/s over
    /// 0.1 s (clockwise, as in section 4); pulley 2 is torque-driven with no
    /// load damping and a zero resistance torque, which the caller steps
    /// through the `pulley[2].torque` input (docs/validation.md: 10 N m at
    /// 0.3 s). Preload 150 N (not given in the text; see docs/validation.md).
    pub fn kubas_section3() -> Self {
        let l = PAPER3_BODY_LENGTH;
        let pulley = |x: f64| PulleyParams {
            radius: 0.08125,
            inertia: 0.02,
            mu_static: 0.8,
            mu_kinetic: 0.8,
            omega_ramp: 0.0,
            ramp_time: 0.1,
            ..PulleyParams::paper_5pk(x, 0.0)
        };
        let mut p1 = pulley(0.0);
        p1.speed_driven = true;
        p1.omega_ramp = -10.0;
        let p2 = pulley(0.253);
        Self {
            pulleys: vec![p1, p2],
            belt: BeltParams {
                n_bodies: 60,
                preload: 150.0,
                ea: 1e4,
                axial_damping: 0.5 * l,
                bending_stiffness: 0.0208 * l,
                bending_damping: 0.0,
                mass_per_length: 1.036,
            },
            contact: ContactParams {
                c1: 0.0,
                c2: 5e6 / l,
                damping: 300.0 / l,
                // the paper's 1 mm is 160 times the 6 um penetration here and
                // switches the damping off (docs/model.md, "Contact")
                p_max: 1e-5,
                points: 1,
            },
            friction: FrictionParams::default(),
            solver: SolverParams::default(),
            gravity: 9.81,
            probe_body: 45,
        }
    }
}

/// A parameter the model refuses, with the name the user knows it by.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamError {
    /// The parameter that is wrong.
    pub parameter: Param,
    /// What is wrong with it and how to fix it.
    pub message: Message,
}

impl ParamError {
    /// The error as text, the parameter spelt `name` and the message by
    /// `s`: `name must be ... (got ...)` for a range, `name: ...` otherwise.
    pub fn render(&self, name: &str, s: &dyn Spelling) -> String {
        let message = self.message.render(s);
        if message.starts_with("must ") {
            format!("{name} {message}")
        } else {
            format!("{name}: {message}")
        }
    }
}

impl std::fmt::Display for ParamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.render(&self.parameter.to_string(), &Plain))
    }
}

impl std::error::Error for ParamError {}

pub(crate) fn param_error(parameter: Param, message: impl Into<Message>) -> ParamError {
    ParamError {
        parameter,
        message: message.into(),
    }
}

impl From<&str> for Message {
    fn from(s: &str) -> Self {
        Self(vec![Part::from(s)])
    }
}

impl From<String> for Message {
    fn from(s: String) -> Self {
        Self(vec![Part::from(s)])
    }
}

/// Largest body count accepted (the model description's maximum of the
/// body count), to bound the work of one call: mounting (the equilibrium
/// relaxation in `Drive::new`) grows faster than n^2 with the body count
/// (2-core development machine: 150 bodies 0.09 s, 600 1.2 s, 1200 6.6 s,
/// 2400 83 s), and so does the cost per simulated second.
pub const MAX_BODIES: usize = declared_max(Param::BeltBodies);

/// Shortest tensioner arm accepted [m]: the pivot must not sit at the
/// pulley centre (the arm would have no lever for the hub force).
pub const MIN_ARM_LENGTH: f64 = 1e-3;

fn check(ok: bool, name: Param, what: impl Into<Message>, value: f64) -> Result<(), ParamError> {
    if ok {
        Ok(())
    } else {
        let mut m = msg!["must be "];
        m.0.extend(what.into().0);
        m.0.push(Part::from(format!(" (got {})", shown(value))));
        Err(param_error(name, m))
    }
}

/// A value as a refusal shows it: `0.027`, `1e300` (not 301 digits).
fn shown(x: f64) -> String {
    if x != 0.0 && x.is_finite() && !(1e-4..1e6).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// `v` is finite and inside `p`'s declared range ([`Param::declared`]):
/// the one check of every single-parameter range.
fn declared(p: Param, v: f64) -> Result<(), ParamError> {
    let r = p.declared();
    check(r.contains(v), p, r.describe(), v)
}

/// A count `n` inside `p`'s declared (integer) range.
fn declared_count(p: Param, n: usize) -> Result<(), ParamError> {
    let r = p.declared();
    let x = n as f64;
    let range = match (r.min, r.max) {
        (Some(lo), Some(hi)) => format!("in {lo}..={hi}"),
        (Some(lo), None) => format!(">= {lo}"),
        (None, Some(hi)) => format!("<= {hi}"),
        (None, None) => return Ok(()),
    };
    if r.min.is_some_and(|lo| x < lo) || r.max.is_some_and(|hi| x > hi) {
        return Err(param_error(p, format!("must be {range} (got {n})")));
    }
    Ok(())
}

/// `v` > 0 where the declared range starts at 0 inclusive because 0 is
/// valid while a feature is off: `p` must be positive when `flag` is set.
fn positive_when(p: Param, flag: Param, v: f64) -> Result<(), ParamError> {
    check(v > 0.0, p, msg!["> 0 when ", flag, " is set"], v)
}

impl PulleyParams {
    /// Checks each parameter of the pulley with index `j` against its
    /// declared range ([`Param::declared`]); [`DriveParams::validate`] adds
    /// the rules that involve several parameters.
    pub fn validate_ranges(&self, j: usize) -> Result<(), ParamError> {
        // The declared coordinate range keeps the layout's path lengths
        // from overflowing.
        declared(Param::PulleyX(j), self.x)?;
        declared(Param::PulleyY(j), self.y)?;
        declared(Param::PulleyRadius(j), self.radius)?;
        declared(Param::PulleyInertia(j), self.inertia)?;
        declared(Param::PulleyMuStatic(j), self.mu_static)?;
        declared(Param::PulleyMuKinetic(j), self.mu_kinetic)?;
        declared(Param::PulleyLoadDamping(j), self.load_damping)?;
        declared(Param::PulleyTorqueRamp(j), self.torque_ramp)?;
        declared(Param::PulleyOmegaRamp(j), self.omega_ramp)?;
        declared(Param::PulleyRampTime(j), self.ramp_time)?;
        declared(Param::PulleyGrooveAngle(j), self.groove_angle)?;
        declared(Param::PulleyDecouplerStiffness(j), self.decoupler_stiffness)?;
        declared(Param::PulleyDecouplerDamping(j), self.decoupler_damping)?;
        declared(Param::PulleyRotorInertia(j), self.rotor_inertia)?;
        declared(Param::PulleyArmPivotX(j), self.arm_pivot[0])?;
        declared(Param::PulleyArmPivotY(j), self.arm_pivot[1])?;
        declared(Param::PulleyArmInertia(j), self.arm_inertia)?;
        declared(Param::PulleyArmStiffness(j), self.arm_stiffness)?;
        declared(Param::PulleyArmDamping(j), self.arm_damping)?;
        declared(Param::PulleyArmFriction(j), self.arm_friction)
    }
}

impl DriveParams {
    /// Checks every parameter: its declared range ([`Param::declared`],
    /// from the model description) and the rules that involve several
    /// parameters. Geometric checks (overlap, wrap, arc resolution) are made
    /// by [`crate::belt::layout::Layout::new`].
    pub fn validate(&self) -> Result<(), ParamError> {
        declared_count(Param::PulleyCount, self.pulleys.len())?;
        let b = &self.belt;
        declared_count(Param::BeltBodies, b.n_bodies)?;
        declared(Param::BeltPreload, b.preload)?;
        declared(Param::BeltEa, b.ea)?;
        check(
            b.preload < 0.5 * b.ea,
            Param::BeltPreload,
            msg!["below half of ", Param::BeltEa, " (strain < 50 %)"],
            b.preload,
        )?;
        declared(Param::BeltAxialDamping, b.axial_damping)?;
        declared(Param::BeltBendingStiffness, b.bending_stiffness)?;
        declared(Param::BeltBendingDamping, b.bending_damping)?;
        declared(Param::BeltMassPerLength, b.mass_per_length)?;
        let c = &self.contact;
        declared(Param::ContactC1, c.c1)?;
        declared(Param::ContactC2, c.c2)?;
        check(
            c.c1 > 0.0 || c.c2 > 0.0,
            Param::ContactC2,
            msg![
                "> 0 when ",
                Param::ContactC1,
                " is 0 (no contact stiffness)"
            ],
            c.c2,
        )?;
        declared(Param::ContactDamping, c.damping)?;
        declared(Param::ContactPMax, c.p_max)?;
        declared_count(Param::ContactPoints, c.points)?;
        let f = &self.friction;
        declared(Param::FrictionDv, f.dv)?;
        declared(Param::FrictionCreepMax, f.creep_max)?;
        declared(Param::FrictionCreepDampingTime, f.creep_damping_time)?;
        declared(Param::FrictionZoneFactor, f.zone_factor)?;
        if f.zone_bodies > 0 && f.zone_start >= b.n_bodies {
            return Err(param_error(
                Param::FrictionZoneStart,
                format!("must be in 1..={} (got {})", b.n_bodies, f.zone_start + 1),
            ));
        }
        if f.zone_bodies > b.n_bodies {
            return Err(param_error(
                Param::FrictionZoneBodies,
                format!("must be in 0..={} (got {})", b.n_bodies, f.zone_bodies),
            ));
        }
        declared(Param::Gravity, self.gravity)?;
        if self.probe_body != PROBE_AUTO && self.probe_body >= b.n_bodies {
            return Err(param_error(
                Param::ProbeBody,
                format!(
                    "must be in 1..={} or 0 (chosen automatically; got {})",
                    b.n_bodies,
                    self.probe_body + 1
                ),
            ));
        }
        let s = &self.solver;
        declared(Param::SolverRelTol, s.rel_tol)?;
        declared(Param::SolverAbsTol, s.abs_tol)?;
        declared(Param::SolverInitialStep, s.initial_step)?;
        declared_count(
            Param::SolverMaxSteps,
            usize::try_from(s.max_steps).unwrap_or(usize::MAX),
        )?;
        for (j, p) in self.pulleys.iter().enumerate() {
            p.validate_ranges(j)?;
            check(
                p.mu_kinetic <= p.mu_static,
                Param::PulleyMuKinetic(j),
                msg![
                    "<= ",
                    Param::PulleyMuStatic(j),
                    format!(" = {}", p.mu_static)
                ],
                p.mu_kinetic,
            )?;
            // declared: [0, pi); a groove narrower than 10 deg (other than
            // 0, flat) would multiply mu by more than 11
            let g = p.groove_angle;
            check(
                g == 0.0 || g >= MIN_GROOVE_ANGLE,
                Param::PulleyGrooveAngle(j),
                format!(
                    "0 (flat) or in [{MIN_GROOVE_ANGLE:.4}, pi) rad, i.e. 10..180 deg \
                     (V-ribbed belts: 40 deg = 0.6981 rad)"
                ),
                g,
            )?;
            if p.decoupler {
                let on = Param::PulleyDecoupler(j);
                positive_when(
                    Param::PulleyDecouplerStiffness(j),
                    on,
                    p.decoupler_stiffness,
                )?;
                check(
                    p.decoupler_damping > 0.0,
                    Param::PulleyDecouplerDamping(j),
                    msg![
                        "finite and > 0 when ",
                        Param::PulleyDecoupler(j),
                        " is set (the spring relaxes through it while the clutch overruns; \
                         e.g. 0.02 N m s/rad)"
                    ],
                    p.decoupler_damping,
                )?;
                positive_when(Param::PulleyRotorInertia(j), on, p.rotor_inertia)?;
            }
            if p.tensioner {
                let arm = (p.x - p.arm_pivot[0]).hypot(p.y - p.arm_pivot[1]);
                if arm < MIN_ARM_LENGTH {
                    return Err(param_error(
                        Param::PulleyArmPivotX(j),
                        msg![
                            format!(
                                "must lie at least {MIN_ARM_LENGTH} m from the pulley centre ("
                            ),
                            Param::PulleyX(j),
                            ", ",
                            Param::PulleyY(j),
                            format!(
                                "), which sets the arm length (got an arm of {arm:e} m; \
                                 automotive tensioner arms are 0.05-0.1 m)"
                            ),
                        ],
                    ));
                }
                let on = Param::PulleyTensioner(j);
                positive_when(Param::PulleyArmInertia(j), on, p.arm_inertia)?;
                positive_when(Param::PulleyArmStiffness(j), on, p.arm_stiffness)?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Rust program that builds a drive directly is refused the declared
    /// ranges with the same rule as an FMU user, in engineering names.
    #[test]
    fn library_users_get_the_declared_ranges() {
        let refusal = |f: &dyn Fn(&mut DriveParams)| {
            let mut p = DriveParams::default();
            f(&mut p);
            p.validate().unwrap_err().to_string()
        };
        assert_eq!(
            refusal(&|p| p.pulleys[0].radius = 0.0),
            "pulley 1 radius must be finite and > 0 m (got 0)"
        );
        assert_eq!(
            refusal(&|p| p.solver.rel_tol = 1.0),
            "relative tolerance must be finite and in (0, 1) (got 1)"
        );
        assert_eq!(
            refusal(&|p| p.pulleys[1].arm_pivot[0] = 1e300),
            "pulley 2 tensioner pivot x must be finite and in [-1000, 1000] m (got 1e300)"
        );
        assert_eq!(
            refusal(&|p| p.belt.n_bodies = MAX_BODIES + 1),
            "number of belt bodies must be in 3..=2000 (got 2001)"
        );
        // 0 is the declared (inclusive) minimum of the decoupler spring: valid
        // without a decoupler, refused with one (a rule of two parameters)
        let mut p = DriveParams::default();
        p.pulleys[1].decoupler_stiffness = 0.0;
        p.validate().unwrap();
        p.pulleys[1].decoupler = true;
        assert_eq!(
            p.validate().unwrap_err().to_string(),
            "pulley 2 decoupler stiffness must be > 0 when pulley 2 decoupler is set (got 0)"
        );
        assert_eq!((MAX_PULLEYS, MAX_BODIES), (6, 2000));
    }
}
