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
//! `M_arm = -k (alpha - alpha_free) - d alpha' - M_c S(alpha' / w_c) + M_stop`
//!
//! a torsion spring of free angle alpha_free, a viscous damper and the
//! pivot's Coulomb friction M_c regularised with the friction laws' odd
//! S-curve S(u) = (3u - u^3)/2 (saturated at |u| = 1) over the rate
//! w_c = [`FRICTION_RATE`]. The friction makes the damping asymmetric: it
//! adds to the spring when the arm is pushed back (belt tension rising)
//! and subtracts from it when the arm follows the belt.
//!
//! Hub-load friction (optional): damping that grows with the hub load, as in
//! automotive tensioners whose damping bushing or friction shoe is pressed
//! by the hub force: a pivot friction torque mu_h r_f |F_hub| S(alpha' /
//! w_c) beside the constant M_c, regularised alike ([`Arm::hub_friction`]:
//! torque, partials in the rate and the hub force, dissipation).
//!
//! End stops (optional, [`Stops`]): past a stop angle by delta the arm meets
//! a stiff, damped contact, `M_stop = max(0, k_s delta + d_s w(delta /
//! delta_r) delta')` pushing it back (delta' the rate of penetration, w the
//! smoothstep of the belt contact's damping ramp, eq. 10-11, over
//! delta_r = [`STOP_DAMPING_RAMP`], so the torque is continuous when the arm
//! touches; never pulling, like the belt contact). At rest against a stop
//! the arm sits past it by the excess moment over k_s.

use super::contact::{smoothstep, smoothstep_slope};
use super::friction::{s_curve, s_curve_slope};
use crate::model::param_id::{msg, Param};
use crate::model::params::{
    check, declared, param_error, positive_when, ParamError, MIN_ARM_LENGTH,
};

/// Arm rate over which the pivot friction builds up [rad/s]: 0.57 deg/s,
/// small against the rates of an arm that flutters by tenths of a degree at
/// tens of Hz (0.1-1 rad/s), large enough to keep the friction slope
/// M_c * 1.5 / w_c within what the explicit method steps over.
pub const FRICTION_RATE: f64 = 1e-2;

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
    /// End stops, if any.
    pub stops: Option<Stops>,
    /// The spring as given by its torque at a nominal angle (in the frame
    /// of the mounted arm), if it is; else its free angle follows from the
    /// belt's moment at mounting.
    pub nominal: Option<NominalSpring>,
}

/// Hub-load friction torque on the arm and its partial derivatives.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HubFriction {
    /// Torque on the arm [N m].
    pub torque: f64,
    /// d torque / d alpha' [N m s/rad].
    pub d_rate: f64,
    /// d torque / d F_hub (x, y) [m].
    pub d_force: [f64; 2],
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
            stops: None,
            nominal: None,
        }
    }

    /// The arm of `p` with the pulley mounted at `centre` (its spring's free
    /// angle is set by the mounting, `Drive::new`).
    pub fn new(p: &TensionerArm, centre: [f64; 2]) -> Self {
        Self {
            inertia: p.inertia,
            stiffness: p.stiffness,
            damping: p.damping,
            friction: p.friction,
            hub_friction: p.hub_friction * p.friction_radius,
            stops: p
                .stops
                .as_ref()
                .map(|s| Stops::new(s, p.stiffness, p.inertia)),
            nominal: p.nominal,
            ..Self::mounted(p.pivot, centre)
        }
    }

    /// Torque of the spring alone at `angle` [N m].
    pub fn spring_torque(&self, angle: f64) -> f64 {
        -self.stiffness * (angle - self.free_angle)
    }

    /// Spring, damper, pivot friction and end stops at `angle`, rate `rate`.
    pub fn torque(&self, angle: f64, rate: f64) -> ArmTorque {
        let u = rate / FRICTION_RATE;
        let mut t = ArmTorque {
            torque: self.spring_torque(angle) - self.damping * rate - self.friction * s_curve(u),
            d_angle: -self.stiffness,
            d_rate: -self.damping - self.friction * s_curve_slope(u) / FRICTION_RATE,
        };
        if let Some(s) = &self.stops {
            let (torque, d_angle, d_rate) = s.torque(angle, rate);
            t.torque += torque;
            t.d_angle += d_angle;
            t.d_rate += d_rate;
        }
        t
    }

    /// Hub-load friction at arm rate `rate` under the belt's hub force
    /// `hub` (the force on the pulley's hub, [N]): -mu_h r_f |F_hub|
    /// S(alpha' / w_c), the pivot friction's S-curve and rate (its partial
    /// in F_hub is -mu_h r_f S F_hub / |F_hub|; none at a zero hub force,
    /// where |F| has no derivative and the torque vanishes).
    #[inline(always)]
    pub fn hub_friction(&self, rate: f64, hub: [f64; 2]) -> HubFriction {
        if self.hub_friction == 0.0 {
            return HubFriction::default();
        }
        let f = hub[0].hypot(hub[1]);
        let u = rate / FRICTION_RATE;
        let (s, ds) = (s_curve(u), s_curve_slope(u) / FRICTION_RATE);
        let m = self.hub_friction;
        let d_force = if f > 0.0 {
            [-m * s * hub[0] / f, -m * s * hub[1] / f]
        } else {
            [0.0; 2]
        };
        HubFriction {
            torque: -m * f * s,
            d_rate: -m * f * ds,
            d_force,
        }
    }

    /// Power the hub-load friction dissipates at `rate` under the hub force
    /// `hub` [W] (>= 0: the S-curve is odd).
    pub fn hub_friction_dissipation(&self, rate: f64, hub: [f64; 2]) -> f64 {
        -self.hub_friction(rate, hub).torque * rate
    }

    /// The pivot friction's torque scale under the hub force `hub`: M_c +
    /// mu_h r_f |F_hub| [N m], the Coulomb torque once the arm slides.
    pub fn friction_torque(&self, hub: [f64; 2]) -> f64 {
        self.friction + self.hub_friction * hub[0].hypot(hub[1])
    }

    /// Equivalent viscous damping [N m s/rad] of the pivot friction
    /// (constant and hub-load) for an arm rate swinging as V sin(omega t)
    /// under the hub force `hub`: the describing function of the law, its
    /// first harmonic over the amplitude, N(V) = (2 M_f / (pi V))
    /// int_0^pi S(V sin(th) / w_c) sin(th) dth with M_f =
    /// [`Self::friction_torque`] (the hub force's own swing left out:
    /// sgn(alpha') times a swing of |F_hub| at the same frequency has no
    /// first harmonic in phase with alpha' beyond second order). In closed
    /// form, a = w_c / V: for V <= w_c (inside the ramp) M_f / w_c (3/2 -
    /// 3/8 V^2 / w_c^2); beyond it, with th0 = asin(a), (4 M_f / (pi V))
    /// times cos th0 + (3 / (2a)) (th0 - sin th0 cos th0) / 2 - (1 /
    /// (2a^3)) (3 th0 / 8 - sin 2th0 / 4 + sin 4th0 / 32), which tends to
    /// the Coulomb law's 4 M_f / (pi V) as V grows. V = omega A for an
    /// angle amplitude A.
    pub fn friction_describing(&self, hub: [f64; 2], rate_amplitude: f64) -> f64 {
        let m = self.friction_torque(hub);
        let v = rate_amplitude.abs();
        if m == 0.0 {
            return 0.0;
        }
        if v <= FRICTION_RATE {
            let u = v / FRICTION_RATE;
            return m / FRICTION_RATE * (1.5 - 0.375 * u * u);
        }
        let a = FRICTION_RATE / v;
        let t0 = a.asin();
        let (s0, c0) = t0.sin_cos();
        let sin2 = 0.5 * (t0 - s0 * c0);
        let sin4 = 0.375 * t0 - 0.25 * (2.0 * t0).sin() + (4.0 * t0).sin() / 32.0;
        let half = c0 + 1.5 / a * sin2 - 0.5 / (a * a * a) * sin4;
        4.0 * m / (std::f64::consts::PI * v) * half
    }

    /// Elastic energy of the spring and the end stops [J].
    pub fn energy(&self, angle: f64) -> f64 {
        let e = angle - self.free_angle;
        let stops = self.stops.as_ref().map_or(0.0, |s| s.energy(angle));
        0.5 * self.stiffness * e * e + stops
    }

    /// Power dissipated by the damper, the pivot friction and the end stops
    /// at `angle`, `rate` [W] (>= 0).
    pub fn dissipation(&self, angle: f64, rate: f64) -> f64 {
        let stops = self
            .stops
            .as_ref()
            .map_or(0.0, |s| s.dissipation(angle, rate));
        (self.damping * rate + self.friction * s_curve(rate / FRICTION_RATE)) * rate + stops
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

    /// Central differences of the torque against the analytic partials, in
    /// the friction's ramp (|u| < 1) and beyond it.
    #[test]
    fn partials_match_finite_differences() {
        let a = arm();
        for &(x, v) in &[(0.02, 0.004), (-0.1, -0.007), (0.05, 0.3), (0.0, -2.0)] {
            let t = a.torque(x, v);
            let h = 1e-7;
            let fd_x = (a.torque(x + h, v).torque - a.torque(x - h, v).torque) / (2.0 * h);
            let hv = 1e-9;
            let fd_v = (a.torque(x, v + hv).torque - a.torque(x, v - hv).torque) / (2.0 * hv);
            // central differences: truncation ~h^2 * third derivative
            // (friction: 1.5 M_c / w_c^3 * h^2 = 4.5e-12 relative), rounding
            // ~eps * |torque| / h ~ 1e-8: 1e-6 relative to the slope.
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

    /// The spring is the gradient of its energy, damper and friction
    /// dissipate: power balance -dE/dt + torque * rate = -dissipation.
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

    /// The hub-load friction's partials against central differences of
    /// itself (in the ramp and beyond it), its dissipation >= 0 and its
    /// torque mu_h r_f |F| once sliding.
    #[test]
    fn hub_friction_partials_and_dissipation() {
        let mut a = arm();
        a.hub_friction = 0.3 * 0.02;
        let hub = [-310.0, 420.0];
        let f = 310.0f64.hypot(420.0);
        for &v in &[0.004, -0.007, 0.3, -2.0] {
            let h = a.hub_friction(v, hub);
            let hv = 1e-9;
            let fd_v = (a.hub_friction(v + hv, hub).torque - a.hub_friction(v - hv, hub).torque)
                / (2.0 * hv);
            // truncation 1.5 m |F| / w_c^3 hv^2 ~ 2e-12 relative, rounding
            // eps |torque| / hv ~ 1e-6 against slopes >= 1e-2 (0 beyond
            // the ramp): 1e-6 of the ramp's slope
            let scale = a.hub_friction * f * 1.5 / FRICTION_RATE;
            assert!((fd_v - h.d_rate).abs() <= 1e-6 * scale, "{fd_v} {h:?}");
            for i in 0..2 {
                let mut p = hub;
                let mut m = hub;
                p[i] += 1e-4;
                m[i] -= 1e-4;
                let fd = (a.hub_friction(v, p).torque - a.hub_friction(v, m).torque) / 2e-4;
                // |F| is smooth at 500 N: truncation ~1e-4^2 / 500 relative
                assert!((fd - h.d_force[i]).abs() <= 1e-8, "{fd} {h:?}");
            }
            assert!(a.hub_friction_dissipation(v, hub) >= 0.0);
        }
        // sliding: the full mu_h r_f |F| against the motion
        let h = a.hub_friction(0.3, hub);
        assert!((h.torque + 0.006 * f).abs() < 1e-12, "{h:?}");
        // none without the coefficient
        assert_eq!(arm().hub_friction(0.3, hub), HubFriction::default());
    }

    /// The describing function against the first harmonic of the law
    /// itself (midpoint rule, 20,000 points: ~1e-8), inside and beyond the
    /// ramp; it tends to 4 M_f / (pi V) and is continuous at V = w_c.
    #[test]
    fn friction_describing_is_the_laws_first_harmonic() {
        let mut a = arm();
        a.friction = 0.7;
        a.hub_friction = 0.3 * 0.02;
        let hub = [-310.0, 420.0];
        let m = a.friction_torque(hub);
        assert!((m - (0.7 + 0.006 * 310.0f64.hypot(420.0))).abs() < 1e-12);
        for v in [0.003, 0.01, 0.0101, 0.02, 0.3, 5.0] {
            let n = 20_000;
            let h = std::f64::consts::PI / n as f64;
            let first: f64 = (0..n)
                .map(|i| {
                    let th = (i as f64 + 0.5) * h;
                    // the friction alone: the torque less the spring's
                    // constant and the damper's d alpha'
                    let w = v * th.sin();
                    a.torque(0.0, 0.0).torque
                        - a.torque(0.0, w).torque
                        - a.damping * w
                        - a.hub_friction(w, hub).torque
                })
                .zip((0..n).map(|i| ((i as f64 + 0.5) * h).sin()))
                .map(|(t, s)| t * s * h)
                .sum::<f64>()
                * 2.0
                / (std::f64::consts::PI * v);
            let d = a.friction_describing(hub, v);
            assert!((d / first - 1.0).abs() < 1e-6, "V {v}: {d} vs {first}");
        }
        let coulomb = 4.0 * m / (std::f64::consts::PI * 5.0);
        assert!((a.friction_describing(hub, 5.0) / coulomb - 1.0).abs() < 1e-5);
        let below = a.friction_describing(hub, FRICTION_RATE * (1.0 - 1e-12));
        let above = a.friction_describing(hub, FRICTION_RATE * (1.0 + 1e-12));
        assert!((below / above - 1.0).abs() < 1e-9, "{below} {above}");
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
