//! The linear system of an implicit stage, `(I - c J) x = b`, solved in
//! O(n) for the belt's block Jacobian (`solver/jacobian/`).
//!
//! 1. Reduction to velocities: positions and creep states are eliminated
//!    exactly (dq = b_q + c dv; dz = b_z + c (g_q dq + g_v dv + g_w dw)), which
//!    leaves 3 unknowns per body plus one per torque-driven pulley:
//!    `S = I - c^2 dA/dq - c dA/dv - (creep terms)`.
//! 2. S is block tridiagonal with 3x3 blocks, cyclic (the belt is a closed
//!    loop), plus dense rows and columns for the pulley speeds and the
//!    tensioner arms' rates (each arm's angle is eliminated like a body's
//!    position: d alpha = b_alpha + c d omega_arm, and its pivot friction's
//!    deflection alike). Body n-1, the free
//!    pulleys and the arms form a border of 3 + (free pulleys) + (arms)
//!    unknowns, its size a type parameter (no unused rows or columns); bodies 0..n-2 are
//!    eliminated in order by block Gaussian elimination (fill-in only in the
//!    border), the border is solved densely (LU with partial pivoting), and
//!    the bodies are found by back substitution.
//!
//! 3. The impulse states (`solver/jacobian/`) have rows but no columns: they
//!    follow from the solution, x_q = b_q + c G x.
//!
//! Factoring costs a few hundred flops per body, each solve about sixty; no
//! allocation after construction.

use crate::model::matmul::mm;
use crate::model::params::MAX_PULLEYS;
use crate::model::simd::{self, Isa};
use crate::model::state::BodyIndex;
use crate::model::system::BeltSystem;
use crate::solver::jacobian::{
    ArmJacobian, BodyArmJacobian, BodyJacobian, Jacobian, NEXT, PREV, SELF,
};
use nalgebra::{Matrix2, Matrix3, RowVector3, SMatrix, SVector, Vector2, Vector3};

/// The factors for a border of `NB` unknowns: body n-1 (3), the free
/// (torque-driven) pulleys and the tensioner arms. The border's size is a
/// type parameter so that its dense products have no unused rows and columns.
#[derive(Clone, Debug, PartialEq)]
pub struct Factors<const NB: usize> {
    c: f64,
    /// Border index of pulley j's speed (3 + k), or None if speed-driven.
    slot: [Option<usize>; MAX_PULLEYS],
    /// Border index of the rate of pulley j's tensioner arm, if it has one.
    arm_slot: [Option<usize>; MAX_PULLEYS],
    /// Per body i < n-1: inverse of the eliminated diagonal block.
    dinv: Vec<Matrix3<f64>>,
    /// L_i D'_{i-1}^-1 (multiplier of the previous block row).
    l: Vec<Matrix3<f64>>,
    /// Upper block S_{i,i+1}.
    u: Vec<Matrix3<f64>>,
    /// Border columns after elimination (3 x NB).
    e: Vec<SMatrix<f64, 3, NB>>,
    /// Border rows after elimination, times D'_i^-1 (NB x 3).
    fd: Vec<SMatrix<f64, NB, 3>>,
    /// LU factors of the border's Schur complement, and its row order.
    g: SMatrix<f64, NB, NB>,
    perm: [usize; NB],
    /// Scratch: reduced right-hand sides.
    rv: Vec<Vector3<f64>>,
    bz: Vec<f64>,
    /// Decoupler of pulley j, eliminated exactly: its unknowns (twist,
    /// rotor speed) are A^-1 b + h x_hub, A = I - c J_dd its own block,
    /// h = c A^-1 J_d,hub; `dec_ainv`, `dec_h`.
    dec_ainv: [Matrix2<f64>; MAX_PULLEYS],
    dec_h: [Vector2<f64>; MAX_PULLEYS],
}

/// `I - c J` factored; one variant per border size 3 + free pulleys + arms.
#[derive(Clone, Debug, PartialEq)]
#[allow(clippy::large_enum_variant)] // one per drive: its size does not matter
pub enum IterationMatrix {
    /// Border of 3 unknowns.
    B3(Factors<3>),
    /// Border of 4 unknowns.
    B4(Factors<4>),
    /// Border of 5 unknowns.
    B5(Factors<5>),
    /// Border of 6 unknowns.
    B6(Factors<6>),
    /// Border of 7 unknowns.
    B7(Factors<7>),
    /// Border of 8 unknowns.
    B8(Factors<8>),
    /// Border of 9 unknowns.
    B9(Factors<9>),
    /// Border of 10 unknowns.
    B10(Factors<10>),
    /// Border of 11 unknowns.
    B11(Factors<11>),
    /// Border of 12 unknowns.
    B12(Factors<12>),
    /// Border of 13 unknowns.
    B13(Factors<13>),
    /// Border of 14 unknowns.
    B14(Factors<14>),
    /// Border of 15 unknowns.
    B15(Factors<15>),
    /// Border of 16 unknowns.
    B16(Factors<16>),
    /// Border of 17 unknowns.
    B17(Factors<17>),
    /// Border of 18 unknowns.
    B18(Factors<18>),
    /// Border of 19 unknowns.
    B19(Factors<19>),
}

// one variant per border size up to every slot's pulley free and on an arm
const _: () = assert!(3 + 2 * MAX_PULLEYS == 19);

macro_rules! each {
    ($m:expr, $f:ident => $e:expr) => {
        match $m {
            IterationMatrix::B3($f) => $e,
            IterationMatrix::B4($f) => $e,
            IterationMatrix::B5($f) => $e,
            IterationMatrix::B6($f) => $e,
            IterationMatrix::B7($f) => $e,
            IterationMatrix::B8($f) => $e,
            IterationMatrix::B9($f) => $e,
            IterationMatrix::B10($f) => $e,
            IterationMatrix::B11($f) => $e,
            IterationMatrix::B12($f) => $e,
            IterationMatrix::B13($f) => $e,
            IterationMatrix::B14($f) => $e,
            IterationMatrix::B15($f) => $e,
            IterationMatrix::B16($f) => $e,
            IterationMatrix::B17($f) => $e,
            IterationMatrix::B18($f) => $e,
            IterationMatrix::B19($f) => $e,
        }
    };
}

impl IterationMatrix {
    /// Storage for the iteration matrix of `sys` (border size from its free pulleys, decouplers and arms).
    pub fn new(sys: &BeltSystem) -> Self {
        let free = (0..sys.np)
            .filter(|&j| !sys.pulleys[j].speed_driven)
            .count();
        match 3 + free + sys.state_layout.n_arms() {
            3 => Self::B3(Factors::new(sys)),
            4 => Self::B4(Factors::new(sys)),
            5 => Self::B5(Factors::new(sys)),
            6 => Self::B6(Factors::new(sys)),
            7 => Self::B7(Factors::new(sys)),
            8 => Self::B8(Factors::new(sys)),
            9 => Self::B9(Factors::new(sys)),
            10 => Self::B10(Factors::new(sys)),
            11 => Self::B11(Factors::new(sys)),
            12 => Self::B12(Factors::new(sys)),
            13 => Self::B13(Factors::new(sys)),
            14 => Self::B14(Factors::new(sys)),
            15 => Self::B15(Factors::new(sys)),
            16 => Self::B16(Factors::new(sys)),
            17 => Self::B17(Factors::new(sys)),
            18 => Self::B18(Factors::new(sys)),
            _ => Self::B19(Factors::new(sys)),
        }
    }

    /// Unknowns in the border (3 + free pulleys + arms).
    pub fn border_size(&self) -> usize {
        each!(self, f => f.perm.len())
    }

    /// Factors `I - c J`. Returns false if a pivot block is singular.
    /// Runs an AVX2 build where the CPU has it (no FMA: the same numbers
    /// to the last bit).
    pub fn factor(&mut self, sys: &BeltSystem, jac: &Jacobian, c: f64) -> bool {
        self.factor_with(Isa::detected().min(Isa::Avx2), sys, jac, c)
    }

    /// Overwrites `b` (a full state-sized vector) with x, `(I - c J) x = b`.
    pub fn solve(&mut self, sys: &BeltSystem, jac: &Jacobian, b: &mut [f64]) {
        self.solve_with(Isa::detected().min(Isa::Avx2), sys, jac, b);
    }

    /// [`Self::factor`] built for `isa`.
    fn factor_with(&mut self, isa: Isa, sys: &BeltSystem, jac: &Jacobian, c: f64) -> bool {
        simd::dispatch_with(
            isa,
            (self, sys, jac),
            #[inline(always)]
            |(m, sys, jac)| each!(m, f => f.factor(sys, jac, c)),
        )
    }

    /// [`Self::solve`] built for `isa`.
    fn solve_with(&mut self, isa: Isa, sys: &BeltSystem, jac: &Jacobian, b: &mut [f64]) {
        simd::dispatch_with(
            isa,
            (self, sys, jac, b),
            #[inline(always)]
            |(m, sys, jac, b)| each!(m, f => f.solve(sys, jac, b)),
        );
    }
}

/// Body i's position entries (x, y, phi) of a state-sized vector.
#[inline(always)]
fn positions(b: &[f64], i: usize) -> Vector3<f64> {
    let o = BodyIndex::of(i);
    Vector3::new(b[o.x], b[o.y], b[o.angle])
}

impl<const NB: usize> Factors<NB> {
    fn new(sys: &BeltSystem) -> Self {
        let m = sys.n.saturating_sub(1);
        let mut slot = [None; MAX_PULLEYS];
        let mut k = 3;
        for (j, s) in slot.iter_mut().enumerate().take(sys.np) {
            if !sys.pulleys[j].speed_driven {
                *s = Some(k);
                k += 1;
            }
        }
        let mut arm_slot = [None; MAX_PULLEYS];
        for (j, s) in arm_slot.iter_mut().enumerate().take(sys.np) {
            if sys.pulleys[j].arm.is_some() {
                *s = Some(k);
                k += 1;
            }
        }
        Self {
            c: 0.0,
            slot,
            arm_slot,
            dinv: vec![Matrix3::zeros(); m],
            l: vec![Matrix3::zeros(); m],
            u: vec![Matrix3::zeros(); m],
            e: vec![SMatrix::zeros(); m],
            fd: vec![SMatrix::zeros(); m],
            g: SMatrix::identity(),
            perm: std::array::from_fn(|i| i),
            rv: vec![Vector3::zeros(); sys.n],
            bz: vec![0.0; sys.n],
            dec_ainv: [Matrix2::zeros(); MAX_PULLEYS],
            dec_h: [Vector2::zeros(); MAX_PULLEYS],
        }
    }

    /// Reduced block S_{i,nb} of body `b` for neighbour slot (PREV, SELF, NEXT).
    #[inline(always)]
    fn block(b: &BodyJacobian, c: f64, slot: usize) -> Matrix3<f64> {
        let mut s = -(c * c) * b.accel_by_position[slot] - c * b.accel_by_velocity[slot];
        if slot == SELF {
            s += Matrix3::identity() - mm(&(c * b.accel_by_creep), &Self::h_row(b, c));
        }
        s
    }

    /// H_i = c^2 g_q + c g_v: how the creep increment follows the velocity increment.
    #[inline(always)]
    fn h_row(b: &BodyJacobian, c: f64) -> RowVector3<f64> {
        (c * c) * b.creep_rate_by_position + c * b.creep_rate_by_velocity
    }

    /// Border column of body `b` for pulley j (3-vector), S_{i,w_j}.
    #[inline(always)]
    fn pulley_column(b: &BodyJacobian, c: f64, j: usize) -> Vector3<f64> {
        -c * b.accel_by_pulley_speed[j]
            - (c * c * b.creep_rate_by_pulley_speed[j]) * b.accel_by_creep
    }

    /// Pulley j's row for body `b`'s velocities, R_{j,i}.
    #[inline(always)]
    fn pulley_row(b: &BodyJacobian, c: f64, j: usize) -> RowVector3<f64> {
        -(c * c) * b.pulley_accel_by_position[j]
            - c * b.pulley_accel_by_velocity[j]
            - (c * b.pulley_accel_by_creep[j]) * Self::h_row(b, c)
    }

    /// Border column of body `b` (its arm rows `a`) for the rate of pulley
    /// j's arm (3-vector): its angle enters as c times the rate, directly
    /// and through the creep.
    #[inline(always)]
    fn arm_column(b: &BodyJacobian, a: &BodyArmJacobian, c: f64, j: usize) -> Vector3<f64> {
        -c * (c * a.accel_by_arm_angle[j] + a.accel_by_arm_rate[j])
            - (c * c * (c * a.creep_rate_by_arm_angle[j] + a.creep_rate_by_arm_rate[j]))
                * b.accel_by_creep
    }

    /// The pivot of an arm's friction deflection row, 1 - c dz'/dz: the
    /// deflection depends on the arm's rate only (its hub-force partial is
    /// left out of the Jacobian), so it is eliminated like the arm's angle,
    /// dz = (b_z + c dz'/d alpha' d alpha') / (1 - c dz'/dz).
    #[inline(always)]
    fn deflection_pivot(a: &ArmJacobian, c: f64) -> f64 {
        1.0 - c * a.deflection_rate_by_deflection
    }

    /// The row of pulley j's arm for body `b`'s velocities.
    #[inline(always)]
    fn arm_row(b: &BodyJacobian, a: &BodyArmJacobian, c: f64, j: usize) -> RowVector3<f64> {
        -(c * c) * a.arm_accel_by_position[j]
            - c * a.arm_accel_by_velocity[j]
            - (c * a.arm_accel_by_creep[j]) * Self::h_row(b, c)
    }

    /// Border entries (rows of body n-1 and the pulleys) of body i's columns.
    #[inline(always)]
    fn border_rows(k: &View, i: usize) -> SMatrix<f64, NB, 3> {
        let n = k.bodies.len();
        let last = n - 1;
        let mut f = SMatrix::<f64, NB, 3>::zeros();
        if i == 0 {
            f.fixed_view_mut::<3, 3>(0, 0)
                .copy_from(&Self::block(&k.bodies[last], k.c, NEXT));
        }
        if i + 2 == n {
            let mut v = f.fixed_view_mut::<3, 3>(0, 0);
            v += Self::block(&k.bodies[last], k.c, PREV);
        }
        let b = &k.bodies[i];
        let touching = b.touching;
        for (j, s) in k.slots().iter().enumerate() {
            if let Some(s) = *s {
                if touching & (1 << j) != 0 {
                    f.fixed_view_mut::<1, 3>(s, 0)
                        .copy_from(&Self::pulley_row(b, k.c, j));
                }
            }
        }
        for (j, s) in k.arm_slots().iter().enumerate() {
            if let Some(s) = *s {
                if touching & (1 << j) != 0 {
                    f.fixed_view_mut::<1, 3>(s, 0).copy_from(&Self::arm_row(
                        b,
                        &k.arm_bodies[i],
                        k.c,
                        j,
                    ));
                }
            }
        }
        f
    }

    /// Border columns (body n-1 and pulley speeds) of body i's rows.
    #[inline(always)]
    fn border_cols(k: &View, i: usize) -> SMatrix<f64, 3, NB> {
        let n = k.bodies.len();
        let mut e = SMatrix::<f64, 3, NB>::zeros();
        if i == 0 {
            e.fixed_view_mut::<3, 3>(0, 0)
                .copy_from(&Self::block(&k.bodies[0], k.c, PREV));
        }
        let b = &k.bodies[i];
        if i + 2 == n {
            let mut v = e.fixed_view_mut::<3, 3>(0, 0);
            v += Self::block(b, k.c, NEXT);
        }
        let touching = b.touching;
        for (j, s) in k.slots().iter().enumerate() {
            if let Some(s) = *s {
                if touching & (1 << j) != 0 {
                    e.fixed_view_mut::<3, 1>(0, s)
                        .copy_from(&Self::pulley_column(b, k.c, j));
                }
            }
        }
        for (j, s) in k.arm_slots().iter().enumerate() {
            if let Some(s) = *s {
                if touching & (1 << j) != 0 {
                    e.fixed_view_mut::<3, 1>(0, s).copy_from(&Self::arm_column(
                        b,
                        &k.arm_bodies[i],
                        k.c,
                        j,
                    ));
                }
            }
        }
        e
    }

    /// The border block G before the elimination of bodies 0..n-2: body
    /// n-1, the free pulleys' speeds and the arms' rates, with their
    /// couplings through the bodies' creep.
    #[inline(always)]
    fn border_block(view: &View, jac: &Jacobian) -> SMatrix<f64, NB, NB> {
        let c = view.c;
        let (bodies, arm_bodies) = (view.bodies, view.arm_bodies);
        let last = bodies.len() - 1;
        // border block G: body n-1 and pulleys
        let mut g = SMatrix::<f64, NB, NB>::identity();
        g.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&Self::block(&bodies[last], c, SELF));
        let touching_last = bodies[last].touching;
        for (j, sj) in view.slots().iter().enumerate() {
            let Some(kj) = *sj else { continue };
            if touching_last & (1 << j) != 0 {
                g.fixed_view_mut::<3, 1>(0, kj)
                    .copy_from(&Self::pulley_column(&bodies[last], c, j));
                g.fixed_view_mut::<1, 3>(kj, 0)
                    .copy_from(&Self::pulley_row(&bodies[last], c, j));
            }
            // pulley-pulley: R_{j,w_k} = delta - c pw - c^2 sum_i pz_ij gw_ik
            for (k, sk) in view.slots().iter().enumerate() {
                let Some(kk) = *sk else { continue };
                let mut v =
                    if j == k { 1.0 } else { 0.0 } - c * jac.pulley_accel_by_pulley_speed[j][k];
                for b in bodies {
                    if b.touching & (1 << j) != 0 {
                        v -= c * c * b.pulley_accel_by_creep[j] * b.creep_rate_by_pulley_speed[k];
                    }
                }
                g[(kj, kk)] = v;
            }
            // pulley-arm: its own arm directly (pa, pr), every arm through
            // the creep of the bodies on both
            for (k, sk) in view.arm_slots().iter().enumerate() {
                let Some(kk) = *sk else { continue };
                let mut v = 0.0;
                if j == k {
                    v -= c
                        * (c * jac.arms[j].pulley_accel_by_arm_angle
                            + jac.arms[j].pulley_accel_by_arm_rate);
                }
                for (b, a) in bodies.iter().zip(arm_bodies) {
                    if b.touching & (1 << j) != 0 {
                        v -= c
                            * c
                            * b.pulley_accel_by_creep[j]
                            * (c * a.creep_rate_by_arm_angle[k] + a.creep_rate_by_arm_rate[k]);
                    }
                }
                g[(kj, kk)] = v;
            }
        }
        // arm rows: body n-1, pulley speeds, arm rates
        for (j, sj) in view.arm_slots().iter().enumerate() {
            let Some(kj) = *sj else { continue };
            if touching_last & (1 << j) != 0 {
                g.fixed_view_mut::<3, 1>(0, kj).copy_from(&Self::arm_column(
                    &bodies[last],
                    &arm_bodies[last],
                    c,
                    j,
                ));
                g.fixed_view_mut::<1, 3>(kj, 0).copy_from(&Self::arm_row(
                    &bodies[last],
                    &arm_bodies[last],
                    c,
                    j,
                ));
            }
            let touching = |b: &BodyJacobian| b.touching & (1 << j) != 0;
            for (k, sk) in view.slots().iter().enumerate() {
                let Some(kk) = *sk else { continue };
                let mut v = if j == k {
                    -c * jac.arms[j].arm_accel_by_pulley_speed
                } else {
                    0.0
                };
                for (b, a) in bodies.iter().zip(arm_bodies) {
                    if touching(b) {
                        v -= c * c * a.arm_accel_by_creep[j] * b.creep_rate_by_pulley_speed[k];
                    }
                }
                g[(kj, kk)] = v;
            }
            for (k, sk) in view.arm_slots().iter().enumerate() {
                let Some(kk) = *sk else { continue };
                let mut v = if j == k {
                    let a = &jac.arms[j];
                    1.0 - c * (c * a.arm_accel_by_angle + a.arm_accel_by_rate)
                        - c * c * a.arm_accel_by_deflection * a.deflection_rate_by_rate
                            / Self::deflection_pivot(a, c)
                } else {
                    0.0
                };
                for (b, a) in bodies.iter().zip(arm_bodies) {
                    if touching(b) {
                        v -= c
                            * c
                            * a.arm_accel_by_creep[j]
                            * (c * a.creep_rate_by_arm_angle[k] + a.creep_rate_by_arm_rate[k]);
                    }
                }
                g[(kj, kk)] = v;
            }
        }
        g
    }

    /// LU factors of the border block `g` in place, with partial pivoting
    /// (unused slots are identity); its row order, None if it is singular.
    #[inline(always)]
    fn lu(g: &mut SMatrix<f64, NB, NB>) -> Option<[usize; NB]> {
        let mut perm: [usize; NB] = std::array::from_fn(|i| i);
        for k in 0..NB {
            let p = (k..NB)
                .max_by(|&a, &b| g[(a, k)].abs().total_cmp(&g[(b, k)].abs()))
                .unwrap_or(k);
            if g[(p, k)] == 0.0 || !g[(p, k)].is_finite() {
                return None;
            }
            if p != k {
                g.swap_rows(p, k);
                perm.swap(p, k);
            }
            for r in k + 1..NB {
                let l = g[(r, k)] / g[(k, k)];
                g[(r, k)] = l;
                for cc in k + 1..NB {
                    g[(r, cc)] -= l * g[(k, cc)];
                }
            }
        }
        Some(perm)
    }

    #[inline(always)]
    fn factor(&mut self, sys: &BeltSystem, jac: &Jacobian, c: f64) -> bool {
        let n = sys.n;
        let m = n - 1;
        self.c = c;
        let view = View::new(sys, jac, c, self.slot, self.arm_slot);
        let bodies = view.bodies;
        let mut g = Self::border_block(&view, jac);
        // decouplers: eliminate twist and rotor speed; a free hub's diagonal
        // gains -c (J_h,d h)
        for j in 0..sys.np {
            if sys.pulleys[j].decoupler.is_none() {
                continue;
            }
            let d = &jac.decouplers[j];
            let a = Matrix2::new(
                1.0 - c * d.twist_rate_by_twist,
                -c * d.twist_rate_by_rotor_speed,
                -c * d.rotor_accel_by_twist,
                1.0 - c * d.rotor_accel_by_rotor_speed,
            );
            let Some(ainv) = a.try_inverse() else {
                return false;
            };
            let h = ainv
                * Vector2::new(
                    c * d.twist_rate_by_hub_speed,
                    c * d.rotor_accel_by_hub_speed,
                );
            self.dec_ainv[j] = ainv;
            self.dec_h[j] = h;
            if let Some(kj) = self.slot[j] {
                g[(kj, kj)] -=
                    c * (d.hub_accel_by_twist * h[0] + d.hub_accel_by_rotor_speed * h[1]);
            }
        }
        // forward elimination over bodies 0..n-2, into the factors' slices
        let (dinv_s, l_s, u_s) = (&mut self.dinv[..m], &mut self.l[..m], &mut self.u[..m]);
        let (e_s, fd_s) = (&mut self.e[..m], &mut self.fd[..m]);
        for i in 0..m {
            let mut d = Self::block(&bodies[i], c, SELF);
            let mut e = Self::border_cols(&view, i);
            let mut f = Self::border_rows(&view, i);
            if i > 0 {
                let lower = Self::block(&bodies[i], c, PREV);
                let l = mm(&lower, &dinv_s[i - 1]);
                d -= mm(&l, &u_s[i - 1]);
                e -= mm(&l, &e_s[i - 1]);
                f -= mm(&fd_s[i - 1], &u_s[i - 1]);
                l_s[i] = l;
            }
            let Some(dinv) = d.try_inverse() else {
                return false;
            };
            dinv_s[i] = dinv;
            u_s[i] = if i + 1 < m {
                Self::block(&bodies[i], c, NEXT)
            } else {
                Matrix3::zeros()
            };
            let fd = mm(&f, &dinv);
            g -= mm(&fd, &e);
            e_s[i] = e;
            fd_s[i] = fd;
        }
        let Some(perm) = Self::lu(&mut g) else {
            return false;
        };
        self.g = g;
        self.perm = perm;
        true
    }

    /// Writes body i's increments: velocities `dv`, positions `b_q + c dv`,
    /// creep state from `bz` (its reduced right-hand side) and the pulley
    /// speed increments `dw`; `arm` is the body's arm rows if the drive has arms.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn recover(
        bj: &BodyJacobian,
        arm: Option<&BodyArmJacobian>,
        c: f64,
        dw: &[f64],
        dr: &[f64],
        b: &mut [f64],
        i: usize,
        dv: Vector3<f64>,
        bz: f64,
    ) {
        let o = BodyIndex::of(i);
        let dq = positions(b, i) + c * dv;
        // bz is b_z + c g_q b_q (+ c g_alpha b_alpha); add the terms of the
        // increments
        let mut dz = bz
            + c * (c * bj.creep_rate_by_position.dot(&dv.transpose())
                + bj.creep_rate_by_velocity.dot(&dv.transpose()));
        if bj.touching != 0 {
            for (g, w) in bj.creep_rate_by_pulley_speed.iter().zip(dw) {
                dz += c * g * w;
            }
            if let Some(a) = arm {
                for ((ga, gr), r) in a
                    .creep_rate_by_arm_angle
                    .iter()
                    .zip(&a.creep_rate_by_arm_rate)
                    .zip(dr)
                {
                    dz += c * (c * ga + gr) * r;
                }
            }
        }
        b[o.x..=o.angle].copy_from_slice(dq.as_slice());
        b[o.vx..=o.spin].copy_from_slice(dv.as_slice());
        b[o.creep] = dz;
    }

    /// Step 1 of [`Self::solve`], forward along the belt: each body's
    /// reduced right-hand side (positions and creep eliminated), eliminated
    /// as soon as it is formed (kept in `rv`, `bz`). Returns the border's
    /// right-hand side.
    #[inline(always)]
    fn forward(
        &mut self,
        view: &View,
        sys: &BeltSystem,
        jac: &Jacobian,
        b: &[f64],
    ) -> SVector<f64, NB> {
        let n = sys.n;
        let m = n - 1;
        let c = self.c;
        let (bodies, arm_bodies) = (view.bodies, view.arm_bodies);
        let (l_s, fd_s) = (&self.l[..m], &self.fd[..m]);
        let (rv_s, bz_s) = (&mut self.rv[..n], &mut self.bz[..n]);
        let mut rw = SVector::<f64, NB>::zeros();
        for (j, s) in view.slots().iter().enumerate() {
            if let Some(k) = *s {
                rw[k] = b[sys.state_layout.pulley(j).speed];
            }
        }
        // the arms' angle increments' right-hand sides b_alpha, which enter
        // like the bodies' positions
        let mut b_arm = [0.0; MAX_PULLEYS];
        for (j, s) in view.arm_slots().iter().enumerate() {
            if let Some(k) = *s {
                let o = sys.state_layout.arm(j);
                b_arm[j] = b[o.angle];
                let a = &jac.arms[j];
                rw[k] = b[o.rate]
                    + c * a.arm_accel_by_angle * b[o.angle]
                    + c * a.arm_accel_by_deflection * b[o.deflection]
                        / Self::deflection_pivot(a, c);
                if let Some(kp) = view.slot[j] {
                    rw[kp] += c * a.pulley_accel_by_arm_angle * b[o.angle];
                }
            }
        }
        let mut prev_rv = Vector3::zeros();
        let (mut q_prev, mut q_self) = (positions(b, n - 1), positions(b, 0));
        for (i, bj) in bodies.iter().enumerate() {
            let o = BodyIndex::of(i);
            let q_next = positions(b, if i + 1 == n { 0 } else { i + 1 });
            let mut bz = b[o.creep] + c * bj.creep_rate_by_position.dot(&q_self.transpose());
            let mut rv = Vector3::new(b[o.vx], b[o.vy], b[o.spin])
                + c * (mm(&bj.accel_by_position[PREV], &q_prev)
                    + mm(&bj.accel_by_position[SELF], &q_self)
                    + mm(&bj.accel_by_position[NEXT], &q_next));
            if bj.touching != 0 {
                if let Some(a) = arm_bodies.get(i) {
                    for (j, s) in view.arm_slots().iter().enumerate() {
                        if s.is_some() && bj.touching & (1 << j) != 0 {
                            bz += c * a.creep_rate_by_arm_angle[j] * b_arm[j];
                            rv += (c * b_arm[j]) * a.accel_by_arm_angle[j];
                        }
                    }
                }
            }
            bz_s[i] = bz;
            rv += (c * bz) * bj.accel_by_creep;
            if bj.touching != 0 {
                for (j, s) in view.slots().iter().enumerate() {
                    if let Some(k) = *s {
                        if bj.touching & (1 << j) != 0 {
                            rw[k] += c
                                * (bj.pulley_accel_by_position[j].dot(&q_self.transpose())
                                    + bj.pulley_accel_by_creep[j] * bz);
                        }
                    }
                }
                if let Some(a) = arm_bodies.get(i) {
                    for (j, s) in view.arm_slots().iter().enumerate() {
                        if let Some(k) = *s {
                            if bj.touching & (1 << j) != 0 {
                                rw[k] += c
                                    * (a.arm_accel_by_position[j].dot(&q_self.transpose())
                                        + a.arm_accel_by_creep[j] * bz);
                            }
                        }
                    }
                }
            }
            if i < m {
                if i > 0 {
                    rv -= mm(&l_s[i], &prev_rv);
                }
                rw -= mm(&fd_s[i], &rv);
                prev_rv = rv;
            } else {
                let mut top = rw.fixed_view_mut::<3, 1>(0, 0);
                top += rv;
            }
            rv_s[i] = rv;
            (q_prev, q_self) = (q_self, q_next);
        }
        rw
    }

    /// The border's unknowns from the LU factors: L U x = P rw.
    #[inline(always)]
    fn border_solve(&self, rw: &SVector<f64, NB>) -> SVector<f64, NB> {
        let mut xb = SVector::<f64, NB>::zeros();
        for k in 0..NB {
            xb[k] = rw[self.perm[k]];
        }
        for k in 0..NB {
            for r in k + 1..NB {
                xb[r] -= self.g[(r, k)] * xb[k];
            }
        }
        for k in (0..NB).rev() {
            let mut s = xb[k];
            for cc in k + 1..NB {
                s -= self.g[(k, cc)] * xb[cc];
            }
            xb[k] = s / self.g[(k, k)];
        }
        xb
    }

    /// Two sweeps along the belt: forward, each body's reduced right-hand
    /// side and its elimination; backward, its velocities by substitution and
    /// then its positions and creep state.
    #[inline(always)]
    fn solve(&mut self, sys: &BeltSystem, jac: &Jacobian, b: &mut [f64]) {
        let n = sys.n;
        let m = n - 1;
        let c = self.c;
        let view = View::new(sys, jac, c, self.slot, self.arm_slot);
        let (bodies, arm_bodies) = (view.bodies, view.arm_bodies);
        let mut rw = self.forward(&view, sys, jac, b);
        // decouplers: their part of the hub rows' right-hand side
        let mut dec_g = [Vector2::zeros(); MAX_PULLEYS];
        for (j, g) in dec_g.iter_mut().enumerate().take(sys.np) {
            if sys.pulleys[j].decoupler.is_none() {
                continue;
            }
            let o = sys.state_layout.decoupler(j);
            let gv = self.dec_ainv[j] * Vector2::new(b[o.twist], b[o.rotor_speed]);
            *g = gv;
            if let Some(k) = view.slot[j] {
                let d = &jac.decouplers[j];
                rw[k] += c * (d.hub_accel_by_twist * gv[0] + d.hub_accel_by_rotor_speed * gv[1]);
            }
        }
        let xb = self.border_solve(&rw);
        // pulley speeds and angles
        let mut dw = [0.0; MAX_PULLEYS];
        for (j, s) in view.slots().iter().enumerate() {
            if let Some(k) = *s {
                dw[j] = xb[k];
                let o = sys.state_layout.pulley(j);
                b[o.speed] = xb[k];
                b[o.angle] += c * xb[k];
            }
        }
        for j in 0..sys.np {
            if sys.pulleys[j].decoupler.is_some() {
                let o = sys.state_layout.decoupler(j);
                let x = dec_g[j] + self.dec_h[j] * dw[j];
                b[o.twist] = x[0];
                b[o.rotor_speed] = x[1];
            }
        }
        // arm rates and angles
        let mut dr = [0.0; MAX_PULLEYS];
        for (j, s) in view.arm_slots().iter().enumerate() {
            if let Some(k) = *s {
                dr[j] = xb[k];
                let o = sys.state_layout.arm(j);
                b[o.rate] = xb[k];
                b[o.angle] += c * xb[k];
                let a = &jac.arms[j];
                b[o.deflection] = (b[o.deflection] + c * a.deflection_rate_by_rate * xb[k])
                    / Self::deflection_pivot(a, c);
            }
        }
        // 2. backward: velocities, then positions and creep of each body
        let (dinv_s, u_s, e_s) = (&self.dinv[..m], &self.u[..m], &self.e[..m]);
        let (rv_s, bz_s) = (&self.rv[..n], &self.bz[..n]);
        let (dw, dr) = (&dw[..sys.np], &dr[..sys.np]);
        Self::recover(
            &bodies[n - 1],
            arm_bodies.get(n - 1),
            c,
            dw,
            dr,
            b,
            n - 1,
            Vector3::new(xb[0], xb[1], xb[2]),
            bz_s[n - 1],
        );
        let mut next = Vector3::zeros();
        for i in (0..m).rev() {
            let mut r = rv_s[i] - mm(&e_s[i], &xb);
            if i + 1 < m {
                r -= mm(&u_s[i], &next);
            }
            next = mm(&dinv_s[i], &r);
            Self::recover(
                &bodies[i],
                arm_bodies.get(i),
                c,
                dw,
                dr,
                b,
                i,
                next,
                bz_s[i],
            );
        }
        // 3. impulses and the input energy: nothing depends on them, their
        //    rows give x_q = b_q + c (dG/dy) x
        let (rows, power) = jac.impulse_rows(sys, b);
        b[sys.state_layout.energy().work_in] += c * power;
        for (j, r) in rows.iter().enumerate().take(sys.np) {
            for (q, v) in sys.state_layout.impulses(j).range().zip(r) {
                b[q] += c * v;
            }
        }
    }
}

/// What the factorization and the solves read in their loops, taken once
/// per call: the Jacobian's per-body rows as slices and the border slots by
/// value. The kernels run inside `simd::dispatch_with`, whose argument tuple
/// carries no no-alias guarantee, so reached through `self` and `jac` every
/// vector's pointer and length and every slot would be reloaded after each
/// store (11 % more instructions in the solves, 5 % in the factorization on
/// the 150-body 5PK drive; docs/benchmarks.md).
struct View<'a> {
    c: f64,
    bodies: &'a [BodyJacobian],
    /// Empty if the drive has no tensioner arm.
    arm_bodies: &'a [BodyArmJacobian],
    slot: [Option<usize>; MAX_PULLEYS],
    arm_slot: [Option<usize>; MAX_PULLEYS],
    np: usize,
}

impl<'a> View<'a> {
    #[inline(always)]
    fn new(
        sys: &BeltSystem,
        jac: &'a Jacobian,
        c: f64,
        slot: [Option<usize>; MAX_PULLEYS],
        arm_slot: [Option<usize>; MAX_PULLEYS],
    ) -> Self {
        Self {
            c,
            bodies: &jac.bodies[..sys.n],
            arm_bodies: &jac.arm_bodies,
            slot,
            arm_slot,
            np: sys.np,
        }
    }

    /// Border index of each pulley's speed, if a state.
    #[inline(always)]
    fn slots(&self) -> &[Option<usize>] {
        &self.slot[..self.np]
    }

    /// Border index of each pulley's arm rate, if it has an arm.
    #[inline(always)]
    fn arm_slots(&self) -> &[Option<usize>] {
        &self.arm_slot[..self.np]
    }
}

#[cfg(test)]
pub(crate) mod tests;
