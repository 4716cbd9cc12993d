//! Analytic Jacobian of the belt's right-hand side (`model/system/`), for the
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
//! `solver/rosenbrock/`), the input energy has its row (below).
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
//!
//! Here the storage types and the evaluation's outline
//! (`BeltSystem::jacobian`); beside it `storage.rs` (construction, impulse
//! rows, save/load, the dense matrix of the tests), `contact.rs` (the
//! contact's rows at the centre and along the body, with the arms' moving
//! centres), `belt.rs` (SDE rows, relaxation and transverse damping),
//! `pulleys.rs` (load damping, decouplers, tensioner arms) and `tests.rs`.

mod belt;
mod contact;
mod pulleys;
mod storage;
#[cfg(test)]
mod tests;

use crate::model::elements::friction::{with_law, Law};
use crate::model::params::MAX_PULLEYS;
use crate::model::simd::{self, Isa};
use crate::model::system::{BeltSystem, PulleyConst};
use nalgebra::{Matrix2x3, Matrix3, RowVector3, Vector2, Vector3};

/// Derivatives of one body's rows: accelerations (vx', vy', omega') and creep rate z'.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BodyJacobian {
    /// d(acceleration)/d(position) of body i-1, i, i+1.
    pub(crate) accel_by_position: [Matrix3<f64>; 3],
    /// d(acceleration)/d(velocity) of body i-1, i, i+1.
    pub(crate) accel_by_velocity: [Matrix3<f64>; 3],
    /// d(acceleration)/dz (own creep).
    pub(crate) accel_by_creep: Vector3<f64>,
    /// d(acceleration)/d(pulley speed j).
    pub(crate) accel_by_pulley_speed: [Vector3<f64>; MAX_PULLEYS],
    /// dz'/d(own position).
    pub(crate) creep_rate_by_position: RowVector3<f64>,
    /// dz'/d(own velocity).
    pub(crate) creep_rate_by_velocity: RowVector3<f64>,
    /// dz'/d(pulley speed j).
    pub(crate) creep_rate_by_pulley_speed: [f64; MAX_PULLEYS],
    /// d(pulley j acceleration)/d(this body's position).
    pub(crate) pulley_accel_by_position: [RowVector3<f64>; MAX_PULLEYS],
    /// d(pulley j acceleration)/d(this body's velocity).
    pub(crate) pulley_accel_by_velocity: [RowVector3<f64>; MAX_PULLEYS],
    /// d(pulley j acceleration)/d(this body's z).
    pub(crate) pulley_accel_by_creep: [f64; MAX_PULLEYS],
    /// Bit j set: the body touches pulley j (only those entries are non-zero).
    pub(crate) touching: u8,
}

/// One body's columns in the impulse rows of one pulley (its belt torque
/// and hub force); non-zero only where the body touches the pulley
/// ([`BodyJacobian::touching`]). Kept apart from [`BodyJacobian`], one
/// pulley's together: only the impulse rows read them, while the
/// factorization and the stage solves walk the body rows
/// (docs/benchmarks.md).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImpulseColumns {
    /// d(belt torque on the pulley)/d(this body's position):
    /// the belt-torque impulse's row (all pulleys, speed-driven too).
    pub(crate) torque_by_position: RowVector3<f64>,
    /// d(belt torque on the pulley)/d(this body's velocity).
    pub(crate) torque_by_velocity: RowVector3<f64>,
    /// d(belt torque on the pulley)/d(this body's z).
    pub(crate) torque_by_creep: f64,
    /// d(force on the pulley's hub)/d(this body's position):
    /// the hub-force impulse's rows.
    pub(crate) hub_by_position: Matrix2x3<f64>,
    /// d(force on the pulley's hub)/d(this body's velocity).
    pub(crate) hub_by_velocity: Matrix2x3<f64>,
    /// d(force on the pulley's hub)/d(this body's z).
    pub(crate) hub_by_creep: Vector2<f64>,
}

/// Derivatives of a decoupler's rows (twist rate, rotor acceleration) and
/// of its hub's acceleration with respect to twist, hub speed and rotor
/// speed (`elements::decoupler`). The hub's own d(alpha)/d(omega_hub) term
/// is in `Jacobian::pulley_accel_by_pulley_speed`. Zero where the hub is
/// speed-driven (its speed is then an input, its acceleration prescribed).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DecouplerJacobian {
    /// d(twist')/d(twist).
    pub(crate) twist_rate_by_twist: f64,
    /// d(twist')/d(omega_hub).
    pub(crate) twist_rate_by_hub_speed: f64,
    /// d(twist')/d(omega_rotor).
    pub(crate) twist_rate_by_rotor_speed: f64,
    /// d(rotor alpha)/d(twist).
    pub(crate) rotor_accel_by_twist: f64,
    /// d(rotor alpha)/d(omega_hub).
    pub(crate) rotor_accel_by_hub_speed: f64,
    /// d(rotor alpha)/d(omega_rotor).
    pub(crate) rotor_accel_by_rotor_speed: f64,
    /// d(hub alpha)/d(twist).
    pub(crate) hub_accel_by_twist: f64,
    /// d(hub alpha)/d(omega_rotor).
    pub(crate) hub_accel_by_rotor_speed: f64,
    /// d(drive torque)/d(twist) of a speed-driven hub (the
    /// drive-torque impulse's row; zero on a torque-driven hub).
    pub(crate) drive_torque_by_twist: f64,
    /// d(drive torque)/d(omega_rotor).
    pub(crate) drive_torque_by_rotor_speed: f64,
}

/// Derivatives of a tensioner arm's rate row (arm acceleration) with
/// respect to its own angle and rate (spring, damper, pivot friction, the
/// lever of the hub force and the contacts' dependence on the moving
/// centre) and its pulley's speed; and of that pulley's acceleration with
/// respect to the arm (`elements::tensioner`). The angle row is
/// d(angle)/dt = rate.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ArmJacobian {
    /// d(arm acceleration)/d(arm angle).
    pub(crate) arm_accel_by_angle: f64,
    /// d(arm acceleration)/d(rate).
    pub(crate) arm_accel_by_rate: f64,
    /// d(arm acceleration)/d(pulley speed).
    pub(crate) arm_accel_by_pulley_speed: f64,
    /// d(pulley acceleration)/d(arm angle).
    pub(crate) pulley_accel_by_arm_angle: f64,
    /// d(pulley acceleration)/d(arm rate).
    pub(crate) pulley_accel_by_arm_rate: f64,
    /// d(belt torque on the pulley)/d(arm angle): the impulse rows' arm
    /// columns.
    pub(crate) torque_by_arm_angle: f64,
    /// d(belt torque on the pulley)/d(arm rate).
    pub(crate) torque_by_arm_rate: f64,
    /// d(force on the hub)/d(arm angle).
    pub(crate) hub_by_arm_angle: Vector2<f64>,
    /// d(force on the hub)/d(arm rate).
    pub(crate) hub_by_arm_rate: Vector2<f64>,
    /// d(arm acceleration)/d(pivot friction deflection): -k_p / I.
    pub(crate) arm_accel_by_deflection: f64,
    /// d(deflection rate)/d(arm rate).
    pub(crate) deflection_rate_by_rate: f64,
    /// d(deflection rate)/d(deflection).
    pub(crate) deflection_rate_by_deflection: f64,
}

/// How one body's rows and a tensioner arm's row depend on each other,
/// per pulley slot j (zero unless the body touches pulley j and it sits on
/// an arm): the contact sees the body relative to the moving centre.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BodyArmJacobian {
    /// d(acceleration)/d(arm angle).
    pub(crate) accel_by_arm_angle: [Vector3<f64>; MAX_PULLEYS],
    /// d(acceleration)/d(arm rate).
    pub(crate) accel_by_arm_rate: [Vector3<f64>; MAX_PULLEYS],
    /// dz'/d(arm angle).
    pub(crate) creep_rate_by_arm_angle: [f64; MAX_PULLEYS],
    /// dz'/d(arm rate).
    pub(crate) creep_rate_by_arm_rate: [f64; MAX_PULLEYS],
    /// d(arm acceleration)/d(this body's position).
    pub(crate) arm_accel_by_position: [RowVector3<f64>; MAX_PULLEYS],
    /// d(arm acceleration)/d(this body's velocity).
    pub(crate) arm_accel_by_velocity: [RowVector3<f64>; MAX_PULLEYS],
    /// d(arm acceleration)/d(this body's z).
    pub(crate) arm_accel_by_creep: [f64; MAX_PULLEYS],
}

impl BodyJacobian {
    /// Zeroes the body's entries of pulley j.
    #[inline(always)]
    pub(crate) fn clear_pulley(&mut self, j: usize) {
        self.accel_by_pulley_speed[j] = Vector3::zeros();
        self.creep_rate_by_pulley_speed[j] = 0.0;
        self.pulley_accel_by_position[j] = RowVector3::zeros();
        self.pulley_accel_by_velocity[j] = RowVector3::zeros();
        self.pulley_accel_by_creep[j] = 0.0;
    }
}

impl BodyArmJacobian {
    /// Zeroes the body's entries of the arm under pulley j.
    #[inline(always)]
    pub(crate) fn clear_pulley(&mut self, j: usize) {
        self.accel_by_arm_angle[j] = Vector3::zeros();
        self.accel_by_arm_rate[j] = Vector3::zeros();
        self.creep_rate_by_arm_angle[j] = 0.0;
        self.creep_rate_by_arm_rate[j] = 0.0;
        self.arm_accel_by_position[j] = RowVector3::zeros();
        self.arm_accel_by_velocity[j] = RowVector3::zeros();
        self.arm_accel_by_creep[j] = 0.0;
    }
}

/// Block Jacobian of the whole belt drive.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Jacobian {
    /// Per body, its rows.
    pub(crate) bodies: Vec<BodyJacobian>,
    /// Per body, its columns in the impulse rows of pulley j.
    pub(crate) impulse: Vec<[ImpulseColumns; MAX_PULLEYS]>,
    /// d(pulley j acceleration)/d(pulley speed k), torque-driven pulleys.
    pub(crate) pulley_accel_by_pulley_speed: [[f64; MAX_PULLEYS]; MAX_PULLEYS],
    /// Pulley j's speed is a state (torque-driven) rather than an input.
    pub(crate) free: [bool; MAX_PULLEYS],
    /// Decoupler of pulley j (zero if it has none).
    pub(crate) decouplers: [DecouplerJacobian; MAX_PULLEYS],
    /// d(belt torque on pulley j)/d(omega_j), torque-driven pulleys (a
    /// speed-driven pulley's speed is an input).
    pub(crate) torque_by_pulley_speed: [f64; MAX_PULLEYS],
    /// d(hub force j)/d(omega_j).
    pub(crate) hub_by_pulley_speed: [Vector2<f64>; MAX_PULLEYS],
    /// The input power's row (the `energy.input` accumulator): per pulley
    /// the prescribed speed a speed-driven pulley's drive torque is
    /// multiplied with (0 for a torque-driven pulley).
    pub(crate) power_speed: [f64; MAX_PULLEYS],
    /// The applied torque multiplying the speed of a torque-driven pulley
    /// (of the rotor behind a decoupler) in the input power's row.
    pub(crate) power_applied: [f64; MAX_PULLEYS],
    /// Tensioner arm of pulley j (zero if it has none).
    pub(crate) arms: [ArmJacobian; MAX_PULLEYS],
    /// Per body, its coupling with the arms (empty in a drive without arms).
    pub(crate) arm_bodies: Vec<BodyArmJacobian>,
    /// The drive's pulley count: the slots past it stay zero and are not
    /// saved.
    slots: usize,
}

/// Index of the neighbour blocks in `accel_by_position`/`accel_by_velocity`.
pub(crate) const PREV: usize = 0;
/// Index of the body's own block in `accel_by_position`/`accel_by_velocity`.
pub(crate) const SELF: usize = 1;
/// Index of the next body's block in `accel_by_position`/`accel_by_velocity`.
pub(crate) const NEXT: usize = 2;

#[inline(always)]
fn perp(h: Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-h.y, h.x)
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
        let np = self.np;
        let mut omega_p = [0.0; MAX_PULLEYS];
        for (j, w) in omega_p.iter_mut().enumerate().take(np) {
            *w = self.pulley_speed(j, t, y);
        }
        jac.pulley_accel_by_pulley_speed = [[0.0; MAX_PULLEYS]; MAX_PULLEYS];
        jac.torque_by_pulley_speed = [0.0; MAX_PULLEYS];
        jac.hub_by_pulley_speed = [Vector2::zeros(); MAX_PULLEYS];
        let mut buf = None;
        let pulleys = self.pulleys_in_effect(&mut buf);
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
            jac.arms[j] = ArmJacobian::default();
            let pc = &self.pulleys[j];
            if let Some(arm) = &pc.arm {
                let o = self.state_layout.arm(j);
                let (a, w) = (y[o.angle], y[o.rate]);
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

        let along = (friction, y, &omega_p, pulleys, &centre);
        let arms = Arms {
            lever: &lever,
            lever_rate: &lever_rate,
            inv_arm: &inv_arm,
        };
        self.contact_centre_rows(along, &mut hub_force, jac, arms);
        // The contact along the body: one build per point count, a loop over
        // the bodies in each.
        match self.points {
            1 => {}
            2 => self.contact_along_rows::<2>(along, &mut hub_force, jac, arms),
            3 => self.contact_along_rows::<3>(along, &mut hub_force, jac, arms),
            4 => self.contact_along_rows::<4>(along, &mut hub_force, jac, arms),
            5 => self.contact_along_rows::<5>(along, &mut hub_force, jac, arms),
            k => panic!(
                "{k} contact points outside 1..={}",
                crate::model::elements::contact::MAX_POINTS
            ),
        }

        self.sde_rows(y, jac);
        self.damping_rows(y, jac);
        self.pulley_rows(pulleys, y, &omega_p, jac);
        self.arm_rows(y, &hub_force, &inv_arm, jac);
    }
}

/// What the contact along the body reads: the friction law, the state, the
/// pulley speeds, the pulleys and their centres with velocities (see
/// `jacobian_impl`).
type Along<'a, L> = (
    &'a L,
    &'a [f64],
    &'a [f64; MAX_PULLEYS],
    &'a [PulleyConst; MAX_PULLEYS],
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
