//! The paper's friction law, eq. 12-19 as printed: velocity-regularised
//! Coulomb friction with a creep term. Within the stick band |v_T| < dv the
//! coefficient blends the creep spring mu1 = mu_s S(z / Delta_max) into
//! +-mu_s with beta = S(|v_T| / dv) (eq. 13); beyond dv it slides, softening
//! from mu_s to mu_k over dv..1.5 dv (Fig. 6c). Stiff for small dv: the
//! viscous slope mu_s / dv sets the stable step of an explicit method.

use super::{s_curve, s_curve_slope, Law};
use crate::model::elements::contact::{smoothstep, smoothstep_slope};

/// The kubas2014 law with its constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kubas2014 {
    /// 1 / dv, dv the transition velocity [s/m].
    pub inv_dv: f64,
    /// Creep displacement of full static friction, Delta_max [m].
    pub creep_max: f64,
    /// 1 / Delta_max [1/m].
    pub inv_creep_max: f64,
}

impl Kubas2014 {
    /// The law for the transition velocity `dv` [m/s] and Delta_max =
    /// `creep_max` [m].
    pub fn new(dv: f64, creep_max: f64) -> Self {
        Self {
            inv_dv: 1.0 / dv,
            creep_max,
            inv_creep_max: 1.0 / creep_max,
        }
    }
}

impl Law for Kubas2014 {
    #[inline(always)]
    fn coefficient(&self, v_t: f64, z: f64, mu_s: f64, mu_k: f64) -> f64 {
        let w = v_t.abs() * self.inv_dv;
        // both branches evaluated and one selected: no jump, so that the
        // contact loop vectorises
        // eq. 13: mu = (1 - beta) mu1(Delta) + beta mu_s
        let beta = s_curve(w);
        let mu1 = mu_s * s_curve(z * self.inv_creep_max);
        let stick = (1.0 - beta) * mu1 + (beta * mu_s).copysign(v_t);
        // Fig. 6c: mu_s -> mu_k over dv..1.5 dv, then mu_k.
        let slide = (mu_s + (mu_k - mu_s) * smoothstep((w - 1.0) * 2.0)).copysign(v_t);
        if w < 1.0 {
            stick
        } else {
            slide
        }
    }

    // Not inlined: inlined into the Jacobian's loop over the pulleys, the
    // compiler hoisted the law's arithmetic in z out of it, so that every
    // body paid for it, in contact or not (stiff 5PK run, callgrind: +0.58 %
    // instructions against +0.14 % with a call per contact).
    #[inline(never)]
    fn coefficient_jac(&self, v_t: f64, z: f64, mu_s: f64, mu_k: f64) -> (f64, f64, f64) {
        let mu = self.coefficient(v_t, z, mu_s, mu_k);
        let w = v_t.abs() * self.inv_dv;
        if w < 1.0 {
            let beta = s_curve(w);
            let u = z * self.inv_creep_max;
            let mu1 = mu_s * s_curve(u);
            let sign = if v_t < 0.0 { -1.0 } else { 1.0 };
            let dmu_dv = s_curve_slope(w) * self.inv_dv * (mu_s - sign * mu1);
            let dmu_dz = (1.0 - beta) * mu_s * s_curve_slope(u) * self.inv_creep_max;
            (mu, dmu_dv, dmu_dz)
        } else {
            let dmu_dv = (mu_k - mu_s) * smoothstep_slope((w - 1.0) * 2.0) * 2.0 * self.inv_dv;
            (mu, dmu_dv, 0.0)
        }
    }

    /// Delta_max: mu1 is full static friction there.
    #[inline(always)]
    fn creep_cap(&self) -> f64 {
        self.creep_max
    }

    /// With u = |z| / Delta_max: mu_s Delta_max (3u^2/4 - u^4/8) for u <= 1
    /// (the integral of S in mu1), then mu_s per metre beyond it.
    #[inline(always)]
    fn spring_energy(&self, z: f64, mu_s: f64, _mu_k: f64) -> f64 {
        let u = z.abs() * self.inv_creep_max;
        let elastic = |u: f64| 0.75 * u * u - 0.125 * u * u * u * u;
        let beyond = (u - 1.0).max(0.0);
        let slide = mu_s * beyond;
        self.creep_max * (mu_s * elastic(u.min(1.0)) + slide)
    }

    /// Friction follows the sliding velocity itself (a step that jumps
    /// across the stick band |v_T| < dv lands on the sliding branch, whose
    /// linearisation has no friction slope).
    fn follows_sliding_velocity(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::assert_partials;
    use super::*;

    #[test]
    fn kubas_law_regularised_coulomb() {
        let f = Kubas2014::new(1e-5, 1e-4);
        let (ms, mk) = (1.05, 1.0);
        assert!((f.coefficient(1e-5, 0.0, ms, mk) - ms).abs() < 1e-12);
        assert!((f.coefficient(-2e-5, 0.0, ms, mk) + mk).abs() < 1e-12);
        assert_eq!(f.coefficient(0.0, 0.0, ms, mk), 0.0);
        // at v = 0 the creep term alone acts (mu1 of eq. 13)
        assert!((f.coefficient(0.0, 1e-4, ms, mk) - ms).abs() < 1e-12);
        // continuous at dv
        let a = f.coefficient(1e-5 * (1.0 - 1e-9), 0.0, ms, mk);
        let b = f.coefficient(1e-5 * (1.0 + 1e-9), 0.0, ms, mk);
        assert!((a - b).abs() < 1e-6);
    }

    /// The partials against central differences in each branch: the stick
    /// band |v_T| < dv (both signs, creep inside and beyond Delta_max, where
    /// dmu/dz vanishes), the softening band dv..1.5 dv and full sliding
    /// beyond it (dmu/dz = 0, dmu/dv = 0 at mu_k).
    #[test]
    fn partials_in_every_branch() {
        let f = Kubas2014::new(1e-3, 1e-4);
        let (ms, mk) = (1.05, 0.9);
        for &v in &[-8e-4, -2e-4, 3e-4, 9e-4] {
            for &z in &[-1.2e-4, -5e-5, 0.0, 4e-5, 9e-5] {
                assert_partials(&f, v, z, ms, mk);
            }
        }
        for &(v, expect_dv) in &[
            (1.2e-3, true),
            (-1.4e-3, true),
            (2e-3, false),
            (-0.5, false),
        ] {
            let (_, dv, dz) = f.coefficient_jac(v, 5e-5, ms, mk);
            assert_eq!(dz, 0.0);
            assert_eq!(dv != 0.0, expect_dv, "v={v}");
            assert_partials(&f, v, 5e-5, ms, mk);
        }
    }
}
