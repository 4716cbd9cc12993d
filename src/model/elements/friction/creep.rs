//! The elastic-plastic creep law of the paper's ref. [11] (the FMU's
//! default): friction follows the creep displacement z alone. Within
//! |z| <= Delta_max a Kelvin-Voigt element, the creep spring
//! mu_s S(z / Delta_max) N plus a damper of relaxation time tau on it, so the
//! tangential modes of the bodies on a wrap decay (the paper's law gets this
//! damping from its viscous slope mu_s / dv; docs/model.md, "Friction");
//! beyond it sliding, softening from mu_s to mu_k over
//! Delta_max..1.5 Delta_max as the paper's law does over dv..1.5 dv (Fig. 6c).

use super::{s_curve, s_curve_slope, Law};
use crate::model::elements::contact::{smoothstep, smoothstep_slope};

/// Creep displacement at which the creep law slides at mu_k (1.5 Delta_max:
/// the static-to-kinetic transition spans Delta_max..1.5 Delta_max, as the
/// paper's spans dv..1.5 dv).
const SLIDE_AT: f64 = 1.5;

/// The creep law with its constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Creep {
    /// Creep displacement of full static friction, Delta_max [m].
    pub creep_max: f64,
    /// 1 / Delta_max [1/m].
    pub inv_creep_max: f64,
    /// Relaxation time of the creep spring over Delta_max, tau / Delta_max [s/m].
    pub damping_per_creep: f64,
}

impl Creep {
    /// The law for Delta_max = `creep_max` [m] and the spring's relaxation
    /// time tau = `damping_time` [s].
    pub fn new(creep_max: f64, damping_time: f64) -> Self {
        Self {
            creep_max,
            inv_creep_max: 1.0 / creep_max,
            damping_per_creep: damping_time / creep_max,
        }
    }
}

impl Law for Creep {
    /// In the elastic range |z| <= Delta_max the creep rate is v_T, and the
    /// damper adds mu_s S'(u) tau du/dt, u = z / Delta_max; the sum stays
    /// within the static bound mu_s (Coulomb). Beyond it the sliding
    /// coefficient, independent of the velocity.
    #[inline(always)]
    fn coefficient(&self, v_t: f64, z: f64, mu_s: f64, mu_k: f64) -> f64 {
        let u = z * self.inv_creep_max;
        let a = u.abs();
        // both branches evaluated and one selected: no jump, so that the
        // contact loop vectorises
        // elastic: the creep spring and its damper, within the static
        // bound +-mu_s (a clamp by comparisons, like f64::clamp without
        // its assertion, so that it vectorises)
        let damper = 1.5 * (1.0 - u * u) * self.damping_per_creep * v_t;
        let spring_damper = mu_s * (s_curve(u) + damper);
        let elastic = if spring_damper > mu_s {
            mu_s
        } else if spring_damper < -mu_s {
            -mu_s
        } else {
            spring_damper
        };
        let sliding = (mu_s + (mu_k - mu_s) * smoothstep((a - 1.0) * 2.0)).copysign(u);
        if a <= 1.0 {
            elastic
        } else {
            sliding
        }
    }

    // Not inlined: inlined into the Jacobian's loop over the pulleys, the
    // compiler hoisted the law's arithmetic in z out of it, so that every
    // body paid for it, in contact or not (stiff 5PK run, callgrind: +0.58 %
    // instructions against +0.14 % with a call per contact).
    #[inline(never)]
    fn coefficient_jac(&self, v_t: f64, z: f64, mu_s: f64, mu_k: f64) -> (f64, f64, f64) {
        let mu = self.coefficient(v_t, z, mu_s, mu_k);
        let u = z * self.inv_creep_max;
        let a = u.abs();
        if a <= 1.0 {
            if mu.abs() >= mu_s {
                // clamped at the static bound
                return (mu, 0.0, 0.0);
            }
            let c = self.damping_per_creep;
            let dmu_dv = mu_s * s_curve_slope(u) * c;
            // d/du of S(u) + S'(u) c v_t, S''(u) = -3 u
            let dmu_dz = mu_s * (s_curve_slope(u) - 3.0 * u * c * v_t) * self.inv_creep_max;
            (mu, dmu_dv, dmu_dz)
        } else {
            let dmu_dz =
                (mu_k - mu_s) * smoothstep_slope((a - 1.0) * 2.0) * 2.0 * self.inv_creep_max;
            (mu, 0.0, dmu_dz)
        }
    }

    /// 1.5 Delta_max: the creep holds where sliding at mu_k is reached.
    #[inline(always)]
    fn creep_cap(&self) -> f64 {
        SLIDE_AT * self.creep_max
    }

    /// With u = |z| / Delta_max: mu_s Delta_max (3u^2/4 - u^4/8) for u <= 1
    /// (the integral of S), and beyond it the integral of the softening
    /// mu_s + (mu_k - mu_s) smoothstep(2 (u - 1)).
    #[inline(always)]
    fn spring_energy(&self, z: f64, mu_s: f64, mu_k: f64) -> f64 {
        let u = z.abs() * self.inv_creep_max;
        let elastic = |u: f64| 0.75 * u * u - 0.125 * u * u * u * u;
        let beyond = (u - 1.0).max(0.0);
        // the smoothstep's integral over [0, x] is x^3 - x^4/2 (x <= 1),
        // then 1/2 + (x - 1)
        let x = 2.0 * beyond;
        let w = x.min(1.0);
        let ramp = w * w * w - 0.5 * w * w * w * w + (x - 1.0).max(0.0);
        let slide = mu_s * beyond + 0.5 * (mu_k - mu_s) * ramp;
        self.creep_max * (mu_s * elastic(u.min(1.0)) + slide)
    }

    /// Friction follows the creep displacement z: the body velocities carry
    /// the damped artificial modes and the creep velocities that set the slip.
    fn follows_sliding_velocity(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::assert_partials;
    use super::*;

    #[test]
    fn creep_law_elastic_then_kinetic() {
        let f = Creep::new(1e-4, 0.0);
        let (ms, mk) = (1.05, 1.0);
        assert_eq!(f.coefficient(0.3, 0.0, ms, mk), 0.0);
        assert!((f.coefficient(0.3, 1e-4, ms, mk) - ms).abs() < 1e-12);
        assert!((f.coefficient(0.3, -1.5e-4, ms, mk) + mk).abs() < 1e-12);
        assert!((f.coefficient(0.3, 1e-3, ms, mk) - mk).abs() < 1e-12);
        // independent of velocity
        assert_eq!(
            f.coefficient(1e-9, 5e-5, ms, mk),
            f.coefficient(10.0, 5e-5, ms, mk)
        );
        // creep holds at its cap while pushed outward, unloads freely
        let cap = f.creep_cap();
        assert_eq!(f.creep_rate(0.1, cap), 0.0);
        assert_eq!(f.creep_rate(-0.1, cap), -0.1);
        assert_eq!(f.creep_rate(0.1, 1e-4), 0.1);
    }

    /// The partials against central differences in each branch of the law:
    /// the spring with its damper (both signs of z and v_T), the damper's
    /// clamp at +-mu_s (partials 0), the softening band Delta_max..1.5
    /// Delta_max and beyond it (mu_k). The damper's slope mu_s S'(u) tau /
    /// Delta_max is ~1e3 per m/s here, so the tolerance is relative to the
    /// partial (steps 1e-9 m/s and 1e-10 m: truncation ~1e-10 relative).
    #[test]
    fn partials_in_every_branch() {
        let f = Creep::new(1e-4, 3e-4);
        let (ms, mk) = (1.05, 0.9);
        // elastic: spring + damper below the clamp
        for &(v, z) in &[(1e-3, 2e-5), (-4e-4, -6e-5), (2e-4, 9e-5), (-1e-3, 0.0)] {
            let (mu, _, dz) = f.coefficient_jac(v, z, ms, mk);
            assert!(mu.abs() < ms && dz != 0.0, "v={v} z={z}: elastic");
            assert_partials(&f, v, z, ms, mk);
        }
        // damper clamped at the static bound: no slope
        let (mu, dv, dz) = f.coefficient_jac(1.0, 5e-5, ms, mk);
        assert_eq!((mu, dv, dz), (ms, 0.0, 0.0));
        assert_partials(&f, 1.0, 5e-5, ms, mk);
        // softening band and beyond (velocity-independent)
        for &z in &[1.1e-4, -1.3e-4, 1.45e-4, 1.6e-4, -2e-4] {
            let (_, dv, _) = f.coefficient_jac(0.3, z, ms, mk);
            assert_eq!(dv, 0.0);
            assert_partials(&f, 0.3, z, ms, mk);
        }
    }
}
