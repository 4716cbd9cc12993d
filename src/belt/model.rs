//! Equations of motion of belt bodies and pulleys (eq. 20-24) with contact
//! (eq. 4-11) and friction (eq. 12-19): the right-hand side of the ODE.
//!
//! State layout (one contiguous `f64` vector, bodies first so the Jacobian
//! of the chain is banded):
//! * body i: `[x, y, phi, vx, vy, omega, z]` at `7 i`, z = creep displacement;
//! * pulley j: `[theta, omega]` at `7 n + 2 j`;
//! * `[work_in, energy_dissipated]` last.

use super::contact::ContactLaw;
use super::friction::Friction;
use super::layout::Layout;
use super::params::{DriveParams, FrictionLaw, MAX_PULLEYS};
use super::trig;
use std::sync::{Mutex, TryLockError};

/// Values per body in the state vector.
pub const BODY_DOF: usize = 7;

/// Inputs held over a communication step: value at `t0` plus a rate (FMI
/// input derivatives), so inputs ramp linearly within the step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Inputs {
    pub t0: f64,
    pub torque: [f64; MAX_PULLEYS],
    pub torque_rate: [f64; MAX_PULLEYS],
    pub omega_ref: [f64; MAX_PULLEYS],
    pub omega_ref_rate: [f64; MAX_PULLEYS],
}

/// Constant data of one pulley in the hot loop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PulleyConst {
    pub cx: f64,
    pub cy: f64,
    pub radius: f64,
    pub radius2: f64,
    pub inv_inertia: f64,
    pub inertia: f64,
    pub mu_s: f64,
    pub mu_k: f64,
    pub speed_driven: bool,
    pub load_damping: f64,
    pub torque_ramp: f64,
    pub omega_ramp: f64,
    pub ramp_time: f64,
}

/// Observer of the force evaluation, used for outputs. The hot path uses
/// [`NoRecord`], whose calls compile away.
pub trait Recorder {
    const ACTIVE: bool;
    /// Translational SDE `k` (between body k-1 and body k): its tension and
    /// the midpoint of the gap it spans.
    fn sde(&mut self, _k: usize, _tension: f64, _mid: [f64; 2]) {}
    /// Contact of `body` with `pulley`: normal force, signed friction force
    /// along the pulley tangent, relative velocity v_T, penetration.
    fn contact(&mut self, _body: usize, _pulley: usize, _n: f64, _f: f64, _v_t: f64, _p: f64) {}
    /// Force the belt exerts on a pulley's hub.
    fn hub_force(&mut self, _pulley: usize, _fx: f64, _fy: f64) {}
    /// Per pulley: torque of the belt, torque a speed drive must supply, acceleration.
    fn pulley(&mut self, _pulley: usize, _belt_torque: f64, _drive_torque: f64, _alpha: f64) {}
    fn power(&mut self, _input: f64, _dissipated: f64) {}
}

pub struct NoRecord;
impl Recorder for NoRecord {
    const ACTIVE: bool = false;
}

/// The belt drive as an ODE system.
#[derive(Clone, Debug, PartialEq)]
pub struct BeltSystem {
    pub n: usize,
    pub np: usize,
    pub pulleys: [PulleyConst; MAX_PULLEYS],
    pub half_length: f64,
    pub mass: f64,
    pub inv_mass: f64,
    pub inertia: f64,
    pub inv_inertia: f64,
    /// Translational SDE: stiffness EA/l, damping B/l.
    pub k_axial: f64,
    pub b_axial: f64,
    /// Torsional SDE: stiffness EI/l, damping.
    pub k_bend: f64,
    pub b_bend: f64,
    pub gravity: f64,
    pub contact: ContactLaw,
    pub friction: Friction,
    /// Friction factor of every body (1 outside the modified zone).
    pub zone_factor: Vec<f64>,
    /// Squared regularisation length of the SDE direction (zero-length gap).
    pub eps2: f64,
    /// Mass-proportional damping [1/s] used only while the mounted belt is
    /// relaxed into static equilibrium (see `Drive::new`); 0 when running.
    pub relax_damping: f64,
    pub inputs: Inputs,
    /// Scratch of the right-hand side (not part of the model).
    pub scratch: Scratch,
}

pub(crate) use super::trig::wrap_angle;

/// Bodies per block of the right-hand side (scratch of ~9 KiB, stays in L1).
pub const BLOCK: usize = 64;

/// Structure-of-arrays scratch of one block of bodies (see [`BeltSystem::rhs`]).
#[derive(Clone)]
struct Block {
    // body m = 0..len + 2 (body i0 - 1 + m)
    x: [f64; BLOCK + 2],
    y: [f64; BLOCK + 2],
    phi: [f64; BLOCK + 2],
    vx: [f64; BLOCK + 2],
    vy: [f64; BLOCK + 2],
    w: [f64; BLOCK + 2],
    /// Half body vector (l/2) (cos phi, sin phi).
    hx: [f64; BLOCK + 2],
    hy: [f64; BLOCK + 2],
    // SDE k = 0..=len (SDE i0 + k, between body m = k and m = k + 1): force
    // on body k + 1 (minus it on body k), torque on body k + 1 and on body
    // k, dissipated power
    fx: [f64; BLOCK + 1],
    fy: [f64; BLOCK + 1],
    torque_cur: [f64; BLOCK + 1],
    torque_prev: [f64; BLOCK + 1],
    diss: [f64; BLOCK + 1],
    // body j = 0..len (body i0 + j): own forces, creep rate, contact test
    ofx: [f64; BLOCK],
    ofy: [f64; BLOCK],
    dz: [f64; BLOCK],
    /// min over pulleys of d^2 - r^2 (negative: inside a pulley)
    margin: [f64; BLOCK],
    contacts: Contacts,
}

/// Contacts evaluated per batch.
const CONTACTS: usize = 64;

/// A batch of body-pulley contacts of a block, structure of arrays.
#[derive(Clone)]
struct Contacts {
    // inputs: block body index, pulley, centre relative to the pulley,
    // velocity, creep, radius, pulley surface speed, friction coefficients
    body: [u32; CONTACTS],
    pulley: [u32; CONTACTS],
    rx: [f64; CONTACTS],
    ry: [f64; CONTACTS],
    vx: [f64; CONTACTS],
    vy: [f64; CONTACTS],
    z: [f64; CONTACTS],
    radius: [f64; CONTACTS],
    surface: [f64; CONTACTS],
    mu_s: [f64; CONTACTS],
    mu_k: [f64; CONTACTS],
    // results: force on the body, creep rate, power, recorded values
    fx: [f64; CONTACTS],
    fy: [f64; CONTACTS],
    dz: [f64; CONTACTS],
    diss: [f64; CONTACTS],
    normal: [f64; CONTACTS],
    f: [f64; CONTACTS],
    v_t: [f64; CONTACTS],
    p: [f64; CONTACTS],
}

impl Block {
    fn new() -> Self {
        Self {
            x: [0.0; BLOCK + 2],
            y: [0.0; BLOCK + 2],
            phi: [0.0; BLOCK + 2],
            vx: [0.0; BLOCK + 2],
            vy: [0.0; BLOCK + 2],
            w: [0.0; BLOCK + 2],
            hx: [0.0; BLOCK + 2],
            hy: [0.0; BLOCK + 2],
            fx: [0.0; BLOCK + 1],
            fy: [0.0; BLOCK + 1],
            torque_cur: [0.0; BLOCK + 1],
            torque_prev: [0.0; BLOCK + 1],
            diss: [0.0; BLOCK + 1],
            ofx: [0.0; BLOCK],
            ofy: [0.0; BLOCK],
            dz: [0.0; BLOCK],
            margin: [0.0; BLOCK],
            contacts: Contacts {
                body: [0; CONTACTS],
                pulley: [0; CONTACTS],
                rx: [0.0; CONTACTS],
                ry: [0.0; CONTACTS],
                vx: [0.0; CONTACTS],
                vy: [0.0; CONTACTS],
                z: [0.0; CONTACTS],
                radius: [0.0; CONTACTS],
                surface: [0.0; CONTACTS],
                mu_s: [0.0; CONTACTS],
                mu_k: [0.0; CONTACTS],
                fx: [0.0; CONTACTS],
                fy: [0.0; CONTACTS],
                dz: [0.0; CONTACTS],
                diss: [0.0; CONTACTS],
                normal: [0.0; CONTACTS],
                f: [0.0; CONTACTS],
                v_t: [0.0; CONTACTS],
                p: [0.0; CONTACTS],
            },
        }
    }

    /// Moves the last two bodies and the last SDE of a block of `len`
    /// bodies to the front: they are the first of the next block.
    #[inline(always)]
    fn carry(&mut self, len: usize) {
        for a in [
            &mut self.x,
            &mut self.y,
            &mut self.phi,
            &mut self.vx,
            &mut self.vy,
            &mut self.w,
            &mut self.hx,
            &mut self.hy,
        ] {
            a[0] = a[len];
            a[1] = a[len + 1];
        }
        for a in [
            &mut self.fx,
            &mut self.fy,
            &mut self.torque_cur,
            &mut self.torque_prev,
            &mut self.diss,
        ] {
            a[0] = a[len];
        }
    }
}

/// The right-hand side's block scratch, held by the system so that no
/// evaluation allocates or clears it. A clone gets its own; it takes no
/// part in comparisons.
pub struct Scratch(Mutex<Box<Block>>);

impl Scratch {
    fn new() -> Self {
        Self(Mutex::new(Box::new(Block::new())))
    }
}

impl Clone for Scratch {
    fn clone(&self) -> Self {
        Self::new()
    }
}

impl PartialEq for Scratch {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl std::fmt::Debug for Scratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Scratch")
    }
}

/// Sum in four interleaved partial sums (vectorises).
#[inline(always)]
fn sum(v: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let mut chunks = v.chunks_exact(4);
    for c in &mut chunks {
        for (a, x) in acc.iter_mut().zip(c) {
            *a += x;
        }
    }
    let rest: f64 = chunks.remainder().iter().sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + rest
}

impl BeltSystem {
    pub fn new(params: &DriveParams, layout: &Layout) -> Self {
        let l = layout.body_length;
        let b = &params.belt;
        let mass = b.mass_per_length * l;
        let inertia = mass * l * l / 12.0; // eq. 2
        let zero = PulleyConst {
            cx: 0.0,
            cy: 0.0,
            radius: 0.0,
            radius2: 0.0,
            inv_inertia: 0.0,
            inertia: 0.0,
            mu_s: 0.0,
            mu_k: 0.0,
            speed_driven: false,
            load_damping: 0.0,
            torque_ramp: 0.0,
            omega_ramp: 0.0,
            ramp_time: 1.0,
        };
        let mut pulleys = [zero; MAX_PULLEYS];
        for (pc, p) in pulleys.iter_mut().zip(&params.pulleys) {
            *pc = PulleyConst {
                cx: p.x,
                cy: p.y,
                radius: p.radius,
                radius2: p.radius * p.radius,
                inv_inertia: 1.0 / p.inertia,
                inertia: p.inertia,
                mu_s: p.mu_static,
                mu_k: p.mu_kinetic,
                speed_driven: p.speed_driven,
                load_damping: p.load_damping,
                torque_ramp: p.torque_ramp,
                omega_ramp: p.omega_ramp,
                ramp_time: p.ramp_time,
            };
        }
        let f = &params.friction;
        let n = b.n_bodies;
        let mut zone_factor = vec![1.0; n];
        for k in 0..f.zone_bodies {
            zone_factor[(f.zone_start + k) % n] = f.zone_factor;
        }
        let c = &params.contact;
        Self {
            n,
            np: params.pulleys.len(),
            pulleys,
            half_length: 0.5 * l,
            mass,
            inv_mass: 1.0 / mass,
            inertia,
            inv_inertia: 1.0 / inertia,
            k_axial: b.ea / l,
            b_axial: b.axial_damping / l,
            k_bend: b.bending_stiffness / l,
            b_bend: b.bending_damping / l,
            gravity: params.gravity,
            contact: ContactLaw {
                c1: c.c1 * l,
                c2: c.c2 * l,
                b: c.damping * l,
                inv_p_max: 1.0 / c.p_max,
            },
            friction: Friction::new(f.law, f.dv, f.creep_max, f.creep_damping_time),
            zone_factor,
            eps2: (1e-6 * l) * (1e-6 * l),
            relax_damping: 0.0,
            inputs: Inputs::default(),
            scratch: Scratch::new(),
        }
    }

    pub fn dim(&self) -> usize {
        BODY_DOF * self.n + 2 * self.np + 2
    }

    pub fn pulley_offset(&self, j: usize) -> usize {
        BODY_DOF * self.n + 2 * j
    }

    pub fn energy_offset(&self) -> usize {
        BODY_DOF * self.n + 2 * self.np
    }

    /// Torque input plus built-in ramp on pulley j at time t.
    #[inline]
    pub fn applied_torque(&self, j: usize, t: f64) -> f64 {
        let p = &self.pulleys[j];
        let inp = &self.inputs;
        inp.torque[j] + inp.torque_rate[j] * (t - inp.t0) + ramp(p, p.torque_ramp, t)
    }

    /// Prescribed speed of a speed-driven pulley j at time t, and its rate.
    #[inline]
    pub fn prescribed_speed(&self, j: usize, t: f64) -> (f64, f64) {
        let p = &self.pulleys[j];
        let inp = &self.inputs;
        let w = inp.omega_ref[j] + inp.omega_ref_rate[j] * (t - inp.t0) + ramp(p, p.omega_ramp, t);
        let dw = inp.omega_ref_rate[j] + ramp_rate(p, p.omega_ramp, t);
        (w, dw)
    }

    /// Angular speed of pulley j used by the contact: the state for
    /// torque-driven pulleys, the prescription for speed-driven ones.
    #[inline]
    pub fn pulley_speed(&self, j: usize, t: f64, y: &[f64]) -> f64 {
        if self.pulleys[j].speed_driven {
            self.prescribed_speed(j, t).0
        } else {
            y[self.pulley_offset(j) + 1]
        }
    }

    /// dy/dt = f(t, y). Allocates nothing.
    ///
    /// The bodies are processed in blocks of [`BLOCK`] with the block's
    /// data in structure-of-arrays scratch on the stack, in four steps that
    /// each loop over the block: (1) end points of every body (eq. 20-23,
    /// one branch-free sin/cos per body), (2) the translational and torsional
    /// SDE between neighbours, (3) contact and friction (eq. 4-19) of the
    /// bodies a cheap vectorised distance test finds inside a pulley, (4)
    /// the accelerations. Steps 1, 2 and the test of step 3 vectorise. The
    /// last body and SDE of a block are carried into the next, so every
    /// sin/cos and every SDE is evaluated once (one of each twice at the
    /// closing of the loop).
    pub fn rhs<R: Recorder>(&self, t: f64, y: &[f64], dy: &mut [f64], rec: &mut R) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked above).
            unsafe { self.rhs_avx2(t, y, dy, rec) };
            return;
        }
        self.rhs_portable(t, y, dy, rec);
    }

    /// [`Self::rhs`] compiled for AVX2 (4 doubles per vector instead of
    /// SSE2's 2). Same operations, so the same results to the last bit
    /// (no FMA: it would change rounding).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn rhs_avx2<R: Recorder>(&self, t: f64, y: &[f64], dy: &mut [f64], rec: &mut R) {
        self.rhs_impl(t, y, dy, rec);
    }

    /// [`Self::rhs`] for the baseline instruction set (SSE2 on x86-64),
    /// whatever the CPU supports; public for the test of the dispatch.
    #[doc(hidden)]
    pub fn rhs_portable<R: Recorder>(&self, t: f64, y: &[f64], dy: &mut [f64], rec: &mut R) {
        self.rhs_impl(t, y, dy, rec);
    }

    #[inline(always)]
    fn rhs_impl<R: Recorder>(&self, t: f64, y: &[f64], dy: &mut [f64], rec: &mut R) {
        let n = self.n;
        let np = self.np;
        assert!(y.len() >= self.dim() && dy.len() >= self.dim());
        let mut local = None;
        let mut guard = match self.scratch.0.try_lock() {
            Ok(g) => Some(g),
            Err(TryLockError::Poisoned(p)) => Some(p.into_inner()),
            // in use by another thread: a block of our own
            Err(TryLockError::WouldBlock) => None,
        };
        let blk: &mut Block = match guard.as_mut() {
            Some(g) => g,
            None => local.insert(Block::new()),
        };

        let mut omega_p = [0.0; MAX_PULLEYS];
        for (j, w) in omega_p.iter_mut().enumerate().take(np) {
            *w = self.pulley_speed(j, t, y);
        }
        let mut belt_torque = [0.0; MAX_PULLEYS];
        let mut p_diss = 0.0;

        let mut i0 = 0;
        while i0 < n {
            let len = BLOCK.min(n - i0);
            let first = i0 == 0;
            p_diss += self.block(blk, i0, len, first, y, dy, &omega_p, &mut belt_torque, rec);
            i0 += len;
            if i0 < n {
                blk.carry(len);
            }
        }

        // Pulleys (eq. 24).
        let mut p_in = 0.0;
        for j in 0..np {
            let pc = &self.pulleys[j];
            let o = self.pulley_offset(j);
            let w = omega_p[j];
            let applied = self.applied_torque(j, t);
            let load = pc.load_damping * w;
            dy[o] = w;
            let (alpha, drive) = if pc.speed_driven {
                let alpha = self.prescribed_speed(j, t).1;
                let drive = pc.inertia * alpha - belt_torque[j] - applied + load;
                (alpha, drive)
            } else {
                ((applied - load + belt_torque[j]) * pc.inv_inertia, 0.0)
            };
            dy[o + 1] = alpha;
            p_in += (applied + drive) * w;
            p_diss += load * w;
            if R::ACTIVE {
                rec.pulley(j, belt_torque[j], drive, alpha);
            }
        }
        let e = self.energy_offset();
        dy[e] = p_in;
        dy[e + 1] = p_diss;
        if R::ACTIVE {
            rec.power(p_in, p_diss);
        }
    }

    /// Bodies `i0..i0 + len` of the right-hand side (see [`Self::rhs`]).
    /// Returns the power dissipated in their contacts and left SDEs.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn block<R: Recorder>(
        &self,
        b: &mut Block,
        i0: usize,
        len: usize,
        first: bool,
        y: &[f64],
        dy: &mut [f64],
        omega_p: &[f64; MAX_PULLEYS],
        belt_torque: &mut [f64; MAX_PULLEYS],
        rec: &mut R,
    ) -> f64 {
        let n = self.n;
        let hl = self.half_length;
        assert!(len <= BLOCK);
        let mut p_diss = 0.0;

        // (1) Body data, index m <-> body i0 - 1 + m (cyclic); m = 0 and 1
        // were carried from the previous block unless this is the first.
        let m0 = if first { 0 } else { 2 };
        let last = i0 + len == n;
        let mut load = |m: usize, s: &[f64]| {
            b.x[m] = s[0];
            b.y[m] = s[1];
            b.phi[m] = s[2];
            b.vx[m] = s[3];
            b.vy[m] = s[4];
            b.w[m] = s[5];
        };
        // m = 0 of the first block is body n - 1, m = len + 1 of the last
        // is body 0; in between the bodies are contiguous.
        let (m_lo, m_hi) = (m0.max(1), if last { len + 1 } else { len + 2 });
        if first {
            load(0, &y[BODY_DOF * (n - 1)..BODY_DOF * n]);
        }
        let bodies = &y[BODY_DOF * (i0 + m_lo - 1)..BODY_DOF * (i0 + m_hi - 1)];
        for (m, s) in (m_lo..m_hi).zip(bodies.chunks_exact(BODY_DOF)) {
            load(m, s);
        }
        if last {
            load(len + 1, &y[..BODY_DOF]);
        }
        for m in m0..len + 2 {
            let (sn, cs) = trig::sin_cos(b.phi[m]);
            b.hx[m] = hl * cs;
            b.hy[m] = hl * sn;
        }

        // (2) SDE k joins the right end of body m = k to the left end of
        // body m = k + 1 (eq. 20-23); k = 0 was carried unless first.
        let (ks, bs, kt, bt, eps2) = (
            self.k_axial,
            self.b_axial,
            self.k_bend,
            self.b_bend,
            self.eps2,
        );
        let k0 = if first { 0 } else { 1 };
        for k in k0..len + 1 {
            let (p, c) = (k, k + 1);
            // end points (gap) and their velocities
            let d0 = (b.x[c] - b.hx[c]) - (b.x[p] + b.hx[p]);
            let d1 = (b.y[c] - b.hy[c]) - (b.y[p] + b.hy[p]);
            let dd0 = (b.vx[c] + b.w[c] * b.hy[c]) - (b.vx[p] - b.w[p] * b.hy[p]);
            let dd1 = (b.vy[c] - b.w[c] * b.hx[c]) - (b.vy[p] + b.w[p] * b.hx[p]);
            let d2 = d0 * d0 + d1 * d1;
            let rate = (d0 * dd0 + d1 * dd1) / (d2 + eps2);
            // Zero-rest-length Kelvin-Voigt element: elastic force EA/l * gap
            // vector, damping along the gap (regularised at zero gap).
            let fx = ks * d0 + bs * rate * d0;
            let fy = ks * d1 + bs * rate * d1;
            b.fx[k] = fx;
            b.fy[k] = fy;
            // torques of the end forces about each body's centre
            let t_cur = b.hx[c] * fy - b.hy[c] * fx; // (-h) x (-F)
            let t_prev = b.hx[p] * fy - b.hy[p] * fx; // h x F
            let dphi = trig::wrap_angle(b.phi[c] - b.phi[p]);
            let dw = b.w[c] - b.w[p];
            let moment = kt * dphi + bt * dw;
            b.torque_cur[k] = t_cur - moment;
            b.torque_prev[k] = t_prev + moment;
            b.diss[k] = bs * rate * rate * d2 + bt * dw * dw;
        }
        // dissipation of SDEs i0..i0 + len (each counted in its own block)
        p_diss += sum(&b.diss[..len]);
        if R::ACTIVE {
            for k in 0..len {
                let (p, c) = (k, k + 1);
                // the same gap and rate as above
                let d0 = (b.x[c] - b.hx[c]) - (b.x[p] + b.hx[p]);
                let d1 = (b.y[c] - b.hy[c]) - (b.y[p] + b.hy[p]);
                let dd0 = (b.vx[c] + b.w[c] * b.hy[c]) - (b.vx[p] - b.w[p] * b.hy[p]);
                let dd1 = (b.vy[c] - b.w[c] * b.hx[c]) - (b.vy[p] + b.w[p] * b.hx[p]);
                let d2 = d0 * d0 + d1 * d1;
                let rate = (d0 * dd0 + d1 * dd1) / (d2 + eps2);
                let l = d2.sqrt();
                let tension = ks * l + bs * rate * l;
                let mid = [
                    0.5 * ((b.x[c] - b.hx[c]) + (b.x[p] + b.hx[p])),
                    0.5 * ((b.y[c] - b.hy[c]) + (b.y[p] + b.hy[p])),
                ];
                rec.sde(i0 + k, tension, mid);
            }
        }

        // (3) Contact and friction (eq. 4-19): a vectorised test of the body
        // centre against every pulley circle, then the force laws only for
        // the bodies inside one.
        let weight = self.mass * self.gravity;
        for j in 0..len {
            b.ofx[j] = 0.0;
            b.ofy[j] = -weight;
            b.dz[j] = 0.0;
            b.margin[j] = f64::INFINITY;
        }
        // margin < 0 exactly when some d^2 < r^2 (a - b < 0 iff a < b)
        for pc in &self.pulleys[..self.np] {
            for j in 0..len {
                let (rx, ry) = (b.x[j + 1] - pc.cx, b.y[j + 1] - pc.cy);
                let v = rx * rx + ry * ry - pc.radius2;
                b.margin[j] = if v < b.margin[j] { v } else { b.margin[j] };
            }
        }
        // Bodies inside a pulley are collected (in body, then pulley
        // order) and evaluated in batches by a loop that vectorises.
        let zone = &self.zone_factor[i0..i0 + len];
        let bodies = &y[BODY_DOF * i0..BODY_DOF * (i0 + len)];
        let mut cnt = 0;
        for j in 0..len {
            if b.margin[j] >= 0.0 {
                continue;
            }
            let m = j + 1;
            let zf = zone[j];
            for (q, pc) in self.pulleys[..self.np].iter().enumerate() {
                let (rx, ry) = (b.x[m] - pc.cx, b.y[m] - pc.cy);
                if rx * rx + ry * ry >= pc.radius2 {
                    continue;
                }
                let k = &mut b.contacts;
                k.body[cnt] = j as u32;
                k.pulley[cnt] = q as u32;
                k.rx[cnt] = rx;
                k.ry[cnt] = ry;
                k.vx[cnt] = b.vx[m];
                k.vy[cnt] = b.vy[m];
                k.z[cnt] = bodies[BODY_DOF * j + 6];
                k.radius[cnt] = pc.radius;
                k.surface[cnt] = omega_p[q] * pc.radius;
                k.mu_s[cnt] = pc.mu_s * zf;
                k.mu_k[cnt] = pc.mu_k * zf;
                cnt += 1;
                if cnt == CONTACTS {
                    p_diss += self.contacts(b, cnt, i0, belt_torque, rec);
                    cnt = 0;
                }
            }
        }
        if cnt > 0 {
            p_diss += self.contacts(b, cnt, i0, belt_torque, rec);
        }

        // (4) Accelerations (eq. 20-23): own forces, the left SDE (j) and
        // the right SDE (j + 1) of each body.
        let (inv_m, inv_i, c) = (self.inv_mass, self.inv_inertia, self.relax_damping);
        let out = &mut dy[BODY_DOF * i0..BODY_DOF * (i0 + len)];
        for (j, d) in out.chunks_exact_mut(BODY_DOF).enumerate() {
            let m = j + 1;
            let ax = (b.ofx[j] - b.fx[j] + b.fx[j + 1]) * inv_m - c * b.vx[m];
            let ay = (b.ofy[j] - b.fy[j] + b.fy[j + 1]) * inv_m - c * b.vy[m];
            let torque = b.torque_cur[j] + b.torque_prev[j + 1];
            d[0] = b.vx[m];
            d[1] = b.vy[m];
            d[2] = b.w[m];
            d[3] = ax;
            d[4] = ay;
            d[5] = torque * inv_i - c * b.w[m];
            d[6] = b.dz[j];
        }
        p_diss
    }

    /// Contact and friction forces (eq. 4-19) of the first `cnt`
    /// collected contacts of a block, added to the bodies' own forces and
    /// the pulleys' belt torque in collection order. Returns their power.
    #[inline(always)]
    fn contacts<R: Recorder>(
        &self,
        b: &mut Block,
        cnt: usize,
        i0: usize,
        belt_torque: &mut [f64; MAX_PULLEYS],
        rec: &mut R,
    ) -> f64 {
        let k = &mut b.contacts;
        // one loop per friction law, so that each has no branch to vectorise
        let creep = self.friction.law == FrictionLaw::Creep;
        macro_rules! contact_loop {
            ($mu:expr) => {
                for c in 0..cnt {
                    let (rx, ry) = (k.rx[c], k.ry[c]);
                    let (vx, vy, z) = (k.vx[c], k.vy[c], k.z[c]);
                    // eq. 4-8: direction, penetration and its rate
                    let dist = (rx * rx + ry * ry).sqrt();
                    let inv = 1.0 / dist.max(1e-12);
                    let (nx, ny) = (rx * inv, ry * inv);
                    let p = k.radius[c] - dist;
                    let p_dot = -(vx * nx + vy * ny);
                    let (normal, elastic) = self.contact.normal_force(p, p_dot);
                    // eq. 14-18 with the pulley radius as lever: v_T = omega r_p - v.tau
                    let (tx, ty) = (-ny, nx);
                    let v_t = k.surface[c] - (vx * tx + vy * ty);
                    #[allow(clippy::redundant_closure_call)]
                    let mu = $mu(v_t, z, k.mu_s[c], k.mu_k[c]);
                    let f = mu * normal; // eq. 19, along +tau
                    k.fx[c] = normal * nx + f * tx;
                    k.fy[c] = normal * ny + f * ty;
                    k.dz[c] = self.friction.creep_rate(v_t, z);
                    k.diss[c] = (normal - elastic) * p_dot + f * v_t;
                    k.normal[c] = normal;
                    k.f[c] = f;
                    k.v_t[c] = v_t;
                    k.p[c] = p;
                }
            };
        }
        let fr = &self.friction;
        if creep {
            contact_loop!(|v, z, ms, mk| fr.creep_coefficient(v, z, ms, mk));
        } else {
            contact_loop!(|v, z, ms, mk| fr.kubas_coefficient(v, z, ms, mk));
        }
        let mut p_diss = 0.0;
        for c in 0..cnt {
            let (j, q) = (k.body[c] as usize, k.pulley[c] as usize);
            b.ofx[j] += k.fx[c];
            b.ofy[j] += k.fy[c];
            b.dz[j] += k.dz[c];
            belt_torque[q] -= k.radius[c] * k.f[c]; // eq. 24
            p_diss += k.diss[c];
            if R::ACTIVE {
                rec.contact(i0 + j, q, k.normal[c], k.f[c], k.v_t[c], k.p[c]);
                rec.hub_force(q, -k.fx[c], -k.fy[c]);
            }
        }
        p_diss
    }

    /// Discrete update after every accepted step: the creep displacement of a
    /// body that touches no pulley is reset, and kept within its cap.
    pub fn after_step(&self, y: &mut [f64]) {
        let cap = self.friction.creep_cap();
        for i in 0..self.n {
            let o = BODY_DOF * i;
            let (x, yy) = (y[o], y[o + 1]);
            let touching = self.pulleys[..self.np].iter().any(|pc| {
                let (rx, ry) = (x - pc.cx, yy - pc.cy);
                rx * rx + ry * ry < pc.radius2
            });
            y[o + 6] = if touching {
                y[o + 6].clamp(-cap, cap)
            } else {
                0.0
            };
        }
    }

    /// Kinetic and potential (elastic + gravity) energy of state `y`.
    pub fn energies(&self, y: &[f64]) -> (f64, f64) {
        let n = self.n;
        let hl = self.half_length;
        let mut kin = 0.0;
        let mut pot = 0.0;
        for i in 0..n {
            let o = BODY_DOF * i;
            let b = &y[o..o + BODY_DOF];
            kin += 0.5 * self.mass * (b[3] * b[3] + b[4] * b[4]) + 0.5 * self.inertia * b[5] * b[5];
            pot += self.mass * self.gravity * b[1];
            for pc in &self.pulleys[..self.np] {
                let dist = (b[0] - pc.cx).hypot(b[1] - pc.cy);
                pot += self.contact.energy(pc.radius - dist);
            }
            let q = &y[BODY_DOF * ((i + n - 1) % n)..];
            let (s, c) = b[2].sin_cos();
            let (sq, cq) = q[2].sin_cos();
            let gx = (b[0] - hl * c) - (q[0] + hl * cq);
            let gy = (b[1] - hl * s) - (q[1] + hl * sq);
            pot += 0.5 * self.k_axial * (gx * gx + gy * gy);
            let dphi = wrap_angle(b[2] - q[2]);
            pot += 0.5 * self.k_bend * dphi * dphi;
        }
        for j in 0..self.np {
            let w = y[self.pulley_offset(j) + 1];
            kin += 0.5 * self.pulleys[j].inertia * w * w;
        }
        (kin, pot)
    }
}

fn ramp(p: &PulleyConst, amp: f64, t: f64) -> f64 {
    if amp == 0.0 || t <= 0.0 {
        0.0
    } else if t >= p.ramp_time {
        amp
    } else {
        amp * t / p.ramp_time
    }
}

fn ramp_rate(p: &PulleyConst, amp: f64, t: f64) -> f64 {
    if amp != 0.0 && t > 0.0 && t < p.ramp_time {
        amp / p.ramp_time
    } else {
        0.0
    }
}
