//! Transverse damping of the belt (`belt.transverseDamping`): a viscous
//! damper on each body's centre velocity across the body's own axis,
//! `F = -m gamma (v . n) n`, n the body's unit normal, m its mass and
//! gamma the damping rate [1/s]. It stands for what damps a real belt's
//! span vibration beside the rubber's hysteresis in bending (which a span
//! carries almost none of: see docs/model.md, "Span damping"): the air and
//! the belt's ends at the pulleys. A span mode of angular frequency omega
//! gets the damping ratio gamma / (2 omega), whatever the belt's mass.
//!
//! A body travelling along its own axis, on a straight span or as a chord
//! seated on a pulley (its centre moves at right angles to the pulley's
//! radius, along the chord), has v . n = 0: the law takes no power from a
//! belt running steadily, only from motion across the belt's line.

/// The damper of one body: rate gamma [1/s].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransverseDamper {
    /// Damping rate gamma [1/s] (force per mass and transverse speed).
    pub rate: f64,
}

impl TransverseDamper {
    /// Acceleration `-gamma (v . n) n` of a body with half body vector
    /// `h = (l/2)(cos phi, sin phi)` (any length: only its direction
    /// counts, through `inv_h2 = 1 / |h|^2`) and centre velocity `v`, and
    /// the power it dissipates per unit body mass, `gamma (v . n)^2`.
    #[inline(always)]
    pub fn acceleration(&self, h: [f64; 2], inv_h2: f64, v: [f64; 2]) -> ([f64; 2], f64) {
        // n |h| = (-h_y, h_x); (v . n)^2 = (v . n |h|)^2 / |h|^2
        let vn = -v[0] * h[1] + v[1] * h[0];
        let g = self.rate * vn * inv_h2;
        ([g * h[1], -g * h[0]], self.rate * vn * vn * inv_h2)
    }

    /// Partial derivatives of [`Self::acceleration`] for a body at angle
    /// `phi` (n = (-sin phi, cos phi), t = (cos phi, sin phi)): with respect
    /// to the velocity, `-gamma n n^T` (row-major `[[xx, xy], [yx, yy]]`),
    /// and to the angle, `gamma ((v . t) n + (v . n) t)` (dn/dphi = -t).
    #[inline(always)]
    pub fn partials(&self, phi: f64, v: [f64; 2]) -> ([[f64; 2]; 2], [f64; 2]) {
        let (s, c) = phi.sin_cos();
        let (n, t) = ([-s, c], [c, s]);
        let g = self.rate;
        let d_v = [
            [-g * n[0] * n[0], -g * n[0] * n[1]],
            [-g * n[1] * n[0], -g * n[1] * n[1]],
        ];
        let (vt, vn) = (v[0] * t[0] + v[1] * t[1], v[0] * n[0] + v[1] * n[1]);
        let d_phi = [g * (vt * n[0] + vn * t[0]), g * (vt * n[1] + vn * t[1])];
        (d_v, d_phi)
    }

    /// Whether the damper acts (gamma != 0; the paper's sets have none).
    #[inline(always)]
    pub fn acts(&self) -> bool {
        self.rate != 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LAW: TransverseDamper = TransverseDamper { rate: 25.0 };

    fn acc(phi: f64, v: [f64; 2]) -> [f64; 2] {
        let l2 = 0.004;
        let h = [l2 * phi.cos(), l2 * phi.sin()];
        LAW.acceleration(h, 1.0 / (l2 * l2), v).0
    }

    /// The partials against central differences, at angles all round.
    #[test]
    #[allow(clippy::needless_range_loop)] // rows and columns of the 2 x 2 partials
    fn partials_match_finite_differences() {
        for k in 0..12 {
            let phi = -3.0 + 0.55 * k as f64;
            let v = [3.0 - 0.7 * k as f64, -1.5 + 0.4 * k as f64];
            let (d_v, d_phi) = LAW.partials(phi, v);
            let e = 1e-6;
            let (ap, am) = (acc(phi + e, v), acc(phi - e, v));
            for r in 0..2 {
                let fd = (ap[r] - am[r]) / (2.0 * e);
                assert!((fd - d_phi[r]).abs() < 1e-6 * (1.0 + fd.abs()), "dphi {r}");
            }
            for c in 0..2 {
                let (mut vp, mut vm) = (v, v);
                vp[c] += e;
                vm[c] -= e;
                let (ap, am) = (acc(phi, vp), acc(phi, vm));
                for r in 0..2 {
                    let fd = (ap[r] - am[r]) / (2.0 * e);
                    assert!((fd - d_v[r][c]).abs() < 1e-7, "dv {r}{c}");
                }
            }
        }
    }

    /// Motion along the body's axis is free; motion across it is damped at
    /// the rate gamma, and the power is the force times the velocity.
    #[test]
    fn damps_only_the_motion_across_the_body() {
        let phi: f64 = 0.7;
        let (t, n) = ([phi.cos(), phi.sin()], [-phi.sin(), phi.cos()]);
        let along = acc(phi, [2.0 * t[0], 2.0 * t[1]]);
        assert!(along[0].abs() < 1e-12 && along[1].abs() < 1e-12);
        let across = acc(phi, [3.0 * n[0], 3.0 * n[1]]);
        assert!((across[0] + 75.0 * n[0]).abs() < 1e-9);
        assert!((across[1] + 75.0 * n[1]).abs() < 1e-9);
        let l2 = 0.004;
        let v = [1.0, -2.0];
        let (a, p) = LAW.acceleration([l2 * t[0], l2 * t[1]], 1.0 / (l2 * l2), v);
        assert!((p + a[0] * v[0] + a[1] * v[1]).abs() < 1e-9 && p >= 0.0);
    }
}
