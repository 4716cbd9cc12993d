//! The spring-damper elements (SDE) that join neighbouring belt bodies,
//! eq. 20-23 of section 2.1: a translational Kelvin-Voigt element between
//! the end points of two bodies ([`AxialSde`]) and a torsional one between
//! their angles ([`TorsionalSde`]). Force, partial derivatives, stored
//! energy and dissipated power of each law live here and nowhere else; the
//! right-hand side, the Jacobian, the outputs and the energy balance call
//! these functions.

use crate::model::matmul::mm;
use nalgebra::{Matrix2, Vector2};

/// The end of a belt body that an SDE attaches to: the body centre
/// `(x, y)`, the half body vector `h = (l/2)(cos phi, sin phi)` (eq. 1),
/// the centre's velocity `(vx, vy)` and the angular velocity `w`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyEnd {
    /// Centre x [m].
    pub x: f64,
    /// Centre y [m].
    pub y: f64,
    /// Half body vector, x component [m].
    pub hx: f64,
    /// Half body vector, y component [m].
    pub hy: f64,
    /// Centre velocity x [m/s].
    pub vx: f64,
    /// Centre velocity y [m/s].
    pub vy: f64,
    /// Angular velocity [rad/s].
    pub w: f64,
}

/// Gap vector `d` from the right end of body `p` (centre + h) to the left
/// end of the following body `c` (centre - h), and its time derivative
/// (eq. 20-21; the end velocity is v + w x (+-h)).
#[inline(always)]
pub fn gap(p: BodyEnd, c: BodyEnd) -> ([f64; 2], [f64; 2]) {
    let d0 = (c.x - c.hx) - (p.x + p.hx);
    let d1 = (c.y - c.hy) - (p.y + p.hy);
    let dd0 = (c.vx + c.w * c.hy) - (p.vx - p.w * p.hy);
    let dd1 = (c.vy - c.w * c.hx) - (p.vy + p.w * p.hx);
    ([d0, d1], [dd0, dd1])
}

/// Translational SDE: a zero-rest-length Kelvin-Voigt element between the
/// end points of two neighbouring bodies (eq. 20-23). Its elastic force is
/// `k d` (k = EA/l), isotropic; its damping force
/// `b_t d' + (b - b_t) rho d` is `b` times the stretch rate along the gap
/// (eq. 20's `b dl/dt`) and `b_t` times the gap's rate across it (the
/// joint's shear, the bodies' pitching), with the stretch rate
/// `rho = d.d' / (|d|^2 + eps2)` regularised at a zero gap. `b_t = b` is
/// the isotropic element `b d'` (a damper on the same strain as the spring),
/// `b_t = 0` the paper's damper along the gap alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxialSde {
    /// Stiffness EA/l [N/m].
    pub k: f64,
    /// Damping along the gap, B/l [N s/m].
    pub b: f64,
    /// Damping across the gap [N s/m] (`belt.shearDampingFactor` times `b`).
    pub bt: f64,
    /// Squared regularisation length of the direction at a zero gap [m^2].
    pub eps2: f64,
}

/// Regularisation length of the direction at a zero gap, relative to the
/// body length: far below any gap a running belt has (strain 1e-6 of a
/// body). Squared, in metres, it is [`AxialSde::eps2`].
pub const REGULARISATION: f64 = 1e-6;

impl AxialSde {
    /// [`Self::eps2`] for bodies of length `l`: (1e-6 l)^2
    /// ([`REGULARISATION`]).
    pub fn regularisation_eps2(l: f64) -> f64 {
        (REGULARISATION * l) * (REGULARISATION * l)
    }

    /// `(|d|^2, rho)`: squared gap length and stretch rate.
    #[inline(always)]
    pub fn rate(&self, d: [f64; 2], dd: [f64; 2]) -> (f64, f64) {
        let d2 = d[0] * d[0] + d[1] * d[1];
        let rate = (d[0] * dd[0] + d[1] * dd[1]) / (d2 + self.eps2);
        (d2, rate)
    }

    /// Force on the following body (minus it on the preceding one) for gap
    /// `d`, its rate `dd` and the stretch rate `rate` ([`Self::rate`]):
    /// `k d + b_t d' + (b - b_t) rho d`.
    #[inline(always)]
    pub fn force(&self, d: [f64; 2], dd: [f64; 2], rate: f64) -> [f64; 2] {
        let (k, bt, ba) = (self.k, self.bt, self.b - self.bt);
        [
            k * d[0] + bt * dd[0] + ba * rate * d[0],
            k * d[1] + bt * dd[1] + ba * rate * d[1],
        ]
    }

    /// Belt tension carried by the element, the force's component along the
    /// gap: |d| (k + b rho) (the damper across the gap adds nothing along
    /// it, but for the regulariser: b_t rho eps2 / |d|).
    #[inline(always)]
    pub fn tension(&self, d2: f64, rate: f64) -> f64 {
        let l = d2.sqrt();
        self.k * l + self.b * rate * l
    }

    /// Power dissipated by the damper, `b_t |d'|^2 + (b - b_t) rho^2 |d|^2`,
    /// i.e. `b (d'.e)^2 + b_t |d'_across|^2` (e = d/|d|; >= 0 for any
    /// b, b_t >= 0, since rho^2 |d|^2 <= |d'|^2).
    #[inline(always)]
    pub fn dissipation(&self, d2: f64, dd: [f64; 2], rate: f64) -> f64 {
        let dd2 = dd[0] * dd[0] + dd[1] * dd[1];
        self.bt * dd2 + (self.b - self.bt) * rate * rate * d2
    }

    /// Which damper terms the element has: `(along, across)`, the
    /// stretch-rate term `(b - b_t) rho d` (none when b_t = b, the
    /// isotropic damper) and the `b_t d'` term (none when b_t = 0, the
    /// paper's damper along the gap alone). The right-hand side picks its
    /// [`Self::force_dissipation`] build from these once per block.
    #[inline(always)]
    pub fn damper_terms(&self) -> (bool, bool) {
        (self.b - self.bt != 0.0, self.bt != 0.0)
    }

    /// [`Self::force`] and [`Self::dissipation`] for gap `d` and rate `dd`,
    /// without the damper terms the element lacks (`ALONG`, `ACROSS` as
    /// [`Self::damper_terms`] gives them): a drive pays only for the terms
    /// it uses (without `ALONG`, not even the stretch rate's division).
    /// Bit for bit the full law's values at such coefficients (a left-out
    /// term is a zero product added to the sum), but for the sign of a force
    /// component that is exactly zero.
    #[inline(always)]
    pub fn force_dissipation<const ALONG: bool, const ACROSS: bool>(
        &self,
        d: [f64; 2],
        dd: [f64; 2],
    ) -> ([f64; 2], f64) {
        if ALONG && ACROSS {
            let (d2, rate) = self.rate(d, dd);
            return (self.force(d, dd, rate), self.dissipation(d2, dd, rate));
        }
        let (k, bt, ba) = (self.k, self.bt, self.b - self.bt);
        let (mut f, mut diss) = ([k * d[0], k * d[1]], 0.0);
        if ACROSS {
            f = [f[0] + bt * dd[0], f[1] + bt * dd[1]];
            diss = bt * (dd[0] * dd[0] + dd[1] * dd[1]);
        }
        if ALONG {
            let (d2, rate) = self.rate(d, dd);
            f = [f[0] + ba * rate * d[0], f[1] + ba * rate * d[1]];
            diss = ba * rate * rate * d2;
        }
        (f, diss)
    }

    /// Elastic energy stored at squared gap length `d2`: k |d|^2 / 2.
    #[inline(always)]
    pub fn energy(&self, d2: f64) -> f64 {
        0.5 * self.k * d2
    }

    /// The force ([`Self::force`]) and its partial derivatives with respect
    /// to the gap `d` and to its rate `d'`, for the Jacobian:
    /// `F_d = (k + (b - b_t) rho) I + (b - b_t) d (d rho/d d)^T`,
    /// `F_d' = b_t I + (b - b_t) d d^T / (|d|^2 + eps2)`.
    #[inline(always)]
    pub fn partials(
        &self,
        d: [f64; 2],
        dd: [f64; 2],
    ) -> (Vector2<f64>, Matrix2<f64>, Matrix2<f64>) {
        let (d2, rho) = self.rate(d, dd);
        let den = d2 + self.eps2;
        let f = self.force(d, dd, rho);
        let ba = self.b - self.bt;
        let (d, dd) = (Vector2::from(d), Vector2::from(dd));
        let drho_dd = dd / den - (2.0 * rho / den) * d;
        let f_d = Matrix2::identity() * (self.k + ba * rho) + mm(&(ba * d), &drho_dd.transpose());
        let f_dd = Matrix2::identity() * self.bt + mm(&((ba / den) * d), &d.transpose());
        (Vector2::from(f), f_d, f_dd)
    }
}

/// Torsional SDE between the angles of two neighbouring bodies (eq. 22-23):
/// moment `M = k dphi + b dw` on the following body (minus it on the
/// preceding one), k = EI/l.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorsionalSde {
    /// Bending stiffness EI/l [N m/rad].
    pub k: f64,
    /// Bending damping [N m s/rad].
    pub b: f64,
}

impl TorsionalSde {
    /// Moment for the angle difference `dphi` (wrapped to (-pi, pi]) and
    /// the angular velocity difference `dw`.
    #[inline(always)]
    pub fn moment(&self, dphi: f64, dw: f64) -> f64 {
        self.k * dphi + self.b * dw
    }

    /// Partial derivatives of [`Self::moment`]: `(dM/d dphi, dM/d dw)`.
    #[inline(always)]
    pub fn partials(&self) -> (f64, f64) {
        (self.k, self.b)
    }

    /// Power dissipated by the damper, b dw^2.
    #[inline(always)]
    pub fn dissipation(&self, dw: f64) -> f64 {
        self.b * dw * dw
    }

    /// Whether the element has its damper (b != 0; the paper's sets have
    /// none). The right-hand side picks its [`Self::moment_dissipation`]
    /// build from this once per block.
    #[inline(always)]
    pub fn damped(&self) -> bool {
        self.b != 0.0
    }

    /// [`Self::moment`] and [`Self::dissipation`], without the damper when
    /// not `DAMPED` ([`Self::damped`] false): `(k dphi, 0)`. Bit for bit the
    /// full law's values at b = 0 (the left-out `0 dw` and `0 dw^2` are
    /// zeros added), but for the sign of an exactly zero moment; the
    /// right-hand side likewise leaves the zero out of the SDE's dissipation.
    #[inline(always)]
    pub fn moment_dissipation<const DAMPED: bool>(&self, dphi: f64, dw: f64) -> (f64, f64) {
        if DAMPED {
            (self.moment(dphi, dw), self.dissipation(dw))
        } else {
            (self.k * dphi, 0.0)
        }
    }

    /// Elastic energy k dphi^2 / 2.
    #[inline(always)]
    pub fn energy(&self, dphi: f64) -> f64 {
        0.5 * self.k * dphi * dphi
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The isotropic element (b_t = b, the default) and the paper's
    /// (b_t = 0, damping along the gap only) and one damping more across the
    /// gap than along it (b_t = 3 b): every law below holds for each.
    const LAWS: [AxialSde; 3] = [
        AxialSde {
            k: 2.0e6,
            b: 35.0,
            bt: 35.0,
            eps2: 1e-16,
        },
        AxialSde {
            k: 2.0e6,
            b: 35.0,
            bt: 0.0,
            eps2: 1e-16,
        },
        AxialSde {
            k: 2.0e6,
            b: 35.0,
            bt: 105.0,
            eps2: 1e-16,
        },
    ];

    fn force_of(law: &AxialSde, d: [f64; 2], dd: [f64; 2]) -> [f64; 2] {
        law.force(d, dd, law.rate(d, dd).1)
    }

    /// The builds without the damper terms a law lacks give the full law's
    /// force and power to the bit (a zero's sign aside: with d and d' both
    /// -0 the full law adds a +0 the build leaves out), at the paper's
    /// element (b_t = 0), the isotropic one (b_t = b), one without damping
    /// and one with more damping across than along (every term), over gaps
    /// and rates of both signs, zeros of both signs among them.
    #[test]
    fn force_dissipation_is_the_full_law_bit_for_bit() {
        let undamped = AxialSde {
            b: 0.0,
            bt: 0.0,
            ..LAWS[0]
        };
        let vals = [0.0, -0.0, 1.2e-4, -3.0e-5, 2.0e-3, -0.7, 0.5, 1.0e-9];
        for law in LAWS.iter().chain([&undamped]) {
            let full = |d, dd| {
                let (d2, rate) = law.rate(d, dd);
                (law.force(d, dd, rate), law.dissipation(d2, dd, rate))
            };
            let (along, across) = law.damper_terms();
            assert_eq!(along, law.b != law.bt);
            assert_eq!(across, law.bt != 0.0);
            let pairs = || vals.iter().flat_map(|&a| vals.iter().map(move |&b| [a, b]));
            for (d, dd) in pairs().flat_map(|d| pairs().map(move |dd| (d, dd))) {
                let built = match (along, across) {
                    (true, true) => law.force_dissipation::<true, true>(d, dd),
                    (true, false) => law.force_dissipation::<true, false>(d, dd),
                    (false, true) => law.force_dissipation::<false, true>(d, dd),
                    (false, false) => law.force_dissipation::<false, false>(d, dd),
                };
                let (a, b) = (built, full(d, dd));
                for (a, b) in [a.0[0], a.0[1], a.1].into_iter().zip([b.0[0], b.0[1], b.1]) {
                    // a zero's sign may differ (a left-out -0 term)
                    let same = a.to_bits() == b.to_bits() || (a == 0.0 && b == 0.0);
                    assert!(same, "{law:?} {d:?} {dd:?}: {a:e} against {b:e}");
                }
            }
        }
    }

    /// Central differences of the force against [`AxialSde::partials`].
    /// Steps of 1e-4 of the gap and rate: the force is smooth there (a
    /// quotient of quadratics, linear in the rate across the gap), so the
    /// truncation error is ~(1e-4)^2 relative and rounding ~1e-16 / 1e-4;
    /// 1e-6 relative covers both.
    #[test]
    fn axial_partials_match_differences() {
        for law in &LAWS {
            for &(d, dd) in &[
                ([1.2e-4, -3.0e-5], [0.02, 0.5]),
                ([-2.0e-3, 4.0e-4], [-1.5, 0.3]),
                ([5.0e-5, 5.0e-5], [0.0, 0.0]),
            ] {
                let (f, f_d, f_dd) = law.partials(d, dd);
                assert_eq!([f[0], f[1]], force_of(law, d, dd));
                for c in 0..2 {
                    let h = 1e-4 * (d[0].abs() + d[1].abs());
                    let (mut a, mut b) = (d, d);
                    a[c] += h;
                    b[c] -= h;
                    let (fa, fb) = (force_of(law, a, dd), force_of(law, b, dd));
                    let hv = 1e-4 * (dd[0].abs() + dd[1].abs()).max(1.0);
                    let (mut a, mut b) = (dd, dd);
                    a[c] += hv;
                    b[c] -= hv;
                    let (ga, gb) = (force_of(law, d, a), force_of(law, d, b));
                    for r in 0..2 {
                        let fd = (fa[r] - fb[r]) / (2.0 * h);
                        let gd = (ga[r] - gb[r]) / (2.0 * hv);
                        let scale = f_d.abs().max() + 1.0;
                        assert!(
                            (f_d[(r, c)] - fd).abs() <= 1e-6 * scale,
                            "{law:?} {f_d:?} {fd}"
                        );
                        let scale = f_dd.abs().max() + 1e-9;
                        assert!(
                            (f_dd[(r, c)] - gd).abs() <= 1e-6 * scale,
                            "{law:?} {f_dd:?} {gd}"
                        );
                    }
                }
            }
        }
    }

    /// The elastic force is the gradient of the energy, the damping power is
    /// the damping force times the gap rate (exact but for the regulariser
    /// eps2 in rho's denominator: relative difference eps2 / |d|^2 = 1e-8 here),
    /// and the tension is the force's component along the gap (its length
    /// when the damper acts along the gap only).
    #[test]
    fn axial_energy_and_dissipation_agree_with_the_force() {
        for law in &LAWS {
            let d = [1.0e-4, 2.0e-5];
            let dd = [0.3, -0.1];
            let (d2, rate) = law.rate(d, dd);
            let h = 1e-9;
            let de = (law.energy((d[0] + h) * (d[0] + h) + d[1] * d[1])
                - law.energy((d[0] - h) * (d[0] - h) + d[1] * d[1]))
                / (2.0 * h);
            let elastic = law.force(d, [0.0; 2], 0.0);
            assert!(
                (de - elastic[0]).abs() <= 1e-6 * elastic[0].abs(),
                "{de} {elastic:?}"
            );
            let f = law.force(d, dd, rate);
            let damping_power = (f[0] - elastic[0]) * dd[0] + (f[1] - elastic[1]) * dd[1];
            let diss = law.dissipation(d2, dd, rate);
            assert!(
                (diss - damping_power).abs() <= 1e-7 * diss,
                "{law:?} {diss} {damping_power}"
            );
            let len = d2.sqrt();
            let along = (f[0] * d[0] + f[1] * d[1]) / len;
            assert!(
                (law.tension(d2, rate) - along).abs() <= 1e-7 * along.abs(),
                "{law:?}"
            );
            if law.bt == 0.0 {
                let norm = (f[0] * f[0] + f[1] * f[1]).sqrt();
                assert!((law.tension(d2, rate) - norm).abs() <= 1e-12 * norm);
            }
        }
    }

    /// A gap that turns at constant length (the bodies' pitching, the
    /// joint's shear) meets the damper b_t across it and none along it; a
    /// gap that stretches in its own direction meets b along it; the
    /// dissipation is never negative, not even for b_t > b or d' across.
    #[test]
    fn axial_damper_along_and_across_the_gap() {
        for law in &LAWS {
            let d = [2.0e-4, 0.0];
            // across: d' normal to d, rho = 0
            let dd = [0.0, 0.4];
            let (d2, rate) = law.rate(d, dd);
            assert_eq!(rate, 0.0);
            let f = law.force(d, dd, rate);
            assert_eq!(f, [law.k * d[0], law.bt * dd[1]]);
            assert_eq!(law.dissipation(d2, dd, rate), law.bt * (dd[1] * dd[1]));
            // along: d' parallel to d, rho |d| = |d'| (1 - eps2/|d|^2): the
            // regulariser's 2.5e-9 relative of the damping force bounds the
            // difference
            let dd = [0.4, 0.0];
            let (d2, rate) = law.rate(d, dd);
            let f = law.force(d, dd, rate);
            let along = law.k * d[0] + law.b * dd[0];
            assert!((f[0] - along).abs() <= 1e-8 * along && f[1] == 0.0);
            let diss = law.dissipation(d2, dd, rate);
            assert!((diss - law.b * 0.16).abs() <= 1e-7 * diss, "{diss}");
            // regular at a closed gap: the damper across acts alone
            let f = force_of(law, [0.0; 2], [0.3, -0.2]);
            assert_eq!(f, [law.bt * 0.3, law.bt * -0.2]);
            for (d, dd) in [
                ([1e-4, 1e-4], [1.0, -1.0]),
                ([1e-4, -3e-5], [0.2, 0.9]),
                ([0.0, 0.0], [0.5, 0.5]),
                ([1e-9, 0.0], [3.0, 0.01]),
            ] {
                let (d2, rate) = law.rate(d, dd);
                assert!(law.dissipation(d2, dd, rate) >= 0.0, "{law:?} {d:?} {dd:?}");
            }
        }
    }

    /// Moment linear in both arguments: differences are exact up to
    /// rounding (1e-9 relative).
    #[test]
    fn torsional_partials_energy_and_dissipation() {
        let t = TorsionalSde { k: 0.05, b: 1e-4 };
        let (kp, kw) = t.partials();
        let (dphi, dw, h) = (0.02, -3.0, 1e-3);
        let fp = (t.moment(dphi + h, dw) - t.moment(dphi - h, dw)) / (2.0 * h);
        let fw = (t.moment(dphi, dw + h) - t.moment(dphi, dw - h)) / (2.0 * h);
        assert!((kp - fp).abs() <= 1e-9 * kp && (kw - fw).abs() <= 1e-9 * kw);
        let de = (t.energy(dphi + h) - t.energy(dphi - h)) / (2.0 * h);
        assert!((de - t.moment(dphi, 0.0)).abs() <= 1e-9 * de.abs());
        let damping_power = (t.moment(dphi, dw) - t.moment(dphi, 0.0)) * dw;
        assert!((t.dissipation(dw) - damping_power).abs() <= 1e-12 * damping_power.abs());
    }

    /// The torsional SDE's builds give the full law's moment and dissipation
    /// to the bit (a zero's sign aside), with and without the damper, over
    /// angle and rate differences of both signs including +-0.
    #[test]
    fn moment_dissipation_is_the_full_law_bit_for_bit() {
        let vals = [0.0, -0.0, 1.2e-4, -3.0e-5, 2.0e-3, -0.7, 0.5, 3.0];
        for t in [
            TorsionalSde { k: 0.05, b: 1e-4 },
            TorsionalSde { k: 0.05, b: 0.0 },
        ] {
            assert_eq!(t.damped(), t.b != 0.0);
            for (&dphi, &dw) in vals.iter().flat_map(|a| vals.iter().map(move |b| (a, b))) {
                let built = if t.damped() {
                    t.moment_dissipation::<true>(dphi, dw)
                } else {
                    t.moment_dissipation::<false>(dphi, dw)
                };
                let full = (t.moment(dphi, dw), t.dissipation(dw));
                for (a, b) in [(built.0, full.0), (built.1, full.1)] {
                    // a zero's sign may differ (a left-out -0 term)
                    let same = a.to_bits() == b.to_bits() || (a == 0.0 && b == 0.0);
                    assert!(same, "{t:?} {dphi:e} {dw:e}: {a:e} against {b:e}");
                }
            }
        }
    }

    #[test]
    fn gap_of_touching_ends_is_zero() {
        // two bodies on the x axis, end to end, moving together
        let p = BodyEnd {
            x: 0.0,
            y: 0.0,
            hx: 0.5,
            hy: 0.0,
            vx: 1.0,
            vy: 0.0,
            w: 0.0,
        };
        let c = BodyEnd { x: 1.0, ..p };
        assert_eq!(gap(p, c), ([0.0, 0.0], [0.0, 0.0]));
        // rotating the following body about its centre moves its left end down
        let c = BodyEnd { w: 2.0, ..c };
        assert_eq!(gap(p, c).1, [0.0, -1.0]);
    }
}
