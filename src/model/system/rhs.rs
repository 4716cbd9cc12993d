//! The right-hand side dy/dt = f(t, y) (eq. 20-24): the bodies block by
//! block in the structure-of-arrays scratch of [`super::workspace`], then
//! the pulleys, decouplers and tensioner arms.

use super::contact_kernels::{contact_along_arc, contact_arc, ArcOut};
use super::workspace::{
    body_sums, padded, sum, sum4, Block, BlockEnergy, Workspace, BLOCK, BODY_COL, PAD, SDE_COL,
};
use super::{BeltSystem, NoRecord, PulleyConst, Recorder, StoredEnergy, BODY_DOF};
use crate::model::elements::friction::{with_law, Law};
use crate::model::elements::sde::{self, AxialSde, TorsionalSde};
use crate::model::params::MAX_PULLEYS;
use crate::model::simd::{self, Isa};
use crate::model::trig;

/// What the body blocks of the right-hand side read and accumulate per
/// pulley: speeds and centres (x, y, vx, vy) in, belt torque and the belt's
/// force on a tensioner pulley's hub out.
struct PulleyState<'a> {
    omega: &'a [f64; MAX_PULLEYS],
    centre: &'a [[f64; 4]; MAX_PULLEYS],
    belt_torque: &'a mut [f64; MAX_PULLEYS],
    hub: &'a mut [[f64; 2]; MAX_PULLEYS],
}

/// The bodies `lo..hi` of a block (`len` bodies) whose centres lie within
/// `r2` (a squared radius) of the pulley centre `centre`: the one arc a
/// pulley's contact loop runs over, `None` when no body is that close.
/// Vectorised: every lane is tested, the padding masked.
#[inline(always)]
fn arc_range(b: &Block, len: usize, centre: &[f64; 4], r2: f64) -> Option<(usize, usize)> {
    let (cx, cy) = (centre[0], centre[1]);
    let (mut lo, mut hi) = (len, 0);
    let end = padded(len);
    assert!(end < BLOCK + 1 + PAD);
    for j in 0..end {
        let (rx, ry) = (b.x[j + 1] - cx, b.y[j + 1] - cy);
        let inside = (rx * rx + ry * ry < r2) & (j < len);
        lo = lo.min(if inside { j } else { len });
        hi = hi.max(if inside { j + 1 } else { 0 });
    }
    (lo < hi).then_some((lo, hi))
}

/// Adds the contact forces, creep rates (and, with `moments`, the contact
/// moments) of pulley `q` on the arc `lo..hi` to the bodies' own, reports
/// each contact to the recorder, and returns the arc's moment about the
/// pulley axis, its power and the sum of its forces on the bodies.
#[inline(always)]
fn collect_arc<R: Recorder>(
    b: &mut Block,
    i0: usize,
    q: usize,
    lo: usize,
    hi: usize,
    moments: bool,
    rec: &mut R,
) -> (f64, f64, [f64; 2]) {
    let end = lo + padded(hi - lo);
    for j in lo..end {
        b.ofx[j] += b.cfx[j];
        b.ofy[j] += b.cfy[j];
        b.dz[j] += b.cdz[j];
    }
    if moments {
        for j in lo..end {
            b.otq[j] += b.cmq[j];
        }
    }
    if R::ACTIVE {
        for j in lo..hi {
            let v = b.rec_q[j];
            if v[6] != 0.0 {
                rec.contact(i0 + j, q, v[0], v[1], v[2], v[3]);
                rec.belt_loss(v[7]);
                rec.creep_spring_power(v[8]);
            }
        }
    }
    let [torque, diss, fx, fy] = sum4(
        [&b.torque_q, &b.diss_q, &b.cfx, &b.cfy].map(|c| &c[lo..end]),
        hi - lo,
    );
    (torque, diss, [fx, fy])
}

/// Step (2) of [`BeltSystem::rhs`] over the SDEs `ks` of a block: SDE k
/// joins the right end of body m = k to the left end of body m = k + 1
/// (eq. 20-23); its forces, torques and dissipated power go to the SDE
/// columns. Built for the damper terms the drive has: the axial ones
/// ([`AxialSde::force_dissipation`]) and the torsional one
/// ([`TorsionalSde::moment_dissipation`]; without it the SDE's dissipation
/// is the axial damper's alone). With `ENERGY` also the SDE's elastic
/// energy ([`AxialSde::energy`], [`TorsionalSde::energy`]) to `esde`.
#[inline(always)]
fn sde_loop<const ALONG: bool, const ACROSS: bool, const BENDING: bool, const ENERGY: bool>(
    b: &mut Block,
    axial: AxialSde,
    bend: TorsionalSde,
    ks: std::ops::Range<usize>,
) {
    assert!(ks.end < BODY_COL.min(SDE_COL));
    for k in ks {
        let (p, c) = (k, k + 1);
        let (d, dd) = sde::gap(b.body_end(p), b.body_end(c));
        let ([fx, fy], diss) = axial.force_dissipation::<ALONG, ACROSS>(d, dd);
        b.fx[k] = fx;
        b.fy[k] = fy;
        // torques of the end forces about each body's centre
        let t_cur = b.hx[c] * fy - b.hy[c] * fx; // (-h) x (-F)
        let t_prev = b.hx[p] * fy - b.hy[p] * fx; // h x F
        let dphi = trig::wrap_angle(b.phi[c] - b.phi[p]);
        let dw = b.w[c] - b.w[p];
        let (moment, bend_diss) = bend.moment_dissipation::<BENDING>(dphi, dw);
        b.torque_cur[k] = t_cur - moment;
        b.torque_prev[k] = t_prev + moment;
        b.diss[k] = if BENDING { diss + bend_diss } else { diss };
        if ENERGY {
            // the elastic energy of both springs, beside their forces
            b.esde[k] = axial.energy(d[0] * d[0] + d[1] * d[1]) + bend.energy(dphi);
        }
    }
}

/// With `pad` (the AVX-512 build) a loop over `from..to` runs on to a
/// multiple of [`PAD`] bodies (see [`BeltSystem::block`]).
#[inline(always)]
fn upto(pad: bool, from: usize, to: usize) -> usize {
    if pad {
        from + padded(to - from)
    } else {
        to
    }
}

impl BeltSystem {
    /// dy/dt = f(t, y), with the scratch in `ws`. Allocates nothing.
    ///
    /// The bodies are processed in blocks of [`BLOCK`] with the block's
    /// data in structure-of-arrays scratch (`ws`), in four steps that
    /// each loop over the block: (1) end points of every body (eq. 20-23,
    /// one branch-free sin/cos per body), (2) the translational and torsional
    /// SDE between neighbours, (3) contact and friction (eq. 4-19) of the
    /// bodies a cheap vectorised distance test finds inside a pulley, (4)
    /// the accelerations. Steps 1, 2 and the test of step 3 vectorise. The
    /// last body and SDE of a block are carried into the next, so every
    /// sin/cos and every SDE is evaluated once (one of each twice at the
    /// closing of the loop).
    pub fn rhs<R: Recorder>(
        &self,
        ws: &mut Workspace,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
        rec: &mut R,
    ) {
        self.rhs_with::<R, false>(Isa::detected(), ws, t, y, dy, rec);
    }

    /// [`Self::rhs`] (the same `dy` to the last bit) and, in the same pass
    /// over the bodies, the stored energy of `y` (as
    /// [`Self::stored_energy`], to round-off): each SDE's and contact's
    /// energy beside its force, the creep springs' from the contact's
    /// elastic force, the bodies' kinetic energy from their velocities. A
    /// build of its own: [`Self::rhs`] does none of this work.
    pub fn rhs_energy(
        &self,
        ws: &mut Workspace,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
    ) -> StoredEnergy {
        self.rhs_with::<NoRecord, true>(Isa::detected(), ws, t, y, dy, &mut NoRecord)
    }

    /// [`Self::rhs`] (`ENERGY`: [`Self::rhs_energy`]) compiled for `isa`
    /// (the baseline if the CPU lacks it).
    #[inline]
    fn rhs_with<R: Recorder, const ENERGY: bool>(
        &self,
        isa: Isa,
        ws: &mut Workspace,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
        rec: &mut R,
    ) -> StoredEnergy {
        simd::dispatch_wide(
            isa,
            (ws, dy, rec),
            #[inline(always)]
            move |(ws, dy, rec)| self.rhs_impl::<R, false, ENERGY>(ws, t, y, dy, rec, false),
            #[inline(always)]
            move |(ws, dy, rec)| {
                self.rhs_impl::<R, true, ENERGY>(ws, t, y, dy, rec, isa == Isa::Avx512)
            },
        )
    }

    /// [`Self::rhs`] compiled for one instruction set, if the CPU has it
    /// (false if not); for the tests that the builds agree to the bit and
    /// for benchmarks. Public, but not part of the model's interface.
    #[doc(hidden)]
    pub fn rhs_build<R: Recorder>(
        &self,
        build: Isa,
        ws: &mut Workspace,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
        rec: &mut R,
    ) -> bool {
        if !build.available() {
            return false;
        }
        self.rhs_with::<R, false>(build, ws, t, y, dy, rec);
        true
    }

    /// [`Self::rhs_energy`] compiled for one instruction set, if the CPU
    /// has it (None if not); for the tests. Not part of the model's
    /// interface.
    #[doc(hidden)]
    pub fn rhs_energy_build(
        &self,
        build: Isa,
        ws: &mut Workspace,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
    ) -> Option<StoredEnergy> {
        build
            .available()
            .then(|| self.rhs_with::<NoRecord, true>(build, ws, t, y, dy, &mut NoRecord))
    }

    /// `WIDE`: compiled into a build with AVX (the layout conversions then
    /// move four bodies at a time); only the AVX2 and AVX-512 builds, called
    /// after the CPU check, set it. `pad`: the body loops run on to a
    /// multiple of [`PAD`] (the AVX-512 build, see [`Self::block`]).
    #[inline(always)]
    fn rhs_impl<R: Recorder, const WIDE: bool, const ENERGY: bool>(
        &self,
        ws: &mut Workspace,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
        rec: &mut R,
        pad: bool,
    ) -> StoredEnergy {
        let n = self.n;
        let np = self.np;
        assert!(y.len() >= self.dim() && dy.len() >= self.dim());
        let blk: &mut Block = &mut ws.block;
        let mut buf = None;
        let pulleys = self.pulleys_in_effect(&mut buf);

        let mut omega_p = [0.0; MAX_PULLEYS];
        for (j, w) in omega_p.iter_mut().enumerate().take(np) {
            *w = self.pulley_speed(j, t, y);
        }
        // pulley centres and their velocities (x, y, vx, vy): a tensioner's
        // pulley moves with its arm
        let mut centres = [[0.0; 4]; MAX_PULLEYS];
        for (j, c) in centres.iter_mut().enumerate().take(np) {
            let (p, v) = self.pulley_centre(j, y);
            *c = [p[0], p[1], v[0], v[1]];
        }
        let mut belt_torque = [0.0; MAX_PULLEYS];
        // force of the belt on each pulley's hub
        let mut hub = [[0.0; 2]; MAX_PULLEYS];
        let mut p_diss = 0.0;
        // with ENERGY: the bodies' kinetic energy, the SDEs' and contacts'
        // elastic energy, the creep springs' energy, the bodies' heights
        let mut energy = BlockEnergy::default();

        let mut i0 = 0;
        while i0 < n {
            let len = BLOCK.min(n - i0);
            let first = i0 == 0;
            let state = PulleyState {
                omega: &omega_p,
                centre: &centres,
                belt_torque: &mut belt_torque,
                hub: &mut hub,
            };
            p_diss += self.block::<R, WIDE, ENERGY>(
                blk,
                pulleys,
                i0,
                len,
                first,
                y,
                dy,
                state,
                rec,
                pad,
                &mut energy,
            );
            i0 += len;
            if i0 < n {
                blk.carry(len);
                if ENERGY {
                    blk.esde[0] = blk.esde[len];
                }
            }
        }

        let p_in = self.pulley_rates(
            pulleys,
            t,
            y,
            dy,
            &omega_p,
            &belt_torque,
            &hub,
            &mut p_diss,
            rec,
        );
        self.arm_rates(y, dy, &hub, &mut p_diss);
        let e = self.state_layout.energy();
        dy[e.work_in] = p_in;
        dy[e.dissipated] = p_diss;
        if R::ACTIVE {
            rec.power(p_in, p_diss);
        }
        if ENERGY {
            self.stored_energy_of(energy, y)
        } else {
            StoredEnergy::default()
        }
    }

    /// The pulleys' rows of the right-hand side (eq. 24): angle, speed,
    /// decoupler twist and rotor speed, impulses; the drives' and loads'
    /// power added to `p_diss` in pulley order. Returns the input power.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn pulley_rates<R: Recorder>(
        &self,
        pulleys: &[PulleyConst; MAX_PULLEYS],
        t: f64,
        y: &[f64],
        dy: &mut [f64],
        omega_p: &[f64; MAX_PULLEYS],
        belt_torque: &[f64; MAX_PULLEYS],
        hub: &[[f64; 2]; MAX_PULLEYS],
        p_diss: &mut f64,
        rec: &mut R,
    ) -> f64 {
        let np = self.np;
        // Pulleys (eq. 24).
        let mut p_in = 0.0;
        for j in 0..np {
            let pc = &pulleys[j];
            let o = self.state_layout.pulley(j);
            let w = omega_p[j];
            let applied = self.applied_torque(j, t);
            dy[o.angle] = w;
            let prescribed = if pc.speed_driven {
                self.prescribed_speed(j, t).1
            } else {
                0.0
            };
            let bal = if let Some(dc) = &pc.decoupler {
                // The load and the applied torque act on the rotor behind
                // the decoupler; the hub carries the clutch's -s M.
                let d = self.state_layout.decoupler(j);
                let (twist, w_r) = (y[d.twist], y[d.rotor_speed]);
                let rel = dc.relative_rate(w, w_r);
                let law = dc.law(twist, rel);
                let m = dc.sense * law.torque;
                let load = pc.load_damping * w_r;
                dy[d.twist] = law.twist_rate;
                dy[d.rotor_speed] = (applied + m - load) * pc.rotor_inv_inertia;
                let mut hub = *pc;
                hub.load_damping = 0.0;
                let bal = hub.balance(w, -m, belt_torque[j], prescribed);
                dy[o.speed] = bal.alpha;
                p_in += bal.drive * w + applied * w_r;
                // the rotor load's power, then the clutch's M w less the
                // spring's energy rate
                *p_diss += dc.dissipation_after(load * w_r, &law, twist, rel);
                if R::ACTIVE {
                    rec.decoupler(j, law.torque, w_r);
                }
                bal
            } else {
                let bal = pc.balance(w, applied, belt_torque[j], prescribed);
                dy[o.speed] = bal.alpha;
                let (power_in, power_load) = pc.power(w, applied, &bal);
                p_in += power_in;
                *p_diss += power_load;
                bal
            };
            if R::ACTIVE {
                rec.pulley(j, belt_torque[j], bal.drive, bal.alpha);
                rec.hub_force(j, hub[j][0], hub[j][1]);
            }
            let q = self.state_layout.impulses(j).range();
            dy[q].copy_from_slice(&[belt_torque[j], bal.drive, hub[j][0], hub[j][1]]);
        }
        p_in
    }

    /// The tensioner arms' rows (angle, rate, pivot friction deflection) of
    /// the right-hand side, with
    /// the belt's force on each arm's hub `hub`; their dissipation added to
    /// `p_diss`.
    #[inline(always)]
    fn arm_rates(
        &self,
        y: &[f64],
        dy: &mut [f64],
        hub: &[[f64; 2]; MAX_PULLEYS],
        p_diss: &mut f64,
    ) {
        let np = self.np;
        // Tensioner arms: I_arm alpha'' = (c - pivot) x F_hub + M_arm.
        for (j, pc) in self.pulleys[..np].iter().enumerate() {
            let Some(arm) = &pc.arm else { continue };
            let o = self.state_layout.arm(j);
            let (a, w) = (y[o.angle], y[o.rate]);
            dy[o.angle] = w;
            if self.relaxation.pulleys_held {
                dy[o.rate] = 0.0;
                dy[o.deflection] = 0.0;
                continue;
            }
            let moment = arm.moment(a, hub[j]).0;
            let f = arm.pivot_friction(y[o.deflection], w, hub[j]);
            dy[o.rate] = (moment + arm.torque(a, w).torque + f.torque) / arm.inertia;
            dy[o.deflection] = f.deflection_rate;
            *p_diss += arm.dissipation(a, w) + f.dissipation;
        }
    }

    /// Bodies `i0..i0 + len` of the right-hand side (see [`Self::rhs`]), in
    /// its four steps. Returns the power dissipated in their contacts and
    /// left SDEs.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn block<R: Recorder, const WIDE: bool, const ENERGY: bool>(
        &self,
        b: &mut Block,
        pulleys: &[PulleyConst; MAX_PULLEYS],
        i0: usize,
        len: usize,
        first: bool,
        y: &[f64],
        dy: &mut [f64],
        state: PulleyState,
        rec: &mut R,
        pad: bool,
        energy: &mut BlockEnergy,
    ) -> f64 {
        let n = self.n;
        let hl = self.half_length;
        assert!(len <= BLOCK);
        let mut p_diss = 0.0;

        // (1) Body data, index m <-> body i0 - 1 + m (cyclic); m = 0 and 1
        // were carried from the previous block unless this is the first.
        let m0 = if first { 0 } else { 2 };
        let last = i0 + len == n;
        // m = 0 of the first block is body n - 1, m = len + 1 of the last
        // is body 0; in between the bodies are contiguous.
        // Columns from m = 1 on (body i0, already carried unless this is
        // the first block: gathered again, the same values) so that the
        // four-body stores start on the line boundary of the columns'
        // index 1 (see [`Block`]); from m = 2 every other store straddled
        // two lines.
        let (m_lo, m_hi) = (1, if last { len + 1 } else { len + 2 });
        if first {
            b.gather::<WIDE>(0, &y[BODY_DOF * (n - 1)..BODY_DOF * n]);
        }
        b.gather::<WIDE>(
            m_lo,
            &y[BODY_DOF * (i0 + m_lo - 1)..BODY_DOF * (i0 + m_hi - 1)],
        );
        if last {
            b.gather::<WIDE>(len + 1, &y[..BODY_DOF]);
        }
        // With `pad` (the AVX-512 build) the loops of steps 1, 2 and 4 run
        // on to a multiple of PAD bodies, as the contact loops do: no scalar
        // remainder of up to 7 bodies (that of the SDE loop gathered each
        // body's seven values with a vector gather); the lanes past the
        // block compute on stale scratch values and are never read. The
        // narrower builds' remainders are short: padding them cost more
        // instructions than it saved.
        let m_end = upto(pad, m0, len + 2);
        assert!(m_end <= BODY_COL);
        for m in m0..m_end {
            let (sn, cs) = trig::sin_cos(b.phi[m]);
            b.hx[m] = hl * cs;
            b.hy[m] = hl * sn;
        }

        self.sde_step::<R, ENERGY>(b, i0, len, first, pad, &mut p_diss, rec, energy);
        let along =
            self.contact_step::<R, ENERGY>(b, pulleys, i0, len, state, &mut p_diss, rec, energy);
        self.acceleration_step::<R>(b, len, pad, along, &mut p_diss, rec);
        b.scatter::<WIDE>(&mut dy[BODY_DOF * i0..BODY_DOF * (i0 + len)]);
        p_diss
    }

    /// Step (2) of [`Self::block`]: the SDEs between the block's bodies,
    /// their dissipation added to `p_diss` (with `ENERGY` their elastic
    /// energy and the bodies' kinetic energy and heights to `energy`).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn sde_step<R: Recorder, const ENERGY: bool>(
        &self,
        b: &mut Block,
        i0: usize,
        len: usize,
        first: bool,
        pad: bool,
        p_diss: &mut f64,
        rec: &mut R,
        energy: &mut BlockEnergy,
    ) {
        // (2) SDE k joins the right end of body m = k to the left end of
        // body m = k + 1 (eq. 20-23); k = 0 was carried unless first.
        let (axial, bend) = (self.axial, self.bend);
        let k0 = if first { 0 } else { 1 };
        let k_end = upto(pad, k0, len + 1);
        assert!(k_end < BODY_COL.min(SDE_COL));
        // the loop built for the damper terms the drive's SDEs have: the
        // paper's set (damping along the gap) skips the term across it, the
        // isotropic damper (the FMU's default) the stretch rate, and a belt
        // without bending damping (both) the torsional damper
        let ks = k0..k_end;
        match (axial.damper_terms(), bend.damped()) {
            ((true, true), true) => sde_loop::<true, true, true, ENERGY>(b, axial, bend, ks),
            ((true, false), true) => sde_loop::<true, false, true, ENERGY>(b, axial, bend, ks),
            ((false, true), true) => sde_loop::<false, true, true, ENERGY>(b, axial, bend, ks),
            ((false, false), true) => sde_loop::<false, false, true, ENERGY>(b, axial, bend, ks),
            ((true, true), false) => sde_loop::<true, true, false, ENERGY>(b, axial, bend, ks),
            ((true, false), false) => sde_loop::<true, false, false, ENERGY>(b, axial, bend, ks),
            ((false, true), false) => sde_loop::<false, true, false, ENERGY>(b, axial, bend, ks),
            ((false, false), false) => sde_loop::<false, false, false, ENERGY>(b, axial, bend, ks),
        }
        // dissipation of SDEs i0..i0 + len (each counted in its own block)
        *p_diss += sum(&b.diss[..len]);
        if ENERGY {
            // their elastic energy; the bodies' kinetic energy and heights
            energy.elastic += sum(&b.esde[..len]);
            let [v2, w2, height] = body_sums(b, len);
            energy.kinetic += 0.5 * self.mass * v2 + 0.5 * self.inertia * w2;
            energy.height += height;
        }
        if R::ACTIVE {
            rec.belt_loss(sum(&b.diss[..len]));
            for k in 0..len {
                let (p, c) = (k, k + 1);
                let (d, dd) = sde::gap(b.body_end(p), b.body_end(c));
                let (d2, rate) = axial.rate(d, dd);
                let mid = [
                    0.5 * ((b.x[c] - b.hx[c]) + (b.x[p] + b.hx[p])),
                    0.5 * ((b.y[c] - b.hy[c]) + (b.y[p] + b.hy[p])),
                ];
                rec.sde(i0 + k, axial.tension(d2, rate), mid);
            }
        }
    }

    /// Step (3) of [`Self::block`]: contact and friction of the block's
    /// bodies with every pulley, into the bodies' own forces and creep
    /// rates, each pulley's belt torque and hub force (`state`); their power
    /// added to `p_diss`. Returns whether the contact acts along the body
    /// (moments in `otq`).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn contact_step<R: Recorder, const ENERGY: bool>(
        &self,
        b: &mut Block,
        pulleys: &[PulleyConst; MAX_PULLEYS],
        i0: usize,
        len: usize,
        state: PulleyState,
        p_diss: &mut f64,
        rec: &mut R,
        energy: &mut BlockEnergy,
    ) -> bool {
        let PulleyState {
            omega: omega_p,
            centre,
            belt_torque,
            hub,
        } = state;
        // (3) Contact and friction (eq. 4-19), pulley by pulley in chunks of
        // LANES bodies: a vectorised test of the body centres against the
        // pulley circle, then, if any is inside, the force laws for the whole
        // chunk with the results of the bodies outside discarded. Each body
        // sums its contacts in pulley order, as a plain loop would.
        let weight = self.mass * self.gravity;
        b.zf[..len].copy_from_slice(&self.zone_factor[i0..i0 + len]);
        let end = padded(len);
        assert!(end < BLOCK + 1 + PAD);
        for j in 0..end {
            b.ofx[j] = 0.0;
            b.ofy[j] = -weight;
            b.dz[j] = 0.0;
        }
        let along = self.points > 1;
        if along {
            b.otq[..end].fill(0.0);
        }
        for (q, pc) in pulleys[..self.np].iter().enumerate() {
            let surface = omega_p[q] * pc.lever;
            let c = &centre[q];
            // the contact loop compiled for the drive's friction law (the
            // contact along the body: one scalar loop for both)
            let (torque, diss, on_bodies) = with_law!(self.friction, law => {
                if along {
                    self.contacts_along::<R, ENERGY>(b, i0, len, q, pc, c, omega_p[q], rec, &law, energy)
                } else {
                    self.contacts::<R, ENERGY>(b, i0, len, q, pc, c, surface, rec, &law, energy)
                }
            });
            belt_torque[q] -= torque; // eq. 24
            *p_diss += diss;
            // the hub carries the reaction of the contact forces on the bodies
            hub[q][0] -= on_bodies[0];
            hub[q][1] -= on_bodies[1];
        }
        along
    }

    /// Step (4) of [`Self::block`]: the accelerations of the block's
    /// bodies; the transverse dampers' power added to `p_diss`.
    #[inline(always)]
    fn acceleration_step<R: Recorder>(
        &self,
        b: &mut Block,
        len: usize,
        pad: bool,
        along: bool,
        p_diss: &mut f64,
        rec: &mut R,
    ) {
        // (4) Accelerations (eq. 20-23): own forces, the left SDE (j) and
        // the right SDE (j + 1) of each body.
        let (inv_m, inv_i, c) = (self.inv_mass, self.inv_inertia, self.relaxation.damping);
        for j in 0..upto(pad, 0, len) {
            let m = j + 1;
            b.ax[j] = (b.ofx[j] - b.fx[j] + b.fx[j + 1]) * inv_m - c * b.vx[m];
            b.ay[j] = (b.ofy[j] - b.fy[j] + b.fy[j + 1]) * inv_m - c * b.vy[m];
            let torque = b.torque_cur[j] + b.torque_prev[j + 1];
            b.alpha[j] = torque * inv_i - c * b.w[m];
        }
        // transverse damping of the body centres (elements::transverse),
        // its power with the belt's losses
        if self.transverse.acts() {
            let inv_h2 = 1.0 / (self.half_length * self.half_length);
            let mut power = 0.0;
            for j in 0..len {
                let m = j + 1;
                let (a, p) =
                    self.transverse
                        .acceleration([b.hx[m], b.hy[m]], inv_h2, [b.vx[m], b.vy[m]]);
                b.ax[j] += a[0];
                b.ay[j] += a[1];
                power += p;
            }
            *p_diss += self.mass * power;
            if R::ACTIVE {
                rec.belt_loss(self.mass * power);
            }
        }
        if along {
            for j in 0..len {
                b.alpha[j] += b.otq[j] * inv_i;
            }
        }
    }

    /// Contact and friction forces (eq. 4-19) of bodies 0..len of a block
    /// with pulley `q` (centre and its velocity `centre` = [x, y, vx, vy],
    /// surface speed `surface`), friction law `friction`: added to the
    /// bodies' own forces and creep rates. Returns the
    /// moment r f about the pulley's axis summed over the contacts, their
    /// power, and the sum of the contact forces on the bodies.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn contacts<R: Recorder, const ENERGY: bool>(
        &self,
        b: &mut Block,
        i0: usize,
        len: usize,
        q: usize,
        pc: &PulleyConst,
        centre: &[f64; 4],
        surface: f64,
        rec: &mut R,
        friction: &impl Law,
        energy: &mut BlockEnergy,
    ) -> (f64, f64, [f64; 2]) {
        // the bodies lo..hi span every body inside the circle (usually one
        // arc); the rest of the block is skipped
        let Some((lo, hi)) = arc_range(b, len, centre, pc.radius2) else {
            return (0.0, 0.0, [0.0; 2]);
        };
        // columns of bodies lo..hi (separate slices: no aliasing, no bounds
        // checks, the loop vectorises)
        let end = lo + padded(hi - lo);
        contact_arc::<ENERGY>(
            self,
            pc,
            centre,
            surface,
            friction,
            hi - lo,
            [
                &b.x[lo + 1..=end],
                &b.y[lo + 1..=end],
                &b.vx[lo + 1..=end],
                &b.vy[lo + 1..=end],
                &b.z[lo + 1..=end],
                &b.zf[lo..end],
            ],
            &mut b.cfx[lo..end],
            &mut b.cfy[lo..end],
            &mut b.cdz[lo..end],
            &mut b.torque_q[lo..end],
            &mut b.diss_q[lo..end],
            [&mut b.en_q[lo..end], &mut b.cr_q[lo..end]],
            R::ACTIVE.then_some(&mut b.rec_q[lo..end]),
        );
        if ENERGY {
            energy.add_contacts(b, lo, end);
        }
        collect_arc(b, i0, q, lo, hi, false, rec)
    }

    /// [`Self::contacts`] with the contact along the body (more than one
    /// `contact.points`, [`contact::point`]): the bodies lo..hi whose
    /// centres lie within reach of the pulley (`PulleyConst::reach`) run
    /// through [`contact_along_arc`] in lanes, as the centre contact's
    /// bodies run through [`contact_arc`]; the contact moments on the
    /// bodies are added to `otq`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn contacts_along<R: Recorder, const ENERGY: bool>(
        &self,
        b: &mut Block,
        i0: usize,
        len: usize,
        q: usize,
        pc: &PulleyConst,
        centre: &[f64; 4],
        omega: f64,
        rec: &mut R,
        law: &impl Law,
        energy: &mut BlockEnergy,
    ) -> (f64, f64, [f64; 2]) {
        let Some((lo, hi)) = arc_range(b, len, centre, pc.reach * pc.reach) else {
            return (0.0, 0.0, [0.0; 2]);
        };
        let end = lo + padded(hi - lo);
        let body = [
            &b.x[lo + 1..=end],
            &b.y[lo + 1..=end],
            &b.vx[lo + 1..=end],
            &b.vy[lo + 1..=end],
            &b.w[lo + 1..=end],
            &b.z[lo + 1..=end],
            &b.hx[lo + 1..=end],
            &b.hy[lo + 1..=end],
            &b.zf[lo..end],
        ];
        let out = ArcOut {
            fx: &mut b.cfx[lo..end],
            fy: &mut b.cfy[lo..end],
            dz: &mut b.cdz[lo..end],
            moment: &mut b.cmq[lo..end],
            torque: &mut b.torque_q[lo..end],
            diss: &mut b.diss_q[lo..end],
            energy: [&mut b.en_q[lo..end], &mut b.cr_q[lo..end]],
            rec: R::ACTIVE.then_some(&mut b.rec_q[lo..end]),
        };
        let valid = hi - lo;
        // one build of the lane loop per point count (the points unrolled)
        match self.points {
            2 => contact_along_arc::<2, ENERGY>(self, pc, centre, omega, law, valid, body, out),
            3 => contact_along_arc::<3, ENERGY>(self, pc, centre, omega, law, valid, body, out),
            4 => contact_along_arc::<4, ENERGY>(self, pc, centre, omega, law, valid, body, out),
            5 => contact_along_arc::<5, ENERGY>(self, pc, centre, omega, law, valid, body, out),
            k => unreachable!("contact.points = {k} along the body"),
        }
        if ENERGY {
            energy.add_contacts(b, lo, end);
        }
        collect_arc(b, i0, q, lo, hi, true, rec)
    }
}
