//! The creep reset after every accepted step, and the contact test it
//! uses.

use super::{BeltSystem, PulleyConst};
use crate::model::elements::contact;
use crate::model::elements::friction::Law;
use crate::model::params::MAX_PULLEYS;
use crate::model::state;
use crate::model::trig;

impl BeltSystem {
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
            let creep = state::body(y, i).creep();
            // a creep of +0 stays +0 either way (reset, or clamped): only
            // the bodies that carry a creep, those on or just off a wrap,
            // need the contact test
            if creep.to_bits() == 0 {
                continue;
            }
            let z = if self.touching(i, y, &centres).is_some() {
                creep.clamp(-cap, cap)
            } else {
                0.0
            };
            changed |= z.to_bits() != creep.to_bits();
            state::body_mut(y, i).set_creep(z);
        }
        changed
    }

    /// The first pulley body `i` touches in state `y` (pulley centres
    /// given): as the right-hand side's contact has it, the body's centre
    /// inside the pulley's contact circle with one point ([`contact::distance2`]
    /// below the squared radius), else one of its points with a positive
    /// penetration ([`contact::point_position`], [`contact::penetration`]),
    /// the same arithmetic as the right-hand side's.
    /// The test of [`Self::after_step`] (and of the modal analysis' contact
    /// regions).
    #[inline]
    pub fn touching(&self, i: usize, y: &[f64], centres: &[[f64; 2]]) -> Option<usize> {
        let body = state::body(y, i);
        let [x, yy] = body.position();
        let mut pulleys = self.pulleys[..self.np].iter().zip(centres);
        if self.points == 1 {
            return pulleys.position(|(pc, c)| {
                contact::distance2([x - c[0], yy - c[1]]) < pc.radii[0] * pc.radii[0]
            });
        }
        // no point of a body lies farther than l/2 from its centre: a body
        // out of every pulley's reach touches none (the common case, and
        // no sin/cos for it)
        let near = |pc: &PulleyConst, c: &[f64; 2]| {
            contact::distance2([x - c[0], yy - c[1]]) < pc.reach * pc.reach
        };
        if !pulleys.clone().any(|(pc, c)| near(pc, c)) {
            return None;
        }
        // the body's half vector as the right-hand side forms it
        let (s, c) = trig::sin_cos(body.angle());
        let h = [self.half_length * c, self.half_length * s];
        let quad = contact::quadrature(self.points);
        pulleys.position(|(pc, c)| {
            let r = [x - c[0], yy - c[1]];
            near(pc, c)
                && quad.iter().zip(&pc.radii).any(|(&(xi, _), &rg)| {
                    contact::penetration(contact::point_position(r, xi, h), rg) > 0.0
                })
        })
    }
}
