//! The Jacobian's storage: construction, the impulse rows applied to a
//! vector, saving and restoring, the dense matrix of the tests.

use super::{
    ArmJacobian, BodyArmJacobian, BodyJacobian, DecouplerJacobian, ImpulseColumns, Jacobian, NEXT,
    PREV, SELF,
};
use crate::model::matmul::mm;
use crate::model::params::MAX_PULLEYS;
use crate::model::system::{BeltSystem, BODY_DOF};
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
            pw: [[0.0; MAX_PULLEYS]; MAX_PULLEYS],
            free,
            dec: [DecouplerJacobian::default(); MAX_PULLEYS],
            tw: [0.0; MAX_PULLEYS],
            hw: [Vector2::zeros(); MAX_PULLEYS],
            power_speed: [0.0; MAX_PULLEYS],
            power_applied: [0.0; MAX_PULLEYS],
            arm: [ArmJacobian::default(); MAX_PULLEYS],
            arm_bodies: if sys.n_arms > 0 {
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
            for m in b.aq.iter_mut().chain(b.av.iter_mut()) {
                m.iter_mut().for_each(&mut *f);
            }
            b.az.iter_mut().for_each(&mut *f);
            for v in &mut b.aw[..np] {
                v.iter_mut().for_each(&mut *f);
            }
            b.gq.iter_mut().chain(b.gv.iter_mut()).for_each(&mut *f);
            b.gw[..np]
                .iter_mut()
                .chain(&mut b.pz[..np])
                .for_each(&mut *f);
            for v in b.pq[..np].iter_mut().chain(&mut b.pv[..np]) {
                v.iter_mut().for_each(&mut *f);
            }
            // field by field over the pulleys (the saved order)
            for c in im.iter_mut() {
                c.tq.iter_mut().for_each(&mut *f);
            }
            for c in im.iter_mut() {
                c.tv.iter_mut().for_each(&mut *f);
            }
            for c in im.iter_mut() {
                f(&mut c.tz);
            }
            for c in im.iter_mut() {
                c.hq.iter_mut().for_each(&mut *f);
            }
            for c in im.iter_mut() {
                c.hv.iter_mut().for_each(&mut *f);
            }
            for c in im.iter_mut() {
                c.hz.iter_mut().for_each(&mut *f);
            }
            let mut touching = f64::from(b.touching);
            f(&mut touching);
            b.touching = touching as u8;
        }
        for row in &mut self.pw[..np] {
            row[..np].iter_mut().for_each(&mut *f);
        }
        for d in &mut self.dec[..np] {
            for v in [
                &mut d.tt, &mut d.th, &mut d.tr, &mut d.rt, &mut d.rh, &mut d.rr, &mut d.ht,
                &mut d.hr, &mut d.dt, &mut d.dr,
            ] {
                f(v);
            }
        }
        self.tw[..np].iter_mut().for_each(&mut *f);
        self.power_speed[..np]
            .iter_mut()
            .chain(&mut self.power_applied[..np])
            .for_each(&mut *f);
        for v in &mut self.hw[..np] {
            v.iter_mut().for_each(&mut *f);
        }
        for a in &mut self.arm[..np] {
            for v in [
                &mut a.aa, &mut a.ar, &mut a.aw, &mut a.pa, &mut a.pr, &mut a.ta, &mut a.tr,
            ] {
                f(v);
            }
            a.fa.iter_mut().chain(a.fr.iter_mut()).for_each(&mut *f);
        }
        for b in &mut self.arm_bodies {
            for v in b.aa[..np].iter_mut().chain(&mut b.ar[..np]) {
                v.iter_mut().for_each(&mut *f);
            }
            for v in b.rq[..np].iter_mut().chain(&mut b.rv[..np]) {
                v.iter_mut().for_each(&mut *f);
            }
            b.ga[..np]
                .iter_mut()
                .chain(&mut b.gr[..np])
                .chain(&mut b.rz[..np])
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
            let o = BODY_DOF * i;
            let (dq, dv, dz) = (
                Vector3::new(x[o], x[o + 1], x[o + 2]),
                Vector3::new(x[o + 3], x[o + 4], x[o + 5]),
                x[o + 6],
            );
            for j in 0..np {
                if b.touching & (1 << j) != 0 {
                    let c = &im[j];
                    torque[j] += c.tq.dot(&dq.transpose()) + c.tv.dot(&dv.transpose()) + c.tz * dz;
                    hub[j] += mm(&c.hq, &dq) + mm(&c.hv, &dv) + c.hz * dz;
                }
            }
        }
        let mut out = [[0.0; 4]; MAX_PULLEYS];
        let mut power = 0.0;
        for j in 0..np {
            let pc = &sys.pulleys[j];
            // input power: (applied + drive) omega, applied omega_rotor
            // behind a decoupler
            if pc.decoupler.is_some() {
                power += self.power_applied[j] * x[pc.decoupler_offset + 1];
            } else if self.free[j] {
                power += self.power_applied[j] * x[sys.pulley_offset(j) + 1];
            }
            if self.free[j] {
                let dw = x[sys.pulley_offset(j) + 1];
                torque[j] += self.tw[j] * dw;
                hub[j] += self.hw[j] * dw;
            }
            if pc.arm.is_some() {
                let (o, a) = (pc.arm_offset, &self.arm[j]);
                torque[j] += a.ta * x[o] + a.tr * x[o + 1];
                hub[j] += a.fa * x[o] + a.fr * x[o + 1];
            }
            // drive torque of a speed-driven pulley: prescribed terms less
            // the belt's torque (and plus a decoupler's clutch torque)
            let drive = if pc.speed_driven {
                let mut d = -torque[j];
                if pc.decoupler.is_some() {
                    let o = pc.decoupler_offset;
                    d += self.dec[j].dt * x[o] + self.dec[j].dr * x[o + 1];
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
            let o = BODY_DOF * i;
            for r in 0..3 {
                set(o + r, o + 3 + r, 1.0); // dq/dt = v
            }
            for (slot, nb) in [(PREV, (i + n - 1) % n), (SELF, i), (NEXT, (i + 1) % n)] {
                let on = BODY_DOF * nb;
                for r in 0..3 {
                    for c in 0..3 {
                        set(o + 3 + r, on + c, b.aq[slot][(r, c)]);
                        set(o + 3 + r, on + 3 + c, b.av[slot][(r, c)]);
                    }
                }
            }
            for r in 0..3 {
                set(o + 3 + r, o + 6, b.az[r]);
                set(o + 6, o + r, b.gq[r]);
                set(o + 6, o + 3 + r, b.gv[r]);
            }
            for j in 0..sys.np {
                let w = sys.pulley_offset(j) + 1;
                for r in 0..3 {
                    set(o + 3 + r, w, b.aw[j][r]);
                    set(w, o + r, b.pq[j][r]);
                    set(w, o + 3 + r, b.pv[j][r]);
                }
                set(o + 6, w, b.gw[j]);
                set(w, o + 6, b.pz[j]);
            }
        }
        for j in 0..sys.np {
            let o = sys.pulley_offset(j);
            if self.free[j] {
                set(o, o + 1, 1.0);
            }
            for k in 0..sys.np {
                set(o + 1, sys.pulley_offset(k) + 1, self.pw[j][k]);
            }
            if sys.pulleys[j].decoupler.is_some() {
                let (d, dj) = (sys.pulleys[j].decoupler_offset, &self.dec[j]);
                let h = o + 1;
                set(d, d, dj.tt);
                set(d, h, dj.th);
                set(d, d + 1, dj.tr);
                set(d + 1, d, dj.rt);
                set(d + 1, h, dj.rh);
                set(d + 1, d + 1, dj.rr);
                set(h, d, dj.ht);
                set(h, d + 1, dj.hr);
            }
            if sys.pulleys[j].arm.is_some() {
                let (a, aj) = (sys.pulleys[j].arm_offset, &self.arm[j]);
                set(a, a + 1, 1.0);
                set(a + 1, a, aj.aa);
                set(a + 1, a + 1, aj.ar);
                set(a + 1, o + 1, aj.aw);
                set(o + 1, a, aj.pa);
                set(o + 1, a + 1, aj.pr);
                for (i, b) in self.arm_bodies.iter().enumerate() {
                    let ob = BODY_DOF * i;
                    for r in 0..3 {
                        set(ob + 3 + r, a, b.aa[j][r]);
                        set(ob + 3 + r, a + 1, b.ar[j][r]);
                        set(a + 1, ob + r, b.rq[j][r]);
                        set(a + 1, ob + 3 + r, b.rv[j][r]);
                    }
                    set(ob + 6, a, b.ga[j]);
                    set(ob + 6, a + 1, b.gr[j]);
                    set(a + 1, ob + 6, b.rz[j]);
                }
            }
        }
        // impulse rows: the linear map applied to each unit vector
        let mut e = vec![0.0; dim];
        for col in 0..sys.controlled_dim() {
            e[col] = 1.0;
            let (rows, power) = self.impulse_rows(sys, &e);
            e[col] = 0.0;
            set(sys.energy_offset(), col, power);
            for (j, r) in rows.iter().enumerate().take(sys.np) {
                for (k, v) in r.iter().enumerate() {
                    set(sys.impulse_offset(j) + k, col, *v);
                }
            }
        }
        m
    }
}
