//! The stored energy of a state (kinetic, elastic, creep springs,
//! gravity; belt, pulleys, decoupler rotors and tensioner arms) and the
//! energy balance the stiff method checks.

use super::workspace::BlockEnergy;
use super::{wrap_angle, BeltSystem};
use crate::model::elements::contact;
use crate::model::elements::friction::Law;
use crate::model::elements::sde::{self, BodyEnd};
use crate::model::params::MAX_PULLEYS;
use crate::model::state;
use crate::model::trig;
use crate::solver::rosenbrock::EnergyBalance;

impl BeltSystem {
    /// The creep springs' energy of state `y` [J] ([`StoredEnergy::creep`]):
    /// the elastic normal force times the spring energy per newton
    /// (elements::friction, `Law::spring_energy`). Part of the potential
    /// energy; the integrated friction work less it is what friction has
    /// dissipated.
    pub fn creep_spring_energy(&self, y: &[f64]) -> f64 {
        self.stored_energy(y).creep
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
        let o = self.state_layout.energy();
        let (work_in, dissipated) = (y[o.work_in], y[o.dissipated]);
        EnergyBalance {
            balance: work_in - dissipated - e.kinetic - (e.potential - e.creep),
            scale: e.belt,
            magnitude: work_in.abs() + dissipated.abs() + e.kinetic + e.potential.abs(),
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
        let end = |b: state::Body| {
            let (s, c) = trig::sin_cos(b.angle());
            let [x, y] = b.position();
            BodyEnd {
                x,
                y,
                hx: hl * c,
                hy: hl * s,
                ..BodyEnd::default()
            }
        };
        let (mut kin, mut elastic, mut gravity, mut creep) = (0.0, 0.0, 0.0, 0.0);
        let last = state::body(y, n - 1);
        let (mut prev, mut prev_angle) = (end(last), last.angle());
        for (i, b) in state::bodies(y, n).enumerate() {
            let ([vx, vy], spin) = (b.velocity(), b.spin());
            let [bx, by] = b.position();
            kin += 0.5 * self.mass * (vx * vx + vy * vy) + 0.5 * self.inertia * spin * spin;
            gravity += self.mass * self.gravity * by;
            let cur = end(b);
            let (d, _) = sde::gap(prev, cur);
            elastic += self.axial.energy(d[0] * d[0] + d[1] * d[1]);
            elastic += self.bend.energy(wrap_angle(b.angle() - prev_angle));
            for (pc, c) in self.pulleys[..self.np].iter().zip(&centres) {
                let (rx, ry) = (bx - c[0], by - c[1]);
                // no contact point lies farther than l/2 from the centre
                if contact::distance2([rx, ry]) >= pc.reach * pc.reach {
                    continue;
                }
                let mut force = 0.0;
                for (&(xi, w), &radius) in quad.iter().zip(&pc.radii) {
                    let point = contact::point_position([rx, ry], xi, [cur.hx, cur.hy]);
                    let p = contact::penetration(point, radius);
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
                            .spring_energy(b.creep(), pc.mu_s * zf, pc.mu_k * zf);
                }
            }
            (prev, prev_angle) = (cur, b.angle());
        }
        self.with_pulleys(kin, elastic, creep, gravity, y)
    }

    /// The stored energy from the blocks' sums of [`Self::rhs_energy`].
    pub(super) fn stored_energy_of(&self, e: BlockEnergy, y: &[f64]) -> StoredEnergy {
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
            let w = y[self.state_layout.pulley(j).speed];
            kin += 0.5 * pc.inertia * w * w;
            if let Some(dc) = &pc.decoupler {
                let d = self.state_layout.decoupler(j);
                let w_r = y[d.rotor_speed];
                kin += 0.5 * pc.rotor_inertia * w_r * w_r;
                pot += dc.energy(y[d.twist]);
            }
            if let Some(arm) = &pc.arm {
                // arm and pulley swinging about the pivot; the spring
                let o = self.state_layout.arm(j);
                let (a, w) = (y[o.angle], y[o.rate]);
                kin += 0.5 * arm.inertia * w * w;
                pot += arm.energy(a) + arm.friction_energy(y[o.deflection]);
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
