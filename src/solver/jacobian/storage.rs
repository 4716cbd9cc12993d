//! The Jacobian's storage: construction, the impulse rows applied to a
//! vector, saving and restoring, the dense matrix of the tests.

use super::{
    ArmJacobian, BodyArmJacobian, BodyJacobian, DecouplerJacobian, ImpulseColumns, Jacobian, NEXT,
    PREV, SELF,
};
use crate::model::matmul::mm;
use crate::model::params::MAX_PULLEYS;
use crate::model::state::BodyIndex;
use crate::model::system::BeltSystem;
use nalgebra::{Vector2, Vector3};

impl Jacobian {
    /// Zero Jacobian shaped for `sys`.
    pub fn new(sys: &BeltSystem) -> Self {
        let mut free = [false; MAX_PULLEYS];
        for (j, f) in free.iter_mut().enumerate().take(sys.np) {
            *f = !sys.pulleys[j].speed_driven;
        }
        Self {
            bodies: vec![BodyJacobian::default(); sys.n],
            impulse: vec![[ImpulseColumns::default(); MAX_PULLEYS]; sys.n],
            pulley_accel_by_pulley_speed: [[0.0; MAX_PULLEYS]; MAX_PULLEYS],
            free,
            decouplers: [DecouplerJacobian::default(); MAX_PULLEYS],
            torque_by_pulley_speed: [0.0; MAX_PULLEYS],
            hub_by_pulley_speed: [Vector2::zeros(); MAX_PULLEYS],
            power_speed: [0.0; MAX_PULLEYS],
            power_applied: [0.0; MAX_PULLEYS],
            arms: [ArmJacobian::default(); MAX_PULLEYS],
            arm_bodies: if sys.state_layout.n_arms() > 0 {
                vec![BodyArmJacobian::default(); sys.n]
            } else {
                Vec::new()
            },
            slots: sys.np,
        }
    }

    /// Visits every stored number of the drive's pulleys (for saving and
    /// restoring a Jacobian that is kept across steps, so a restored run
    /// continues bit-identically); the unused slots are zero.
    fn visit(&mut self, f: &mut impl FnMut(&mut f64)) {
        let np = self.slots;
        for (b, im) in self.bodies.iter_mut().zip(&mut self.impulse) {
            let im = &mut im[..np];
            for m in b
                .accel_by_position
                .iter_mut()
                .chain(b.accel_by_velocity.iter_mut())
            {
                m.iter_mut().for_each(&mut *f);
            }
            b.accel_by_creep.iter_mut().for_each(&mut *f);
            for v in &mut b.accel_by_pulley_speed[..np] {
                v.iter_mut().for_each(&mut *f);
            }
            b.creep_rate_by_position
                .iter_mut()
                .chain(b.creep_rate_by_velocity.iter_mut())
                .for_each(&mut *f);
            b.creep_rate_by_pulley_speed[..np]
                .iter_mut()
                .chain(&mut b.pulley_accel_by_creep[..np])
                .for_each(&mut *f);
            for v in b.pulley_accel_by_position[..np]
                .iter_mut()
                .chain(&mut b.pulley_accel_by_velocity[..np])
            {
                v.iter_mut().for_each(&mut *f);
            }
            // field by field over the pulleys (the saved order)
            for c in im.iter_mut() {
                c.torque_by_position.iter_mut().for_each(&mut *f);
            }
            for c in im.iter_mut() {
                c.torque_by_velocity.iter_mut().for_each(&mut *f);
            }
            for c in im.iter_mut() {
                f(&mut c.torque_by_creep);
            }
            for c in im.iter_mut() {
                c.hub_by_position.iter_mut().for_each(&mut *f);
            }
            for c in im.iter_mut() {
                c.hub_by_velocity.iter_mut().for_each(&mut *f);
            }
            for c in im.iter_mut() {
                c.hub_by_creep.iter_mut().for_each(&mut *f);
            }
            let mut touching = f64::from(b.touching);
            f(&mut touching);
            b.touching = touching as u8;
        }
        for row in &mut self.pulley_accel_by_pulley_speed[..np] {
            row[..np].iter_mut().for_each(&mut *f);
        }
        for d in &mut self.decouplers[..np] {
            for v in [
                &mut d.twist_rate_by_twist,
                &mut d.twist_rate_by_hub_speed,
                &mut d.twist_rate_by_rotor_speed,
                &mut d.rotor_accel_by_twist,
                &mut d.rotor_accel_by_hub_speed,
                &mut d.rotor_accel_by_rotor_speed,
                &mut d.hub_accel_by_twist,
                &mut d.hub_accel_by_rotor_speed,
                &mut d.drive_torque_by_twist,
                &mut d.drive_torque_by_rotor_speed,
            ] {
                f(v);
            }
        }
        self.torque_by_pulley_speed[..np]
            .iter_mut()
            .for_each(&mut *f);
        self.power_speed[..np]
            .iter_mut()
            .chain(&mut self.power_applied[..np])
            .for_each(&mut *f);
        for v in &mut self.hub_by_pulley_speed[..np] {
            v.iter_mut().for_each(&mut *f);
        }
        for a in &mut self.arms[..np] {
            for v in [
                &mut a.arm_accel_by_angle,
                &mut a.arm_accel_by_rate,
                &mut a.arm_accel_by_pulley_speed,
                &mut a.pulley_accel_by_arm_angle,
                &mut a.pulley_accel_by_arm_rate,
                &mut a.torque_by_arm_angle,
                &mut a.torque_by_arm_rate,
                &mut a.arm_accel_by_deflection,
                &mut a.deflection_rate_by_rate,
                &mut a.deflection_rate_by_deflection,
            ] {
                f(v);
            }
            a.hub_by_arm_angle
                .iter_mut()
                .chain(a.hub_by_arm_rate.iter_mut())
                .for_each(&mut *f);
        }
        for b in &mut self.arm_bodies {
            for v in b.accel_by_arm_angle[..np]
                .iter_mut()
                .chain(&mut b.accel_by_arm_rate[..np])
            {
                v.iter_mut().for_each(&mut *f);
            }
            for v in b.arm_accel_by_position[..np]
                .iter_mut()
                .chain(&mut b.arm_accel_by_velocity[..np])
            {
                v.iter_mut().for_each(&mut *f);
            }
            b.creep_rate_by_arm_angle[..np]
                .iter_mut()
                .chain(&mut b.creep_rate_by_arm_rate[..np])
                .chain(&mut b.arm_accel_by_creep[..np])
                .for_each(&mut *f);
        }
    }

    /// The impulse rows applied to `x` (a full state vector): the rates of
    /// belt torque, drive torque and hub force x, y of each pulley that the
    /// linearisation gives for the state change `x` (`[pulley][4]`), and the
    /// rate of the input power (the `energy.input` row). Inlined into the
    /// stage solve (built for its instruction set).
    #[inline(always)]
    pub fn impulse_rows(&self, sys: &BeltSystem, x: &[f64]) -> ([[f64; 4]; MAX_PULLEYS], f64) {
        let np = sys.np;
        let mut torque = [0.0; MAX_PULLEYS];
        let mut hub = [Vector2::zeros(); MAX_PULLEYS];
        for (i, (b, im)) in self.bodies.iter().zip(&self.impulse).enumerate() {
            if b.touching == 0 {
                continue;
            }
            let o = BodyIndex::of(i);
            let (dq, dv, dz) = (
                Vector3::new(x[o.x], x[o.y], x[o.angle]),
                Vector3::new(x[o.vx], x[o.vy], x[o.spin]),
                x[o.creep],
            );
            for j in 0..np {
                if b.touching & (1 << j) != 0 {
                    let c = &im[j];
                    torque[j] += c.torque_by_position.dot(&dq.transpose())
                        + c.torque_by_velocity.dot(&dv.transpose())
                        + c.torque_by_creep * dz;
                    hub[j] += mm(&c.hub_by_position, &dq)
                        + mm(&c.hub_by_velocity, &dv)
                        + c.hub_by_creep * dz;
                }
            }
        }
        let mut out = [[0.0; 4]; MAX_PULLEYS];
        let mut power = 0.0;
        let states = &sys.state_layout;
        for j in 0..np {
            let pc = &sys.pulleys[j];
            // input power: (applied + drive) omega, applied omega_rotor
            // behind a decoupler
            if pc.decoupler.is_some() {
                power += self.power_applied[j] * x[states.decoupler(j).rotor_speed];
            } else if self.free[j] {
                power += self.power_applied[j] * x[states.pulley(j).speed];
            }
            if self.free[j] {
                let dw = x[states.pulley(j).speed];
                torque[j] += self.torque_by_pulley_speed[j] * dw;
                hub[j] += self.hub_by_pulley_speed[j] * dw;
            }
            if pc.arm.is_some() {
                let (o, a) = (states.arm(j), &self.arms[j]);
                let (angle, rate) = (x[o.angle], x[o.rate]);
                torque[j] += a.torque_by_arm_angle * angle + a.torque_by_arm_rate * rate;
                hub[j] += a.hub_by_arm_angle * angle + a.hub_by_arm_rate * rate;
            }
            // drive torque of a speed-driven pulley: prescribed terms less
            // the belt's torque (and plus a decoupler's clutch torque)
            let drive = if pc.speed_driven {
                let mut d = -torque[j];
                if pc.decoupler.is_some() {
                    let o = states.decoupler(j);
                    d += self.decouplers[j].drive_torque_by_twist * x[o.twist]
                        + self.decouplers[j].drive_torque_by_rotor_speed * x[o.rotor_speed];
                }
                d
            } else {
                0.0
            };
            power += self.power_speed[j] * drive;
            out[j] = [torque[j], drive, hub[j].x, hub[j].y];
        }
        (out, power)
    }

    /// The input power's row at time `t` (`power_speed`, `power_applied`):
    /// input power (applied + drive) omega is the drive torque's row times a
    /// prescribed speed plus the applied torque times a state speed. They
    /// depend on the time only, so the stiff method sets them at the start
    /// of every step (`StiffSystem::step_rows`), also in a kept Jacobian.
    pub fn set_power_row(&mut self, sys: &BeltSystem, t: f64) {
        for j in 0..sys.np {
            self.power_speed[j] = if sys.pulleys[j].speed_driven {
                sys.prescribed_speed(j, t).0
            } else {
                0.0
            };
            self.power_applied[j] = sys.applied_torque(j, t);
        }
    }

    /// Appends the stored numbers to `out`.
    pub fn save(&self, out: &mut Vec<f64>) {
        let mut copy = self.clone();
        copy.visit(&mut |x| out.push(*x));
    }

    /// Reads what [`save`](Self::save) wrote; false if `src` has the wrong
    /// length or holds a non-finite number (nothing is changed then).
    pub fn load(&mut self, src: &[f64]) -> bool {
        let mut len = 0;
        self.clone().visit(&mut |_| len += 1);
        if src.len() != len || !src.iter().all(|x| x.is_finite()) {
            return false;
        }
        let mut it = src.iter();
        self.visit(&mut |x| *x = *it.next().expect("length checked"));
        true
    }

    /// The Jacobian as a dense matrix (row-major, `dim x dim`), for tests.
    pub fn to_dense(&self, sys: &BeltSystem) -> Vec<f64> {
        let n = sys.n;
        let dim = sys.dim();
        let mut m = vec![0.0; dim * dim];
        let mut set = |r: usize, c: usize, v: f64| m[r * dim + c] += v;
        for (i, b) in self.bodies.iter().enumerate() {
            let o = BodyIndex::of(i);
            let (q, v, z) = (o.coordinates(), o.rates(), o.creep);
            for (&qr, &vr) in q.iter().zip(&v) {
                set(qr, vr, 1.0); // dq/dt = v
            }
            for (slot, nb) in [(PREV, (i + n - 1) % n), (SELF, i), (NEXT, (i + 1) % n)] {
                let on = BodyIndex::of(nb);
                for (r, &vr) in v.iter().enumerate() {
                    for c in 0..3 {
                        set(vr, on.coordinates()[c], b.accel_by_position[slot][(r, c)]);
                        set(vr, on.rates()[c], b.accel_by_velocity[slot][(r, c)]);
                    }
                }
            }
            for r in 0..3 {
                set(v[r], z, b.accel_by_creep[r]);
                set(z, q[r], b.creep_rate_by_position[r]);
                set(z, v[r], b.creep_rate_by_velocity[r]);
            }
            for j in 0..sys.np {
                let w = sys.state_layout.pulley(j).speed;
                for r in 0..3 {
                    set(v[r], w, b.accel_by_pulley_speed[j][r]);
                    set(w, q[r], b.pulley_accel_by_position[j][r]);
                    set(w, v[r], b.pulley_accel_by_velocity[j][r]);
                }
                set(z, w, b.creep_rate_by_pulley_speed[j]);
                set(w, z, b.pulley_accel_by_creep[j]);
            }
        }
        for j in 0..sys.np {
            let states = &sys.state_layout;
            let p = states.pulley(j);
            if self.free[j] {
                set(p.angle, p.speed, 1.0);
            }
            for k in 0..sys.np {
                set(
                    p.speed,
                    states.pulley(k).speed,
                    self.pulley_accel_by_pulley_speed[j][k],
                );
            }
            if sys.pulleys[j].decoupler.is_some() {
                let dj = &self.decouplers[j];
                let (d, r, h) = (
                    states.decoupler(j).twist,
                    states.decoupler(j).rotor_speed,
                    p.speed,
                );
                set(d, d, dj.twist_rate_by_twist);
                set(d, h, dj.twist_rate_by_hub_speed);
                set(d, r, dj.twist_rate_by_rotor_speed);
                set(r, d, dj.rotor_accel_by_twist);
                set(r, h, dj.rotor_accel_by_hub_speed);
                set(r, r, dj.rotor_accel_by_rotor_speed);
                set(h, d, dj.hub_accel_by_twist);
                set(h, r, dj.hub_accel_by_rotor_speed);
            }
            if sys.pulleys[j].arm.is_some() {
                let aj = &self.arms[j];
                let (a, ar) = (states.arm(j).angle, states.arm(j).rate);
                set(a, ar, 1.0);
                set(ar, a, aj.arm_accel_by_angle);
                set(ar, ar, aj.arm_accel_by_rate);
                set(ar, p.speed, aj.arm_accel_by_pulley_speed);
                set(p.speed, a, aj.pulley_accel_by_arm_angle);
                set(p.speed, ar, aj.pulley_accel_by_arm_rate);
                let z = states.arm(j).deflection;
                set(ar, z, aj.arm_accel_by_deflection);
                set(z, ar, aj.deflection_rate_by_rate);
                set(z, z, aj.deflection_rate_by_deflection);
                for (i, b) in self.arm_bodies.iter().enumerate() {
                    let ob = BodyIndex::of(i);
                    let (q, v, z) = (ob.coordinates(), ob.rates(), ob.creep);
                    for r in 0..3 {
                        set(v[r], a, b.accel_by_arm_angle[j][r]);
                        set(v[r], ar, b.accel_by_arm_rate[j][r]);
                        set(ar, q[r], b.arm_accel_by_position[j][r]);
                        set(ar, v[r], b.arm_accel_by_velocity[j][r]);
                    }
                    set(z, a, b.creep_rate_by_arm_angle[j]);
                    set(z, ar, b.creep_rate_by_arm_rate[j]);
                    set(ar, z, b.arm_accel_by_creep[j]);
                }
            }
        }
        // impulse rows: the linear map applied to each unit vector
        let mut e = vec![0.0; dim];
        for col in 0..sys.controlled_dim() {
            e[col] = 1.0;
            let (rows, power) = self.impulse_rows(sys, &e);
            e[col] = 0.0;
            set(sys.state_layout.energy().work_in, col, power);
            for (j, r) in rows.iter().enumerate().take(sys.np) {
                for (q, v) in sys.state_layout.impulses(j).range().zip(r) {
                    set(q, col, *v);
                }
            }
        }
        m
    }
}
