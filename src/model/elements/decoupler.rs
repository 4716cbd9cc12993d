//! One-way decoupler (overrunning alternator decoupler) between a pulley's
//! hub and its rotor (docs/model.md, "Accessory drives").
//!
//! A torsion spring k with a parallel damper d (Kelvin-Voigt) sits in
//! series with a one-way clutch. The state is the spring's twist delta
//! (not the rotor angle: a rotor that overruns for many turns would wind
//! up an angle difference that a real clutch never stores), with
//! w = s (omega_hub - omega_rotor) the relative rate in the clutch's
//! driving sense s = +-1. The spring-damper would carry u = k delta + d w;
//! the clutch transmits only driving torque, M = g(u) >= 0, and when it
//! overruns the spring relaxes through its damper. With the damper's rate
//! delta' = (M - k delta) / d this is one law for both cases:
//!
//! * engaged (u > 0): M = u, delta' = w;
//! * overrunning (u < 0): M = 0, delta' = -k delta / d.
//!
//! The clutch is regularised over the torque band eps = [`CLUTCH_BAND`]:
//! g(u) = 0 (u <= 0), u^2 (2 eps - u) / eps^2 (0 < u < eps), u (u >= eps);
//! g is continuously differentiable and 0 <= g(u) <= max(u, 0), so the
//! dissipated power M w - k delta delta' = ((M - k delta)^2 + M (u - M)) / d
//! is never negative, and engaged beyond the band the clutch transmits the
//! spring-damper's torque exactly (delta' = w: no creep of the spring at a
//! steady load).

use crate::model::param_id::{msg, Param};
use crate::model::params::{check, declared, positive_when, ParamError};

/// Torque band over which the one-way clutch engages [N m]: a thousandth
/// of an alternator's typical 5-20 N m drag.
pub const CLUTCH_BAND: f64 = 1e-2;

/// Constants of one decoupler.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decoupler {
    /// Spring [N m/rad], damper [N m s/rad] (> 0), clutch sense s = +-1.
    pub stiffness: f64,
    /// Damper [N m s/rad] (> 0).
    pub damping: f64,
    /// Clutch sense s: +1 drives the rotor counterclockwise, -1 clockwise.
    pub sense: f64,
}

/// A decoupler as the user gives it (`pulley[j].decoupler.*`,
/// `pulley[j].rotor.inertia`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DecouplerParams {
    /// Spring [N m/rad] (> 0).
    pub stiffness: f64,
    /// Damper parallel to the spring [N m s/rad] (> 0).
    pub damping: f64,
    /// The clutch drives the rotor clockwise (negative omega) instead of
    /// counterclockwise.
    pub clockwise: bool,
    /// Moment of inertia of the rotor behind the decoupler [kg m^2] (> 0).
    pub rotor_inertia: f64,
}

/// The model description's start values (every slot starts alike).
impl Default for DecouplerParams {
    fn default() -> Self {
        Self::read(0, &|p: Param| p.start())
    }
}

impl DecouplerParams {
    /// Pulley `j`'s decoupler from its parameter values `v`; `None` unless
    /// `pulley[j].decoupler` is set.
    pub fn from_values(j: usize, v: &dyn Fn(Param) -> f64) -> Option<Self> {
        (v(Param::PulleyDecoupler(j)) != 0.0).then(|| Self::read(j, v))
    }

    fn read(j: usize, v: &dyn Fn(Param) -> f64) -> Self {
        Self {
            stiffness: v(Param::PulleyDecouplerStiffness(j)),
            damping: v(Param::PulleyDecouplerDamping(j)),
            clockwise: v(Param::PulleyDecouplerClockwise(j)) != 0.0,
            rotor_inertia: v(Param::PulleyRotorInertia(j)),
        }
    }

    /// Every Real parameter of the decoupler of pulley `j` with its value.
    pub fn values(&self, j: usize) -> [(Param, f64); 3] {
        [
            (Param::PulleyDecouplerStiffness(j), self.stiffness),
            (Param::PulleyDecouplerDamping(j), self.damping),
            (Param::PulleyRotorInertia(j), self.rotor_inertia),
        ]
    }

    /// Checks the decoupler of pulley `j`: each parameter's declared range
    /// and that spring, damper and rotor are there.
    pub fn validate(&self, j: usize) -> Result<(), ParamError> {
        for (p, x) in self.values(j) {
            declared(p, x)?;
        }
        let on = Param::PulleyDecoupler(j);
        positive_when(Param::PulleyDecouplerStiffness(j), on, self.stiffness)?;
        check(
            self.damping > 0.0,
            Param::PulleyDecouplerDamping(j),
            msg![
                "finite and > 0 when ",
                on,
                " is set (the spring relaxes through it while the clutch overruns; \
                 e.g. 0.02 N m s/rad)"
            ],
            self.damping,
        )?;
        positive_when(Param::PulleyRotorInertia(j), on, self.rotor_inertia)
    }

    /// The law's constants.
    pub fn law(&self) -> Decoupler {
        Decoupler {
            stiffness: self.stiffness,
            damping: self.damping,
            sense: if self.clockwise { -1.0 } else { 1.0 },
        }
    }
}

/// Torque and twist rate of a decoupler with their partial derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DecouplerLaw {
    /// Torque the clutch transmits in its driving sense, M >= 0 [N m]: the
    /// hub receives -s M, the rotor +s M.
    pub torque: f64,
    /// Rate of the spring's twist [rad/s].
    pub twist_rate: f64,
    /// d M / d delta, d M / d w, d delta' / d delta, d delta' / d w.
    pub torque_d_twist: f64,
    /// d M / d w.
    pub torque_d_rate: f64,
    /// d delta' / d delta.
    pub rate_d_twist: f64,
    /// d delta' / d w.
    pub rate_d_rate: f64,
}

/// Regularised one-way clutch g(u) and its slope.
fn clutch(u: f64) -> (f64, f64) {
    let e = CLUTCH_BAND;
    if u <= 0.0 {
        (0.0, 0.0)
    } else if u < e {
        (
            u * u * (2.0 * e - u) / (e * e),
            u * (4.0 * e - 3.0 * u) / (e * e),
        )
    } else {
        (u, 1.0)
    }
}

impl Decoupler {
    /// The law at twist `twist` and relative rate `w` = s (omega_hub -
    /// omega_rotor).
    pub fn law(&self, twist: f64, w: f64) -> DecouplerLaw {
        let (k, d) = (self.stiffness, self.damping);
        let u = k * twist + d * w;
        let (m, g1) = clutch(u);
        // (M - k delta) / d, written without cancellation: -k delta / d
        // while overrunning, w - (u - M) / d in the band, w beyond it
        let e = CLUTCH_BAND;
        let twist_rate = if u <= 0.0 {
            -k * twist / d
        } else if u < e {
            let r = u * (e - u) * (e - u) / (e * e);
            w - r / d
        } else {
            w
        };
        DecouplerLaw {
            torque: m,
            twist_rate,
            torque_d_twist: g1 * k,
            torque_d_rate: g1 * d,
            rate_d_twist: (g1 - 1.0) * k / d,
            rate_d_rate: g1,
        }
    }

    /// Relative rate in the clutch's driving sense.
    pub fn relative_rate(&self, omega_hub: f64, omega_rotor: f64) -> f64 {
        self.sense * (omega_hub - omega_rotor)
    }

    /// Elastic energy of the spring [J].
    pub fn energy(&self, twist: f64) -> f64 {
        0.5 * self.stiffness * twist * twist
    }

    /// Power dissipated in the damper and the slipping clutch [W] (>= 0):
    /// the power the hub gives, M w, less the spring's energy rate.
    pub fn dissipation(&self, twist: f64, w: f64) -> f64 {
        self.dissipation_after(0.0, &self.law(twist, w), twist, w)
    }

    /// `before` plus the power dissipated in the damper and the slipping
    /// clutch, `law` being [`Self::law`] at (`twist`, `w`), summed as
    /// (before + M w) - k delta delta': the right-hand side adds the rotor
    /// load's power first, and this keeps its rounding.
    #[inline(always)]
    pub fn dissipation_after(&self, before: f64, law: &DecouplerLaw, twist: f64, w: f64) -> f64 {
        before + law.torque * w - self.stiffness * twist * law.twist_rate
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dec() -> Decoupler {
        Decoupler {
            stiffness: 30.0,
            damping: 0.02,
            sense: -1.0,
        }
    }

    /// Engaged, in the clutch band and overrunning: central differences
    /// against the analytic partials.
    #[test]
    fn partials_match_finite_differences() {
        let c = dec();
        // u = 30 delta + 0.02 w: engaged (u ~ 3), in the band (u = 4e-3),
        // overrunning (u ~ -1.3)
        for &(x, w) in &[(0.1, 2.0), (1e-4, 0.05), (0.02, -95.0), (-0.01, 3.0)] {
            let l = c.law(x, w);
            let h = 1e-9;
            let dx = |f: fn(&DecouplerLaw) -> f64| {
                (f(&c.law(x + h, w)) - f(&c.law(x - h, w))) / (2.0 * h)
            };
            let dw = |f: fn(&DecouplerLaw) -> f64| {
                (f(&c.law(x, w + h)) - f(&c.law(x, w - h))) / (2.0 * h)
            };
            // the law is piecewise quadratic and no sample is within h of a
            // kink: central differences are exact but for rounding,
            // eps |value| / h ~ 2e-16 * 1.5e2 / 1e-9 = 3e-5 for twist rates
            // of ~1.5e2 rad/s; 1e-4 per unit of the partial's scale.
            let tol = |a: f64| 1e-4 * a.abs().max(1.0);
            let checks = [
                (dx(|l| l.torque), l.torque_d_twist),
                (dw(|l| l.torque), l.torque_d_rate),
                (dx(|l| l.twist_rate), l.rate_d_twist),
                (dw(|l| l.twist_rate), l.rate_d_rate),
            ];
            for (fd, an) in checks {
                assert!((fd - an).abs() <= tol(an), "({x}, {w}): fd {fd} vs {an}");
            }
        }
    }

    /// One-way: the torque is never negative; engaged it is the spring and
    /// damper's torque, overrunning the spring relaxes; the dissipated
    /// power is never negative.
    #[test]
    fn one_way_and_dissipative() {
        let c = dec();
        let l = c.law(0.1, 2.0);
        // engaged: the spring-damper's torque exactly, the spring follows w
        assert!((l.torque - (3.0 + 0.04)).abs() < 1e-12);
        assert_eq!(l.twist_rate, 2.0);
        let o = c.law(0.02, -95.0);
        assert_eq!(o.torque, 0.0);
        assert!((o.twist_rate + 30.0 * 0.02 / 0.02).abs() < 1e-12);
        for i in -50..50 {
            for j in -50..50 {
                let (x, w) = (f64::from(i) * 1e-3, f64::from(j) * 0.7);
                assert!(c.law(x, w).torque >= 0.0);
                assert!(c.dissipation(x, w) >= -1e-12, "({x}, {w})");
            }
        }
        // clutch driving in -z: a rotor at -90 rad/s runs ahead of a hub at
        // -80 rad/s, i.e. overruns (w < 0)
        assert_eq!(c.relative_rate(-80.0, -90.0), -10.0);
    }
}
