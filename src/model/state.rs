//! A belt body's block of the state vector, by name: its position, angle,
//! velocity, spin and creep displacement ([`body`], [`body_mut`]), so that
//! no code outside the model counts components. Where the other states sit
//! (pulleys, decouplers, tensioner arms, the energy accumulators, the
//! impulses) is [`BeltSystem`](crate::model::system::BeltSystem)'s: its
//! `pulley_offset`, `energy_offset` and `impulse_offset`.

use crate::model::system::BODY_DOF;

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

/// Body `i` of a state, read by name.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body<'a>(&'a [f64]);

/// Body `i` of the state `y`.
#[inline(always)]
pub fn body(y: &[f64], i: usize) -> Body<'_> {
    Body(&y[BODY_DOF * i..BODY_DOF * (i + 1)])
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
    }
}
