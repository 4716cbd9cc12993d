//! The pulleys' rows of the Jacobian: load damping, the decouplers'
//! twist and rotor, the tensioner arms' own terms.

use super::{DecouplerJacobian, Jacobian};
use crate::model::params::MAX_PULLEYS;
use crate::model::system::{BeltSystem, PulleyConst};
use nalgebra::Vector2;

impl BeltSystem {
    /// The pulleys' load damping and the decouplers' rows.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // indices run over several parallel arrays
    pub(super) fn pulley_rows(
        &self,
        pulleys: &[PulleyConst; MAX_PULLEYS],
        y: &[f64],
        omega_p: &[f64; MAX_PULLEYS],
        jac: &mut Jacobian,
    ) {
        let np = self.np;
        // Pulley load damping (eq. 24, Fig. 13), on the hub or, through a
        // decoupler, on its rotor; the decoupler's terms.
        for j in 0..np {
            let pc = &pulleys[j];
            let Some(dc) = &pc.decoupler else {
                if !pc.speed_driven {
                    jac.pulley_accel_by_pulley_speed[j][j] += pc.balance_partials().0;
                }
                continue;
            };
            let d = self.state_layout.decoupler(j);
            let (twist, w_r) = (y[d.twist], y[d.rotor_speed]);
            let law = dc.law(twist, dc.relative_rate(omega_p[j], w_r));
            let s = dc.sense;
            // w = s (omega_h - omega_r): dw/d omega_h = s, dw/d omega_r = -s;
            // the hub's torque is -s M, the rotor's +s M
            let free = if pc.speed_driven { 0.0 } else { 1.0 };
            let inv_r = pc.rotor_inv_inertia;
            jac.decouplers[j] = DecouplerJacobian {
                twist_rate_by_twist: law.rate_d_twist,
                twist_rate_by_hub_speed: free * law.rate_d_rate * s,
                twist_rate_by_rotor_speed: -law.rate_d_rate * s,
                rotor_accel_by_twist: s * law.torque_d_twist * inv_r,
                rotor_accel_by_hub_speed: free * law.torque_d_rate * inv_r,
                rotor_accel_by_rotor_speed: (-law.torque_d_rate - pc.load_damping) * inv_r,
                hub_accel_by_twist: free * -s * law.torque_d_twist * pc.inv_inertia,
                hub_accel_by_rotor_speed: free * law.torque_d_rate * pc.inv_inertia,
                drive_torque_by_twist: (1.0 - free) * s * law.torque_d_twist,
                drive_torque_by_rotor_speed: (1.0 - free) * -law.torque_d_rate,
            };
            if !pc.speed_driven {
                jac.pulley_accel_by_pulley_speed[j][j] -= law.torque_d_rate * pc.inv_inertia;
            }
        }
    }

    /// The tensioner arms' own rows, with the force on each arm's hub
    /// `hub_force` (from the contacts) and 1 / I_arm `inv_arm`.
    #[inline(always)]
    pub(super) fn arm_rows(
        &self,
        y: &[f64],
        hub_force: &[[f64; 2]; MAX_PULLEYS],
        inv_arm: &[f64; MAX_PULLEYS],
        jac: &mut Jacobian,
    ) {
        let np = self.np;
        // Tensioner arms: spring, damper, the pivot friction's presliding
        // deflection and the lever of the hub force (its angle derivative at
        // a given force); the deflection's own row (its hub-force partial
        // left out: `elements::tensioner::PivotFriction`)
        for j in 0..np {
            let pc = &self.pulleys[j];
            let Some(arm) = &pc.arm else { continue };
            let o = self.state_layout.arm(j);
            let (a, w) = (y[o.angle], y[o.rate]);
            let own = arm.torque(a, w);
            let f = arm.pivot_friction(y[o.deflection], w, hub_force[j]);
            let inv = inv_arm[j];
            // the friction's damping term through the hub force F_hub, and
            // so through every state F_hub depends on: the arm's angle and
            // rate, the pulley's speed and the bodies on the pulley (the
            // hub-force impulse's rows)
            let df = Vector2::new(f.d_force[0], f.d_force[1]) * inv;
            let aj = &mut jac.arms[j];
            aj.arm_accel_by_angle +=
                (own.d_angle + arm.moment(a, hub_force[j]).1) * inv + df.dot(&aj.hub_by_arm_angle);
            aj.arm_accel_by_rate += (own.d_rate + f.d_rate) * inv + df.dot(&aj.hub_by_arm_rate);
            aj.arm_accel_by_deflection = f.d_deflection * inv;
            if inv != 0.0 {
                aj.deflection_rate_by_rate = f.rate_by_rate;
                aj.deflection_rate_by_deflection = f.rate_by_deflection;
            }
            if df != Vector2::zeros() {
                aj.arm_accel_by_pulley_speed += df.dot(&jac.hub_by_pulley_speed[j]);
                let bit = 1u8 << j;
                for ((b, imp), ab) in jac
                    .bodies
                    .iter()
                    .zip(&jac.impulse)
                    .zip(jac.arm_bodies.iter_mut())
                {
                    if b.touching & bit == 0 {
                        continue;
                    }
                    let c = &imp[j];
                    ab.arm_accel_by_position[j] += df.transpose() * c.hub_by_position;
                    ab.arm_accel_by_velocity[j] += df.transpose() * c.hub_by_velocity;
                    ab.arm_accel_by_creep[j] += df.dot(&c.hub_by_creep);
                }
            }
        }
    }
}
