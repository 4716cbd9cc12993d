//! Automatic tensioner: a pulley whose centre sits on an arm pivoting about
//! a fixed point (docs/model.md, "Automatic tensioner arm").
//!
//! The arm angle alpha is measured from the mounted position, positive
//! counterclockwise. The pulley centre is
//! `c(alpha) = pivot + R (cos(phi0 + alpha), sin(phi0 + alpha))`, R and phi0
//! the arm length and direction at mounting. Besides the moment of the
//! belt's hub force about the pivot, the arm carries
//!
//! `M_arm = -k (alpha - alpha_free) - d alpha' - M_c S(alpha' / w_c)`
//!
//! a torsion spring of free angle alpha_free, a viscous damper and the
//! pivot's Coulomb friction M_c regularised with the friction laws' odd
//! S-curve S(u) = (3u - u^3)/2 (saturated at |u| = 1) over the rate
//! w_c = [`FRICTION_RATE`]. The friction makes the damping asymmetric: it
//! adds to the spring when the arm is pushed back (belt tension rising)
//! and subtracts from it when the arm follows the belt.

use super::friction::{s_curve, s_curve_slope};

/// Arm rate over which the pivot friction builds up [rad/s]: 0.57 deg/s,
/// small against the rates of an arm that flutters by tenths of a degree at
/// tens of Hz (0.1-1 rad/s), large enough to keep the friction slope
/// M_c * 1.5 / w_c within what the explicit method steps over.
pub const FRICTION_RATE: f64 = 1e-2;

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
        }
    }

    /// Torque of the spring alone at `angle` [N m].
    pub fn spring_torque(&self, angle: f64) -> f64 {
        -self.stiffness * (angle - self.free_angle)
    }

    /// Spring, damper and pivot friction at `angle`, rate `rate`.
    pub fn torque(&self, angle: f64, rate: f64) -> ArmTorque {
        let u = rate / FRICTION_RATE;
        ArmTorque {
            torque: self.spring_torque(angle) - self.damping * rate - self.friction * s_curve(u),
            d_angle: -self.stiffness,
            d_rate: -self.damping - self.friction * s_curve_slope(u) / FRICTION_RATE,
        }
    }

    /// Elastic energy of the spring [J].
    pub fn energy(&self, angle: f64) -> f64 {
        let e = angle - self.free_angle;
        0.5 * self.stiffness * e * e
    }

    /// Power dissipated by the damper and the pivot friction [W] (>= 0).
    pub fn dissipation(&self, rate: f64) -> f64 {
        (self.damping * rate + self.friction * s_curve(rate / FRICTION_RATE)) * rate
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

    /// Spring free angle that balances a belt moment `belt_moment` about
    /// the pivot with the arm at its mounted position (angle 0): the spring
    /// then carries the moment, -k (0 - alpha_free) + M_belt = 0.
    pub fn free_angle_for(&self, belt_moment: f64) -> f64 {
        -belt_moment / self.stiffness
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
            let balance = p + de * v + a.dissipation(v);
            assert!(balance.abs() < 1e-9, "{balance}");
            assert!(a.dissipation(v) >= 0.0);
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
}
