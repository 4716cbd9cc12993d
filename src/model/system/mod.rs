//! Equations of motion of belt bodies and pulleys (eq. 20-24) with contact
//! (eq. 4-11) and friction (eq. 12-19): the right-hand side of the ODE.
//!
//! State layout (one contiguous `f64` vector, bodies first so the Jacobian
//! of the chain is banded):
//! * body i: `[x, y, phi, vx, vy, omega, z]` at `7 i`, z = creep displacement;
//! * pulley j: `[theta, omega]` at `7 n + 2 j`;
//! * `[work_in, energy_dissipated]`;
//! * per pulley with a decoupler, in pulley order: `[twist, rotor omega]`
//!   (`elements::decoupler`);
//! * per pulley on a tensioner arm, in pulley order: `[arm angle, arm rate]`
//!   (`elements::tensioner`); the pulley's centre moves with the arm;
//! * per pulley: the impulses `[belt torque, drive torque, hub force x, hub
//!   force y]` integrated since the start of the current communication step
//!   (quadrature states: they feed nothing back and are left out of the
//!   error control; their means over the step are outputs, see `drive.rs`).

use crate::model::elements::contact::{self, ContactLaw};
use crate::model::elements::decoupler::DecouplerParams;
use crate::model::elements::friction::{with_law, Friction, Law};
use crate::model::elements::groove::friction_factor;
pub use crate::model::elements::pulley::PulleyConst;
use crate::model::elements::sde::{self, AxialSde, BodyEnd, TorsionalSde};
use crate::model::elements::tensioner::Arm;
use crate::model::elements::transverse::TransverseDamper;
use crate::model::layout::Layout;
use crate::model::params::{DriveParams, MAX_PULLEYS};
use crate::model::simd::{self, Isa};
use crate::model::trig;
use crate::solver::knobs::TUNING;
use crate::solver::rosenbrock::EnergyBalance;

/// Values per body in the state vector.
pub const BODY_DOF: usize = 7;

/// Impulse states per pulley: belt torque, drive torque, hub force x, y.
pub const IMPULSES: usize = 4;

/// Inputs held over a communication step: value at `t0` plus a rate (FMI
/// input derivatives), so inputs ramp linearly within the step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Inputs {
    /// Time the inputs were set [s].
    pub t0: f64,
    /// Torque input per pulley at `t0` [N m].
    pub torque: [f64; MAX_PULLEYS],
    /// Rate of the torque input [N m/s].
    pub torque_rate: [f64; MAX_PULLEYS],
    /// Speed reference per speed-driven pulley at `t0` [rad/s].
    pub omega_ref: [f64; MAX_PULLEYS],
    /// Rate of the speed reference [rad/s^2].
    pub omega_ref_rate: [f64; MAX_PULLEYS],
}

/// Observer of the force evaluation, used for outputs. The hot path uses
/// [`NoRecord`], whose calls compile away.
pub trait Recorder {
    /// False for [`NoRecord`]: the recording code then compiles away.
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
    /// Per decoupler pulley: the torque its clutch transmits (>= 0, in the
    /// clutch's driving sense) and the rotor's speed.
    fn decoupler(&mut self, _pulley: usize, _torque: f64, _rotor_omega: f64) {}
    /// Power put in by drives and inputs, and power dissipated [W].
    fn power(&mut self, _input: f64, _dissipated: f64) {}
    /// A share of the power dissipated in the belt (SDE dampers, contact
    /// damping, friction slip without the creep springs); the shares of
    /// one evaluation add up to the belt's loss.
    fn belt_loss(&mut self, _p: f64) {}
    /// A contact's power stored in its creep spring (elements::friction):
    /// the part of `power`'s dissipated power that is not lost.
    fn creep_spring_power(&mut self, _p: f64) {}
}

/// The recorder of the hot path: records nothing.
pub struct NoRecord;
impl Recorder for NoRecord {
    const ACTIVE: bool = false;
}

/// What the right-hand side changes while the mounted belt is relaxed into
/// static equilibrium (`Drive::new`); all off ([`Relaxation::NONE`]) while
/// the drive runs. The drive's physical constants stay as they are.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Relaxation {
    /// Mass-proportional damping of the bodies' translation and rotation
    /// [1/s].
    pub damping: f64,
    /// Friction between belt and pulleys switched off (the creep
    /// displacement still follows its rate law).
    pub frictionless: bool,
    /// Every pulley, decoupler rotor and tensioner arm held at rest: inputs
    /// and built-in ramps are ignored and every pulley is treated as
    /// speed-driven; the arms stay where they were placed.
    pub pulleys_held: bool,
}

impl Relaxation {
    /// The running drive: nothing changed.
    pub const NONE: Self = Self {
        damping: 0.0,
        frictionless: false,
        pulleys_held: false,
    };
}

/// The belt drive as an ODE system: the constants of every body, SDE,
/// contact and pulley, and the inputs held over the current step. The
/// scratch of an evaluation is a [`Workspace`] the caller owns.
#[derive(Clone, Debug, PartialEq)]
pub struct BeltSystem {
    /// Belt bodies n.
    pub(crate) n: usize,
    /// Pulleys.
    pub(crate) np: usize,
    /// Pulleys with a decoupler (2 states each, after the energies).
    pub(crate) n_decouplers: usize,
    /// Pulleys on a tensioner arm (2 states each, after the decouplers').
    pub(crate) n_arms: usize,
    pub(crate) pulleys: [PulleyConst; MAX_PULLEYS],
    /// Half the body length l/2 [m].
    pub(crate) half_length: f64,
    /// Body mass m and moment of inertia I (eq. 2), with their inverses.
    pub(crate) mass: f64,
    pub(crate) inv_mass: f64,
    pub(crate) inertia: f64,
    pub(crate) inv_inertia: f64,
    /// Translational SDE between neighbouring bodies (EA/l, B/l).
    pub(crate) axial: AxialSde,
    /// Torsional SDE between neighbouring bodies (EI/l, damping).
    pub(crate) bend: TorsionalSde,
    /// Damping of each body's motion across its axis (span damping).
    pub(crate) transverse: TransverseDamper,
    /// Gravitational acceleration [m/s^2] (acts in -y).
    pub(crate) gravity: f64,
    pub(crate) contact: ContactLaw,
    pub(crate) friction: Friction,
    /// Friction factor of every body (1 outside the modified zone).
    pub(crate) zone_factor: Vec<f64>,
    /// The equilibrium relaxation's settings ([`Relaxation::NONE`] when
    /// running).
    pub(crate) relaxation: Relaxation,
    pub(crate) inputs: Inputs,
    /// Contact points along each body (`contact.points`,
    /// [`contact::quadrature`]; 1 = the body centre, the paper's contact).
    pub(crate) points: usize,
}

pub(crate) use crate::model::trig::wrap_angle;

/// What the body blocks of the right-hand side read and accumulate per
/// pulley: speeds and centres (x, y, vx, vy) in, belt torque and the belt's
/// force on a tensioner pulley's hub out.
struct PulleyState<'a> {
    omega: &'a [f64; MAX_PULLEYS],
    centre: &'a [[f64; 4]; MAX_PULLEYS],
    belt_torque: &'a mut [f64; MAX_PULLEYS],
    hub: &'a mut [[f64; 2]; MAX_PULLEYS],
}

/// Bodies per block of the right-hand side (scratch of ~9 KiB, stays in L1).
pub const BLOCK: usize = 64;

/// The contact loops run to a multiple of `PAD` bodies (the widest vector,
/// AVX-512's 8 doubles), so that a short arc does not end in scalar
/// iterations of the force laws; the lanes past the end compute on stale
/// scratch values and are discarded. (Padding the other loops the same way
/// measured slower.)
const PAD: usize = 8;

#[inline(always)]
fn padded(len: usize) -> usize {
    len.next_multiple_of(PAD)
}

/// Length of a body column: body m = 0..len + 2 plus the padding, rounded
/// up to whole 64-byte cache lines.
const BODY_COL: usize = (BLOCK + 2 + PAD).next_multiple_of(8);
/// Length of an SDE column (k = 0..=len plus the padding), whole cache lines.
const SDE_COL: usize = (BLOCK + 1 + PAD).next_multiple_of(8);
/// Length of a column of the block's own bodies (j = 0..len plus the
/// padding), whole cache lines.
const OWN_COL: usize = (BLOCK + PAD).next_multiple_of(8);

/// Structure-of-arrays scratch of one block of bodies (see [`BeltSystem::rhs`]).
///
/// Laid out on 64-byte cache lines, the same wherever the allocator puts
/// it: the loops over the block's own bodies (j, body column index m = j + 1,
/// SDE k = j and j + 1) start each column's vector loads on a line boundary,
/// so an AVX-512 load (64 bytes) straddles two lines only where it reads a
/// neighbour (x[k] beside x[k + 1]). With the allocator's 16-byte alignment
/// the straddling loads, and the AVX-512 right-hand side's time, depended on
/// where the block landed (docs/benchmarks.md).
#[derive(Clone)]
#[repr(C, align(64))]
struct Block {
    /// Puts index 1 of the body columns on a line boundary.
    _lead: [f64; 7],
    // body m = 0..len + 2 (body i0 - 1 + m)
    x: [f64; BODY_COL],
    y: [f64; BODY_COL],
    phi: [f64; BODY_COL],
    vx: [f64; BODY_COL],
    vy: [f64; BODY_COL],
    w: [f64; BODY_COL],
    z: [f64; BODY_COL],
    /// Half body vector (l/2) (cos phi, sin phi).
    hx: [f64; BODY_COL],
    hy: [f64; BODY_COL],
    /// Puts the SDE columns on a line boundary.
    _gap: [f64; 1],
    // SDE k = 0..=len (SDE i0 + k, between body m = k and m = k + 1): force
    // on body k + 1 (minus it on body k), torque on body k + 1 and on body
    // k, dissipated power
    fx: [f64; SDE_COL],
    fy: [f64; SDE_COL],
    torque_cur: [f64; SDE_COL],
    torque_prev: [f64; SDE_COL],
    diss: [f64; SDE_COL],
    // body j = 0..len (body i0 + j): friction zone factor, own forces
    // (gravity, contact), creep rate, accelerations
    zf: [f64; OWN_COL],
    ofx: [f64; OWN_COL],
    ofy: [f64; OWN_COL],
    dz: [f64; OWN_COL],
    ax: [f64; OWN_COL],
    ay: [f64; OWN_COL],
    alpha: [f64; OWN_COL],
    // contacts of body j with the pulley at hand: moment r f, power, and
    // the recorded values (normal force, friction force, v_T, penetration,
    // force on the body, inside)
    cfx: [f64; OWN_COL],
    cfy: [f64; OWN_COL],
    cdz: [f64; OWN_COL],
    torque_q: [f64; OWN_COL],
    diss_q: [f64; OWN_COL],
    rec_q: [[f64; 9]; OWN_COL],
    // contact along the body: the contact moments on body j about its
    // centre, summed over the pulleys, and that of the pulley at hand
    otq: [f64; OWN_COL],
    cmq: [f64; OWN_COL],
    // only in the evaluation that also takes the stored energy
    // ([`BeltSystem::rhs_energy`]): the elastic energy of the contacts of
    // body j with the pulley at hand and of its creep spring, and that of
    // SDE k
    en_q: [f64; OWN_COL],
    cr_q: [f64; OWN_COL],
    esde: [f64; SDE_COL],
}

// The layout the loops rely on (see [`Block`]).
const _: () = assert!(
    std::mem::offset_of!(Block, x) % 64 == 56
        && std::mem::offset_of!(Block, hy) % 64 == 56
        && std::mem::offset_of!(Block, fx) % 64 == 0
        && std::mem::offset_of!(Block, zf) % 64 == 0
        && std::mem::offset_of!(Block, rec_q) % 64 == 0
        && std::mem::offset_of!(Block, otq) % 64 == 0
        && std::mem::offset_of!(Block, cmq) % 64 == 0
        && std::mem::offset_of!(Block, esde) % 64 == 0
);

impl Block {
    /// Body m's end data as the SDE law reads it.
    #[inline(always)]
    fn body_end(&self, m: usize) -> BodyEnd {
        BodyEnd {
            x: self.x[m],
            y: self.y[m],
            hx: self.hx[m],
            hy: self.hy[m],
            vx: self.vx[m],
            vy: self.vy[m],
            w: self.w[m],
        }
    }

    fn new() -> Self {
        const C: [f64; BODY_COL] = [0.0; BODY_COL];
        const S: [f64; SDE_COL] = [0.0; SDE_COL];
        const B: [f64; OWN_COL] = [0.0; OWN_COL];
        Self {
            _lead: [0.0; 7],
            x: C,
            y: C,
            phi: C,
            vx: C,
            vy: C,
            w: C,
            z: C,
            hx: C,
            hy: C,
            _gap: [0.0; 1],
            fx: S,
            fy: S,
            torque_cur: S,
            torque_prev: S,
            diss: S,
            zf: B,
            ofx: B,
            ofy: B,
            dz: B,
            ax: B,
            ay: B,
            alpha: B,
            cfx: B,
            cfy: B,
            cdz: B,
            torque_q: B,
            diss_q: B,
            rec_q: [[0.0; 9]; OWN_COL],
            otq: B,
            cmq: B,
            en_q: B,
            cr_q: B,
            esde: S,
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
            &mut self.z,
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

    /// Copies the consecutive bodies of `src` (`[x, y, phi, vx, vy, omega,
    /// z]` each) into the columns at index `m` onwards
    /// ([`simd::gather`]; `WIDE` only in the AVX builds).
    #[inline(always)]
    fn gather<const WIDE: bool>(&mut self, m: usize, src: &[f64]) {
        assert!(m + src.len() / BODY_DOF <= BLOCK + 2);
        simd::gather::<WIDE, BODY_COL>(
            [
                &mut self.x,
                &mut self.y,
                &mut self.phi,
                &mut self.vx,
                &mut self.vy,
                &mut self.w,
                &mut self.z,
            ],
            m,
            src,
        );
    }

    /// Writes the derivatives of bodies 0..len of the block into `dst`
    /// (`[vx, vy, omega, ax, ay, alpha, dz/dt]` each), the inverse of
    /// [`Self::gather`] ([`simd::scatter`]).
    #[inline(always)]
    fn scatter<const WIDE: bool>(&self, dst: &mut [f64]) {
        assert!(dst.len() / BODY_DOF <= BLOCK);
        let cols: [&[f64]; BODY_DOF] = [
            &self.vx[1..],
            &self.vy[1..],
            &self.w[1..],
            &self.ax,
            &self.ay,
            &self.alpha,
            &self.dz,
        ];
        simd::scatter::<WIDE>(cols, dst);
    }
}

/// Scratch of the right-hand side ([`BeltSystem::rhs`]): one block of
/// bodies in structure-of-arrays form (~20 KiB), allocated once by its
/// owner (the integrator's caller) so that no evaluation allocates. It
/// carries nothing from one evaluation to the next.
#[derive(Clone)]
pub struct Workspace {
    block: Box<Block>,
}

impl Workspace {
    /// A fresh workspace (one allocation).
    pub fn new() -> Self {
        Self {
            block: Box::new(Block::new()),
        }
    }
}

impl Default for Workspace {
    fn default() -> Self {
        Self::new()
    }
}

impl std::fmt::Debug for Workspace {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Workspace").finish_non_exhaustive()
    }
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

/// [`sum`] of the first `len` values of each of four columns at once,
/// bit for bit: the same partial sums over the whole chunks of four, the
/// remainder summed in order, then combined as [`sum`] combines them. The
/// columns run on to a multiple of [`PAD`] with +0 past `len` (a contact
/// loop's discarded lanes), so the remainder is summed as a whole chunk
/// (adding +0 leaves a sum unchanged but for the sign of a zero, which
/// the combination absorbs: the partial sums, started at +0, are never -0).
#[inline(always)]
fn sum4(cols: [&[f64]; 4], len: usize) -> [f64; 4] {
    let full = len & !3;
    let padded = cols[0].len();
    assert!(padded.is_multiple_of(PAD) && len <= padded && cols.iter().all(|c| c.len() == padded));
    let mut acc = [[0.0; 4]; 4];
    // the whole chunks as arrays of four: no bounds checks, one vector add
    // per column and chunk
    let [c0, c1, c2, c3] = cols.map(|c| c[..full].as_chunks::<4>().0);
    for (((x0, x1), x2), x3) in c0.iter().zip(c1).zip(c2).zip(c3) {
        for (a, x) in acc.iter_mut().zip([x0, x1, x2, x3]) {
            for (a, x) in a.iter_mut().zip(x) {
                *a += x;
            }
        }
    }
    std::array::from_fn(|s| {
        let [a0, a1, a2, a3] = acc[s];
        let rest = if full < padded {
            let r = &cols[s][full..full + 4];
            ((r[0] + r[1]) + r[2]) + r[3]
        } else {
            0.0
        };
        (a0 + a1) + (a2 + a3) + rest
    })
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

/// What the blocks of [`BeltSystem::rhs_energy`] sum of the stored energy.
#[derive(Clone, Copy, Debug, Default)]
struct BlockEnergy {
    /// Kinetic energy of the bodies [J].
    kinetic: f64,
    /// Elastic energy of the SDEs and contacts [J].
    elastic: f64,
    /// Energy of the creep springs [J].
    creep: f64,
    /// Sum of the body centres' heights [m].
    height: f64,
}

impl BlockEnergy {
    /// Adds the contact and creep-spring energies of the bodies `lo..end`
    /// (a contact arc, padded; the lanes outside hold zeros).
    #[inline(always)]
    fn add_contacts(&mut self, b: &Block, lo: usize, end: usize) {
        self.elastic += sum(&b.en_q[lo..end]);
        self.creep += sum(&b.cr_q[lo..end]);
    }
}

/// Over the bodies m = 1..=len of a block: the sums of v^2, omega^2 and the
/// height y, in four interleaved partial sums.
#[inline(always)]
fn body_sums(b: &Block, len: usize) -> [f64; 3] {
    let (vx, vy, w, y) = (&b.vx[1..=len], &b.vy[1..=len], &b.w[1..=len], &b.y[1..=len]);
    let full = len & !3;
    fn fours(c: &[f64], full: usize) -> &[[f64; 4]] {
        c[..full].as_chunks::<4>().0
    }
    let chunks = |c| fours(c, full);
    let (mut av, mut aw, mut ay) = ([0.0; 4], [0.0; 4], [0.0; 4]);
    for (((vx, vy), w), y) in chunks(vx)
        .iter()
        .zip(chunks(vy))
        .zip(chunks(w))
        .zip(chunks(y))
    {
        let lanes = av.iter_mut().zip(&mut aw).zip(&mut ay);
        for (((av, aw), ay), ((vx, vy), (w, y))) in
            lanes.zip(vx.iter().zip(vy).zip(w.iter().zip(y)))
        {
            *av += vx * vx + vy * vy;
            *aw += w * w;
            *ay += y;
        }
    }
    let mut rest = [0.0; 3];
    for j in full..len {
        rest[0] += vx[j] * vx[j] + vy[j] * vy[j];
        rest[1] += w[j] * w[j];
        rest[2] += y[j];
    }
    let total = |[a0, a1, a2, a3]: [f64; 4], r: f64| (a0 + a1) + (a2 + a3) + r;
    [total(av, rest[0]), total(aw, rest[1]), total(ay, rest[2])]
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
    /// The system of validated `params` on the mounted `layout`.
    pub fn new(params: &DriveParams, layout: &Layout) -> Self {
        let l = layout.body_length;
        let b = &params.belt;
        let mass = b.mass_per_length * l;
        let inertia = mass * l * l / 12.0; // eq. 2
        let n = b.n_bodies;
        let np = params.pulleys.len();
        let mut n_dec = 0;
        let mut n_arms = 0;
        let n_dec_all = params
            .pulleys
            .iter()
            .filter(|p| p.decoupler.is_some())
            .count();
        let mut pulleys = [PulleyConst::NONE; MAX_PULLEYS];
        for (j, (pc, p)) in pulleys.iter_mut().zip(&params.pulleys).enumerate() {
            let radii = contact::point_radii(p.radius, l, params.contact.points);
            *pc = PulleyConst {
                cx: p.x,
                cy: p.y,
                radius: p.radius,
                radius2: p.radius * p.radius,
                // the chordal effect of the straight bodies (elements::contact)
                lever: contact::chordal_lever(
                    p.radius,
                    layout.wrap_of(j).map_or(0.0, |w| w.penetration),
                    l,
                ),
                levers: contact::point_levers(
                    p.radius,
                    layout.wrap_of(j).map_or(0.0, |w| w.penetration),
                    l,
                    params.contact.points,
                ),
                radii,
                reach: radii.iter().fold(0.0, |a: f64, &b| a.max(b)) + 0.5 * l,
                inv_inertia: 1.0 / p.inertia,
                inertia: p.inertia,
                // the groove's wedge effect (elements::groove)
                mu_s: p.mu_static * friction_factor(p.groove_angle, p.back_side),
                mu_k: p.mu_kinetic * friction_factor(p.groove_angle, p.back_side),
                // the damping ramp: the user's contact.pMax, or from the
                // wrap's equilibrium penetration (elements::contact)
                inv_p_max: 1.0
                    / contact::auto_p_max(
                        params.contact.p_max,
                        layout.wrap_of(j).map_or(0.0, |w| w.penetration),
                    ),
                speed_driven: p.speed_driven,
                load_damping: p.load_damping,
                torque_ramp: p.torque_ramp,
                omega_ramp: p.omega_ramp,
                ramp_time: p.ramp_time,
                decoupler: p.decoupler.as_ref().map(DecouplerParams::law),
                rotor_inertia: p.decoupler.map_or(0.0, |d| d.rotor_inertia),
                rotor_inv_inertia: p.decoupler.map_or(0.0, |d| 1.0 / d.rotor_inertia),
                decoupler_offset: BODY_DOF * n + 2 * np + 2 + 2 * n_dec,
                arm: p.arm.as_ref().map(|a| Arm::new(a, [p.x, p.y])),
                arm_offset: BODY_DOF * n + 2 * np + 2 + 2 * n_dec_all + 2 * n_arms,
            };
            n_dec += usize::from(p.decoupler.is_some());
            n_arms += usize::from(p.arm.is_some());
        }
        let f = &params.friction;
        let mut zone_factor = vec![1.0; n];
        for k in 0..f.zone_bodies {
            zone_factor[(f.zone_start + k) % n] = f.zone_factor;
        }
        let c = &params.contact;
        Self {
            n,
            np,
            n_decouplers: n_dec,
            n_arms,
            pulleys,
            half_length: 0.5 * l,
            mass,
            inv_mass: 1.0 / mass,
            inertia,
            inv_inertia: 1.0 / inertia,
            axial: AxialSde {
                k: b.ea / l,
                b: b.axial_damping / l,
                bt: b.shear_damping_factor * b.axial_damping / l,
                eps2: (TUNING.sde_regularisation * l) * (TUNING.sde_regularisation * l),
            },
            bend: TorsionalSde {
                k: b.bending_stiffness / l,
                b: b.bending_damping / l,
            },
            transverse: TransverseDamper {
                rate: b.transverse_damping,
            },
            gravity: params.gravity,
            contact: ContactLaw {
                c1: c.c1 * l,
                c2: c.c2 * l,
                b: c.damping * l,
            },
            friction: Friction::new(f.law, f.dv, f.creep_max, f.creep_damping_time),
            zone_factor,
            relaxation: Relaxation::NONE,
            inputs: Inputs::default(),
            points: params.contact.points,
        }
    }

    /// Length of the state vector.
    pub fn dim(&self) -> usize {
        self.impulse_offset(0) + IMPULSES * self.np
    }

    /// States whose error the integrators control: all but the impulses at
    /// the end, which feed nothing back.
    pub fn controlled_dim(&self) -> usize {
        self.impulse_offset(0)
    }

    /// Offset of pulley j's impulses `[belt torque, drive torque, hub force
    /// x, hub force y]` (after the decoupler and arm states).
    pub fn impulse_offset(&self, j: usize) -> usize {
        BODY_DOF * self.n + 2 * self.np + 2 + 2 * self.n_decouplers + 2 * self.n_arms + IMPULSES * j
    }

    /// Centre of pulley j in state `y` and its velocity: the fixed centre,
    /// or the end of its tensioner arm, `c(alpha)` and `c'(alpha) alpha'`.
    #[inline]
    pub fn pulley_centre(&self, j: usize, y: &[f64]) -> ([f64; 2], [f64; 2]) {
        let pc = &self.pulleys[j];
        match &pc.arm {
            None => ([pc.cx, pc.cy], [0.0, 0.0]),
            Some(arm) => {
                let (a, w) = (y[pc.arm_offset], y[pc.arm_offset + 1]);
                let (c, dc) = arm.centre(a);
                (c, [dc[0] * w, dc[1] * w])
            }
        }
    }

    /// Offset of pulley j's `[theta, omega]` in the state.
    pub fn pulley_offset(&self, j: usize) -> usize {
        BODY_DOF * self.n + 2 * j
    }

    /// Offset of `[work_in, energy_dissipated]` in the state.
    pub fn energy_offset(&self) -> usize {
        BODY_DOF * self.n + 2 * self.np
    }

    /// Number of belt bodies n.
    pub fn n_bodies(&self) -> usize {
        self.n
    }

    /// Number of pulleys.
    pub fn n_pulleys(&self) -> usize {
        self.np
    }

    /// Number of pulleys with a one-way decoupler.
    pub fn n_decouplers(&self) -> usize {
        self.n_decouplers
    }

    /// The pulleys' constants, in pulley order.
    pub fn pulleys(&self) -> &[PulleyConst] {
        &self.pulleys[..self.np]
    }

    /// Half the body length l/2 [m].
    pub fn half_length(&self) -> f64 {
        self.half_length
    }

    /// Mass of one body [kg].
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// Moment of inertia of one body about its centre (eq. 2) [kg m^2].
    pub fn inertia(&self) -> f64 {
        self.inertia
    }

    /// Gravitational acceleration [m/s^2], acting in -y.
    pub fn gravity(&self) -> f64 {
        self.gravity
    }

    /// The translational SDE between neighbouring bodies.
    pub fn axial(&self) -> AxialSde {
        self.axial
    }

    /// The torsional SDE between neighbouring bodies.
    pub fn bend(&self) -> TorsionalSde {
        self.bend
    }

    /// The transverse (span) damping of every body.
    pub fn transverse(&self) -> TransverseDamper {
        self.transverse
    }

    /// The normal-force law of every contact.
    pub fn contact(&self) -> ContactLaw {
        self.contact
    }

    /// Contact points along each body (`contact.points`).
    pub fn contact_points(&self) -> usize {
        self.points
    }

    /// The friction law of every contact.
    pub fn friction(&self) -> Friction {
        self.friction
    }

    /// Friction factor of each body (1 outside the modified zone).
    pub fn zone_factor(&self) -> &[f64] {
        &self.zone_factor
    }

    /// The inputs held over the current step.
    pub fn inputs(&self) -> &Inputs {
        &self.inputs
    }

    /// The equilibrium relaxation's settings in effect.
    pub fn relaxation(&self) -> Relaxation {
        self.relaxation
    }

    /// The same drive with the relaxation settings `r` (its constants
    /// unchanged).
    pub fn with_relaxation(&self, r: Relaxation) -> Self {
        Self {
            relaxation: r,
            ..self.clone()
        }
    }

    /// Pulley j as the equations see it: during the relaxation without
    /// friction and held at rest (speed-driven) as its settings say.
    #[inline(always)]
    pub(crate) fn pulley_in_effect(&self, j: usize) -> PulleyConst {
        let mut pc = self.pulleys[j];
        let r = &self.relaxation;
        if r.frictionless {
            pc.mu_s = 0.0;
            pc.mu_k = 0.0;
        }
        if r.pulleys_held {
            pc.speed_driven = true;
        }
        pc
    }

    /// All pulleys as [`Self::pulley_in_effect`] gives them: the system's
    /// own array while running, else `buf` filled (left empty while running:
    /// filling it on every call cost the right-hand side 1.7 % of its
    /// instructions).
    #[inline(always)]
    pub(crate) fn pulleys_in_effect<'a>(
        &'a self,
        buf: &'a mut Option<[PulleyConst; MAX_PULLEYS]>,
    ) -> &'a [PulleyConst; MAX_PULLEYS] {
        if self.relaxation == Relaxation::NONE {
            return &self.pulleys;
        }
        let buf = buf.insert([PulleyConst::NONE; MAX_PULLEYS]);
        for (j, pc) in buf.iter_mut().enumerate().take(self.np) {
            *pc = self.pulley_in_effect(j);
        }
        buf
    }

    /// Torque input plus built-in ramp on pulley j at time t (0 while the
    /// relaxation holds the pulleys).
    #[inline]
    pub fn applied_torque(&self, j: usize, t: f64) -> f64 {
        if self.relaxation.pulleys_held {
            return 0.0;
        }
        let p = &self.pulleys[j];
        let inp = &self.inputs;
        inp.torque[j] + inp.torque_rate[j] * (t - inp.t0) + p.ramp(p.torque_ramp, t)
    }

    /// Prescribed speed of a speed-driven pulley j at time t, and its rate
    /// (0 while the relaxation holds the pulleys).
    #[inline]
    pub fn prescribed_speed(&self, j: usize, t: f64) -> (f64, f64) {
        if self.relaxation.pulleys_held {
            return (0.0, 0.0);
        }
        let p = &self.pulleys[j];
        let inp = &self.inputs;
        let w = inp.omega_ref[j] + inp.omega_ref_rate[j] * (t - inp.t0) + p.ramp(p.omega_ramp, t);
        let dw = inp.omega_ref_rate[j] + p.ramp_rate(p.omega_ramp, t);
        (w, dw)
    }

    /// Angular speed of pulley j used by the contact: the state for
    /// torque-driven pulleys, the prescription for speed-driven ones.
    #[inline]
    pub fn pulley_speed(&self, j: usize, t: f64, y: &[f64]) -> f64 {
        if self.pulleys[j].speed_driven || self.relaxation.pulleys_held {
            self.prescribed_speed(j, t).0
        } else {
            y[self.pulley_offset(j) + 1]
        }
    }

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

        // Pulleys (eq. 24).
        let mut p_in = 0.0;
        for j in 0..np {
            let pc = &pulleys[j];
            let o = self.pulley_offset(j);
            let w = omega_p[j];
            let applied = self.applied_torque(j, t);
            dy[o] = w;
            let prescribed = if pc.speed_driven {
                self.prescribed_speed(j, t).1
            } else {
                0.0
            };
            let bal = if let Some(dc) = &pc.decoupler {
                // The load and the applied torque act on the rotor behind
                // the decoupler; the hub carries the clutch's -s M.
                let d = pc.decoupler_offset;
                let (twist, w_r) = (y[d], y[d + 1]);
                let rel = dc.relative_rate(w, w_r);
                let law = dc.law(twist, rel);
                let m = dc.sense * law.torque;
                let load = pc.load_damping * w_r;
                dy[d] = law.twist_rate;
                dy[d + 1] = (applied + m - load) * pc.rotor_inv_inertia;
                let mut hub = *pc;
                hub.load_damping = 0.0;
                let bal = hub.balance(w, -m, belt_torque[j], prescribed);
                dy[o + 1] = bal.alpha;
                p_in += bal.drive * w + applied * w_r;
                // the clutch's power M w less the spring's energy rate
                p_diss += load * w_r + law.torque * rel - dc.stiffness * twist * law.twist_rate;
                if R::ACTIVE {
                    rec.decoupler(j, law.torque, w_r);
                }
                bal
            } else {
                let bal = pc.balance(w, applied, belt_torque[j], prescribed);
                dy[o + 1] = bal.alpha;
                let (power_in, power_load) = pc.power(w, applied, &bal);
                p_in += power_in;
                p_diss += power_load;
                bal
            };
            if R::ACTIVE {
                rec.pulley(j, belt_torque[j], bal.drive, bal.alpha);
                rec.hub_force(j, hub[j][0], hub[j][1]);
            }
            let q = self.impulse_offset(j);
            dy[q..q + IMPULSES].copy_from_slice(&[belt_torque[j], bal.drive, hub[j][0], hub[j][1]]);
        }
        // Tensioner arms: I_arm alpha'' = (c - pivot) x F_hub + M_arm.
        for (j, pc) in self.pulleys[..np].iter().enumerate() {
            let Some(arm) = &pc.arm else { continue };
            let o = pc.arm_offset;
            let (a, w) = (y[o], y[o + 1]);
            dy[o] = w;
            if self.relaxation.pulleys_held {
                dy[o + 1] = 0.0;
                continue;
            }
            let moment = arm.moment(a, hub[j]).0;
            dy[o + 1] = (moment + arm.torque(a, w).torque) / arm.inertia;
            p_diss += arm.dissipation(a, w);
        }
        let e = self.energy_offset();
        dy[e] = p_in;
        dy[e + 1] = p_diss;
        if R::ACTIVE {
            rec.power(p_in, p_diss);
        }
        if ENERGY {
            self.stored_energy_of(energy, y)
        } else {
            StoredEnergy::default()
        }
    }

    /// Bodies `i0..i0 + len` of the right-hand side (see [`Self::rhs`]).
    /// Returns the power dissipated in their contacts and left SDEs.
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
        let PulleyState {
            omega: omega_p,
            centre,
            belt_torque,
            hub,
        } = state;
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
        let upto = |from: usize, to: usize| if pad { from + padded(to - from) } else { to };
        let m_end = upto(m0, len + 2);
        assert!(m_end <= BODY_COL);
        for m in m0..m_end {
            let (sn, cs) = trig::sin_cos(b.phi[m]);
            b.hx[m] = hl * cs;
            b.hy[m] = hl * sn;
        }

        // (2) SDE k joins the right end of body m = k to the left end of
        // body m = k + 1 (eq. 20-23); k = 0 was carried unless first.
        let (axial, bend) = (self.axial, self.bend);
        let k0 = if first { 0 } else { 1 };
        let k_end = upto(k0, len + 1);
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
        p_diss += sum(&b.diss[..len]);
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
            p_diss += diss;
            // the hub carries the reaction of the contact forces on the bodies
            hub[q][0] -= on_bodies[0];
            hub[q][1] -= on_bodies[1];
        }

        // (4) Accelerations (eq. 20-23): own forces, the left SDE (j) and
        // the right SDE (j + 1) of each body.
        let (inv_m, inv_i, c) = (self.inv_mass, self.inv_inertia, self.relaxation.damping);
        for j in 0..upto(0, len) {
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
            p_diss += self.mass * power;
            if R::ACTIVE {
                rec.belt_loss(self.mass * power);
            }
        }
        if along {
            for j in 0..len {
                b.alpha[j] += b.otq[j] * inv_i;
            }
        }
        b.scatter::<WIDE>(&mut dy[BODY_DOF * i0..BODY_DOF * (i0 + len)]);
        p_diss
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

    /// Discrete update after every accepted step: the creep displacement of a
    /// body that touches no pulley is reset, and kept within its cap. True
    /// if it changed any.
    pub fn after_step(&self, y: &mut [f64]) -> bool {
        let mut changed = false;
        let cap = self.friction.creep_cap();
        let mut centres = [[0.0; 2]; MAX_PULLEYS];
        for (j, c) in centres.iter_mut().enumerate().take(self.np) {
            *c = self.pulley_centre(j, y).0;
        }
        for i in 0..self.n {
            let o = BODY_DOF * i;
            // a creep of +0 stays +0 either way (reset, or clamped): only
            // the bodies that carry a creep, those on or just off a wrap,
            // need the contact test
            if y[o + 6].to_bits() == 0 {
                continue;
            }
            let z = if self.touching(i, y, &centres).is_some() {
                y[o + 6].clamp(-cap, cap)
            } else {
                0.0
            };
            changed |= z.to_bits() != y[o + 6].to_bits();
            y[o + 6] = z;
        }
        changed
    }

    /// The first pulley body `i` touches in state `y` (pulley centres
    /// given): a contact point of the body inside the pulley's contact
    /// radius (the centre with one point). The test of [`Self::after_step`]
    /// (and of the modal analysis' contact regions).
    #[inline]
    pub fn touching(&self, i: usize, y: &[f64], centres: &[[f64; 2]]) -> Option<usize> {
        let o = BODY_DOF * i;
        let (x, yy) = (y[o], y[o + 1]);
        if self.points == 1 {
            // the centre: the test below with xi h = 0 (its reach holds the
            // centre's circle)
            return self.pulleys[..self.np]
                .iter()
                .zip(centres)
                .position(|(pc, c)| {
                    let (rx, ry) = (x - c[0], yy - c[1]);
                    rx * rx + ry * ry < pc.radii[0] * pc.radii[0]
                });
        }
        let mut pulleys = self.pulleys[..self.np].iter().zip(centres);
        // no point of a body lies farther than l/2 from its centre: a body
        // out of every pulley's reach touches none (the common case, and
        // no sin/cos for it)
        let near = |pc: &PulleyConst, c: &[f64; 2]| {
            let (rx, ry) = (x - c[0], yy - c[1]);
            rx * rx + ry * ry < pc.reach * pc.reach
        };
        if !pulleys.clone().any(|(pc, c)| near(pc, c)) {
            return None;
        }
        let (s, c) = y[o + 2].sin_cos();
        let (hx, hy) = (self.half_length * c, self.half_length * s);
        let quad = contact::quadrature(self.points);
        pulleys.position(|(pc, c)| {
            near(pc, c)
                && quad.iter().zip(&pc.radii).any(|(&(xi, _), &rg)| {
                    let (rx, ry) = (x + xi * hx - c[0], yy + xi * hy - c[1]);
                    rx * rx + ry * ry < rg * rg
                })
        })
    }

    /// Energy stored in the creep springs of every contact of state `y`:
    /// the elastic normal force times the spring energy per newton
    /// (elements::friction, `Law::spring_energy`). Part of the
    /// potential energy; the integrated friction work less it is what
    /// friction has dissipated.
    pub fn creep_spring_energy(&self, y: &[f64]) -> f64 {
        let mut centres = [[0.0; 2]; MAX_PULLEYS];
        for (j, c) in centres.iter_mut().enumerate().take(self.np) {
            *c = self.pulley_centre(j, y).0;
        }
        (0..self.n)
            .map(|i| self.creep_spring_energy_of(i, y, &centres))
            .sum()
    }

    /// [`Self::creep_spring_energy`] of body `i` (pulley centres given).
    fn creep_spring_energy_of(&self, i: usize, y: &[f64], centres: &[[f64; 2]]) -> f64 {
        let b = &y[BODY_DOF * i..BODY_DOF * (i + 1)];
        let zf = self.zone_factor[i];
        let mut e = 0.0;
        for (pc, c) in self.pulleys[..self.np].iter().zip(centres) {
            // the elastic normal force summed over the contact points
            let elastic =
                self.point_penetrations(b, c, &pc.radii, |w, p| w * self.contact.elastic_force(p));
            if elastic > 0.0 {
                e += elastic
                    * self
                        .friction
                        .spring_energy(b[6], pc.mu_s * zf, pc.mu_k * zf);
            }
        }
        e
    }

    /// Sum over the contact points of body `b` (`[x, y, phi, ..]`) with
    /// positive penetration in its contact circle about `c` (`radii`,
    /// [`contact::point_radii`]) of `f(w, p)`, w the point's share of the
    /// law ([`contact::quadrature`]).
    fn point_penetrations(
        &self,
        b: &[f64],
        c: &[f64; 2],
        radii: &[f64],
        f: impl Fn(f64, f64) -> f64,
    ) -> f64 {
        let (s, co) = b[2].sin_cos();
        let (hx, hy) = (self.half_length * co, self.half_length * s);
        contact::quadrature(self.points)
            .iter()
            .zip(radii)
            .map(|(&(xi, w), &radius)| {
                let p = radius - (b[0] + xi * hx - c[0]).hypot(b[1] + xi * hy - c[1]);
                if p > 0.0 {
                    f(w, p)
                } else {
                    0.0
                }
            })
            .sum()
    }

    /// Kinetic and potential (elastic + gravity) energy of state `y`.
    pub fn energies(&self, y: &[f64]) -> (f64, f64) {
        let e = self.stored_energy(y);
        (e.kinetic, e.potential)
    }

    /// The energy balance of state `y`: the input work less the dissipated
    /// energy less the stored energy [J] (constant along the exact flow),
    /// measured against the belt's own stored energy [J]. The dissipated energy is the
    /// integrated friction and damper work less what the creep springs hold
    /// (as the `energy.dissipated` output); the creep springs' energy is
    /// part of the stored energy, so it drops out.
    pub fn energy_balance(&self, y: &[f64]) -> EnergyBalance {
        self.balance_of(y, self.stored_energy(y))
    }

    /// [`Self::energy_balance`] of state `y` with its stored energy `e`
    /// (from [`Self::stored_energy`] or [`Self::rhs_energy`]).
    pub fn balance_of(&self, y: &[f64], e: StoredEnergy) -> EnergyBalance {
        let o = self.energy_offset();
        EnergyBalance {
            balance: y[o] - y[o + 1] - e.kinetic - (e.potential - e.creep),
            scale: e.belt,
            magnitude: y[o].abs() + y[o + 1].abs() + e.kinetic + e.potential.abs(),
        }
    }

    /// The stored energy of state `y` (see [`StoredEnergy`]): one pass over
    /// the bodies, each body's sin/cos taken once and carried to its SDE
    /// with the next, the contact and creep-spring energies only for the
    /// bodies within a pulley's reach (cheap enough for the stiff method to
    /// take once per trial step, [`crate::solver::rosenbrock`]).
    pub fn stored_energy(&self, y: &[f64]) -> StoredEnergy {
        let n = self.n;
        let hl = self.half_length;
        let mut centres = [[0.0; 2]; MAX_PULLEYS];
        for (j, c) in centres.iter_mut().enumerate().take(self.np) {
            *c = self.pulley_centre(j, y).0;
        }
        let quad = contact::quadrature(self.points);
        let end = |b: &[f64]| {
            let (s, c) = trig::sin_cos(b[2]);
            BodyEnd {
                x: b[0],
                y: b[1],
                hx: hl * c,
                hy: hl * s,
                ..BodyEnd::default()
            }
        };
        let (mut kin, mut elastic, mut gravity, mut creep) = (0.0, 0.0, 0.0, 0.0);
        let last = &y[BODY_DOF * (n - 1)..BODY_DOF * n];
        let (mut prev, mut prev_angle) = (end(last), last[2]);
        for (i, b) in y[..BODY_DOF * n].chunks_exact(BODY_DOF).enumerate() {
            kin += 0.5 * self.mass * (b[3] * b[3] + b[4] * b[4]) + 0.5 * self.inertia * b[5] * b[5];
            gravity += self.mass * self.gravity * b[1];
            let cur = end(b);
            let (d, _) = sde::gap(prev, cur);
            elastic += self.axial.energy(d[0] * d[0] + d[1] * d[1]);
            elastic += self.bend.energy(wrap_angle(b[2] - prev_angle));
            for (pc, c) in self.pulleys[..self.np].iter().zip(&centres) {
                let (rx, ry) = (b[0] - c[0], b[1] - c[1]);
                // no contact point lies farther than l/2 from the centre
                if rx * rx + ry * ry >= pc.reach * pc.reach {
                    continue;
                }
                let mut force = 0.0;
                for (&(xi, w), &radius) in quad.iter().zip(&pc.radii) {
                    let (px, py) = (rx + xi * cur.hx, ry + xi * cur.hy);
                    let p = radius - (px * px + py * py).sqrt();
                    if p > 0.0 {
                        elastic += w * self.contact.energy(p);
                        force += w * self.contact.elastic_force(p);
                    }
                }
                if force > 0.0 {
                    let zf = self.zone_factor[i];
                    creep += force
                        * self
                            .friction
                            .spring_energy(b[6], pc.mu_s * zf, pc.mu_k * zf);
                }
            }
            (prev, prev_angle) = (cur, b[2]);
        }
        self.with_pulleys(kin, elastic, creep, gravity, y)
    }

    /// The stored energy from the blocks' sums of [`Self::rhs_energy`].
    fn stored_energy_of(&self, e: BlockEnergy, y: &[f64]) -> StoredEnergy {
        let gravity = self.mass * self.gravity * e.height;
        self.with_pulleys(e.kinetic, e.elastic, e.creep, gravity, y)
    }

    /// [`StoredEnergy`] from the belt's kinetic, elastic (SDEs and
    /// contacts), creep-spring and gravity energy, with the pulleys',
    /// decoupler rotors' and tensioner arms' energy of state `y` added.
    fn with_pulleys(
        &self,
        mut kin: f64,
        elastic: f64,
        creep: f64,
        gravity: f64,
        y: &[f64],
    ) -> StoredEnergy {
        let belt = kin + elastic + creep;
        let mut pot = elastic + creep + gravity;
        for j in 0..self.np {
            let pc = &self.pulleys[j];
            let w = y[self.pulley_offset(j) + 1];
            kin += 0.5 * pc.inertia * w * w;
            if let Some(dc) = &pc.decoupler {
                let d = pc.decoupler_offset;
                kin += 0.5 * pc.rotor_inertia * y[d + 1] * y[d + 1];
                pot += dc.energy(y[d]);
            }
            if let Some(arm) = &pc.arm {
                // arm and pulley swinging about the pivot; the spring
                let (a, w) = (y[pc.arm_offset], y[pc.arm_offset + 1]);
                kin += 0.5 * arm.inertia * w * w;
                pot += arm.energy(a);
            }
        }
        StoredEnergy {
            kinetic: kin,
            potential: pot,
            belt,
            creep,
        }
    }
}

/// The stored energy of a state [J].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StoredEnergy {
    /// Kinetic energy of the belt bodies, pulleys, decoupler rotors and arms.
    pub kinetic: f64,
    /// Elastic energy of the SDEs, contacts, creep springs, decoupler and
    /// arm springs, and the belt's gravity potential.
    pub potential: f64,
    /// The belt's own part: its bodies' kinetic energy and the elastic
    /// energy of its SDEs, contacts and creep springs (no gravity, whose
    /// zero is the frame's, no pulley, whose inertia may be an engine's).
    pub belt: f64,
    /// The creep springs' part of `potential`.
    pub creep: f64,
}

/// Contact and friction (eq. 4-19) of a run of bodies with pulley `pc`
/// (surface speed `surface`, friction law `friction`).
/// `body` holds the columns x, y, vx, vy, z and friction zone factor of the
/// run (the first `valid` bodies, then padding that is ignored); the
/// contact forces and creep rates are added to `ofx`, `ofy`, `dz`, the
/// moments r f about the pulley axis and the dissipated powers stored in
/// `torque`, `diss`, and, if given, the recorded values in `rec`. Bodies
/// outside the circle (between two contacts of the run) add nothing.
/// Separate slices of one length: the loop has no aliasing and no bounds
/// checks and vectorises.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn contact_arc<const ENERGY: bool>(
    sys: &BeltSystem,
    pc: &PulleyConst,
    centre: &[f64; 4],
    surface: f64,
    friction: &impl Law,
    valid: usize,
    body: [&[f64]; 6],
    ofx: &mut [f64],
    ofy: &mut [f64],
    dz: &mut [f64],
    torque: &mut [f64],
    diss: &mut [f64],
    energy: [&mut [f64]; 2],
    mut rec: Option<&mut [[f64; 9]]>,
) {
    let k = ofx.len();
    let [en, cr] = energy;
    let (en, cr) = (&mut en[..k], &mut cr[..k]);
    let [xs, ys, vxs, vys, zs, zfs] = body;
    let (xs, ys, vxs, vys, zs, zfs) = (
        &xs[..k],
        &ys[..k],
        &vxs[..k],
        &vys[..k],
        &zs[..k],
        &zfs[..k],
    );
    let (ofy, dz, torque, diss) = (
        &mut ofy[..k],
        &mut dz[..k],
        &mut torque[..k],
        &mut diss[..k],
    );
    // constants in locals: the compiler need not prove that the stores
    // below leave them alone
    let PulleyConst {
        radius,
        radius2,
        lever,
        mu_s,
        mu_k,
        inv_p_max,
        ..
    } = *pc;
    // the centre and its velocity: the contact sees the body's motion
    // relative to it (a tensioner's pulley moves with its arm)
    let [cx, cy, cvx, cvy] = *centre;
    let law = sys.contact;
    for i in 0..k {
        let z = zs[i];
        let kin = contact::kinematics(
            [xs[i] - cx, ys[i] - cy],
            [vxs[i] - cvx, vys[i] - cvy],
            radius,
            surface,
        );
        let (normal, elastic) = law.normal_force(kin.p, kin.p_dot, inv_p_max);
        let zf = zfs[i];
        let f = friction.coefficient(kin.v_t, z, mu_s * zf, mu_k * zf) * normal; // eq. 19, along +tau
        let [fx, fy] = contact::force(&kin, normal, f);
        let inside = (kin.d2 < radius2) & (i < valid);
        let keep = |v: f64| if inside { v } else { 0.0 };
        ofx[i] = keep(fx);
        ofy[i] = keep(fy);
        dz[i] = keep(friction.creep_rate(kin.v_t, z));
        torque[i] = keep(lever * f); // eq. 24
        diss[i] = keep(contact::dissipation(&kin, normal, elastic, f));
        if ENERGY {
            // the contact's elastic energy beside its force, and its creep
            // spring's: the elastic normal force times the spring energy
            // per newton (elements::friction)
            en[i] = keep(law.energy(kin.p));
            cr[i] = keep(elastic * friction.spring_energy(z, mu_s * zf, mu_k * zf));
        }
        if let Some(r) = rec.as_deref_mut() {
            // the contact's share of the belt's loss: its normal damper and
            // friction slip; and the power its creep spring stores (the
            // friction power less what it dissipates, elements::friction)
            let (ms, mk) = (mu_s * zf, mu_k * zf);
            let loss =
                (normal - elastic) * kin.p_dot + friction.slip_loss(kin.v_t, z, ms, mk, normal);
            let stored = f * kin.v_t
                - friction.dissipated_power(
                    kin.v_t,
                    z,
                    ms,
                    mk,
                    normal,
                    elastic,
                    law.elastic_rate(kin.p, kin.p_dot),
                );
            r[i] = [
                normal,
                f,
                kin.v_t,
                kin.p,
                fx,
                fy,
                f64::from(u8::from(inside)),
                loss,
                stored,
            ];
        }
    }
}

/// Where [`contact_along_arc`] writes, per body of the run: the contact
/// force, creep rate, moment about the body centre, moment about the
/// pulley axis, dissipated power and, if given, the recorded values.
struct ArcOut<'a> {
    fx: &'a mut [f64],
    fy: &'a mut [f64],
    dz: &'a mut [f64],
    moment: &'a mut [f64],
    torque: &'a mut [f64],
    diss: &'a mut [f64],
    /// With the stored energy: the contacts' elastic energy and the creep
    /// spring's.
    energy: [&'a mut [f64]; 2],
    rec: Option<&'a mut [[f64; 9]]>,
}

/// [`contact_arc`] with the contact along the body at `K` points
/// ([`contact::point`] at each, the sums and the body's one creep rate as
/// [`contact::segment`] forms them): `body` holds the columns x, y, vx, vy,
/// omega, z, the half body vector hx, hy and the friction zone factor of
/// the run (the first `valid` bodies, then padding that is ignored); pulley
/// speed `omega`. Every lane computes all its points and keeps those
/// inside their circles, so the loop over the bodies vectorises; a body
/// with no point inside writes zeros.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn contact_along_arc<const K: usize, const ENERGY: bool>(
    sys: &BeltSystem,
    pc: &PulleyConst,
    centre: &[f64; 4],
    omega: f64,
    friction: &impl Law,
    valid: usize,
    body: [&[f64]; 9],
    out: ArcOut,
) {
    let ArcOut {
        fx: ofx,
        fy: ofy,
        dz,
        moment,
        torque,
        diss,
        energy: [en, cr],
        mut rec,
    } = out;
    let k = ofx.len();
    let (en, cr) = (&mut en[..k], &mut cr[..k]);
    let [xs, ys, vxs, vys, ws, zs, hxs, hys, zfs] = body;
    let (xs, ys, vxs, vys, ws, zs, hxs, hys, zfs) = (
        &xs[..k],
        &ys[..k],
        &vxs[..k],
        &vys[..k],
        &ws[..k],
        &zs[..k],
        &hxs[..k],
        &hys[..k],
        &zfs[..k],
    );
    let (ofy, dz, moment, torque, diss) = (
        &mut ofy[..k],
        &mut dz[..k],
        &mut moment[..k],
        &mut torque[..k],
        &mut diss[..k],
    );
    // the points' constants in locals (unrolled over K)
    let quad: [(f64, f64); K] = contact::quadrature(K).try_into().expect("K points");
    let radii: [f64; K] = pc.radii[..K].try_into().expect("K radii");
    let levers: [f64; K] = pc.levers[..K].try_into().expect("K levers");
    let law = sys.contact;
    let laws: [ContactLaw; K] = std::array::from_fn(|g| law.share(quad[g].1));
    let PulleyConst {
        mu_s,
        mu_k,
        inv_p_max,
        ..
    } = *pc;
    let [cx, cy, cvx, cvy] = *centre;
    for i in 0..k {
        let zf = zfs[i];
        let pulley = contact::PulleySide {
            radii: &radii,
            omega,
            levers: &levers,
            mu_s: mu_s * zf,
            mu_k: mu_k * zf,
            inv_p_max,
        };
        let b = contact::BodySide {
            r: [xs[i] - cx, ys[i] - cy],
            v: [vxs[i] - cvx, vys[i] - cvy],
            h: [hxs[i], hys[i]],
            w: ws[i],
            z: zs[i],
        };
        // the sums of contact::segment over the points inside
        let (mut sfx, mut sfy, mut smom, mut stq, mut sdiss) = (0.0, 0.0, 0.0, 0.0, 0.0);
        let (mut snormal, mut sfric, mut selastic, mut selastic_rate, mut sslip) =
            (0.0, 0.0, 0.0, 0.0, 0.0);
        let (mut se, mut sev, mut count, mut sv) = (0.0, 0.0, 0.0, 0.0);
        let mut s_energy = 0.0;
        let mut p_max = f64::MIN;
        // the points unrolled by hand (LLVM keeps a loop over four or five
        // of them, and a loop inside stops the lanes' loop vectorising)
        macro_rules! at {
            ($g:literal) => {
                if $g < K {
                    let g = $g;
                    let pt = contact::point(
                        &laws[g], friction, quad[g].0, radii[g], levers[g], &pulley, &b,
                    );
                    p_max = p_max.max(pt.kin.p);
                    let inside = pt.kin.p > 0.0;
                    let keep = |v: f64| if inside { v } else { 0.0 };
                    sfx += keep(pt.force[0]);
                    sfy += keep(pt.force[1]);
                    smom += keep(pt.moment);
                    stq += keep(levers[g] * pt.f);
                    sdiss += keep(pt.dissipation);
                    snormal += keep(pt.normal);
                    sfric += keep(pt.f);
                    selastic += keep(pt.elastic);
                    selastic_rate += keep(pt.elastic_rate);
                    sslip += keep(pt.f * pt.kin.v_t);
                    se += keep(pt.elastic);
                    sev += keep(pt.elastic * pt.kin.v_t);
                    count += keep(1.0);
                    sv += keep(pt.kin.v_t);
                    if ENERGY {
                        // the point's elastic energy beside its force
                        s_energy += keep(laws[g].energy(pt.kin.p));
                    }
                }
            };
        }
        at!(0);
        at!(1);
        at!(2);
        at!(3);
        at!(4);
        let v_t = contact::body_sliding_velocity(se, sev, count, sv);
        let creep_rate = friction.creep_rate(v_t, b.z);
        let inside = (count > 0.0) & (i < valid);
        let keep = |v: f64| if inside { v } else { 0.0 };
        ofx[i] = keep(sfx);
        ofy[i] = keep(sfy);
        dz[i] = keep(creep_rate);
        moment[i] = keep(smom);
        torque[i] = keep(stq); // eq. 24
        diss[i] = keep(sdiss);
        if ENERGY {
            // the creep spring's energy: the elastic normal force summed
            // over the points times the spring energy per newton
            en[i] = keep(s_energy);
            cr[i] = keep(selastic * friction.spring_energy(b.z, pulley.mu_s, pulley.mu_k));
        }
        if let Some(r) = rec.as_deref_mut() {
            // the contact's share of the belt's loss (normal dampers and
            // friction slip) and the power its creep spring stores
            // (elements::friction, with the body's one creep rate)
            let (ms, mk) = (pulley.mu_s, pulley.mu_k);
            let mu0 = friction.coefficient(0.0, b.z, ms, mk);
            let phi = friction.spring_energy(b.z, ms, mk);
            let slip = sslip - snormal * mu0 * creep_rate;
            let stored = selastic * mu0 * creep_rate + selastic_rate * phi;
            let damper = sdiss - (slip + snormal * mu0 * creep_rate);
            r[i] = [
                snormal,
                sfric,
                v_t,
                p_max,
                sfx,
                sfy,
                f64::from(u8::from(inside)),
                damper + slip.max(0.0),
                stored,
            ];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `sum4` gives each column's `sum` to the last bit, for every length
    /// up to two blocks of padding, with values of mixed sign and size,
    /// zeros of both signs and +0 in the padding (as the contact loops
    /// leave it).
    #[test]
    fn sum4_is_sum_bit_for_bit() {
        let value = |s: usize, i: usize| -> f64 {
            match (s * 7 + i * 13) % 11 {
                0 => -0.0,
                1 => 0.0,
                k => (k as f64 - 5.5) * 10f64.powi((i % 7) as i32 - 3) / 3.0,
            }
        };
        for len in 0..=2 * PAD {
            let cols: Vec<Vec<f64>> = (0..4)
                .map(|s| {
                    (0..padded(len).max(PAD))
                        .map(|i| if i < len { value(s, i) } else { 0.0 })
                        .collect()
                })
                .collect();
            let got = sum4(std::array::from_fn(|s| cols[s].as_slice()), len);
            for s in 0..4 {
                assert_eq!(
                    got[s].to_bits(),
                    sum(&cols[s][..len]).to_bits(),
                    "len {len}, column {s}"
                );
            }
        }
        // all -0: sum gives +0 (its partial sums start at +0), so must sum4
        let z = [-0.0; PAD];
        let got = sum4([&z[..], &z[..], &z[..], &z[..]], 3);
        assert_eq!(got[0].to_bits(), sum(&z[..3]).to_bits());
    }
}
