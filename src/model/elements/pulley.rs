//! A pulley's drive and load, eq. 24 of section 2.1: J alpha = T_applied -
//! d_load omega + T_belt for a torque-driven pulley; a speed-driven pulley
//! follows its prescribed speed and the drive supplies the torque that
//! takes. The built-in start-up ramps of the torque and the speed are here
//! too.

use super::decoupler::Decoupler;
use super::tensioner::Arm;

/// Constant data of one pulley in the hot loop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PulleyConst {
    /// Centre x [m].
    pub cx: f64,
    /// Centre y [m].
    pub cy: f64,
    /// Radius r_p [m].
    pub radius: f64,
    /// r_p^2 [m^2].
    pub radius2: f64,
    /// Lever of the friction on the pulley [m] (r_p atan(h)/h for the
    /// chordal effect, `elements::contact::chordal_lever`): its surface
    /// speed is omega times it and a friction force f turns it by lever
    /// times f (eq. 14, 24).
    pub lever: f64,
    /// Friction levers of the contact points along a body
    /// (`elements::contact::point_levers`; the first is `lever` with one point).
    pub levers: [f64; super::contact::MAX_POINTS],
    /// Contact radii of the points along a body
    /// (`elements::contact::point_radii`; the radius with one point).
    pub radii: [f64; super::contact::MAX_POINTS],
    /// The largest distance from the axis of a body centre some point of
    /// which can touch: the largest contact radius plus l/2.
    pub reach: f64,
    /// 1 / J [1/(kg m^2)].
    pub inv_inertia: f64,
    /// Moment of inertia J [kg m^2].
    pub inertia: f64,
    /// Static friction coefficient with the belt.
    pub mu_s: f64,
    /// Kinetic friction coefficient with the belt.
    pub mu_k: f64,
    /// 1 / p_max of the contact damping ramp on this pulley (eq. 10-11,
    /// `elements::contact::auto_p_max`) [1/m].
    pub inv_p_max: f64,
    /// The speed is prescribed (else the torque).
    pub speed_driven: bool,
    /// Viscous load d_load [N m s/rad].
    pub load_damping: f64,
    /// Amplitude of the built-in torque ramp [N m].
    pub torque_ramp: f64,
    /// Amplitude of the built-in speed ramp [rad/s].
    pub omega_ramp: f64,
    /// Duration of the ramps [s].
    pub ramp_time: f64,
    /// One-way decoupler between hub and rotor, if any (the load and the
    /// applied torque then act on the rotor, `elements::decoupler`).
    pub decoupler: Option<Decoupler>,
    /// Rotor moment of inertia behind the decoupler [kg m^2] and its inverse.
    pub rotor_inertia: f64,
    /// 1 / rotor inertia [1/(kg m^2)].
    pub rotor_inv_inertia: f64,
    /// Tensioner arm the pulley sits on, if any (`cx`, `cy` is then the
    /// mounted centre; the centre moves with the arm, `elements::tensioner`).
    pub arm: Option<Arm>,
}

/// The result of eq. 24 for one pulley.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PulleyBalance {
    /// Angular acceleration [rad/s^2].
    pub alpha: f64,
    /// Torque the speed drive must supply (0 for a torque-driven pulley) [N m].
    pub drive: f64,
    /// Load torque d_load omega [N m].
    pub load: f64,
}

impl PulleyConst {
    /// A pulley that is not there (unused slots of the fixed-size arrays).
    pub const NONE: Self = Self {
        cx: 0.0,
        cy: 0.0,
        radius: 0.0,
        radius2: 0.0,
        levers: [0.0; super::contact::MAX_POINTS],
        radii: [0.0; super::contact::MAX_POINTS],
        reach: 0.0,
        lever: 0.0,
        inv_inertia: 0.0,
        inertia: 0.0,
        mu_s: 0.0,
        mu_k: 0.0,
        inv_p_max: 0.0,
        speed_driven: false,
        load_damping: 0.0,
        torque_ramp: 0.0,
        omega_ramp: 0.0,
        ramp_time: 1.0,
        decoupler: None,
        rotor_inertia: 0.0,
        rotor_inv_inertia: 0.0,
        arm: None,
    };

    /// Eq. 24 at speed `w` with the applied torque `applied`, the belt's
    /// torque `belt_torque` and, for a speed-driven pulley, the prescribed
    /// acceleration `prescribed_alpha`.
    #[inline(always)]
    pub fn balance(
        &self,
        w: f64,
        applied: f64,
        belt_torque: f64,
        prescribed_alpha: f64,
    ) -> PulleyBalance {
        let load = self.load_damping * w;
        let (alpha, drive) = if self.speed_driven {
            let drive = self.inertia * prescribed_alpha - belt_torque - applied + load;
            (prescribed_alpha, drive)
        } else {
            ((applied - load + belt_torque) * self.inv_inertia, 0.0)
        };
        PulleyBalance { alpha, drive, load }
    }

    /// Partial derivatives of a torque-driven pulley's acceleration
    /// ([`Self::balance`]): `(d alpha/d omega, d alpha/d T_belt)`; zero for a
    /// speed-driven one.
    #[inline(always)]
    pub fn balance_partials(&self) -> (f64, f64) {
        if self.speed_driven {
            (0.0, 0.0)
        } else {
            (-self.load_damping * self.inv_inertia, self.inv_inertia)
        }
    }

    /// Power the drive puts in (applied plus drive torque, times speed) and
    /// the power the load dissipates.
    #[inline(always)]
    pub fn power(&self, w: f64, applied: f64, b: &PulleyBalance) -> (f64, f64) {
        ((applied + b.drive) * w, b.load * w)
    }

    /// Built-in ramp of amplitude `amp` at time `t`: 0 before t = 0, linear
    /// up to `ramp_time`, then `amp`.
    #[inline]
    pub fn ramp(&self, amp: f64, t: f64) -> f64 {
        if amp == 0.0 || t <= 0.0 {
            0.0
        } else if t >= self.ramp_time {
            amp
        } else {
            amp * t / self.ramp_time
        }
    }

    /// Time derivative of [`Self::ramp`].
    #[inline]
    pub fn ramp_rate(&self, amp: f64, t: f64) -> f64 {
        if amp != 0.0 && t > 0.0 && t < self.ramp_time {
            amp / self.ramp_time
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pulley(speed_driven: bool) -> PulleyConst {
        PulleyConst {
            radius: 0.06,
            inertia: 2e-3,
            inv_inertia: 500.0,
            load_damping: 0.04,
            speed_driven,
            ramp_time: 0.5,
            ..PulleyConst::NONE
        }
    }

    /// The balance is linear in speed and belt torque: central differences
    /// are exact up to rounding (1e-9 relative).
    #[test]
    fn balance_partials_match_differences() {
        let p = pulley(false);
        let (dw, dt) = p.balance_partials();
        let h = 1e-3;
        let a = |w, t| p.balance(w, 3.0, t, 0.0).alpha;
        let fw = (a(100.0 + h, -2.0) - a(100.0 - h, -2.0)) / (2.0 * h);
        let ft = (a(100.0, -2.0 + h) - a(100.0, -2.0 - h)) / (2.0 * h);
        assert!((dw - fw).abs() <= 1e-9 * fw.abs() && (dt - ft).abs() <= 1e-9 * ft.abs());
        assert_eq!(pulley(true).balance_partials(), (0.0, 0.0));
    }

    /// Power balance of eq. 24: what the drive puts in is what the load
    /// dissipates plus what goes into the belt (-T_belt omega) and into the
    /// pulley's kinetic energy (J alpha omega); exact up to rounding.
    #[test]
    fn power_balance() {
        for p in [pulley(false), pulley(true)] {
            let (w, applied, belt) = (120.0, 5.0, -3.5);
            let b = p.balance(w, applied, belt, 40.0);
            let (p_in, p_load) = p.power(w, applied, &b);
            let rest = p_load - belt * w + p.inertia * b.alpha * w;
            assert!(
                (p_in - rest).abs() <= 1e-12 * p_in.abs().max(1.0),
                "{p_in} {rest}"
            );
        }
    }

    #[test]
    fn ramp_and_its_rate() {
        let p = pulley(false);
        assert_eq!(p.ramp(2.0, -1.0), 0.0);
        assert_eq!(p.ramp(2.0, 0.25), 1.0);
        assert_eq!(p.ramp(2.0, 9.0), 2.0);
        assert_eq!(p.ramp_rate(2.0, 0.25), 4.0);
        assert_eq!(p.ramp_rate(2.0, 0.75), 0.0);
    }
}
