//! The right-hand side's scratch: one block of bodies in structure-of-arrays
//! form ([`Block`], owned through a [`Workspace`]), and the bit-exact sums
//! over its columns.

use crate::model::elements::sde::BodyEnd;
use crate::model::simd;
use crate::model::system::BODY_DOF;

/// Bodies per block of the right-hand side (scratch of ~9 KiB, stays in L1).
pub const BLOCK: usize = 64;

/// The contact loops run to a multiple of `PAD` bodies (the widest vector,
/// AVX-512's 8 doubles), so that a short arc does not end in scalar
/// iterations of the force laws; the lanes past the end compute on stale
/// scratch values and are discarded. (Padding the other loops the same way
/// measured slower.)
pub(super) const PAD: usize = 8;

#[inline(always)]
pub(super) fn padded(len: usize) -> usize {
    len.next_multiple_of(PAD)
}

/// Length of a body column: body m = 0..len + 2 plus the padding, rounded
/// up to whole 64-byte cache lines.
pub(super) const BODY_COL: usize = (BLOCK + 2 + PAD).next_multiple_of(8);
/// Length of an SDE column (k = 0..=len plus the padding), whole cache lines.
pub(super) const SDE_COL: usize = (BLOCK + 1 + PAD).next_multiple_of(8);
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
pub(super) struct Block {
    /// Puts index 1 of the body columns on a line boundary.
    pub(super) _lead: [f64; 7],
    // body m = 0..len + 2 (body i0 - 1 + m)
    pub(super) x: [f64; BODY_COL],
    pub(super) y: [f64; BODY_COL],
    pub(super) phi: [f64; BODY_COL],
    pub(super) vx: [f64; BODY_COL],
    pub(super) vy: [f64; BODY_COL],
    pub(super) w: [f64; BODY_COL],
    pub(super) z: [f64; BODY_COL],
    /// Half body vector (l/2) (cos phi, sin phi).
    pub(super) hx: [f64; BODY_COL],
    pub(super) hy: [f64; BODY_COL],
    /// Puts the SDE columns on a line boundary.
    pub(super) _gap: [f64; 1],
    // SDE k = 0..=len (SDE i0 + k, between body m = k and m = k + 1): force
    // on body k + 1 (minus it on body k), torque on body k + 1 and on body
    // k, dissipated power
    pub(super) fx: [f64; SDE_COL],
    pub(super) fy: [f64; SDE_COL],
    pub(super) torque_cur: [f64; SDE_COL],
    pub(super) torque_prev: [f64; SDE_COL],
    pub(super) diss: [f64; SDE_COL],
    // body j = 0..len (body i0 + j): friction zone factor, own forces
    // (gravity, contact), creep rate, accelerations
    pub(super) zf: [f64; OWN_COL],
    pub(super) ofx: [f64; OWN_COL],
    pub(super) ofy: [f64; OWN_COL],
    pub(super) dz: [f64; OWN_COL],
    pub(super) ax: [f64; OWN_COL],
    pub(super) ay: [f64; OWN_COL],
    pub(super) alpha: [f64; OWN_COL],
    // contacts of body j with the pulley at hand: moment r f, power, and
    // the recorded values (normal force, friction force, v_T, penetration,
    // force on the body, inside)
    pub(super) cfx: [f64; OWN_COL],
    pub(super) cfy: [f64; OWN_COL],
    pub(super) cdz: [f64; OWN_COL],
    pub(super) torque_q: [f64; OWN_COL],
    pub(super) diss_q: [f64; OWN_COL],
    pub(super) rec_q: [[f64; 9]; OWN_COL],
    // contact along the body: the contact moments on body j about its
    // centre, summed over the pulleys, and that of the pulley at hand
    pub(super) otq: [f64; OWN_COL],
    pub(super) cmq: [f64; OWN_COL],
    // only in the evaluation that also takes the stored energy
    // ([`BeltSystem::rhs_energy`]): the elastic energy of the contacts of
    // body j with the pulley at hand and of its creep spring, and that of
    // SDE k
    pub(super) en_q: [f64; OWN_COL],
    pub(super) cr_q: [f64; OWN_COL],
    pub(super) esde: [f64; SDE_COL],
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
    pub(super) fn body_end(&self, m: usize) -> BodyEnd {
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

    pub(super) fn new() -> Self {
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
    pub(super) fn carry(&mut self, len: usize) {
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
    pub(super) fn gather<const WIDE: bool>(&mut self, m: usize, src: &[f64]) {
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
    pub(super) fn scatter<const WIDE: bool>(&self, dst: &mut [f64]) {
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
    pub(super) block: Box<Block>,
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

/// What the blocks of [`BeltSystem::rhs_energy`] sum of the stored energy.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct BlockEnergy {
    /// Kinetic energy of the bodies [J].
    pub(super) kinetic: f64,
    /// Elastic energy of the SDEs and contacts [J].
    pub(super) elastic: f64,
    /// Energy of the creep springs [J].
    pub(super) creep: f64,
    /// Sum of the body centres' heights [m].
    pub(super) height: f64,
}

impl BlockEnergy {
    /// Adds the contact and creep-spring energies of the bodies `lo..end`
    /// (a contact arc, padded; the lanes outside hold zeros).
    #[inline(always)]
    pub(super) fn add_contacts(&mut self, b: &Block, lo: usize, end: usize) {
        self.elastic += sum(&b.en_q[lo..end]);
        self.creep += sum(&b.cr_q[lo..end]);
    }
}

/// [`sum`] of the first `len` values of each of four columns at once,
/// bit for bit: the same partial sums over the whole chunks of four, the
/// remainder summed in order, then combined as [`sum`] combines them. The
/// columns run on to a multiple of [`PAD`] with +0 past `len` (a contact
/// loop's discarded lanes), so the remainder is summed as a whole chunk
/// (adding +0 leaves a sum unchanged but for the sign of a zero, which
/// the combination absorbs: the partial sums, started at +0, are never -0).
#[inline(always)]
pub(super) fn sum4(cols: [&[f64]; 4], len: usize) -> [f64; 4] {
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

/// Over the bodies m = 1..=len of a block: the sums of v^2, omega^2 and the
/// height y, in four interleaved partial sums.
#[inline(always)]
pub(super) fn body_sums(b: &Block, len: usize) -> [f64; 3] {
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
pub(super) fn sum(v: &[f64]) -> f64 {
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
