//! Automatic tensioner: a pulley whose centre sits on an arm pivoting about
//! a fixed point (docs/model.md, "Automatic tensioner arm"): its parameters
//! ([`TensionerArm`], `pulley[j].arm.*`), its law ([`Arm`]) with partial
//! derivatives, energy and dissipation.
//!
//! The arm angle alpha is measured from the mounted position, positive
//! counterclockwise. The pulley centre is
//! `c(alpha) = pivot + R (cos(phi0 + alpha), sin(phi0 + alpha))`, R and phi0
//! the arm length and direction at mounting. Besides the moment of the
//! belt's hub force about the pivot, the arm carries
//!
//! `M_arm = -k (alpha - alpha_free) - d alpha' + M_pivot + M_stop`
//!
//! a torsion spring of free angle alpha_free, a viscous damper, the pivot's
//! friction and the end stops. The friction torque M_f = M_c + mu_h r_f
//! |F_hub| (a constant part and, optionally, a part that grows with the hub
//! load, as in automotive tensioners whose damping bushing or friction shoe
//! is pressed by the hub force) acts through an elasto-plastic presliding
//! law ([`PivotFriction`]): the pivot's contact deflects by z before it
//! slides,
//!
//! `z' = alpha' - beta |alpha'| z / z_ss`, `M_pivot = -k_p z - (1 - beta)
//! c_p z'`,
//!
//! z_ss = M_f / k_p the deflection in sliding, beta = 0 while the deflection
//! unloads (alpha' z <= 0) or lies below the breakaway deflection
//! [`BREAKAWAY`] z_ss, rising to 1 at z_ss ([`breakaway`]; Dupont,
//! Hayward, Armstrong and Altpeter, IEEE Trans. Autom. Control 47 (2002)
//! 787-792). The presliding stiffness k_p = M_f0 / phi_p is set from the
//! installation (M_f0 the friction torque under the installed hub force 2
//! T0 sin(wrap / 2), T0 the installation tension, phi_p the
//! presliding angle `pulley[j].arm.preslidingAngle`) and the presliding
//! damping c_p = 2 sqrt(k_p I_arm) damps the arm's swing on the contact's
//! stiffness critically (the damping term of the LuGre law: Canudas de
//! Wit, Olsson, Astrom and Lischinsky, IEEE Trans. Autom. Control 40 (1995)
//! 419-425), acting on the elastic part of the deflection only, so that the
//! sliding torque is Coulomb's M_f. An arm that moves by much more than
//! phi_p one way slides; a reversal first unloads the deflection, so a
//! ripple far smaller than phi_p (the belt's body passing) stays elastic,
//! and a held arm carries up to half its friction torque without slipping.
//! The friction makes the damping asymmetric: it adds to the spring when
//! the arm is pushed back (belt tension rising) and subtracts from it when
//! the arm follows the belt.
//!
//! End stops (optional, [`Stops`]): past a stop angle by delta the arm meets
//! a stiff, damped contact, `M_stop = max(0, k_s delta + d_s w(delta /
//! delta_r) delta')` pushing it back (delta' the rate of penetration, w the
//! smoothstep of the belt contact's damping ramp, eq. 10-11, over
//! delta_r = [`STOP_DAMPING_RAMP`], so the torque is continuous when the arm
//! touches; never pulling, like the belt contact). At rest against a stop
//! the arm sits past it by the excess moment over k_s.

use super::contact::{smoothstep, smoothstep_slope};
use crate::model::param_id::{msg, Param};
use crate::model::params::{
    check, declared, param_error, positive_when, ParamError, MIN_ARM_LENGTH,
};

/// Breakaway deflection of the pivot friction as a fraction of the sliding
/// one, z_ba / z_ss: below it the presliding is purely elastic (a held arm
/// carries up to half its friction torque without any slip, so a ripple
/// does not make it walk), beyond it the slip sets in smoothly.
pub const BREAKAWAY: f64 = 0.5;

/// The elasto-plastic factor beta(u) of the presliding law at u = |z| /
/// z_ss while the deflection is loaded, and its derivative: 0 up to
/// [`BREAKAWAY`], 1 from 1 on, between them the half sine wave of Dupont,
/// Hayward, Armstrong and Altpeter (IEEE Trans. Autom. Control 47 (2002)
/// 787-792), whose slope is continuous at both ends.
#[inline(always)]
fn breakaway(u: f64) -> (f64, f64) {
    if u <= BREAKAWAY {
        (0.0, 0.0)
    } else if u >= 1.0 {
        (1.0, 0.0)
    } else {
        let w = std::f64::consts::PI / (1.0 - BREAKAWAY);
        let x = w * (u - 0.5 * (1.0 + BREAKAWAY));
        (0.5 + 0.5 * x.sin(), 0.5 * w * x.cos())
    }
}

/// Steps per cycle of [`Arm::friction_describing`]'s integration.
pub const DESCRIBING_POINTS: usize = 4_000;

/// Most cycles [`Arm::friction_describing`] integrates before the loop
/// has settled.
pub const DESCRIBING_CYCLES: usize = 40;

/// Penetration of an end stop over which its damping builds up [rad]
/// (0.057 deg): the contact torque is continuous when the arm touches, and
/// the full damping acts a fraction of a degree into the stop.
pub const STOP_DAMPING_RAMP: f64 = 1e-3;

/// An end stop's stiffness when `pulley[j].arm.stopStiffness` is 0
/// (automatic), as a multiple of the arm's spring: the arm yields a
/// hundredth of what the spring alone would under the same moment, stiff
/// next to the spring while its contact frequency (10 times the arm's on
/// its spring) stays far below the belt's.
pub const AUTO_STOP_STIFFNESS_PER_SPRING: f64 = 100.0;

/// Damping ratio of the arm on an end stop when
/// `pulley[j].arm.stopDamping` is 0 (automatic): d = 2 zeta sqrt(k_s I_arm).
pub const AUTO_STOP_DAMPING_RATIO: f64 = 0.5;

/// A tensioner arm as the user gives it (`pulley[j].arm.*`); the pulley's
/// centre (`x`, `y`) is its mounted position, the arm length the distance
/// from the pivot to it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TensionerArm {
    /// Pivot [m].
    pub pivot: [f64; 2],
    /// Moment of inertia of arm and pulley about the pivot [kg m^2] (> 0).
    pub inertia: f64,
    /// Torsion spring [N m/rad] (> 0); its free angle is found by the
    /// mounting.
    pub stiffness: f64,
    /// Viscous damper [N m s/rad].
    pub damping: f64,
    /// Coulomb friction torque of the pivot [N m].
    pub friction: f64,
    /// Friction coefficient of the hub-load friction mu_h [-]: a pivot
    /// friction torque mu_h |F_hub| r_f besides `friction`.
    pub hub_friction: f64,
    /// Radius r_f at which the hub-load friction acts [m].
    pub friction_radius: f64,
    /// Presliding angle phi_p of the pivot friction [rad] (> 0): how far
    /// the pivot's contact deflects elastically under the friction torque
    /// before it slides.
    pub presliding_angle: f64,
    /// End stops, if the arm has them.
    pub stops: Option<ArmStops>,
    /// The spring as a catalogue gives it, a torque at a nominal arm angle
    /// (`pulley[j].arm.nominalTorque`, `.nominalAngle`); `None`: its free
    /// angle follows from the installation tension with the arm where it
    /// is drawn.
    pub nominal: Option<NominalSpring>,
}

/// A tensioner spring given as a catalogue gives it: the torque it exerts
/// at a nominal arm angle; with the rate (`TensionerArm::stiffness`) its
/// free angle follows. The mounting then finds where the arm sits
/// (`crate::model::layout::installed`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NominalSpring {
    /// Nominal arm angle from the drawn position (`pulley[j].x/y`),
    /// counterclockwise positive [rad].
    pub angle: f64,
    /// Torque of the spring at the nominal angle [N m] (> 0, a magnitude):
    /// it turns the arm so as to press the pulley into the belt.
    pub torque: f64,
}

impl NominalSpring {
    fn read(j: usize, v: &dyn Fn(Param) -> f64) -> Option<Self> {
        let (angle, torque) = (
            v(Param::PulleyArmNominalAngle(j)),
            v(Param::PulleyArmNominalTorque(j)),
        );
        // a nominal angle without a torque is kept, to be refused by
        // `TensionerArm::validate` rather than silently dropped
        (torque != 0.0 || angle != 0.0).then_some(Self { angle, torque })
    }

    /// Free angle of a spring of rate `stiffness` that exerts this torque at
    /// this angle against a belt moment `belt_moment` about the pivot: the
    /// spring torque -k (alpha - alpha_free) is -sign(M_belt) T_n at
    /// alpha_n, so alpha_free = alpha_n - sign(M_belt) T_n / k.
    pub fn free_angle(&self, stiffness: f64, belt_moment: f64) -> f64 {
        self.angle - belt_moment.signum() * self.torque / stiffness
    }
}

/// End stops of a tensioner arm as the user gives them
/// (`pulley[j].arm.minAngle`, ...).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmStops {
    /// Stop angle below the mounted position [rad] (<= 0).
    pub min_angle: f64,
    /// Stop angle above the mounted position [rad] (>= 0).
    pub max_angle: f64,
    /// Contact stiffness [N m/rad]; 0: automatic,
    /// [`AUTO_STOP_STIFFNESS_PER_SPRING`] times the arm's spring.
    pub stiffness: f64,
    /// Contact damping [N m s/rad]; 0: automatic, damping ratio
    /// [`AUTO_STOP_DAMPING_RATIO`] of the arm on the stop.
    pub damping: f64,
}

/// The model description's start values of a tensioner arm (every slot
/// starts alike).
impl Default for TensionerArm {
    fn default() -> Self {
        Self::read(0, &|p: Param| p.start())
    }
}

/// The start values of the stops (every slot starts alike).
impl Default for ArmStops {
    fn default() -> Self {
        Self::read(0, &|p: Param| p.start())
    }
}

impl ArmStops {
    fn read(j: usize, v: &dyn Fn(Param) -> f64) -> Self {
        Self {
            min_angle: v(Param::PulleyArmMinAngle(j)),
            max_angle: v(Param::PulleyArmMaxAngle(j)),
            stiffness: v(Param::PulleyArmStopStiffness(j)),
            damping: v(Param::PulleyArmStopDamping(j)),
        }
    }

    fn values(&self, j: usize) -> [(Param, f64); 4] {
        [
            (Param::PulleyArmMinAngle(j), self.min_angle),
            (Param::PulleyArmMaxAngle(j), self.max_angle),
            (Param::PulleyArmStopStiffness(j), self.stiffness),
            (Param::PulleyArmStopDamping(j), self.damping),
        ]
    }
}

impl TensionerArm {
    /// Pulley `j`'s arm from its parameter values `v` (the FMU's, or the
    /// start values); `None` unless `pulley[j].tensioner` is set.
    pub fn from_values(j: usize, v: &dyn Fn(Param) -> f64) -> Option<Self> {
        (v(Param::PulleyTensioner(j)) != 0.0).then(|| Self::read(j, v))
    }

    fn read(j: usize, v: &dyn Fn(Param) -> f64) -> Self {
        Self {
            pivot: [v(Param::PulleyArmPivotX(j)), v(Param::PulleyArmPivotY(j))],
            inertia: v(Param::PulleyArmInertia(j)),
            stiffness: v(Param::PulleyArmStiffness(j)),
            damping: v(Param::PulleyArmDamping(j)),
            friction: v(Param::PulleyArmFriction(j)),
            hub_friction: v(Param::PulleyArmHubFriction(j)),
            friction_radius: v(Param::PulleyArmFrictionRadius(j)),
            presliding_angle: v(Param::PulleyArmPreslidingAngle(j)),
            stops: (v(Param::PulleyArmStops(j)) != 0.0).then(|| ArmStops::read(j, v)),
            nominal: NominalSpring::read(j, v),
        }
    }

    /// Every Real parameter of the arm of pulley `j` with its value.
    pub fn values(&self, j: usize) -> Vec<(Param, f64)> {
        let mut v = vec![
            (Param::PulleyArmPivotX(j), self.pivot[0]),
            (Param::PulleyArmPivotY(j), self.pivot[1]),
            (Param::PulleyArmInertia(j), self.inertia),
            (Param::PulleyArmStiffness(j), self.stiffness),
            (Param::PulleyArmDamping(j), self.damping),
            (Param::PulleyArmFriction(j), self.friction),
            (Param::PulleyArmHubFriction(j), self.hub_friction),
            (Param::PulleyArmFrictionRadius(j), self.friction_radius),
            (Param::PulleyArmPreslidingAngle(j), self.presliding_angle),
        ];
        if let Some(s) = &self.stops {
            v.extend(s.values(j));
        }
        if let Some(n) = &self.nominal {
            v.push((Param::PulleyArmNominalAngle(j), n.angle));
            v.push((Param::PulleyArmNominalTorque(j), n.torque));
        }
        v
    }

    /// Checks the arm of pulley `j` mounted at `centre`: each parameter's
    /// declared range and the rules that tie them together.
    pub fn validate(&self, j: usize, centre: [f64; 2]) -> Result<(), ParamError> {
        for (p, x) in self.values(j) {
            declared(p, x)?;
        }
        let arm = (centre[0] - self.pivot[0]).hypot(centre[1] - self.pivot[1]);
        if arm < MIN_ARM_LENGTH {
            return Err(param_error(
                Param::PulleyArmPivotX(j),
                msg![
                    format!("must lie at least {MIN_ARM_LENGTH} m from the pulley centre ("),
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
        positive_when(Param::PulleyArmInertia(j), on, self.inertia)?;
        positive_when(Param::PulleyArmStiffness(j), on, self.stiffness)?;
        positive_when(
            Param::PulleyArmPreslidingAngle(j),
            on,
            self.presliding_angle,
        )?;
        if let Some(s) = &self.stops {
            // the declared ranges put the mounted arm (angle 0) between
            // its stops; the lower below the upper
            check(
                s.min_angle < s.max_angle,
                Param::PulleyArmMinAngle(j),
                msg![
                    "< ",
                    Param::PulleyArmMaxAngle(j),
                    format!(" = {}", s.max_angle)
                ],
                s.min_angle,
            )?;
        }
        // a hub-load friction coefficient without the radius it acts at
        // would do nothing: refused, not ignored
        check(
            self.hub_friction == 0.0 || self.friction_radius > 0.0,
            Param::PulleyArmFrictionRadius(j),
            msg![
                "> 0 with ",
                Param::PulleyArmHubFriction(j),
                format!(
                    " = {} (the friction torque is coefficient x hub force x radius)",
                    self.hub_friction
                ),
            ],
            self.friction_radius,
        )?;
        if let Some(n) = &self.nominal {
            // a nominal angle alone says nothing about the spring: refused,
            // not ignored
            check(
                n.torque > 0.0,
                Param::PulleyArmNominalAngle(j),
                msg![
                    "0 unless ",
                    Param::PulleyArmNominalTorque(j),
                    " > 0 gives the spring's torque at that angle (without it the spring's free \
                     angle follows from ",
                    Param::BeltPreload,
                    " with the arm where it is drawn)",
                ],
                n.angle,
            )?;
        }
        Ok(())
    }
}

/// End stops of an arm in the law (automatic stiffness and damping
/// resolved).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stops {
    /// Lower and upper stop angle [rad].
    pub min_angle: f64,
    /// Upper stop angle [rad].
    pub max_angle: f64,
    /// Contact stiffness k_s [N m/rad].
    pub stiffness: f64,
    /// Contact damping d_s [N m s/rad].
    pub damping: f64,
}

impl Stops {
    /// The stops of `s` on an arm of spring `spring` and inertia `inertia`,
    /// their automatic stiffness and damping resolved.
    pub fn new(s: &ArmStops, spring: f64, inertia: f64) -> Self {
        let stiffness = if s.stiffness > 0.0 {
            s.stiffness
        } else {
            AUTO_STOP_STIFFNESS_PER_SPRING * spring
        };
        let damping = if s.damping > 0.0 {
            s.damping
        } else {
            2.0 * AUTO_STOP_DAMPING_RATIO * (stiffness * inertia).sqrt()
        };
        Self {
            min_angle: s.min_angle,
            max_angle: s.max_angle,
            stiffness,
            damping,
        }
    }

    /// The stop the arm presses at `angle`: (direction +1 at the lower, -1
    /// at the upper stop, penetration > 0), or `None` between the stops.
    #[inline(always)]
    fn contact(&self, angle: f64) -> Option<(f64, f64)> {
        if angle < self.min_angle {
            Some((1.0, self.min_angle - angle))
        } else if angle > self.max_angle {
            Some((-1.0, angle - self.max_angle))
        } else {
            None
        }
    }

    /// Torque of the stops at `angle`, `rate` and its partials
    /// (torque, d/d angle, d/d rate).
    #[inline(always)]
    pub fn torque(&self, angle: f64, rate: f64) -> (f64, f64, f64) {
        let Some((sign, pen)) = self.contact(angle) else {
            return (0.0, 0.0, 0.0);
        };
        // penetration rate; the pushing torque and its partials with
        // respect to the penetration and its rate
        let pen_rate = -sign * rate;
        let u = pen / STOP_DAMPING_RAMP;
        let (w, dw) = (smoothstep(u), smoothstep_slope(u) / STOP_DAMPING_RAMP);
        let push = self.stiffness * pen + self.damping * w * pen_rate;
        if push <= 0.0 {
            // leaving faster than the spring relaxes: the stop never pulls
            return (0.0, 0.0, 0.0);
        }
        let d_pen = self.stiffness + self.damping * dw * pen_rate;
        let d_pen_rate = self.damping * w;
        // torque = sign push; d pen / d angle = -sign, d pen_rate / d rate
        // = -sign: sign^2 = 1
        (sign * push, -d_pen, -d_pen_rate)
    }

    /// Elastic energy of the stops at `angle` [J].
    pub fn energy(&self, angle: f64) -> f64 {
        self.contact(angle)
            .map_or(0.0, |(_, pen)| 0.5 * self.stiffness * pen * pen)
    }

    /// Power the stops dissipate at `angle`, `rate` [W] (>= 0): their torque's
    /// power less the elastic energy's rate of change.
    pub fn dissipation(&self, angle: f64, rate: f64) -> f64 {
        let Some((sign, pen)) = self.contact(angle) else {
            return 0.0;
        };
        let pen_rate = -sign * rate;
        // torque . rate = -(push) pen_rate; d E / dt = k pen pen_rate
        let push = (self.torque(angle, rate).0) * sign;
        (push - self.stiffness * pen) * pen_rate
    }
}

/// Constants of one tensioner arm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arm {
    /// Pivot [m].
    pub pivot: [f64; 2],
    /// Arm length R [m] and direction phi0 at mounting [rad].
    pub length: f64,
    /// Direction of the arm at mounting [rad].
    pub phi0: f64,
    /// Moment of inertia of arm and pulley about the pivot [kg m^2].
    pub inertia: f64,
    /// Spring [N m/rad], its free angle [rad], damper [N m s/rad], pivot
    /// Coulomb friction [N m].
    pub stiffness: f64,
    /// Free angle of the spring [rad].
    pub free_angle: f64,
    /// Viscous damper [N m s/rad].
    pub damping: f64,
    /// Coulomb friction torque of the pivot [N m].
    pub friction: f64,
    /// Hub-load friction mu_h r_f [m]: friction torque per newton of hub
    /// force.
    pub hub_friction: f64,
    /// Presliding angle phi_p of the pivot friction [rad].
    pub presliding_angle: f64,
    /// Presliding stiffness k_p of the pivot friction [N m/rad]: the
    /// friction torque under the installed hub force over phi_p
    /// ([`Self::mount_friction`]); 0 without pivot friction.
    pub presliding_stiffness: f64,
    /// Presliding damping c_p = 2 sqrt(k_p I_arm) [N m s/rad].
    pub presliding_damping: f64,
    /// End stops, if any.
    pub stops: Option<Stops>,
    /// The spring as given by its torque at a nominal angle (in the frame
    /// of the mounted arm), if it is; else its free angle follows from the
    /// belt's moment at mounting.
    pub nominal: Option<NominalSpring>,
}

/// The pivot friction's torque on the arm, the rate of its presliding
/// deflection z and their partial derivatives (module comment). The
/// deflection's rate also depends on the hub force through M_f; the stiff
/// method's Jacobian leaves that partial out of the deflection's row (a
/// W-method needs no exact Jacobian; it matters only while the arm slides,
/// where z follows M_f / k_p at the rate |alpha'| / phi_p), so that the
/// deflection is eliminated like the arm's angle.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PivotFriction {
    /// Torque on the arm, -k_p z - (1 - beta) c_p z' [N m].
    pub torque: f64,
    /// d torque / d z [N m/rad].
    pub d_deflection: f64,
    /// d torque / d alpha' [N m s/rad].
    pub d_rate: f64,
    /// d torque / d F_hub (x, y) [m].
    pub d_force: [f64; 2],
    /// z' [rad/s].
    pub deflection_rate: f64,
    /// d z' / d alpha' [-].
    pub rate_by_rate: f64,
    /// d z' / d z [1/s].
    pub rate_by_deflection: f64,
    /// Power dissipated in the contact [W] (>= 0 while |k_p z| <= M_f,
    /// where the deflection stays once there): the torque's power less the
    /// rate of the presliding energy k_p z^2 / 2, k_p z (alpha' - z') + (1 -
    /// beta) c_p z' alpha' = beta |alpha'| (k_p z)^2 / M_f + (1 - beta) c_p
    /// z' alpha'.
    pub dissipation: f64,
}

/// Torque of the arm's own elements and its partial derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmTorque {
    /// Torque on the arm [N m].
    pub torque: f64,
    /// d torque / d alpha, d torque / d alpha'.
    pub d_angle: f64,
    /// d torque / d alpha'.
    pub d_rate: f64,
}

impl Arm {
    /// Arm of length and direction from `pivot` to the mounted pulley
    /// centre `centre`.
    pub fn mounted(pivot: [f64; 2], centre: [f64; 2]) -> Self {
        let (dx, dy) = (centre[0] - pivot[0], centre[1] - pivot[1]);
        Self {
            pivot,
            length: dx.hypot(dy),
            phi0: dy.atan2(dx),
            inertia: 0.0,
            stiffness: 0.0,
            free_angle: 0.0,
            damping: 0.0,
            friction: 0.0,
            hub_friction: 0.0,
            presliding_angle: TensionerArm::default().presliding_angle,
            presliding_stiffness: 0.0,
            presliding_damping: 0.0,
            stops: None,
            nominal: None,
        }
    }

    /// The arm of `p` with the pulley mounted at `centre` (its spring's free
    /// angle is set by the mounting, `Drive::new`).
    pub fn new(p: &TensionerArm, centre: [f64; 2]) -> Self {
        let mut a = Self {
            inertia: p.inertia,
            stiffness: p.stiffness,
            damping: p.damping,
            friction: p.friction,
            hub_friction: p.hub_friction * p.friction_radius,
            presliding_angle: p.presliding_angle,
            stops: p
                .stops
                .as_ref()
                .map(|s| Stops::new(s, p.stiffness, p.inertia)),
            nominal: p.nominal,
            ..Self::mounted(p.pivot, centre)
        };
        a.mount_friction(0.0);
        a
    }

    /// Torque of the spring alone at `angle` [N m].
    pub fn spring_torque(&self, angle: f64) -> f64 {
        -self.stiffness * (angle - self.free_angle)
    }

    /// Spring, damper and end stops at `angle`, rate `rate` (the pivot
    /// friction: [`Self::pivot_friction`]).
    pub fn torque(&self, angle: f64, rate: f64) -> ArmTorque {
        let mut t = ArmTorque {
            torque: self.spring_torque(angle) - self.damping * rate,
            d_angle: -self.stiffness,
            d_rate: -self.damping,
        };
        if let Some(s) = &self.stops {
            let (torque, d_angle, d_rate) = s.torque(angle, rate);
            t.torque += torque;
            t.d_angle += d_angle;
            t.d_rate += d_rate;
        }
        t
    }

    /// Sets the pivot friction's presliding stiffness and damping for the
    /// installed hub force's magnitude `hub` [N]: k_p = M_f / phi_p, c_p =
    /// 2 sqrt(k_p I_arm).
    pub fn mount_friction(&mut self, hub: f64) {
        self.presliding_stiffness = self.friction_torque([hub, 0.0]) / self.presliding_angle;
        self.presliding_damping = 2.0 * (self.presliding_stiffness * self.inertia).sqrt();
    }

    /// The pivot friction (module comment) at presliding deflection `z`,
    /// arm rate `rate` under the hub force `hub`. Without pivot friction
    /// (M_c = mu_h = 0) the deflection stays where it is and nothing acts.
    #[inline(always)]
    pub fn pivot_friction(&self, z: f64, rate: f64, hub: [f64; 2]) -> PivotFriction {
        let f = hub[0].hypot(hub[1]);
        let (mut law, torque_by_m) = self.presliding(z, rate, self.friction_torque_at(f));
        // d torque / d F_hub = d torque / d M_f d M_f / d F_hub, d M_f / d F
        // = mu_h r_f F / |F| (none at a zero hub force)
        if f > 0.0 && torque_by_m != 0.0 {
            let s = torque_by_m * self.hub_friction / f;
            law.d_force = [s * hub[0], s * hub[1]];
        }
        law
    }

    /// The pivot friction at deflection `z` and rate `rate` under the
    /// friction torque scale `m_f` (M_c + mu_h r_f |F_hub|), without its
    /// partials in the hub force, and d torque / d M_f.
    #[inline(always)]
    fn presliding(&self, z: f64, rate: f64, m_f: f64) -> (PivotFriction, f64) {
        let (k, c) = (self.presliding_stiffness, self.presliding_damping);
        if k == 0.0 || (self.friction == 0.0 && self.hub_friction == 0.0) {
            return (PivotFriction::default(), 0.0);
        }
        // M_f floored at a millionth of its mounted value: a belt that
        // leaves the pulley (no hub force) and no constant friction would
        // otherwise make the deflection's relaxation infinitely fast
        let floor = 1e-6 * k * self.presliding_angle;
        let m = m_f.max(floor);
        let kz = k * z;
        // g = z / z_ss, z_ss = M_f / k_p the sliding deflection; beta the
        // elasto-plastic factor (0 while unloading)
        let g = kz / m;
        let (sign, abs) = (rate.signum(), rate.abs());
        let (beta, d_beta) = if rate * z > 0.0 {
            breakaway(g.abs())
        } else {
            (0.0, 0.0)
        };
        let zr = rate - abs * beta * g;
        let rate_by_rate = 1.0 - if rate == 0.0 { 0.0 } else { sign * beta * g };
        // d beta / d z = beta' sgn(z) / z_ss, d |g| / d M_f = -|g| / M_f
        let beta_by_z = d_beta * z.signum() * k / m;
        let rate_by_deflection = -abs * k / m * (beta + g.abs() * d_beta);
        // d z' / d M_f = |alpha'| g (beta + |g| beta') / M_f (none at the
        // floor)
        let (by_torque, beta_by_torque) = if m_f > floor {
            (
                abs * g * (beta + g.abs() * d_beta) / m,
                -d_beta * g.abs() / m,
            )
        } else {
            (0.0, 0.0)
        };
        // the damping acts on the elastic part of the deflection's rate:
        // (1 - beta) c_p z', none once sliding
        let e = 1.0 - beta;
        let law = PivotFriction {
            torque: -kz - c * e * zr,
            d_deflection: -k - c * (e * rate_by_deflection - beta_by_z * zr),
            d_rate: -c * e * rate_by_rate,
            d_force: [0.0; 2],
            deflection_rate: zr,
            rate_by_rate,
            rate_by_deflection,
            dissipation: kz * (rate - zr) + c * e * zr * rate,
        };
        // d torque / d M_f
        let torque_by_m = -c * (e * by_torque - beta_by_torque * zr);
        (law, torque_by_m)
    }

    /// Elastic energy of the pivot friction's presliding deflection `z`
    /// [J].
    pub fn friction_energy(&self, z: f64) -> f64 {
        0.5 * self.presliding_stiffness * z * z
    }

    /// The pivot friction's torque scale under the hub force `hub`: M_c +
    /// mu_h r_f |F_hub| [N m], the Coulomb torque once the arm slides.
    pub fn friction_torque(&self, hub: [f64; 2]) -> f64 {
        self.friction_torque_at(hub[0].hypot(hub[1]))
    }

    /// [`Self::friction_torque`] at the hub force's magnitude `f` [N].
    #[inline(always)]
    fn friction_torque_at(&self, f: f64) -> f64 {
        self.friction + self.hub_friction * f
    }

    /// Equivalent viscous damping [N m s/rad] of the pivot friction
    /// (constant and hub-load) for an arm swinging as A sin(omega t) under
    /// the friction torque scale `m_f` ([`Self::friction_torque`] of the
    /// hub force): the describing function of the law, the damper
    /// that dissipates as much per cycle, W / (pi omega A^2). The law's
    /// deflection is integrated over the swing (RK4 in the phase,
    /// [`DESCRIBING_POINTS`] steps per cycle, well inside the fastest change
    /// of z, which takes a phase of about sqrt(2 z_ss / A) after each
    /// reversal) until one cycle's work W of -k_p z - c_p z' agrees with the
    /// previous one's to 1e-12 (at most [`DESCRIBING_CYCLES`] cycles). A
    /// swing within the breakaway deflection is elastic, and only c_p
    /// dissipates: c_eq = c_p; a swing far beyond it tends to Coulomb's
    /// 4 M_f / (pi omega A). The hub force's own swing and the loop's
    /// in-phase (stiffness) part are left out.
    pub fn friction_describing(&self, m_f: f64, amplitude: f64, omega: f64) -> f64 {
        let a = amplitude.abs();
        if m_f == 0.0 || self.presliding_stiffness == 0.0 || a == 0.0 || omega <= 0.0 {
            return 0.0;
        }
        let n = DESCRIBING_POINTS;
        let h = std::f64::consts::TAU / n as f64;
        let rate = |th: f64| omega * a * th.cos();
        // d z / d theta = z' / omega; the friction's power against the
        // motion per unit phase
        let dz = |th: f64, z: f64| self.presliding(z, rate(th), m_f).0.deflection_rate / omega;
        let power =
            |th: f64, z: f64| -self.presliding(z, rate(th), m_f).0.torque * rate(th) / omega;
        let (mut z, mut last) = (0.0, f64::NAN);
        for _ in 0..DESCRIBING_CYCLES {
            let mut work = 0.0;
            for i in 0..n {
                let th = i as f64 * h;
                let k1 = dz(th, z);
                let k2 = dz(th + 0.5 * h, z + 0.5 * h * k1);
                let k3 = dz(th + 0.5 * h, z + 0.5 * h * k2);
                let k4 = dz(th + h, z + h * k3);
                let z1 = z + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
                work += 0.5 * (power(th, z) + power(th + h, z1)) * h;
                z = z1;
            }
            let settled = (work - last).abs() <= 1e-12 * work.abs();
            last = work;
            if settled {
                break;
            }
        }
        last / (std::f64::consts::PI * omega * a * a)
    }

    /// Elastic energy of the spring and the end stops [J].
    pub fn energy(&self, angle: f64) -> f64 {
        let e = angle - self.free_angle;
        let stops = self.stops.as_ref().map_or(0.0, |s| s.energy(angle));
        0.5 * self.stiffness * e * e + stops
    }

    /// Power dissipated by the damper and the end stops at `angle`, `rate`
    /// [W] (>= 0; the pivot friction's: [`PivotFriction::dissipation`]).
    pub fn dissipation(&self, angle: f64, rate: f64) -> f64 {
        let stops = self
            .stops
            .as_ref()
            .map_or(0.0, |s| s.dissipation(angle, rate));
        self.damping * rate * rate + stops
    }

    /// Pulley centre at `angle` and its derivative d c / d alpha (the
    /// centre's velocity is that times alpha').
    pub fn centre(&self, angle: f64) -> ([f64; 2], [f64; 2]) {
        let (s, c) = (self.phi0 + angle).sin_cos();
        let r = self.length;
        (
            [self.pivot[0] + r * c, self.pivot[1] + r * s],
            [-r * s, r * c],
        )
    }

    /// Moment about the pivot of a force `f` acting at the pulley centre at
    /// `angle` [N m], and its derivative with respect to the angle.
    pub fn moment(&self, angle: f64, f: [f64; 2]) -> (f64, f64) {
        let (s, c) = (self.phi0 + angle).sin_cos();
        let r = self.length;
        // (c - pivot) x f and its derivative (d/d alpha of (R cos, R sin))
        (r * (c * f[1] - s * f[0]), r * (-s * f[1] - c * f[0]))
    }

    /// Spring free angle at mounting under a belt moment `belt_moment`
    /// about the pivot with the arm at its mounted position (angle 0). A
    /// spring given by its nominal torque has its own
    /// ([`NominalSpring::free_angle`]; the mounting put the arm where that
    /// spring balances the belt, `crate::model::layout::installed`);
    /// otherwise the spring carries the moment there, -k (0 - alpha_free) +
    /// M_belt = 0.
    pub fn free_angle_for(&self, belt_moment: f64) -> f64 {
        match &self.nominal {
            Some(n) => n.free_angle(self.stiffness, belt_moment),
            None => -belt_moment / self.stiffness,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arm() -> Arm {
        let mut a = Arm::mounted([0.1, -0.05], [0.16, 0.03]);
        a.inertia = 2e-3;
        a.stiffness = 40.0;
        a.free_angle = 0.3;
        a.damping = 0.05;
        a.friction = 1.5;
        a
    }

    /// Central differences of the torque against the analytic partials.
    #[test]
    fn partials_match_finite_differences() {
        let a = arm();
        for &(x, v) in &[(0.02, 0.004), (-0.1, -0.007), (0.05, 0.3), (0.0, -2.0)] {
            let t = a.torque(x, v);
            let h = 1e-7;
            let fd_x = (a.torque(x + h, v).torque - a.torque(x - h, v).torque) / (2.0 * h);
            let hv = 1e-4;
            let fd_v = (a.torque(x, v + hv).torque - a.torque(x, v - hv).torque) / (2.0 * hv);
            // spring and damper are linear: central differences exact to
            // rounding, eps |torque| / h ~ 1e-8 in the angle (h 1e-7), 1e-10
            // in the rate (h 1e-4): 1e-6 relative to the slope.
            assert!(
                (fd_x - t.d_angle).abs() <= 1e-6 * t.d_angle.abs(),
                "{fd_x} {t:?}"
            );
            assert!(
                (fd_v - t.d_rate).abs() <= 1e-6 * t.d_rate.abs(),
                "{fd_v} {t:?}"
            );
            // moment of a force and its angle derivative
            let f = [120.0, -340.0];
            let (_, dm) = a.moment(x, f);
            let fd_m = (a.moment(x + h, f).0 - a.moment(x - h, f).0) / (2.0 * h);
            assert!((fd_m - dm).abs() <= 1e-6 * dm.abs().max(1.0), "{fd_m} {dm}");
            // the centre's derivative
            let (_, dc) = a.centre(x);
            for i in 0..2 {
                let fd_c = (a.centre(x + h).0[i] - a.centre(x - h).0[i]) / (2.0 * h);
                assert!((fd_c - dc[i]).abs() < 1e-8, "{fd_c} {dc:?}");
            }
        }
    }

    /// The spring is the gradient of its energy, the damper dissipates:
    /// power balance -dE/dt + torque * rate = -dissipation.
    #[test]
    fn energy_and_dissipation() {
        let a = arm();
        for &(x, v) in &[(0.02, 0.004), (-0.1, -0.007), (0.05, 0.3)] {
            let h = 1e-6;
            let de = (a.energy(x + h) - a.energy(x - h)) / (2.0 * h);
            // the energy is quadratic: central differences exact to rounding
            assert!((de + a.spring_torque(x)).abs() < 1e-8, "{de}");
            let p = a.torque(x, v).torque * v;
            let balance = p + de * v + a.dissipation(x, v);
            assert!(balance.abs() < 1e-9, "{balance}");
            assert!(a.dissipation(x, v) >= 0.0);
        }
    }

    /// The mounted arm starts at the given pulley centre, and the free angle
    /// found for a belt moment makes the spring balance it.
    #[test]
    fn mounting_statics() {
        let mut a = arm();
        let (c, _) = a.centre(0.0);
        assert!((c[0] - 0.16).abs() < 1e-15 && (c[1] - 0.03).abs() < 1e-15);
        let m_belt = a.moment(0.0, [300.0, 150.0]).0;
        a.free_angle = a.free_angle_for(m_belt);
        assert!((a.spring_torque(0.0) + m_belt).abs() < 1e-12);
    }

    /// The arm of `arm()` with a constant and a hub-load pivot friction,
    /// its presliding stiffness mounted under `hub`.
    fn frictional(hub: [f64; 2]) -> Arm {
        let mut a = arm();
        a.friction = 0.7;
        a.hub_friction = 0.3 * 0.02;
        a.mount_friction(hub[0].hypot(hub[1]));
        a
    }

    /// The pivot friction's partials against central differences of
    /// itself, its power balance with the presliding energy and its
    /// dissipation >= 0, Coulomb's torque once sliding, nothing without
    /// friction.
    #[test]
    fn pivot_friction_partials_and_dissipation() {
        let hub = [-310.0, 420.0];
        let a = frictional(hub);
        let m = a.friction_torque(hub);
        assert!((m - (0.7 + 0.006 * 310.0f64.hypot(420.0))).abs() < 1e-12);
        assert!((a.presliding_stiffness * a.presliding_angle - m).abs() < 1e-12);
        let zs = m / a.presliding_stiffness;
        // elastic (below the breakaway), slipping while loaded, sliding,
        // unloading
        for &(z, v) in &[
            (0.3 * zs, 0.004),
            (-0.8 * zs, -0.007),
            (0.7 * zs, 0.5),
            (0.99 * zs, 0.3),
            (0.5 * zs, -2.0),
            (-0.9 * zs, 1.5),
        ] {
            let f = a.pivot_friction(z, v, hub);
            // torque partials; in the hub force (|F| smooth at 500 N:
            // truncation ~1e-4^2 / 500 relative)
            let fd_tv = (a.pivot_friction(z, v + 1e-6 * v.abs(), hub).torque
                - a.pivot_friction(z, v - 1e-6 * v.abs(), hub).torque)
                / (2e-6 * v.abs());
            // rounding: eps |torque| / (2e-6 |v|), 1e-9 of a few N m
            let round = 1e-15 * f.torque.abs() / (2e-6 * v.abs());
            assert!(
                (fd_tv - f.d_rate).abs() <= 1e-6 * f.d_rate.abs() + 10.0 * round,
                "{fd_tv} {f:?}"
            );
            for i in 0..2 {
                let (mut hp, mut hm) = (hub, hub);
                hp[i] += 1e-4;
                hm[i] -= 1e-4;
                let fd =
                    (a.pivot_friction(z, v, hp).torque - a.pivot_friction(z, v, hm).torque) / 2e-4;
                assert!(
                    (fd - f.d_force[i]).abs() <= 1e-6 * f.d_force[i].abs() + 1e-12,
                    "{fd} {f:?}"
                );
            }
            // central differences of a function linear in z and, away
            // from v = 0, in v: exact to rounding (eps |v| / h)
            let (hz, hv) = (1e-9 * zs, 1e-6 * v.abs());
            let fd_z = (a.pivot_friction(z + hz, v, hub).deflection_rate
                - a.pivot_friction(z - hz, v, hub).deflection_rate)
                / (2.0 * hz);
            let fd_v = (a.pivot_friction(z, v + hv, hub).deflection_rate
                - a.pivot_friction(z, v - hv, hub).deflection_rate)
                / (2.0 * hv);
            assert!(
                (fd_z - f.rate_by_deflection).abs() <= 1e-6 * f.rate_by_deflection.abs(),
                "{fd_z} {f:?}"
            );
            assert!((fd_v - f.rate_by_rate).abs() <= 1e-6, "{fd_v} {f:?}");
            let fd_t = (a.pivot_friction(z + hz, v, hub).torque
                - a.pivot_friction(z - hz, v, hub).torque)
                / (2.0 * hz);
            assert!(
                (fd_t - f.d_deflection).abs() <= 1e-6 * f.d_deflection.abs(),
                "{fd_t} {f:?}"
            );
            // power: -torque . rate = dE/dt + dissipation
            let de = a.presliding_stiffness * z * f.deflection_rate;
            let balance = f.torque * v + de + f.dissipation;
            assert!(balance.abs() < 1e-12 * m * v.abs().max(1.0), "{balance}");
            assert!(f.dissipation >= 0.0);
            assert!((a.friction_energy(z) - 0.5 * a.presliding_stiffness * z * z).abs() < 1e-18);
        }
        // below the breakaway deflection, or unloading, purely elastic
        for (z, v) in [(0.49 * zs, 0.3), (-0.49 * zs, -0.3), (0.9 * zs, -0.3)] {
            assert_eq!(a.pivot_friction(z, v, hub).deflection_rate, v);
        }
        // sliding at the deflection's attractor: Coulomb's torque, no
        // deflection rate
        let f = a.pivot_friction(zs, 0.3, hub);
        assert!(
            (f.torque + m).abs() < 1e-12 && f.deflection_rate.abs() < 1e-12,
            "{f:?}"
        );
        // a pivot without friction: nothing
        let mut b = arm();
        b.friction = 0.0;
        assert_eq!(b.pivot_friction(1e-4, 0.3, hub), PivotFriction::default());
    }

    /// The describing function: a swing inside the breakaway deflection is
    /// elastic and only the presliding damping dissipates (c_eq = c_p); far
    /// beyond it, Coulomb's 4 M_f / (pi omega A); in between, against the
    /// law's loop integrated at five times the resolution (RK4, 20,000
    /// steps per cycle, the 40th cycle).
    #[test]
    fn friction_describing_is_the_laws_loop() {
        let hub = [-310.0, 420.0];
        let a = frictional(hub);
        let m = a.friction_torque(hub);
        let zs = m / a.presliding_stiffness;
        let omega = 2.0 * std::f64::consts::PI * 40.0;
        for ratio in [0.1, 0.45] {
            let d = a.friction_describing(m, ratio * zs, omega);
            assert!(
                (d / a.presliding_damping - 1.0).abs() < 1e-9,
                "A/z_ss {ratio}: {d}"
            );
        }
        for ratio in [0.7, 1.0, 3.0, 10.0] {
            let amp = ratio * zs;
            let n = 20_000;
            let h = 2.0 * std::f64::consts::PI / n as f64;
            let rate = |th: f64| omega * amp * th.cos();
            // d z / d theta = z' / omega
            let dz = |th: f64, z: f64| a.pivot_friction(z, rate(th), hub).deflection_rate / omega;
            // the friction's power against the motion, per unit phase
            let power =
                |th: f64, z: f64| -a.pivot_friction(z, rate(th), hub).torque * rate(th) / omega;
            let (mut z, mut work) = (0.0, 0.0);
            for cycle in 0..40 {
                for i in 0..n {
                    let th = i as f64 * h;
                    let k1 = dz(th, z);
                    let k2 = dz(th + h / 2.0, z + h / 2.0 * k1);
                    let k3 = dz(th + h / 2.0, z + h / 2.0 * k2);
                    let k4 = dz(th + h, z + h * k3);
                    let z1 = z + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
                    if cycle == 39 {
                        work += 0.5 * (power(th, z) + power(th + h, z1)) * h;
                    }
                    z = z1;
                }
            }
            let loop_damper = work / (std::f64::consts::PI * omega * amp * amp);
            let d = a.friction_describing(m, amp, omega);
            // the trapezoidal sum is second order in the phase step: 1e-6
            // at 4,000 steps, less at 20,000
            assert!(
                (d / loop_damper - 1.0).abs() < 1e-5,
                "A/z_ss {ratio}: {d} vs {loop_damper}"
            );
        }
        let amp = 1e3 * zs;
        let coulomb = 4.0 * m / (std::f64::consts::PI * omega * amp);
        // the loop falls short of Coulomb's by the reversals' elastic
        // travel (~z_ss / A, 0.1 %), the presliding damping adds a share
        // that falls as sqrt(z_ss / A) (~0.6 % here)
        let ratio = a.friction_describing(m, amp, omega) / coulomb;
        assert!((ratio - 1.0).abs() < 0.01, "{ratio}");
    }

    fn stopped() -> Arm {
        let mut a = arm();
        let s = ArmStops {
            min_angle: -0.05,
            max_angle: 0.08,
            stiffness: 0.0,
            damping: 0.0,
        };
        a.stops = Some(Stops::new(&s, a.stiffness, a.inertia));
        a
    }

    /// The automatic stop: 100 times the spring, damping ratio 0.5 on the
    /// arm's inertia.
    #[test]
    fn automatic_stop_stiffness_and_damping() {
        let s = stopped().stops.unwrap();
        assert_eq!(s.stiffness, 4000.0);
        assert!((s.damping - (4000.0f64 * 2e-3).sqrt()).abs() < 1e-12);
    }

    /// The stops' torque against central differences of itself, at both
    /// stops inside and beyond the damping ramp, pressing and leaving; the
    /// power balance with their energy and dissipation; none between them
    /// and never a pull.
    #[test]
    fn stops_partials_energy_and_dissipation() {
        let a = stopped();
        let s = a.stops.unwrap();
        assert_eq!(s.torque(0.0, 3.0), (0.0, 0.0, 0.0));
        for &(x, v) in &[
            (-0.0502, -0.3),
            (-0.0502, 0.05),
            (-0.06, -0.2),
            (0.0803, 0.4),
            (0.0803, -0.02),
            (0.095, 0.1),
        ] {
            let (t, d_angle, d_rate) = s.torque(x, v);
            assert!(t != 0.0, "{x} {v}: in contact");
            // pushes the arm back between the stops
            assert!(t * x < 0.0, "{x} {v}: {t}");
            let h = 1e-8;
            let fd_x = (s.torque(x + h, v).0 - s.torque(x - h, v).0) / (2.0 * h);
            let fd_v = (s.torque(x, v + h).0 - s.torque(x, v - h).0) / (2.0 * h);
            // central differences on a cubic ramp (third derivative
            // d 6 / ramp^2 v ~ 1e6 x 1e-16: truncation 1e-10) and rounding
            // eps |t| / h ~ 1e-8 x 10: 1e-6 relative to the slope (>= 4000)
            assert!(
                (fd_x - d_angle).abs() <= 1e-6 * d_angle.abs(),
                "{fd_x} {d_angle}"
            );
            assert!(
                (fd_v - d_rate).abs() <= 1e-6 * d_angle.abs(),
                "{fd_v} {d_rate}"
            );
            // power balance: torque . rate = -dE/dt - dissipation
            let de = (s.energy(x + h) - s.energy(x - h)) / (2.0 * h) * v;
            let balance = t * v + de + s.dissipation(x, v);
            assert!(
                balance.abs() <= 1e-6 * (t * v).abs().max(1e-3),
                "{x} {v}: {balance}"
            );
            assert!(s.dissipation(x, v) >= 0.0);
        }
        // leaving fast near the surface (1e-5 rad in, 100 rad/s: the damper's
        // 2.8 x 3e-4 x 100 = 0.085 N m beats the spring's 0.04 N m): no
        // pull, the elastic energy lost
        let (t, _, _) = s.torque(-0.05001, 100.0);
        assert_eq!(t, 0.0);
        assert!(s.dissipation(-0.05001, 100.0) > 0.0);
        // the whole arm law carries the stops
        let (x, v) = (0.09, 0.2);
        assert_eq!(
            a.torque(x, v).torque - arm().torque(x, v).torque,
            s.torque(x, v).0
        );
    }
}
