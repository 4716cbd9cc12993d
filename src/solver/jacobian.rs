//! Analytic Jacobian of the belt's right-hand side (system.rs), for the
//! implicit integrator. Stored by blocks, as the physics couples them:
//!
//! * each body's acceleration depends on its own and its two neighbours'
//!   positions and velocities (translational and torsional SDEs, eq. 20-23),
//!   on its own creep z and on the speed of the pulleys it touches (contact
//!   and friction, eq. 9-19);
//! * each body's creep rate dz/dt = v_T depends on its own position and
//!   velocity and on the pulley speed (eq. 18);
//! * each torque-driven pulley's acceleration depends on every body that
//!   touches it and on its own speed (eq. 24, load damping).
//!
//! Positions never depend on anything but velocities (dq/dt = v), pulley
//! angles only on pulley speeds; the dissipated-energy accumulator is left
//! out (the W-method keeps its order with an approximate Jacobian, see
//! rosenbrock.rs), the input energy has its row (below).
//!
//! The impulse states (belt torque, drive torque and hub force of each
//! pulley integrated over the communication step) have rows but no columns:
//! nothing depends on them. Their rows are the exact partials of the
//! integrated forces, so that the stiff method integrates the forces with
//! the same linearisation that moves the pulleys: a fast contact motion it
//! leaves unresolved at the step end then adds to the impulse only what it
//! adds to the pulley's momentum (I omega + d theta - impulse of the applied
//! torque = belt torque impulse holds for both, to the step's round-off).
//! The input energy's row (the drive torques times the prescribed speeds,
//! the applied torques times the state speeds) is there for the same
//! reason: it books the work the drives do with that linearisation too.

use crate::model::elements::contact;
use crate::model::elements::friction::{with_law, Law};
use crate::model::elements::sde::{self, BodyEnd};
use crate::model::params::MAX_PULLEYS;
use crate::model::simd::{self, Isa};
use crate::model::system::{BeltSystem, BODY_DOF};
use crate::model::trig;
use nalgebra::{Matrix2, Matrix2x3, Matrix3, RowVector3, SMatrix, Vector2, Vector3};

/// Derivatives of one body's rows: accelerations (vx', vy', omega') and creep rate z'.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BodyJacobian {
    /// d(acceleration)/d(position) of body i-1, i, i+1.
    pub aq: [Matrix3<f64>; 3],
    /// d(acceleration)/d(velocity) of body i-1, i, i+1.
    pub av: [Matrix3<f64>; 3],
    /// d(acceleration)/dz (own creep).
    pub az: Vector3<f64>,
    /// d(acceleration)/d(pulley speed j).
    pub aw: [Vector3<f64>; MAX_PULLEYS],
    /// dz'/d(own position), dz'/d(own velocity), dz'/d(pulley speed j).
    pub gq: RowVector3<f64>,
    /// dz'/d(own velocity).
    pub gv: RowVector3<f64>,
    /// dz'/d(pulley speed j).
    pub gw: [f64; MAX_PULLEYS],
    /// d(pulley j acceleration)/d(this body's position, velocity, z).
    pub pq: [RowVector3<f64>; MAX_PULLEYS],
    /// d(pulley j acceleration)/d(this body's velocity).
    pub pv: [RowVector3<f64>; MAX_PULLEYS],
    /// d(pulley j acceleration)/d(this body's z).
    pub pz: [f64; MAX_PULLEYS],
    /// Bit j set: the body touches pulley j (only those entries are non-zero).
    pub touching: u8,
}

/// One body's columns in the impulse rows of one pulley (its belt torque
/// and hub force); non-zero only where the body touches the pulley
/// ([`BodyJacobian::touching`]). Kept apart from [`BodyJacobian`], one
/// pulley's together: only the impulse rows read them, while the
/// factorization and the stage solves walk the body rows
/// (docs/benchmarks.md).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImpulseColumns {
    /// d(belt torque on the pulley)/d(this body's position, velocity, z):
    /// the belt-torque impulse's row (all pulleys, speed-driven too).
    pub tq: RowVector3<f64>,
    /// d(belt torque on the pulley)/d(this body's velocity).
    pub tv: RowVector3<f64>,
    /// d(belt torque on the pulley)/d(this body's z).
    pub tz: f64,
    /// d(force on the pulley's hub)/d(this body's position, velocity, z):
    /// the hub-force impulse's rows.
    pub hq: Matrix2x3<f64>,
    /// d(force on the pulley's hub)/d(this body's velocity).
    pub hv: Matrix2x3<f64>,
    /// d(force on the pulley's hub)/d(this body's z).
    pub hz: Vector2<f64>,
}

/// Derivatives of a decoupler's rows (twist rate, rotor acceleration) and
/// of its hub's acceleration with respect to twist, hub speed and rotor
/// speed (`elements::decoupler`). The hub's own d(alpha)/d(omega_hub) term
/// is in `Jacobian::pw`. Zero where the hub is speed-driven (its speed is
/// then an input, its acceleration prescribed).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DecouplerJacobian {
    /// d(twist')/d(twist, omega_hub, omega_rotor).
    pub tt: f64,
    /// d(twist')/d(omega_hub).
    pub th: f64,
    /// d(twist')/d(omega_rotor).
    pub tr: f64,
    /// d(rotor alpha)/d(twist, omega_hub, omega_rotor).
    pub rt: f64,
    /// d(rotor alpha)/d(omega_hub).
    pub rh: f64,
    /// d(rotor alpha)/d(omega_rotor).
    pub rr: f64,
    /// d(hub alpha)/d(twist, omega_rotor).
    pub ht: f64,
    /// d(hub alpha)/d(omega_rotor).
    pub hr: f64,
    /// d(drive torque)/d(twist, omega_rotor) of a speed-driven hub (the
    /// drive-torque impulse's row; zero on a torque-driven hub).
    pub dt: f64,
    /// d(drive torque)/d(omega_rotor).
    pub dr: f64,
}

/// Derivatives of a tensioner arm's rate row (arm acceleration) with
/// respect to its own angle and rate (spring, damper, pivot friction, the
/// lever of the hub force and the contacts' dependence on the moving
/// centre) and its pulley's speed; and of that pulley's acceleration with
/// respect to the arm (`elements::tensioner`). The angle row is
/// d(angle)/dt = rate.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ArmJacobian {
    /// d(arm acceleration)/d(angle, rate, pulley speed).
    pub aa: f64,
    /// d(arm acceleration)/d(rate).
    pub ar: f64,
    /// d(arm acceleration)/d(pulley speed).
    pub aw: f64,
    /// d(pulley acceleration)/d(arm angle, arm rate).
    pub pa: f64,
    /// d(pulley acceleration)/d(arm rate).
    pub pr: f64,
    /// d(belt torque on the pulley)/d(arm angle, arm rate) and d(force on its
    /// hub)/d(arm angle, arm rate): the impulse rows' arm columns.
    pub ta: f64,
    /// d(belt torque on the pulley)/d(arm rate).
    pub tr: f64,
    /// d(force on the hub)/d(arm angle).
    pub fa: Vector2<f64>,
    /// d(force on the hub)/d(arm rate).
    pub fr: Vector2<f64>,
}

/// How one body's rows and a tensioner arm's row depend on each other,
/// per pulley slot j (zero unless the body touches pulley j and it sits on
/// an arm): the contact sees the body relative to the moving centre.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BodyArmJacobian {
    /// d(acceleration)/d(arm angle), d(acceleration)/d(arm rate).
    pub aa: [Vector3<f64>; MAX_PULLEYS],
    /// d(acceleration)/d(arm rate).
    pub ar: [Vector3<f64>; MAX_PULLEYS],
    /// dz'/d(arm angle), dz'/d(arm rate).
    pub ga: [f64; MAX_PULLEYS],
    /// dz'/d(arm rate).
    pub gr: [f64; MAX_PULLEYS],
    /// d(arm acceleration)/d(this body's position, velocity, z).
    pub rq: [RowVector3<f64>; MAX_PULLEYS],
    /// d(arm acceleration)/d(this body's velocity).
    pub rv: [RowVector3<f64>; MAX_PULLEYS],
    /// d(arm acceleration)/d(this body's z).
    pub rz: [f64; MAX_PULLEYS],
}

/// Block Jacobian of the whole belt drive.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Jacobian {
    /// Per body, its rows.
    pub bodies: Vec<BodyJacobian>,
    /// Per body, its columns in the impulse rows of pulley j.
    pub impulse: Vec<[ImpulseColumns; MAX_PULLEYS]>,
    /// d(pulley j acceleration)/d(pulley speed k), torque-driven pulleys.
    pub pw: [[f64; MAX_PULLEYS]; MAX_PULLEYS],
    /// Pulley j's speed is a state (torque-driven) rather than an input.
    pub free: [bool; MAX_PULLEYS],
    /// Decoupler of pulley j (zero if it has none).
    pub dec: [DecouplerJacobian; MAX_PULLEYS],
    /// d(belt torque on pulley j)/d(omega_j) and d(hub force j)/d(omega_j),
    /// torque-driven pulleys (a speed-driven pulley's speed is an input).
    pub tw: [f64; MAX_PULLEYS],
    /// d(hub force j)/d(omega_j).
    pub hw: [Vector2<f64>; MAX_PULLEYS],
    /// The input power's row (the `energy.input` accumulator): per pulley
    /// the prescribed speed a speed-driven pulley's drive torque is
    /// multiplied with (0 for a torque-driven pulley).
    pub power_speed: [f64; MAX_PULLEYS],
    /// The applied torque multiplying the speed of a torque-driven pulley
    /// (of the rotor behind a decoupler) in the input power's row.
    pub power_applied: [f64; MAX_PULLEYS],
    /// Tensioner arm of pulley j (zero if it has none).
    pub arm: [ArmJacobian; MAX_PULLEYS],
    /// Per body, its coupling with the arms (empty in a drive without arms).
    pub arm_bodies: Vec<BodyArmJacobian>,
    /// The drive's pulley count: the slots past it stay zero and are not
    /// saved.
    slots: usize,
}

/// Index of the neighbour blocks in `aq`/`av`.
pub const PREV: usize = 0;
/// Index of the body's own block in `aq`/`av`.
pub const SELF: usize = 1;
/// Index of the next body's block in `aq`/`av`.
pub const NEXT: usize = 2;

#[inline(always)]
fn perp(h: Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-h.y, h.x)
}

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
                    hub[j] += c.hq * dq + c.hv * dv + c.hz * dz;
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

impl BeltSystem {
    /// Evaluates the Jacobian of [`BeltSystem::rhs`] at (t, y) into `jac`.
    /// Allocates nothing. Runs an AVX2 build of the same code where the CPU
    /// has it (no FMA: the same numbers to the last bit).
    pub fn jacobian(&self, t: f64, y: &[f64], jac: &mut Jacobian) {
        self.jacobian_with(Isa::detected().min(Isa::Avx2), t, y, jac);
    }

    /// [`Self::jacobian`] built for `isa`.
    fn jacobian_with(&self, isa: Isa, t: f64, y: &[f64], jac: &mut Jacobian) {
        // a kernel per friction law (and instruction set): one copy of the
        // loops in each, calling the law directly
        with_law!(self.friction, law => self.jacobian_for(&law, isa, t, y, jac));
    }

    /// [`Self::jacobian_with`] for the friction law `friction`.
    fn jacobian_for(&self, friction: &impl Law, isa: Isa, t: f64, y: &[f64], jac: &mut Jacobian) {
        simd::dispatch_with(
            isa,
            (self, y, jac),
            #[inline(always)]
            |(sys, y, jac)| sys.jacobian_impl(friction, t, y, jac),
        );
    }

    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // indices run over several parallel arrays
    fn jacobian_impl(&self, friction: &impl Law, t: f64, y: &[f64], jac: &mut Jacobian) {
        let n = self.n;
        let np = self.np;
        let hl = self.half_length;
        let mut omega_p = [0.0; MAX_PULLEYS];
        for (j, w) in omega_p.iter_mut().enumerate().take(np) {
            *w = self.pulley_speed(j, t, y);
        }
        jac.pw = [[0.0; MAX_PULLEYS]; MAX_PULLEYS];
        jac.tw = [0.0; MAX_PULLEYS];
        jac.hw = [Vector2::zeros(); MAX_PULLEYS];
        let mut buf = None;
        let pulleys = self.pulleys_in_effect(&mut buf);
        let (inv_m, inv_i) = (self.inv_mass, self.inv_inertia);
        let row_scale = [inv_m, inv_m, inv_i];
        // pulley centres and velocities; per arm: c'(alpha), c''(alpha)
        // alpha' (the centre velocity's angle derivative), 1 / I_arm
        let mut centre = [[0.0; 4]; MAX_PULLEYS];
        let mut lever = [Vector2::zeros(); MAX_PULLEYS];
        let mut lever_rate = [Vector2::zeros(); MAX_PULLEYS];
        let mut inv_arm = [0.0; MAX_PULLEYS];
        let mut hub_force = [[0.0; 2]; MAX_PULLEYS];
        for j in 0..np {
            let (c, vc) = self.pulley_centre(j, y);
            centre[j] = [c[0], c[1], vc[0], vc[1]];
            jac.arm[j] = ArmJacobian::default();
            let pc = &self.pulleys[j];
            if let Some(arm) = &pc.arm {
                let (a, w) = (y[pc.arm_offset], y[pc.arm_offset + 1]);
                let dc = arm.centre(a).1;
                lever[j] = Vector2::new(dc[0], dc[1]);
                // c'' = -(c - pivot)
                lever_rate[j] = -w * Vector2::new(c[0] - arm.pivot[0], c[1] - arm.pivot[1]);
                inv_arm[j] = if self.relaxation.pulleys_held {
                    0.0
                } else {
                    1.0 / arm.inertia
                };
            }
        }
        jac.set_power_row(self, t);
        let with_arms = self.n_arms > 0;

        // Contact and friction of each body (eq. 4-19): forces act at the
        // body centre, so only the translational rows and own columns.
        for i in 0..n {
            let o = BODY_DOF * i;
            let b = &mut jac.bodies[i];
            // reset what this evaluation accumulates into or may leave
            // unset; the entries of pulleys j >= np stay zero from `new`
            b.aq = Default::default();
            b.av = Default::default();
            b.az = Vector3::zeros();
            b.gq = RowVector3::zeros();
            b.gv = RowVector3::zeros();
            b.touching = 0;
            for j in 0..np {
                b.aw[j] = Vector3::zeros();
                b.gw[j] = 0.0;
                b.pq[j] = RowVector3::zeros();
                b.pv[j] = RowVector3::zeros();
                b.pz[j] = 0.0;
            }
            for c in &mut jac.impulse[i][..np] {
                *c = ImpulseColumns::default();
            }
            if with_arms {
                jac.arm_bodies[i] = BodyArmJacobian::default();
            }
            let x = [y[o], y[o + 1]];
            let z = y[o + 6];
            let mut fq = Matrix2::zeros();
            let mut fv = Matrix2::zeros();
            if self.points > 1 {
                continue; // below, for all bodies
            }
            for j in 0..np {
                let pc = &pulleys[j];
                let [cx, cy, cvx, cvy] = centre[j];
                // velocity relative to the pulley centre (a tensioner's moves)
                let v = [y[o + 3] - cvx, y[o + 4] - cvy];
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
                    // The contact force F(x - c(alpha), v - c'(alpha) alpha')
                    // on the body and its reaction -F on the hub, whose
                    // moment c'(alpha) . (-F) drives the arm.
                    let (dc, ddc, inv) = (lever[j], lever_rate[j], inv_arm[j]);
                    let force = contact::force(&kin, normal.0, cp.f);
                    hub_force[j][0] -= force[0];
                    hub_force[j][1] -= force[1];
                    let f_a = -(cp.f_x * dc) - cp.f_v * ddc;
                    let f_r = -(cp.f_v * dc);
                    let tau = Vector2::from(kin.t);
                    let ba = &mut jac.arm_bodies[i];
                    ba.aa[j] = Vector3::new(f_a[0] * inv_m, f_a[1] * inv_m, 0.0);
                    ba.ar[j] = Vector3::new(f_r[0] * inv_m, f_r[1] * inv_m, 0.0);
                    if creeping {
                        ba.ga[j] = -(cp.vt_x.dot(&dc.transpose()) + cp.vt_v.dot(&ddc.transpose()));
                        ba.gr[j] = -cp.vt_v.dot(&dc.transpose());
                    }
                    let lq = -(dc.transpose() * cp.f_x) * inv;
                    let lv = -(dc.transpose() * cp.f_v) * inv;
                    ba.rq[j] = RowVector3::new(lq[0], lq[1], 0.0);
                    ba.rv[j] = RowVector3::new(lv[0], lv[1], 0.0);
                    ba.rz[j] = -dc.dot(&tau) * cp.fric_z * inv;
                    let aj = &mut jac.arm[j];
                    aj.aa -= dc.dot(&f_a) * inv;
                    aj.ar -= dc.dot(&f_r) * inv;
                    // impulse rows: the belt torque -r f and the hub force
                    // -F through the moving centre
                    aj.ta += pc.lever
                        * (cp.fric_x.dot(&dc.transpose()) + cp.fric_v.dot(&ddc.transpose()));
                    aj.tr += pc.lever * cp.fric_v.dot(&dc.transpose());
                    aj.fa -= f_a;
                    aj.fr -= f_r;
                    if !pc.speed_driven {
                        aj.aw -= dc.dot(&tau) * cp.fric_w * inv;
                        // the pulley's torque -r_c f through the moving centre
                        let k = -pc.lever * pc.balance_partials().1;
                        aj.pa -=
                            k * (cp.fric_x.dot(&dc.transpose()) + cp.fric_v.dot(&ddc.transpose()));
                        aj.pr -= k * cp.fric_v.dot(&dc.transpose());
                    }
                }
                fq += cp.f_x;
                fv += cp.f_v;
                let tau = kin.t;
                b.az[0] += tau[0] * cp.fric_z * inv_m;
                b.az[1] += tau[1] * cp.fric_z * inv_m;
                let free = !pc.speed_driven;
                if free {
                    b.aw[j][0] += tau[0] * cp.fric_w * inv_m;
                    b.aw[j][1] += tau[1] * cp.fric_w * inv_m;
                }
                // creep rate dz/dt = v_T, frozen at the cap while pushed outward
                if creeping {
                    b.gq[0] += cp.vt_x[0];
                    b.gq[1] += cp.vt_x[1];
                    b.gv[0] += cp.vt_v[0];
                    b.gv[1] += cp.vt_v[1];
                    if free {
                        b.gw[j] += pc.lever;
                    }
                }
                // impulse rows: belt torque -r f, hub force -(N n + f t)
                let r = pc.lever;
                let tv2 = Vector2::new(tau[0], tau[1]);
                jac.impulse[i][j] = ImpulseColumns {
                    tq: RowVector3::new(-r * cp.fric_x[0], -r * cp.fric_x[1], 0.0),
                    tv: RowVector3::new(-r * cp.fric_v[0], -r * cp.fric_v[1], 0.0),
                    tz: -r * cp.fric_z,
                    hq: hub_row(&cp.f_x),
                    hv: hub_row(&cp.f_v),
                    hz: -cp.fric_z * tv2,
                };
                if free {
                    jac.tw[j] += -r * cp.fric_w;
                    jac.hw[j] += -cp.fric_w * tv2;
                }
                // pulley torque -r f on the pulley's acceleration (eq. 24)
                if free {
                    let k = -pc.lever * pc.balance_partials().1;
                    b.pq[j] = RowVector3::new(k * cp.fric_x[0], k * cp.fric_x[1], 0.0);
                    b.pv[j] = RowVector3::new(k * cp.fric_v[0], k * cp.fric_v[1], 0.0);
                    b.pz[j] = k * cp.fric_z;
                    jac.pw[j][j] += k * cp.fric_w;
                }
            }
            for r in 0..2 {
                for c in 0..2 {
                    b.aq[SELF][(r, c)] += fq[(r, c)] * inv_m;
                    b.av[SELF][(r, c)] += fv[(r, c)] * inv_m;
                }
            }
        }

        // The contact along the body: one build per point count, a loop over
        // the bodies in each.
        let arms = Arms {
            lever: &lever,
            lever_rate: &lever_rate,
            inv_arm: &inv_arm,
        };
        let along = (friction, y, &omega_p, pulleys, &centre);
        match self.points {
            1 => {}
            2 => self.contact_along_rows::<2>(along, &mut hub_force, jac, arms),
            3 => self.contact_along_rows::<3>(along, &mut hub_force, jac, arms),
            4 => self.contact_along_rows::<4>(along, &mut hub_force, jac, arms),
            5 => self.contact_along_rows::<5>(along, &mut hub_force, jac, arms),
            k => panic!("{k} contact points outside 1..={}", contact::MAX_POINTS),
        }

        // SDE k joins the right end of body p = k-1 to the left end of body
        // c = k. Gap d = J_d q-ish, generalized forces Q = -J_d^T F (eq. 20-23).
        let (kt, bt) = self.bend.partials();
        // sin/cos of each body angle once: body k's is body k+1's "previous"
        let mut prev_sc = trig::sin_cos(y[BODY_DOF * (n - 1) + 2]);
        for k in 0..n {
            let p = if k == 0 { n - 1 } else { k - 1 };
            let (op, oc) = (BODY_DOF * p, BODY_DOF * k);
            let (sp, cp) = prev_sc;
            let (sc, cc) = trig::sin_cos(y[oc + 2]);
            prev_sc = (sc, cc);
            let hp = Vector2::new(hl * cp, hl * sp);
            let hc = Vector2::new(hl * cc, hl * sc);
            let (hpp, hcp) = (perp(hp), perp(hc));
            let (wp, wc) = (y[op + 5], y[oc + 5]);
            let end = |o: usize, h: Vector2<f64>| BodyEnd {
                x: y[o],
                y: y[o + 1],
                hx: h.x,
                hy: h.y,
                vx: y[o + 3],
                vy: y[o + 4],
                w: y[o + 5],
            };
            let (d, dd) = sde::gap(end(op, hp), end(oc, hc));
            let (force, f_d, f_dd) = self.axial.partials(d, dd);
            // dF/dq and dF/dv (2 x 6 over x_p, y_p, phi_p, x_c, y_c, phi_c)
            // column by column: the gap's Jacobian is J_d = [-I, -h_p^perp,
            // I, -h_c^perp], and d(dd)/dq acts only through the angles
            // (columns w_p h_p and w_c h_c).
            let mut dfq = SMatrix::<f64, 2, 6>::zeros();
            let mut dfv = SMatrix::<f64, 2, 6>::zeros();
            dfq.fixed_view_mut::<2, 2>(0, 0).copy_from(&(-f_d));
            dfq.fixed_view_mut::<2, 2>(0, 3).copy_from(&f_d);
            dfq.set_column(2, &(f_dd * (wp * hp) - f_d * hpp));
            dfq.set_column(5, &(f_dd * (wc * hc) - f_d * hcp));
            dfv.fixed_view_mut::<2, 2>(0, 0).copy_from(&(-f_dd));
            dfv.fixed_view_mut::<2, 2>(0, 3).copy_from(&f_dd);
            dfv.set_column(2, &(-(f_dd * hpp)));
            dfv.set_column(5, &(-(f_dd * hcp)));
            // generalized forces Q = -J_d^T F: rows dF, h_p^perp . dF, -dF,
            // h_c^perp . dF
            let q_of = |df: &SMatrix<f64, 2, 6>| {
                let mut k = SMatrix::<f64, 6, 6>::zeros();
                k.fixed_view_mut::<2, 6>(0, 0).copy_from(df);
                k.set_row(2, &(hpp.transpose() * df));
                k.fixed_view_mut::<2, 6>(3, 0).copy_from(&(-df));
                k.set_row(5, &(hcp.transpose() * df));
                k
            };
            let mut kq = q_of(&dfq);
            let mut kv = q_of(&dfv);
            // explicit angle dependence of the lever arms: d(h_perp . F)/dphi = -h . F
            kq[(2, 2)] -= hp.dot(&force);
            kq[(5, 5)] -= hc.dot(&force);
            // torsional SDE: m = kt (phi_c - phi_p) + bt (w_c - w_p), +m on p, -m on c
            kq[(2, 5)] += kt;
            kq[(2, 2)] -= kt;
            kq[(5, 5)] -= kt;
            kq[(5, 2)] += kt;
            kv[(2, 5)] += bt;
            kv[(2, 2)] -= bt;
            kv[(5, 5)] -= bt;
            kv[(5, 2)] += bt;
            // a 3 x 3 block of Q divided by the mass, mass, inertia of its rows
            let blk = |m: &SMatrix<f64, 6, 6>, r: usize, c: usize| -> Matrix3<f64> {
                Matrix3::from_fn(|i, j| row_scale[i] * m[(r + i, c + j)])
            };
            {
                let bp = &mut jac.bodies[p];
                bp.aq[SELF] += blk(&kq, 0, 0);
                bp.av[SELF] += blk(&kv, 0, 0);
                bp.aq[NEXT] += blk(&kq, 0, 3);
                bp.av[NEXT] += blk(&kv, 0, 3);
            }
            let bc = &mut jac.bodies[k];
            bc.aq[SELF] += blk(&kq, 3, 3);
            bc.av[SELF] += blk(&kv, 3, 3);
            bc.aq[PREV] += blk(&kq, 3, 0);
            bc.av[PREV] += blk(&kv, 3, 0);
        }
        let damping = self.relaxation.damping;
        if damping != 0.0 {
            for b in jac.bodies.iter_mut() {
                for r in 0..3 {
                    b.av[SELF][(r, r)] -= damping;
                }
            }
        }
        // transverse damping of the body centres (elements::transverse)
        let transverse = self.transverse();
        if transverse.acts() {
            for (i, b) in jac.bodies.iter_mut().enumerate() {
                let o = BODY_DOF * i;
                let (d_v, d_phi) = transverse.partials(y[o + 2], [y[o + 3], y[o + 4]]);
                for r in 0..2 {
                    b.aq[SELF][(r, 2)] += d_phi[r];
                    for c in 0..2 {
                        b.av[SELF][(r, c)] += d_v[r][c];
                    }
                }
            }
        }
        // Pulley load damping (eq. 24, Fig. 13), on the hub or, through a
        // decoupler, on its rotor; the decoupler's terms.
        for j in 0..np {
            let pc = &pulleys[j];
            let Some(dc) = &pc.decoupler else {
                if !pc.speed_driven {
                    jac.pw[j][j] += pc.balance_partials().0;
                }
                continue;
            };
            let d = pc.decoupler_offset;
            let (twist, w_r) = (y[d], y[d + 1]);
            let law = dc.law(twist, dc.relative_rate(omega_p[j], w_r));
            let s = dc.sense;
            // w = s (omega_h - omega_r): dw/d omega_h = s, dw/d omega_r = -s;
            // the hub's torque is -s M, the rotor's +s M
            let free = if pc.speed_driven { 0.0 } else { 1.0 };
            let inv_r = pc.rotor_inv_inertia;
            jac.dec[j] = DecouplerJacobian {
                tt: law.rate_d_twist,
                th: free * law.rate_d_rate * s,
                tr: -law.rate_d_rate * s,
                rt: s * law.torque_d_twist * inv_r,
                rh: free * law.torque_d_rate * inv_r,
                rr: (-law.torque_d_rate - pc.load_damping) * inv_r,
                ht: free * -s * law.torque_d_twist * pc.inv_inertia,
                hr: free * law.torque_d_rate * pc.inv_inertia,
                dt: (1.0 - free) * s * law.torque_d_twist,
                dr: (1.0 - free) * -law.torque_d_rate,
            };
            if !pc.speed_driven {
                jac.pw[j][j] -= law.torque_d_rate * pc.inv_inertia;
            }
        }
        // Tensioner arms: spring, damper, pivot friction and the lever of
        // the hub force (its angle derivative at a given force)
        for j in 0..np {
            let pc = &self.pulleys[j];
            let Some(arm) = &pc.arm else { continue };
            let (a, w) = (y[pc.arm_offset], y[pc.arm_offset + 1]);
            let own = arm.torque(a, w);
            let inv = inv_arm[j];
            let aj = &mut jac.arm[j];
            aj.aa += (own.d_angle + arm.moment(a, hub_force[j]).1) * inv;
            aj.ar += own.d_rate * inv;
        }
    }
}

/// What the contact along the body reads: the friction law, the state, the
/// pulley speeds, the pulleys and their centres with velocities (see
/// `jacobian_impl`).
type Along<'a, L> = (
    &'a L,
    &'a [f64],
    &'a [f64; MAX_PULLEYS],
    &'a [crate::model::system::PulleyConst; MAX_PULLEYS],
    &'a [[f64; 4]; MAX_PULLEYS],
);

/// Per pulley on a tensioner arm: c'(alpha), c''(alpha) alpha', 1 / I_arm
/// (see `jacobian_impl`).
#[derive(Clone, Copy)]
struct Arms<'a> {
    lever: &'a [Vector2<f64>; MAX_PULLEYS],
    lever_rate: &'a [Vector2<f64>; MAX_PULLEYS],
    inv_arm: &'a [f64; MAX_PULLEYS],
}

impl BeltSystem {
    /// The bodies' contact rows and columns with the contact along the body
    /// (`contact.points` = K > 1, [`contact::segment_of`]): forces and
    /// moments at the points, so each body's angle and spin columns and its
    /// moment row too. Accumulates the force on each arm's hub into
    /// `hub_force`.
    #[inline(always)]
    fn contact_along_rows<const K: usize>(
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
        pulleys: &[crate::model::system::PulleyConst; MAX_PULLEYS],
        centre: &[[f64; 4]; MAX_PULLEYS],
        hub_force: &mut [[f64; 2]; MAX_PULLEYS],
        jac: &mut Jacobian,
        arms: &Arms,
    ) {
        let o = BODY_DOF * i;
        let (inv_m, inv_i) = (self.inv_mass, self.inv_inertia);
        let rows = Vector3::new(inv_m, inv_m, inv_i);
        let hl = self.half_length;
        // the body's sin/cos once, and only if a pulley is within reach
        let mut sin_cos = None;
        let zf = self.zone_factor[i];
        for j in 0..self.np {
            let pc = &pulleys[j];
            let [cx, cy, cvx, cvy] = centre[j];
            let r = [y[o] - cx, y[o + 1] - cy];
            if r[0] * r[0] + r[1] * r[1] >= pc.reach * pc.reach {
                continue;
            }
            let &mut (sn, cs) = sin_cos.get_or_insert_with(|| trig::sin_cos(y[o + 2]));
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
                v: [y[o + 3] - cvx, y[o + 4] - cvy],
                h: [hl * cs, hl * sn],
                w: y[o + 5],
                z: y[o + 6],
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
                    b.aq[SELF][(r, c)] += aq[r];
                    b.av[SELF][(r, c)] += au[r];
                }
            }
            b.az += acc(d.force_z, d.moment_z);
            b.gq += d.creep_q;
            b.gv += d.creep_u;
            // impulse rows: belt torque -sum lever f, hub force -F
            jac.impulse[i][j] = ImpulseColumns {
                tq: -d.torque_q,
                tv: -d.torque_u,
                tz: -d.torque_z,
                hq: -d.force_q,
                hv: -d.force_u,
                hz: -d.force_z,
            };
            let k = -pc.balance_partials().1;
            if free {
                b.aw[j] += acc(d.force_w, d.moment_w);
                b.gw[j] += d.creep_w;
                jac.tw[j] -= d.torque_w;
                jac.hw[j] -= d.force_w;
                // the pulley's acceleration through its belt torque (eq. 24)
                b.pq[j] = k * d.torque_q;
                b.pv[j] = k * d.torque_u;
                b.pz[j] = k * d.torque_z;
                jac.pw[j][j] += k * d.torque_w;
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
                ba.aa[j] = acc(f_a, m_a);
                ba.ar[j] = acc(f_r, m_r);
                ba.ga[j] = -(dot2(&d.creep_q, &dc) + dot2(&d.creep_u, &ddc));
                ba.gr[j] = -dot2(&d.creep_u, &dc);
                ba.rq[j] = -(dc.transpose() * d.force_q) * inv;
                ba.rv[j] = -(dc.transpose() * d.force_u) * inv;
                ba.rz[j] = -dc.dot(&d.force_z) * inv;
                let aj = &mut jac.arm[j];
                aj.aa -= dc.dot(&f_a) * inv;
                aj.ar -= dc.dot(&f_r) * inv;
                let t_a = dot2(&d.torque_q, &dc) + dot2(&d.torque_u, &ddc);
                let t_r = dot2(&d.torque_u, &dc);
                aj.ta += t_a;
                aj.tr += t_r;
                aj.fa -= f_a;
                aj.fr -= f_r;
                if free {
                    aj.aw -= dc.dot(&d.force_w) * inv;
                    aj.pa -= k * t_a;
                    aj.pr -= k * t_r;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drive::Drive;
    use crate::model::params::{
        ArmStops, DecouplerParams, DriveParams, FrictionLaw, PulleyParams, TensionerArm,
    };
    use crate::model::system::{NoRecord, Workspace};

    /// A small two-pulley drive (r = 50 and 45 mm) with 36 bodies at 120 N
    /// and the automatic contact damping ramp, which differs between the
    /// pulleys (p_max = 12.9 and 14.1 um, half their penetrations).
    fn drive(law: FrictionLaw, speed_driven: bool) -> Drive {
        let mut p = DriveParams::default();
        p.belt.n_bodies = 36;
        p.belt.preload = 120.0;
        p.friction.law = law;
        p.friction.dv = 1e-2;
        p.probe_body = 0;
        let mut p1 = PulleyParams::paper_5pk(0.0, 0.0);
        p1.radius = 0.05;
        let mut p2 = p1.clone();
        p2.radius = 0.045;
        p2.x = 0.25;
        p2.load_damping = 0.3;
        p.pulleys = vec![p1, p2];
        if speed_driven {
            p.pulleys[0].speed_driven = true;
            p.pulleys[0].omega_ramp = -20.0;
            p.pulleys[0].ramp_time = 0.01;
            p.pulleys[0].torque_ramp = 0.0;
        }
        Drive::mounted(&p, 0.0).unwrap()
    }

    /// Compares the analytic Jacobian with central differences of the
    /// right-hand side, column by column (the dissipated-energy row excluded:
    /// the W-method leaves it out; the input-energy and impulse rows
    /// included). Returns the number of
    /// columns checked.
    fn check(sys: &BeltSystem, t: f64, y: &[f64]) -> usize {
        let dim = sys.dim();
        let mut jac = Jacobian::new(sys);
        sys.jacobian(t, y, &mut jac);
        let dense = jac.to_dense(sys);
        let e_rows = sys.energy_offset();
        // every state but the dissipated-energy accumulator
        let states: Vec<usize> = (0..=e_rows).chain(e_rows + 2..dim).collect();
        let (mut a, mut b) = (vec![0.0; dim], vec![0.0; dim]);
        let mut ws = Workspace::new();
        let mut yp = y.to_vec();
        let mut checked = 0;
        // a body's velocity: its column is held to the row's largest
        // velocity entry, not the row's largest (a spring's), so that the
        // dampers' partials (~1e-6 of the springs') are checked too
        let velocity = |cc: usize| cc < BODY_DOF * sys.n && (3..6).contains(&(cc % BODY_DOF));
        for &c in &states {
            // relative steps: positions ~0.1 m, z ~1e-5 m; the bodies'
            // velocities ~1 m/s (spins ~30 rad/s) by 1e-6 of at least 1 (the
            // right-hand side is smooth in them at this scale: a step well
            // inside the friction law's dv = 1e-2 m/s; smaller steps lose
            // digits to rounding in the spin rows, I ~ 1e-7 kg m^2)
            let scale = if c < BODY_DOF * sys.n && c % BODY_DOF == 6 {
                1e-11
            } else if velocity(c) {
                1e-6 * y[c].abs().max(1.0)
            } else {
                1e-8 * y[c].abs().max(1e-2)
            };
            yp[c] = y[c] + scale;
            sys.rhs(&mut ws, t, &yp, &mut a, &mut NoRecord);
            yp[c] = y[c] - scale;
            sys.rhs(&mut ws, t, &yp, &mut b, &mut NoRecord);
            yp[c] = y[c];
            for &r in &states {
                let fd = (a[r] - b[r]) / (2.0 * scale);
                let an = dense[r * dim + c];
                // tolerance relative to the row's largest entry (finite
                // differences lose digits on the small ones); in a velocity
                // column, the row's largest velocity entry
                let row_max = states
                    .iter()
                    .filter(|&&cc| !velocity(c) || velocity(cc))
                    .map(|&cc| dense[r * dim + cc].abs())
                    .fold(0.0, f64::max);
                assert!(
                    (fd - an).abs() <= 1e-5 * row_max + 1e-6 * an.abs().max(fd.abs()),
                    "d f[{r}] / d y[{c}]: analytic {an:e}, differences {fd:e} (row max {row_max:e})"
                );
            }
            checked += 1;
        }
        checked
    }

    /// Perturbs a mounted drive into a generic running state: velocities,
    /// spins, creep at various levels, pulley speeds.
    fn running_state(d: &Drive, creep: &[f64]) -> Vec<f64> {
        let sys = d.system();
        let mut y = d.state().to_vec();
        for i in 0..sys.n {
            let o = BODY_DOF * i;
            let s = (i as f64 * 0.7).sin();
            y[o] += 1e-5 * s;
            y[o + 1] -= 2e-5 * (i as f64 * 1.3).cos();
            y[o + 2] += 0.01 * s;
            y[o + 3] = 0.9 * s;
            y[o + 4] = -0.4 * (i as f64).cos();
            y[o + 5] = 30.0 * s;
            y[o + 6] = creep[i % creep.len()];
        }
        for j in 0..sys.np {
            y[sys.pulley_offset(j) + 1] = -18.0 - j as f64;
        }
        // every third body in contact nearly sticks: v_T a fraction of dv
        for i in (0..sys.n).step_by(3) {
            let o = BODY_DOF * i;
            for j in 0..sys.np {
                let pc = &sys.pulleys[j];
                let r = Vector2::new(y[o] - pc.cx, y[o + 1] - pc.cy);
                if r.norm_squared() < pc.radius2 {
                    let nrm = r.normalize();
                    let tau = perp(nrm);
                    let w = sys.pulley_speed(j, 0.02, &y);
                    let v = (w * pc.lever - 3e-3) * tau + 0.01 * nrm;
                    y[o + 3] = v.x;
                    y[o + 4] = v.y;
                }
            }
        }
        y
    }

    #[test]
    fn jacobian_matches_finite_differences_for_every_force_law() {
        // just beyond the cap, so that differences do not straddle it
        let cap_creep = 1.5e-4 * (1.0 + 1e-6);
        // the SDE's damper across the gap as along it (the default, 1) and
        // along the gap only (the paper's, 0)
        for (law, shear) in [
            (FrictionLaw::Creep, 0.0),
            (FrictionLaw::Creep, 1.0),
            (FrictionLaw::Kubas2014, 1.0),
            (FrictionLaw::Kubas2014, 0.0),
        ] {
            for speed_driven in [false, true] {
                let mut p = drive(law, speed_driven).params().clone();
                p.belt.shear_damping_factor = shear;
                let d = Drive::mounted(&p, 0.0).unwrap();
                assert_eq!(d.system().axial.bt, shear * d.system().axial.b);
                assert_eq!(d.system().friction.creep_max, 1e-4);
                // each pulley its own automatic ramp, half its penetration
                let sys = d.system();
                for j in 0..2 {
                    let p0 = d.layout().wrap_of(j).unwrap().penetration;
                    assert_eq!(sys.pulleys[j].inv_p_max, 1.0 / (0.5 * p0));
                }
                assert_ne!(sys.pulleys[0].inv_p_max, sys.pulleys[1].inv_p_max);
                // creep in the elastic range, in the softening range, at the
                // cap (sliding), and zero (stick at v_T ~ 0 for kubas2014)
                let y = running_state(&d, &[0.0, 3e-5, -7e-5, 1.2e-4, -1.3e-4, cap_creep]);
                // one body per pulley onto the middle of its pulley's ramp
                let mut y = y;
                for (j, pc) in sys.pulleys[..2].iter().enumerate() {
                    let i = (0..sys.n)
                        .find(|&i| {
                            let o = BODY_DOF * i;
                            let r = Vector2::new(y[o] - pc.cx, y[o + 1] - pc.cy);
                            r.norm_squared() < pc.radius2
                        })
                        .unwrap_or_else(|| panic!("a body on pulley {j}"));
                    let o = BODY_DOF * i;
                    let r = Vector2::new(y[o] - pc.cx, y[o + 1] - pc.cy);
                    let on_ramp = Vector2::new(pc.cx, pc.cy)
                        + r.normalize() * (pc.radius - 0.5 / pc.inv_p_max);
                    y[o] = on_ramp.x;
                    y[o + 1] = on_ramp.y;
                }
                let cols = check(d.system(), 0.02, &y);
                assert_eq!(cols, d.system().dim() - 1);
            }
        }
    }

    /// The contact along the body (`contact.points` 2, 3 and 5): the body's
    /// angle and spin columns and its moment row, the creep rate of the
    /// weighted sliding velocity, both friction laws, on a torque-driven
    /// and a speed-driven pulley, and on a tensioner arm's pulley.
    #[test]
    fn jacobian_covers_the_contact_along_the_body() {
        for (points, law, speed_driven, arm) in [
            (3, FrictionLaw::Creep, false, false),
            (3, FrictionLaw::Kubas2014, false, false),
            (3, FrictionLaw::Creep, true, false),
            (2, FrictionLaw::Creep, false, false),
            (5, FrictionLaw::Kubas2014, true, false),
            (3, FrictionLaw::Creep, false, true),
        ] {
            let mut p = drive(law, speed_driven).params().clone();
            p.contact.points = points;
            if arm {
                p.pulleys[1].arm = Some(TensionerArm {
                    pivot: [0.3, 0.06],
                    inertia: 2e-3,
                    stiffness: 40.0,
                    damping: 0.05,
                    ..Default::default()
                });
            }
            let d = Drive::mounted(&p, 0.0).unwrap();
            let sys = d.system();
            assert_eq!(sys.points, points);
            let mut y = running_state(&d, &[0.0, 3e-5, -7e-5, 1.2e-4, -1.3e-4]);
            if arm {
                let o = sys.pulleys[1].arm_offset;
                y[o] = 2e-4;
                y[o + 1] = -0.3;
            }
            let mut jac = Jacobian::new(sys);
            sys.jacobian(0.02, &y, &mut jac);
            // the contact moment couples the angles of bodies on the wraps
            let touching = jac.bodies.iter().filter(|b| b.touching != 0).count();
            assert!(touching > 0);
            assert!(
                jac.bodies.iter().any(|b| b.aq[SELF][(2, 0)] != 0.0),
                "moment row"
            );
            assert!(
                jac.impulse.iter().any(|b| b[0].hq[(0, 2)] != 0.0),
                "angle column"
            );
            let cols = check(sys, 0.02, &y);
            assert_eq!(cols, sys.dim() - 1);
        }
    }

    /// The decoupler's rows and columns, on a torque-driven and on a
    /// speed-driven hub, with the clutch engaged, in its band and
    /// overrunning; the rest of the Jacobian stays right around it.
    #[test]
    fn jacobian_covers_the_decoupler() {
        for speed_driven in [false, true] {
            let mut p = drive(FrictionLaw::Creep, speed_driven).params().clone();
            // hub 1 (speed-driven in the second case) and hub 2 (torque-driven)
            for (j, cw) in [(0, true), (1, false)] {
                p.pulleys[j].decoupler = Some(DecouplerParams {
                    clockwise: cw,
                    ..Default::default()
                });
                p.pulleys[j].load_damping = 0.3;
            }
            let d = Drive::mounted(&p, 0.0).unwrap();
            let sys = d.system();
            assert_eq!(sys.n_decouplers, 2);
            let base = running_state(&d, &[0.0, 3e-5, -7e-5]);
            // hub speeds are -18 and -19 rad/s (running_state), or the
            // prescription -20 rad/s; u = k twist + d w with k = 30, d = 0.02
            for (twist, w_r) in [(0.1, -17.0), (1e-4, -18.0), (0.02, -40.0), (-0.01, 5.0)] {
                let mut y = base.clone();
                for j in 0..2 {
                    let o = sys.pulleys[j].decoupler_offset;
                    y[o] = twist * (1.0 + 0.1 * j as f64);
                    y[o + 1] = w_r;
                }
                let cols = check(sys, 0.02, &y);
                assert_eq!(cols, sys.dim() - 1);
            }
        }
    }

    /// The tensioner arm's rows and columns (its own spring, damper, pivot
    /// friction in and beyond the friction's ramp, the hub force's lever,
    /// every contact on the moving pulley and the pulley's friction torque),
    /// on a torque-driven and on a speed-driven tensioner pulley, with a
    /// decoupler on the other pulley; the rest of the Jacobian stays right
    /// around it.
    #[test]
    fn jacobian_covers_the_tensioner_arm() {
        // end stops at -5e-5 and 1e-4 rad: the states below press the lower
        // (-1e-4, in the stop's damping ramp) and the upper stop
        let stops = ArmStops {
            min_angle: -5e-5,
            max_angle: 1e-4,
            ..ArmStops::default()
        };
        for (law, speed_driven, stops) in [
            (FrictionLaw::Creep, false, None),
            (FrictionLaw::Kubas2014, false, None),
            (FrictionLaw::Creep, true, None),
            (FrictionLaw::Creep, false, Some(stops)),
            (FrictionLaw::Kubas2014, true, Some(stops)),
        ] {
            let mut p = drive(law, false).params().clone();
            // the arm carries pulley 2 (0.25, 0) from a pivot 80 mm above
            // and behind it
            p.pulleys[1].arm = Some(TensionerArm {
                pivot: [0.3, 0.06],
                inertia: 2e-3,
                stiffness: 40.0,
                damping: 0.05,
                friction: 1.5,
                stops,
            });
            p.pulleys[1].speed_driven = speed_driven;
            p.pulleys[0].decoupler = Some(DecouplerParams::default());
            let d = Drive::mounted(&p, 0.0).unwrap();
            let sys = d.system();
            assert_eq!(sys.n_arms, 1);
            let base = running_state(&d, &[0.0, 3e-5, -7e-5]);
            // (angle, rate): friction in its ramp (|rate| < 0.01 rad/s) and
            // beyond it, the centre moving both ways
            for (angle, rate) in [(2e-4, 0.004), (-1e-4, -0.3), (3e-4, 2.0)] {
                let mut y = base.clone();
                let o = sys.pulleys[1].arm_offset;
                y[o] = angle;
                y[o + 1] = rate;
                let cols = check(sys, 0.02, &y);
                assert_eq!(cols, sys.dim() - 1);
                // the arm's row is really coupled to the bodies
                let mut jac = Jacobian::new(sys);
                sys.jacobian(0.02, &y, &mut jac);
                assert!(jac.arm_bodies.iter().any(|b| b.rq[1].norm() > 0.0));
            }
        }
    }

    /// The AVX2 build computes the same numbers to the last bit (it has no
    /// FMA), so results do not depend on the CPU the FMU runs on.
    #[test]
    fn avx2_build_matches_baseline_to_the_bit() {
        if !Isa::Avx2.available() {
            return;
        }
        for law in [FrictionLaw::Creep, FrictionLaw::Kubas2014] {
            let d = drive(law, false);
            let sys = d.system();
            let y = running_state(&d, &[0.0, 3e-5, -7e-5, 1.2e-4]);
            let (mut a, mut b) = (Jacobian::new(sys), Jacobian::new(sys));
            sys.jacobian_with(Isa::Baseline, 0.02, &y, &mut a);
            sys.jacobian_with(Isa::Avx2, 0.02, &y, &mut b);
            let (mut va, mut vb) = (Vec::new(), Vec::new());
            a.save(&mut va);
            b.save(&mut vb);
            assert!(va.iter().any(|&v| v != 0.0));
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&va), bits(&vb), "{law:?}");
        }
    }
}
