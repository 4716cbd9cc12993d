//! The state vector by name, so that no code outside this module counts
//! components: a belt body's block (its position, angle, velocity, spin
//! and creep displacement: [`body`], [`body_mut`], [`BodyIndex`]) and where
//! every other state sits ([`StateLayout`]: a pulley's angle and speed, a
//! decoupler's twist and rotor speed, a tensioner arm's angle, rate and pivot
//! friction deflection, the
//! energy accumulators, the impulses).
//!
//! The order (one contiguous `f64` vector, bodies first so that the
//! Jacobian of the chain is banded):
//! * body i: `[x, y, phi, vx, vy, omega, z]`, z = creep displacement;
//! * pulley j: `[theta, omega]`;
//! * `[work_in, energy_dissipated]`;
//! * per pulley with a decoupler, in pulley order: `[twist, rotor omega]`
//!   (`elements::decoupler`);
//! * per pulley on a tensioner arm, in pulley order: `[arm angle, arm
//!   rate, presliding deflection of the pivot friction]`
//!   (`elements::tensioner`); the pulley's centre moves with the arm;
//! * per pulley: the impulses `[belt torque, drive torque, hub force x, hub
//!   force y]` integrated since the start of the current communication
//!   step (quadrature states: they feed nothing back and are left out of
//!   the error control; their means over the step are outputs).

use crate::model::params::MAX_PULLEYS;
use crate::model::system::{BODY_DOF, IMPULSES};

/// States per tensioner arm: angle, rate, the pivot friction's presliding
/// deflection.
pub const ARM_STATES: usize = 3;

/// The components of a body's block, in their order in the state vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyComponent {
    /// Centre x [m].
    X,
    /// Centre y [m].
    Y,
    /// Angle phi [rad].
    Angle,
    /// Velocity x [m/s].
    Vx,
    /// Velocity y [m/s].
    Vy,
    /// Spin [rad/s].
    Spin,
    /// Creep displacement z [m] (elements::friction).
    Creep,
}

impl BodyComponent {
    /// The component at `k` (0..7) of a body's block.
    pub fn at(k: usize) -> Self {
        use BodyComponent::*;
        [X, Y, Angle, Vx, Vy, Spin, Creep][k]
    }
}

/// Index in the state vector of body `i`'s component `c`.
#[inline(always)]
pub const fn body_index(i: usize, c: BodyComponent) -> usize {
    BODY_DOF * i + c as usize
}

/// Length of the bodies' part of the state (it comes first) for `n` bodies.
#[inline(always)]
pub const fn bodies_len(n: usize) -> usize {
    BODY_DOF * n
}

/// The body and component of index `k` < [`bodies_len`] of the state.
pub fn body_component(k: usize) -> (usize, BodyComponent) {
    (k / BODY_DOF, BodyComponent::at(k % BODY_DOF))
}

/// Where body `i`'s components sit in the state vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BodyIndex {
    /// Centre x [m].
    pub x: usize,
    /// Centre y [m].
    pub y: usize,
    /// Angle phi [rad].
    pub angle: usize,
    /// Velocity x [m/s].
    pub vx: usize,
    /// Velocity y [m/s].
    pub vy: usize,
    /// Spin [rad/s].
    pub spin: usize,
    /// Creep displacement z [m].
    pub creep: usize,
}

impl BodyIndex {
    /// Body `i`'s indices.
    #[inline(always)]
    pub const fn of(i: usize) -> Self {
        let o = BODY_DOF * i;
        Self {
            x: o,
            y: o + 1,
            angle: o + 2,
            vx: o + 3,
            vy: o + 4,
            spin: o + 5,
            creep: o + 6,
        }
    }

    /// The generalised coordinates q = (x, y, phi), as the Jacobian's
    /// blocks order them.
    #[inline(always)]
    pub const fn coordinates(&self) -> [usize; 3] {
        [self.x, self.y, self.angle]
    }

    /// Their rates v = (vx, vy, spin).
    #[inline(always)]
    pub const fn rates(&self) -> [usize; 3] {
        [self.vx, self.vy, self.spin]
    }
}

/// Where a pulley's angle and speed sit in the state vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PulleyIndex {
    /// Angle theta [rad].
    pub angle: usize,
    /// Speed omega [rad/s].
    pub speed: usize,
}

/// Where a decoupler's states sit in the state vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DecouplerIndex {
    /// The spring's twist delta [rad].
    pub twist: usize,
    /// The rotor's speed [rad/s].
    pub rotor_speed: usize,
}

/// Where a tensioner arm's states sit in the state vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ArmIndex {
    /// Arm angle [rad].
    pub angle: usize,
    /// Arm rate [rad/s].
    pub rate: usize,
    /// Presliding deflection of the pivot friction z [rad]
    /// (`elements::tensioner`).
    pub deflection: usize,
}

/// Where the energy accumulators sit in the state vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EnergyIndex {
    /// Work put in by drives and inputs [J].
    pub work_in: usize,
    /// Energy dissipated (friction and damper work) [J].
    pub dissipated: usize,
}

/// Where a pulley's impulses (integrals over the communication step)
/// sit in the state vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImpulseIndex {
    /// Of the belt's torque [N m s].
    pub belt_torque: usize,
    /// Of the speed drive's torque [N m s].
    pub drive_torque: usize,
    /// Of the hub force, x and y [N s].
    pub hub_force: [usize; 2],
}

impl ImpulseIndex {
    /// The four impulses, in this order: belt torque, drive torque, hub
    /// force x, y.
    #[inline(always)]
    pub fn range(&self) -> std::ops::Range<usize> {
        self.belt_torque..self.belt_torque + IMPULSES
    }
}

/// Where every state of a drive sits in the state vector (the order in
/// the module comment): built once from the body count and which pulleys
/// have a decoupler or a tensioner arm.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StateLayout {
    n: usize,
    np: usize,
    n_decouplers: usize,
    n_arms: usize,
    /// Start of each pulley's decoupler states (a pulley with one).
    decoupler: [usize; MAX_PULLEYS],
    /// Start of each pulley's arm states (a pulley on an arm).
    arm: [usize; MAX_PULLEYS],
}

impl StateLayout {
    /// The layout of `n` bodies and the pulleys whose `(decoupler, arm)`
    /// flags `hardware` gives, in pulley order (at most [`MAX_PULLEYS`]).
    pub fn new(n: usize, hardware: &[(bool, bool)]) -> Self {
        let np = hardware.len();
        let n_decouplers = hardware.iter().filter(|h| h.0).count();
        let n_arms = hardware.iter().filter(|h| h.1).count();
        let extra = BODY_DOF * n + 2 * np + 2;
        let (mut decoupler, mut arm) = ([0; MAX_PULLEYS], [0; MAX_PULLEYS]);
        let (mut k_dec, mut k_arm) = (0, 0);
        for (j, &(has_dec, has_arm)) in hardware.iter().enumerate() {
            decoupler[j] = extra + 2 * k_dec;
            arm[j] = extra + 2 * n_decouplers + ARM_STATES * k_arm;
            k_dec += usize::from(has_dec);
            k_arm += usize::from(has_arm);
        }
        Self {
            n,
            np,
            n_decouplers,
            n_arms,
            decoupler,
            arm,
        }
    }

    /// Body `i`'s components.
    #[inline(always)]
    pub const fn body(&self, i: usize) -> BodyIndex {
        BodyIndex::of(i)
    }

    /// Length of the bodies' part (it comes first).
    #[inline(always)]
    pub const fn bodies_len(&self) -> usize {
        BODY_DOF * self.n
    }

    /// Pulley `j`'s angle and speed.
    #[inline(always)]
    pub const fn pulley(&self, j: usize) -> PulleyIndex {
        let o = BODY_DOF * self.n + 2 * j;
        PulleyIndex {
            angle: o,
            speed: o + 1,
        }
    }

    /// The energy accumulators.
    #[inline(always)]
    pub const fn energy(&self) -> EnergyIndex {
        let o = BODY_DOF * self.n + 2 * self.np;
        EnergyIndex {
            work_in: o,
            dissipated: o + 1,
        }
    }

    /// The states of pulley `j`'s decoupler (meaningful for a pulley that
    /// has one).
    #[inline(always)]
    pub const fn decoupler(&self, j: usize) -> DecouplerIndex {
        let o = self.decoupler[j];
        DecouplerIndex {
            twist: o,
            rotor_speed: o + 1,
        }
    }

    /// The states of the tensioner arm pulley `j` sits on (meaningful for
    /// a pulley on an arm).
    #[inline(always)]
    pub const fn arm(&self, j: usize) -> ArmIndex {
        let o = self.arm[j];
        ArmIndex {
            angle: o,
            rate: o + 1,
            deflection: o + 2,
        }
    }

    /// Pulley `j`'s impulses.
    #[inline(always)]
    pub const fn impulses(&self, j: usize) -> ImpulseIndex {
        let o = self.controlled_len() + IMPULSES * j;
        ImpulseIndex {
            belt_torque: o,
            drive_torque: o + 1,
            hub_force: [o + 2, o + 3],
        }
    }

    /// The states whose error the integrators control: all but the
    /// impulses at the end, which feed nothing back.
    #[inline(always)]
    pub const fn controlled_len(&self) -> usize {
        BODY_DOF * self.n + 2 * self.np + 2 + 2 * self.n_decouplers + ARM_STATES * self.n_arms
    }

    /// Length of the state vector.
    #[inline(always)]
    pub const fn dim(&self) -> usize {
        self.controlled_len() + IMPULSES * self.np
    }

    /// Number of belt bodies.
    #[inline(always)]
    pub const fn n_bodies(&self) -> usize {
        self.n
    }

    /// Number of pulleys with a decoupler.
    #[inline(always)]
    pub const fn n_decouplers(&self) -> usize {
        self.n_decouplers
    }

    /// Number of pulleys on a tensioner arm.
    #[inline(always)]
    pub const fn n_arms(&self) -> usize {
        self.n_arms
    }
}

/// Body `i` of a state, read by name.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body<'a>(&'a [f64]);

/// Body `i` of the state `y`.
#[inline(always)]
pub fn body(y: &[f64], i: usize) -> Body<'_> {
    Body(&y[BODY_DOF * i..BODY_DOF * (i + 1)])
}

/// The first `n` bodies of the state `y`, in order.
#[inline(always)]
pub fn bodies(y: &[f64], n: usize) -> impl Iterator<Item = Body<'_>> {
    y[..BODY_DOF * n].chunks_exact(BODY_DOF).map(Body)
}

impl Body<'_> {
    /// Centre (x, y) [m].
    pub fn position(&self) -> [f64; 2] {
        [self.0[0], self.0[1]]
    }
    /// Angle phi [rad].
    pub fn angle(&self) -> f64 {
        self.0[2]
    }
    /// Velocity (vx, vy) [m/s].
    pub fn velocity(&self) -> [f64; 2] {
        [self.0[3], self.0[4]]
    }
    /// Spin [rad/s].
    pub fn spin(&self) -> f64 {
        self.0[5]
    }
    /// Creep displacement z [m].
    pub fn creep(&self) -> f64 {
        self.0[6]
    }
}

/// Body `i` of a state, written by name.
#[derive(Debug, PartialEq)]
pub struct BodyMut<'a>(&'a mut [f64]);

/// Body `i` of the state `y`, to write.
#[inline(always)]
pub fn body_mut(y: &mut [f64], i: usize) -> BodyMut<'_> {
    BodyMut(&mut y[BODY_DOF * i..BODY_DOF * (i + 1)])
}

impl BodyMut<'_> {
    /// Sets the centre (x, y) [m].
    pub fn set_position(&mut self, r: [f64; 2]) {
        self.0[0] = r[0];
        self.0[1] = r[1];
    }
    /// Sets the angle phi [rad].
    pub fn set_angle(&mut self, phi: f64) {
        self.0[2] = phi;
    }
    /// Sets the spin [rad/s].
    pub fn set_spin(&mut self, w: f64) {
        self.0[5] = w;
    }
    /// Sets the creep displacement z [m].
    pub fn set_creep(&mut self, z: f64) {
        self.0[6] = z;
    }
    /// Sets the velocity (vx, vy) [m/s].
    pub fn set_velocity(&mut self, v: [f64; 2]) {
        self.0[3] = v[0];
        self.0[4] = v[1];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_read_the_components_in_their_order() {
        let y: Vec<f64> = (0..2 * BODY_DOF).map(|k| k as f64).collect();
        let b = body(&y, 1);
        assert_eq!(b.position(), [7.0, 8.0]);
        assert_eq!(b.angle(), 9.0);
        assert_eq!(b.velocity(), [10.0, 11.0]);
        assert_eq!(b.spin(), 12.0);
        assert_eq!(b.creep(), 13.0);
        for k in 0..BODY_DOF {
            let c = BodyComponent::at(k);
            assert_eq!(body_index(1, c), BODY_DOF + k);
            assert_eq!(body_component(BODY_DOF + k), (1, c));
        }
        assert_eq!(bodies_len(2), y.len());
        let mut y = y;
        body_mut(&mut y, 0).set_velocity([-1.0, -2.0]);
        assert_eq!(body(&y, 0).velocity(), [-1.0, -2.0]);
        assert_eq!(y[2], 2.0);
        assert_eq!(y[5], 5.0);
        let b = BodyIndex::of(1);
        assert_eq!(
            [b.x, b.y, b.angle, b.vx, b.vy, b.spin, b.creep],
            std::array::from_fn(|k| BODY_DOF + k)
        );
    }

    /// Three bodies, three pulleys: the second with a decoupler, the
    /// first and third on arms; every index once, in the documented order.
    #[test]
    fn the_layout_places_every_state_once_in_order() {
        let s = StateLayout::new(3, &[(false, true), (true, false), (false, true)]);
        let p: Vec<usize> = (0..3)
            .flat_map(|j| [s.pulley(j).angle, s.pulley(j).speed])
            .collect();
        assert_eq!(p, (21..27).collect::<Vec<_>>());
        assert_eq!((s.energy().work_in, s.energy().dissipated), (27, 28));
        assert_eq!((s.decoupler(1).twist, s.decoupler(1).rotor_speed), (29, 30));
        let arm = |j: usize| (s.arm(j).angle, s.arm(j).rate, s.arm(j).deflection);
        assert_eq!(arm(0), (31, 32, 33));
        assert_eq!(arm(2), (34, 35, 36));
        assert_eq!(s.controlled_len(), 37);
        assert_eq!(s.impulses(0).range(), 37..41);
        assert_eq!(s.impulses(2).hub_force, [47, 48]);
        assert_eq!(s.dim(), 49);
        assert_eq!((s.n_decouplers(), s.n_arms()), (1, 2));
    }
}
