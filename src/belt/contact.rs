//! Belt-pulley penalty contact, eq. 4-11.

/// Smoothstep of eq. 10-11 on [0, 1]: 0 below, x^2 (3 - 2x) inside, 1 above.
#[inline(always)]
pub fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// Penalty law of one body (constants already multiplied by the body length).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLaw {
    /// Quadratic stiffness [N/m^2].
    pub c1: f64,
    /// Linear stiffness [N/m].
    pub c2: f64,
    /// Damping [N s/m].
    pub b: f64,
    /// 1 / p_max [1/m].
    pub inv_p_max: f64,
}

/// Derivative of [`smoothstep`].
#[inline(always)]
pub fn smoothstep_slope(x: f64) -> f64 {
    if x <= 0.0 || x >= 1.0 {
        0.0
    } else {
        6.0 * x * (1.0 - x)
    }
}

impl ContactLaw {
    /// Normal force for penetration `p` > 0 and penetration rate `p_dot`
    /// (eq. 9), never negative (the belt cannot pull on the pulley), and its
    /// elastic part.
    #[inline(always)]
    pub fn normal_force(&self, p: f64, p_dot: f64) -> (f64, f64) {
        let elastic = (self.c1 * p + self.c2) * p;
        let n = elastic + smoothstep(p * self.inv_p_max) * self.b * p_dot;
        (n.max(0.0), elastic)
    }

    /// Damping ratio of a body of `mass` bouncing on the pulley at
    /// penetration `p`: delta(p) b / (2 sqrt(k m)) with the tangent
    /// stiffness k = 2 c1 p + c2 (eq. 9-11).
    pub fn damping_ratio(&self, p: f64, mass: f64) -> f64 {
        let k = 2.0 * self.c1 * p + self.c2;
        smoothstep(p * self.inv_p_max) * self.b / (2.0 * (k * mass).sqrt())
    }

    /// [`normal_force`](Self::normal_force) with its partial derivatives
    /// `(N, dN/dp, dN/dp_dot)` (zero where the clamp at 0 is active), for the
    /// Jacobian of the implicit integrator.
    #[inline(always)]
    pub fn normal_force_jac(&self, p: f64, p_dot: f64) -> (f64, f64, f64) {
        let x = p * self.inv_p_max;
        let s = smoothstep(x);
        let n = (self.c1 * p + self.c2) * p + s * self.b * p_dot;
        if n <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        let dn_dp =
            2.0 * self.c1 * p + self.c2 + smoothstep_slope(x) * self.inv_p_max * self.b * p_dot;
        (n, dn_dp, s * self.b)
    }

    /// Elastic energy stored at penetration `p` (the integral of the elastic part).
    pub fn energy(&self, p: f64) -> f64 {
        if p <= 0.0 {
            0.0
        } else {
            p * p * (self.c1 * p / 3.0 + 0.5 * self.c2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smoothstep_ends_and_midpoint() {
        assert_eq!(smoothstep(-1.0), 0.0);
        assert_eq!(smoothstep(0.0), 0.0);
        assert_eq!(smoothstep(0.5), 0.5);
        assert_eq!(smoothstep(1.0), 1.0);
        assert_eq!(smoothstep(3.0), 1.0);
    }

    #[test]
    fn normal_force_derivatives_match_differences() {
        let law = ContactLaw {
            c1: 3.0e9,
            c2: 6.5e5,
            b: 300.0,
            inv_p_max: 1e4,
        };
        for &(p, pd) in &[(2e-5, 0.01), (5e-5, -0.02), (2e-4, 0.3), (1e-4, 0.0)] {
            let (n, dp, dpd) = law.normal_force_jac(p, pd);
            assert_eq!(n, law.normal_force(p, pd).0);
            let (e1, e2) = (1e-10, 1e-7);
            let fp = (law.normal_force(p + e1, pd).0 - law.normal_force(p - e1, pd).0) / (2.0 * e1);
            let fpd =
                (law.normal_force(p, pd + e2).0 - law.normal_force(p, pd - e2).0) / (2.0 * e2);
            assert!((dp - fp).abs() <= 1e-6 * fp.abs().max(1.0), "{dp} {fp}");
            assert!(
                (dpd - fpd).abs() <= 1e-6 * fpd.abs().max(1.0),
                "{dpd} {fpd}"
            );
        }
        // clamped: no force, no slope
        assert_eq!(law.normal_force_jac(1e-6, -100.0), (0.0, 0.0, 0.0));
    }

    #[test]
    fn normal_force_is_elastic_at_rest_and_never_pulls() {
        let law = ContactLaw {
            c1: 3.0e9,
            c2: 6.5e5,
            b: 300.0,
            inv_p_max: 1e3,
        };
        let p = 1e-4;
        let (n, e) = law.normal_force(p, 0.0);
        assert_eq!(n, e);
        assert!((e - (3.0e9 * p * p + 6.5e5 * p)).abs() < 1e-9);
        // Fast separation: damping would pull; the force is clamped at 0.
        assert_eq!(law.normal_force(p, -100.0).0, 0.0);
        // Energy is the integral of the elastic force (Simpson, exact for cubics).
        let (f0, fm, f1) = (0.0, law.normal_force(p / 2.0, 0.0).1, e);
        assert!((law.energy(p) - p / 6.0 * (f0 + 4.0 * fm + f1)).abs() < 1e-15);
    }
}
