//! The contact's rows and columns of the Jacobian: at the body centre
//! (`contact.points` = 1) and along the body, with the coupling to the
//! tensioner arms that move the pulleys.

use super::{Along, ArmJacobian, Arms, BodyArmJacobian, ImpulseColumns, Jacobian, SELF};
use crate::model::elements::contact;
use crate::model::elements::friction::Law;
use crate::model::matmul::mm;
use crate::model::params::MAX_PULLEYS;
use crate::model::state::BodyIndex;
use crate::model::system::{BeltSystem, PulleyConst};
use crate::model::trig;
use nalgebra::{Matrix2, Matrix2x3, RowVector3, Vector2, Vector3};

impl BeltSystem {
    /// The bodies' contact rows and columns with the contact at the body
    /// centre (eq. 4-19; `contact.points` = 1): forces act at the body
    /// centre, so only the translational rows and own columns. Resets every
    /// body's rows first (also for the contact along the body). Accumulates
    /// the force on each arm's hub into `hub_force`.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // indices run over several parallel arrays
    pub(super) fn contact_centre_rows(
        &self,
        (friction, y, omega_p, pulleys, centre): Along<impl Law>,
        hub_force: &mut [[f64; 2]; MAX_PULLEYS],
        jac: &mut Jacobian,
        arms: Arms,
    ) {
        let n = self.n;
        let np = self.np;
        let inv_m = self.inv_mass;
        let with_arms = self.state_layout.n_arms() > 0;
        for i in 0..n {
            let o = BodyIndex::of(i);
            let b = &mut jac.bodies[i];
            // reset what this evaluation accumulates into or may leave
            // unset. A pulley's entries are written only where the body
            // touches it (`touching`), so only the pulleys the body touched
            // at the last evaluation have entries to clear: the others stay
            // zero (from `new`), and a body touches one pulley or two of up
            // to eight (a full reset was a tenth of the Jacobian's time on
            // the accessory drives).
            b.accel_by_position = Default::default();
            b.accel_by_velocity = Default::default();
            b.accel_by_creep = Vector3::zeros();
            b.creep_rate_by_position = RowVector3::zeros();
            b.creep_rate_by_velocity = RowVector3::zeros();
            let touched = b.touching;
            b.touching = 0;
            for j in (0..np).filter(|j| touched & (1 << j) != 0) {
                b.clear_pulley(j);
                jac.impulse[i][j] = ImpulseColumns::default();
                if with_arms {
                    jac.arm_bodies[i].clear_pulley(j);
                }
            }
            let x = [y[o.x], y[o.y]];
            let z = y[o.creep];
            let mut fq = Matrix2::zeros();
            let mut fv = Matrix2::zeros();
            if self.points > 1 {
                continue; // below, for all bodies
            }
            for j in 0..np {
                let pc = &pulleys[j];
                let [cx, cy, cvx, cvy] = centre[j];
                // velocity relative to the pulley centre (a tensioner's moves)
                let v = [y[o.vx] - cvx, y[o.vy] - cvy];
                let kin = contact::kinematics(
                    [x[0] - cx, x[1] - cy],
                    v,
                    pc.radius,
                    omega_p[j] * pc.lever,
                );
                if kin.d2 >= pc.radius2 {
                    continue;
                }
                b.touching |= 1 << j;
                let zf = self.zone_factor[i];
                let normal = self
                    .contact
                    .normal_force_jac(kin.p, kin.p_dot, pc.inv_p_max);
                let cp = contact::force_partials(
                    &kin,
                    v,
                    normal,
                    friction.coefficient_jac(kin.v_t, z, pc.mu_s * zf, pc.mu_k * zf),
                    pc.lever,
                );
                let creeping = friction.creep_rate_slope(kin.v_t, z) != 0.0;
                if pc.arm.is_some() {
                    let arm_rows = (&mut jac.arm_bodies[i], &mut jac.arms[j]);
                    self.centre_contact_arm(
                        pc,
                        j,
                        &kin,
                        normal.0,
                        &cp,
                        creeping,
                        arm_rows,
                        &arms,
                        &mut hub_force[j],
                    );
                }
                fq += cp.f_x;
                fv += cp.f_v;
                let tau = kin.t;
                b.accel_by_creep[0] += tau[0] * cp.fric_z * inv_m;
                b.accel_by_creep[1] += tau[1] * cp.fric_z * inv_m;
                let free = !pc.speed_driven;
                if free {
                    b.accel_by_pulley_speed[j][0] += tau[0] * cp.fric_w * inv_m;
                    b.accel_by_pulley_speed[j][1] += tau[1] * cp.fric_w * inv_m;
                }
                // creep rate dz/dt = v_T, frozen at the cap while pushed outward
                if creeping {
                    b.creep_rate_by_position[0] += cp.vt_x[0];
                    b.creep_rate_by_position[1] += cp.vt_x[1];
                    b.creep_rate_by_velocity[0] += cp.vt_v[0];
                    b.creep_rate_by_velocity[1] += cp.vt_v[1];
                    if free {
                        b.creep_rate_by_pulley_speed[j] += pc.lever;
                    }
                }
                // impulse rows: belt torque -r f, hub force -(N n + f t)
                let r = pc.lever;
                let tv2 = Vector2::new(tau[0], tau[1]);
                jac.impulse[i][j] = ImpulseColumns {
                    torque_by_position: RowVector3::new(-r * cp.fric_x[0], -r * cp.fric_x[1], 0.0),
                    torque_by_velocity: RowVector3::new(-r * cp.fric_v[0], -r * cp.fric_v[1], 0.0),
                    torque_by_creep: -r * cp.fric_z,
                    hub_by_position: hub_row(&cp.f_x),
                    hub_by_velocity: hub_row(&cp.f_v),
                    hub_by_creep: -cp.fric_z * tv2,
                };
                if free {
                    jac.torque_by_pulley_speed[j] += -r * cp.fric_w;
                    jac.hub_by_pulley_speed[j] += -cp.fric_w * tv2;
                }
                // pulley torque -r f on the pulley's acceleration (eq. 24)
                if free {
                    let k = -pc.lever * pc.balance_partials().1;
                    b.pulley_accel_by_position[j] =
                        RowVector3::new(k * cp.fric_x[0], k * cp.fric_x[1], 0.0);
                    b.pulley_accel_by_velocity[j] =
                        RowVector3::new(k * cp.fric_v[0], k * cp.fric_v[1], 0.0);
                    b.pulley_accel_by_creep[j] = k * cp.fric_z;
                    jac.pulley_accel_by_pulley_speed[j][j] += k * cp.fric_w;
                }
            }
            for r in 0..2 {
                for c in 0..2 {
                    b.accel_by_position[SELF][(r, c)] += fq[(r, c)] * inv_m;
                    b.accel_by_velocity[SELF][(r, c)] += fv[(r, c)] * inv_m;
                }
            }
        }
    }

    /// The centre contact of a body with pulley `j` on a tensioner arm: the
    /// contact force F(x - c(alpha), v - c'(alpha) alpha') on the body and
    /// its reaction -F on the hub, whose moment c'(alpha) . (-F) drives the
    /// arm. Writes the body's arm columns and rows (`ba`) and adds to the
    /// arm's rows (`aj`) and the hub force `hub_force`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn centre_contact_arm(
        &self,
        pc: &PulleyConst,
        j: usize,
        kin: &contact::ContactKin,
        normal: f64,
        cp: &contact::ContactPartials,
        creeping: bool,
        (ba, aj): (&mut BodyArmJacobian, &mut ArmJacobian),
        arms: &Arms,
        hub_force: &mut [f64; 2],
    ) {
        let inv_m = self.inv_mass;
        // The contact force F(x - c(alpha), v - c'(alpha) alpha')
        // on the body and its reaction -F on the hub, whose
        // moment c'(alpha) . (-F) drives the arm.
        let (dc, ddc, inv) = (arms.lever[j], arms.lever_rate[j], arms.inv_arm[j]);
        let force = contact::force(kin, normal, cp.f);
        hub_force[0] -= force[0];
        hub_force[1] -= force[1];
        let f_a = -mm(&cp.f_x, &dc) - mm(&cp.f_v, &ddc);
        let f_r = -mm(&cp.f_v, &dc);
        let tau = Vector2::from(kin.t);
        ba.accel_by_arm_angle[j] = Vector3::new(f_a[0] * inv_m, f_a[1] * inv_m, 0.0);
        ba.accel_by_arm_rate[j] = Vector3::new(f_r[0] * inv_m, f_r[1] * inv_m, 0.0);
        if creeping {
            ba.creep_rate_by_arm_angle[j] =
                -(cp.vt_x.dot(&dc.transpose()) + cp.vt_v.dot(&ddc.transpose()));
            ba.creep_rate_by_arm_rate[j] = -cp.vt_v.dot(&dc.transpose());
        }
        let lq = -mm(&dc.transpose(), &cp.f_x) * inv;
        let lv = -mm(&dc.transpose(), &cp.f_v) * inv;
        ba.arm_accel_by_position[j] = RowVector3::new(lq[0], lq[1], 0.0);
        ba.arm_accel_by_velocity[j] = RowVector3::new(lv[0], lv[1], 0.0);
        ba.arm_accel_by_creep[j] = -dc.dot(&tau) * cp.fric_z * inv;
        aj.arm_accel_by_angle -= dc.dot(&f_a) * inv;
        aj.arm_accel_by_rate -= dc.dot(&f_r) * inv;
        // impulse rows: the belt torque -r f and the hub force
        // -F through the moving centre
        aj.torque_by_arm_angle +=
            pc.lever * (cp.fric_x.dot(&dc.transpose()) + cp.fric_v.dot(&ddc.transpose()));
        aj.torque_by_arm_rate += pc.lever * cp.fric_v.dot(&dc.transpose());
        aj.hub_by_arm_angle -= f_a;
        aj.hub_by_arm_rate -= f_r;
        if !pc.speed_driven {
            aj.arm_accel_by_pulley_speed -= dc.dot(&tau) * cp.fric_w * inv;
            // the pulley's torque -r_c f through the moving centre
            let k = -pc.lever * pc.balance_partials().1;
            aj.pulley_accel_by_arm_angle -=
                k * (cp.fric_x.dot(&dc.transpose()) + cp.fric_v.dot(&ddc.transpose()));
            aj.pulley_accel_by_arm_rate -= k * cp.fric_v.dot(&dc.transpose());
        }
    }

    /// The bodies' contact rows and columns with the contact along the body
    /// (`contact.points` = K > 1, [`contact::segment_of`]): forces and
    /// moments at the points, so each body's angle and spin columns and its
    /// moment row too. Accumulates the force on each arm's hub into
    /// `hub_force`.
    #[inline(always)]
    pub(super) fn contact_along_rows<const K: usize>(
        &self,
        (friction, y, omega_p, pulleys, centre): Along<impl Law>,
        hub_force: &mut [[f64; 2]; MAX_PULLEYS],
        jac: &mut Jacobian,
        arms: Arms,
    ) {
        for i in 0..self.n {
            self.contact_along_body::<K>(
                friction, i, y, omega_p, pulleys, centre, hub_force, jac, &arms,
            );
        }
    }

    /// Body i's share of [`Self::contact_along_rows`].
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn contact_along_body<const K: usize>(
        &self,
        friction: &impl Law,
        i: usize,
        y: &[f64],
        omega_p: &[f64; MAX_PULLEYS],
        pulleys: &[PulleyConst; MAX_PULLEYS],
        centre: &[[f64; 4]; MAX_PULLEYS],
        hub_force: &mut [[f64; 2]; MAX_PULLEYS],
        jac: &mut Jacobian,
        arms: &Arms,
    ) {
        let o = BodyIndex::of(i);
        let (inv_m, inv_i) = (self.inv_mass, self.inv_inertia);
        let rows = Vector3::new(inv_m, inv_m, inv_i);
        let hl = self.half_length;
        // the body's sin/cos once, and only if a pulley is within reach
        let mut sin_cos = None;
        let zf = self.zone_factor[i];
        for j in 0..self.np {
            let pc = &pulleys[j];
            let [cx, cy, cvx, cvy] = centre[j];
            let r = [y[o.x] - cx, y[o.y] - cy];
            if r[0] * r[0] + r[1] * r[1] >= pc.reach * pc.reach {
                continue;
            }
            let &mut (sn, cs) = sin_cos.get_or_insert_with(|| trig::sin_cos(y[o.angle]));
            let pulley = contact::PulleySide {
                radii: &pc.radii,
                omega: omega_p[j],
                levers: &pc.levers,
                mu_s: pc.mu_s * zf,
                mu_k: pc.mu_k * zf,
                inv_p_max: pc.inv_p_max,
            };
            let body = contact::BodySide {
                r,
                v: [y[o.vx] - cvx, y[o.vy] - cvy],
                h: [hl * cs, hl * sn],
                w: y[o.spin],
                z: y[o.creep],
            };
            let Some((sg, d)) =
                contact::segment_of::<K>(&self.contact, friction, &pulley, &body, true)
            else {
                continue;
            };
            let b = &mut jac.bodies[i];
            b.touching |= 1 << j;
            let free = !pc.speed_driven;
            // accelerations: force / m, moment / I
            let acc = |f: Vector2<f64>, m: f64| Vector3::new(f[0], f[1], m).component_mul(&rows);
            for c in 0..3 {
                let (fq, fu) = (d.force_q.column(c), d.force_u.column(c));
                let aq = acc(Vector2::new(fq[0], fq[1]), d.moment_q[c]);
                let au = acc(Vector2::new(fu[0], fu[1]), d.moment_u[c]);
                for r in 0..3 {
                    b.accel_by_position[SELF][(r, c)] += aq[r];
                    b.accel_by_velocity[SELF][(r, c)] += au[r];
                }
            }
            b.accel_by_creep += acc(d.force_z, d.moment_z);
            b.creep_rate_by_position += d.creep_q;
            b.creep_rate_by_velocity += d.creep_u;
            // impulse rows: belt torque -sum lever f, hub force -F
            jac.impulse[i][j] = ImpulseColumns {
                torque_by_position: -d.torque_q,
                torque_by_velocity: -d.torque_u,
                torque_by_creep: -d.torque_z,
                hub_by_position: -d.force_q,
                hub_by_velocity: -d.force_u,
                hub_by_creep: -d.force_z,
            };
            let k = -pc.balance_partials().1;
            if free {
                b.accel_by_pulley_speed[j] += acc(d.force_w, d.moment_w);
                b.creep_rate_by_pulley_speed[j] += d.creep_w;
                jac.torque_by_pulley_speed[j] -= d.torque_w;
                jac.hub_by_pulley_speed[j] -= d.force_w;
                // the pulley's acceleration through its belt torque (eq. 24)
                b.pulley_accel_by_position[j] = k * d.torque_q;
                b.pulley_accel_by_velocity[j] = k * d.torque_u;
                b.pulley_accel_by_creep[j] = k * d.torque_z;
                jac.pulley_accel_by_pulley_speed[j][j] += k * d.torque_w;
            }
            if pc.arm.is_some() {
                // the contact sees x - c(alpha) and v - c'(alpha) alpha':
                // its angle and rate columns from the translational ones
                let (dc, ddc, inv) = (arms.lever[j], arms.lever_rate[j], arms.inv_arm[j]);
                hub_force[j][0] -= sg.force[0];
                hub_force[j][1] -= sg.force[1];
                let tr2 = |m: &Matrix2x3<f64>, v: &Vector2<f64>| m.fixed_columns::<2>(0) * v;
                let dot2 = |m: &RowVector3<f64>, v: &Vector2<f64>| m[0] * v[0] + m[1] * v[1];
                let f_a = -tr2(&d.force_q, &dc) - tr2(&d.force_u, &ddc);
                let f_r = -tr2(&d.force_u, &dc);
                let m_a = -dot2(&d.moment_q, &dc) - dot2(&d.moment_u, &ddc);
                let m_r = -dot2(&d.moment_u, &dc);
                let ba = &mut jac.arm_bodies[i];
                ba.accel_by_arm_angle[j] = acc(f_a, m_a);
                ba.accel_by_arm_rate[j] = acc(f_r, m_r);
                ba.creep_rate_by_arm_angle[j] = -(dot2(&d.creep_q, &dc) + dot2(&d.creep_u, &ddc));
                ba.creep_rate_by_arm_rate[j] = -dot2(&d.creep_u, &dc);
                ba.arm_accel_by_position[j] = -mm(&dc.transpose(), &d.force_q) * inv;
                ba.arm_accel_by_velocity[j] = -mm(&dc.transpose(), &d.force_u) * inv;
                ba.arm_accel_by_creep[j] = -dc.dot(&d.force_z) * inv;
                let aj = &mut jac.arms[j];
                aj.arm_accel_by_angle -= dc.dot(&f_a) * inv;
                aj.arm_accel_by_rate -= dc.dot(&f_r) * inv;
                let t_a = dot2(&d.torque_q, &dc) + dot2(&d.torque_u, &ddc);
                let t_r = dot2(&d.torque_u, &dc);
                aj.torque_by_arm_angle += t_a;
                aj.torque_by_arm_rate += t_r;
                aj.hub_by_arm_angle -= f_a;
                aj.hub_by_arm_rate -= f_r;
                if free {
                    aj.arm_accel_by_pulley_speed -= dc.dot(&d.force_w) * inv;
                    aj.pulley_accel_by_arm_angle -= k * t_a;
                    aj.pulley_accel_by_arm_rate -= k * t_r;
                }
            }
        }
    }
}

/// Hub-force impulse row of a centre contact: minus the contact force's
/// partials in (x, y) (or (vx, vy)), and no body-angle column (the centre
/// contact exerts no moment on the body).
#[inline(always)]
fn hub_row(partials: &Matrix2<f64>) -> Matrix2x3<f64> {
    let mut row = Matrix2x3::zeros();
    row.fixed_view_mut::<2, 2>(0, 0).copy_from(&-partials);
    row
}
