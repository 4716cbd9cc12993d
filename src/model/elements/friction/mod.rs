//! Belt-pulley friction, section 2.2: the paper's law (eq. 12-19,
//! [`kubas2014`]) and the elastic-plastic creep law of its ref. [11]
//! ([`creep`]), both driven by the creep displacement `z` of each body,
//! integrated as a state (dz/dt = v_T).
//!
//! Each law is a [`Law`]: its coefficient, the coefficient's partial
//! derivatives, the creep cap, the energy its creep spring stores and
//! whether the friction force follows the sliding velocity itself, in its
//! own file. What follows
//! from these alone (the creep rate, the dissipated power) is written once,
//! here, as the trait's provided methods.
//!
//! [`Friction`] is the drive's choice of law with its parameters.
//! `with_law!` runs a piece of code with the chosen law's own type: the code
//! is compiled once per law, so the loops of the right-hand side and the
//! Jacobian call the law directly and never test which law it is.
//!
//! Both laws use the paper's transition curve of eq. 10 (Fig. 4). "Half of
//! this course" is read as the upper half of the odd S-curve that the
//! smoothstep makes on [-1, 1]: S(u) = (3u - u^3)/2, S(0) = 0, S'(0) = 3/2,
//! S(1) = 1, S'(1) = 0 (docs/model.md, "Friction").

mod creep;
mod kubas2014;

pub use creep::Creep;
pub use kubas2014::Kubas2014;

use crate::model::params::FrictionLaw;

/// Odd S-curve: the upper half of eq. 10's course stretched over [-1, 1].
#[inline(always)]
pub fn s_curve(u: f64) -> f64 {
    let u = u.clamp(-1.0, 1.0);
    0.5 * u * (3.0 - u * u)
}

/// Derivative of [`s_curve`].
#[inline(always)]
pub fn s_curve_slope(u: f64) -> f64 {
    if u.abs() >= 1.0 {
        0.0
    } else {
        1.5 * (1.0 - u * u)
    }
}

/// A belt-pulley friction law: the signed friction coefficient
/// mu(v_T, z; mu_s, mu_k) of a contact, f = mu N along the pulley's tangent
/// (eq. 19), with v_T the relative velocity (pulley surface minus body,
/// eq. 18) and z the creep displacement.
///
/// A new law implements the five required methods in a file of its own
/// beside [`creep`] and [`kubas2014`], with a finite-difference test of
/// [`Law::coefficient_jac`] (`tests::assert_partials`), and gets an arm in
/// `with_law!` (see docs/architecture.md, "What a change touches").
pub trait Law: Copy {
    /// Signed friction coefficient along the pulley's tangent for relative
    /// velocity `v_t` (pulley surface minus body, eq. 18) and creep `z`,
    /// static and kinetic coefficients `mu_s`, `mu_k` of the contact.
    fn coefficient(&self, v_t: f64, z: f64, mu_s: f64, mu_k: f64) -> f64;

    /// [`Law::coefficient`] with its partial derivatives
    /// `(mu, dmu/dv_t, dmu/dz)`, for the Jacobian of the implicit integrator.
    fn coefficient_jac(&self, v_t: f64, z: f64, mu_s: f64, mu_k: f64) -> (f64, f64, f64);

    /// Largest |z| the creep state takes.
    fn creep_cap(&self) -> f64;

    /// Energy stored in the creep spring per newton of normal force [m]:
    /// Phi(z) = integral from 0 to z of mu(0, z') dz', the work of the force
    /// the law gives at rest. Even in z, >= 0, and Phi'(z) = mu(0, z).
    fn spring_energy(&self, z: f64, mu_s: f64, mu_k: f64) -> f64;

    /// Whether the friction force follows the sliding velocity v_T itself
    /// (true: a steep function of v_T, as the paper's law over its stick band
    /// dv) or the creep displacement z (false: the creep velocities are
    /// ~1e-3 of the belt speed and only set the slip). The stiff method
    /// weights the body velocities in its error norm by this
    /// (`SolverTuning::velocity_error_weight`).
    fn follows_sliding_velocity(&self) -> bool;

    /// dz/dt: the creep displacement follows the relative velocity until it
    /// reaches its cap, where it holds while the motion keeps pushing outward.
    #[inline(always)]
    fn creep_rate(&self, v_t: f64, z: f64) -> f64 {
        if z.abs() >= self.creep_cap() && v_t * z > 0.0 {
            0.0
        } else {
            v_t
        }
    }

    /// Slope of [`Law::creep_rate`] in `v_t`: 1, or 0 while held at the cap.
    #[inline(always)]
    fn creep_rate_slope(&self, v_t: f64, z: f64) -> f64 {
        if z.abs() >= self.creep_cap() && v_t * z > 0.0 {
            0.0
        } else {
            1.0
        }
    }

    /// Power lost to friction by a contact with normal force `normal` >= 0
    /// (a share of f v_T, f = mu N): the friction force's power f v_T less
    /// the power f_0 dz/dt stored in the creep spring, f_0 = mu(0, z) N the
    /// force the law gives at rest (the creep law's spring mu_s S(z/Delta_max),
    /// eq. 13's mu1 of kubas2014):
    ///   (f - f_0) dz/dt + f (v_T - dz/dt).
    /// The first term is the creep damper's (the creep law) or the
    /// velocity-dependent part's (kubas2014) power, the second the power of
    /// sliding with the creep held at its cap. Non-negative for the creep
    /// law; kubas2014 can leave the bound mu_s S(z) only towards mu_s, so its
    /// few negative values (sliding before the creep reaches its cap, when
    /// mu_k < mu_s) are clipped to 0.
    #[inline(always)]
    fn slip_loss(&self, v_t: f64, z: f64, mu_s: f64, mu_k: f64, normal: f64) -> f64 {
        let mu = self.coefficient(v_t, z, mu_s, mu_k);
        let mu0 = self.coefficient(0.0, z, mu_s, mu_k);
        let dz = self.creep_rate(v_t, z);
        (normal * ((mu - mu0) * dz + mu * (v_t - dz))).max(0.0)
    }

    /// What a contact's friction adds to the drive's dissipated energy:
    /// the friction power f v_T (f = mu N, `normal` = N >= 0) less the rate
    /// of change of the energy stored in its creep spring, `elastic`
    /// Phi(z) (`elastic` = N_e the elastic part of the normal force,
    /// `elastic_rate` its rate dN_e/dt; [`Law::spring_energy`]):
    ///   f v_T - N_e mu(0, z) dz/dt - dN_e/dt Phi(z)
    ///   = [`Law::slip_loss`] + (N - N_e) mu(0, z) dz/dt - dN_e/dt Phi(z).
    /// Beyond the slip loss it holds the spring's exchange with the normal
    /// force: the spring's stiffness follows N (eq. 13), so it releases its
    /// energy as the contact unloads at a creep z (a body leaving the wrap
    /// with its creep at the cap: a loss) and gains energy the friction
    /// force did not supply as the contact loads at a creep z (a body
    /// landing while its creep builds up). That exchange is not signed:
    /// over a body's pass over a wrap (landing at z = 0, leaving at N = 0)
    /// it adds up to the spring's net work, a loss, but at an instant it
    /// swings both ways (docs/model.md, "Outputs").
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn dissipated_power(
        &self,
        v_t: f64,
        z: f64,
        mu_s: f64,
        mu_k: f64,
        normal: f64,
        elastic: f64,
        elastic_rate: f64,
    ) -> f64 {
        let mu = self.coefficient(v_t, z, mu_s, mu_k);
        let mu0 = self.coefficient(0.0, z, mu_s, mu_k);
        let dz = self.creep_rate(v_t, z);
        normal * mu * v_t - elastic * mu0 * dz - elastic_rate * self.spring_energy(z, mu_s, mu_k)
    }
}

/// The drive's friction: which law, and the parameters of the laws.
/// `with_law!` turns it into the law itself; its own [`Law`] methods test
/// which law on every call and are meant for code outside the force loops
/// (the after-step creep reset, the energy outputs, tests).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Friction {
    /// Which law.
    pub law: FrictionLaw,
    /// 1 / dv [s/m] (kubas2014).
    pub inv_dv: f64,
    /// Creep displacement of full static friction, Delta_max [m].
    pub creep_max: f64,
    /// 1 / Delta_max [1/m].
    pub inv_creep_max: f64,
    /// Relaxation time of the creep spring over Delta_max [s/m] (creep law).
    pub damping_per_creep: f64,
}

impl Friction {
    /// `damping_time`: relaxation time tau of the creep law's spring [s].
    pub fn new(law: FrictionLaw, dv: f64, creep_max: f64, damping_time: f64) -> Self {
        Self {
            law,
            inv_dv: 1.0 / dv,
            creep_max,
            inv_creep_max: 1.0 / creep_max,
            damping_per_creep: damping_time / creep_max,
        }
    }

    /// The creep law with these parameters.
    #[inline(always)]
    pub fn creep(&self) -> Creep {
        Creep {
            creep_max: self.creep_max,
            inv_creep_max: self.inv_creep_max,
            damping_per_creep: self.damping_per_creep,
        }
    }

    /// The kubas2014 law with these parameters.
    #[inline(always)]
    pub fn kubas2014(&self) -> Kubas2014 {
        Kubas2014 {
            inv_dv: self.inv_dv,
            creep_max: self.creep_max,
            inv_creep_max: self.inv_creep_max,
        }
    }
}

/// `with_law!(friction, law => expr)`: evaluates `expr` with `law` bound to
/// the law `friction` (a [`Friction`]) chooses, as its own type ([`Creep`],
/// [`Kubas2014`]). `expr` is compiled once per law (static dispatch): call it
/// around a loop, not inside one. The only `match` on the friction law.
macro_rules! with_law {
    ($friction:expr, $law:ident => $body:expr) => {{
        let friction: $crate::model::elements::friction::Friction = $friction;
        match friction.law {
            $crate::model::params::FrictionLaw::Creep => {
                let $law = friction.creep();
                $body
            }
            $crate::model::params::FrictionLaw::Kubas2014 => {
                let $law = friction.kubas2014();
                $body
            }
        }
    }};
}
pub(crate) use with_law;

/// Each method tests which law (see [`Friction`]).
impl Law for Friction {
    #[inline]
    fn coefficient(&self, v_t: f64, z: f64, mu_s: f64, mu_k: f64) -> f64 {
        with_law!(*self, law => law.coefficient(v_t, z, mu_s, mu_k))
    }
    #[inline]
    fn coefficient_jac(&self, v_t: f64, z: f64, mu_s: f64, mu_k: f64) -> (f64, f64, f64) {
        with_law!(*self, law => law.coefficient_jac(v_t, z, mu_s, mu_k))
    }
    #[inline]
    fn creep_cap(&self) -> f64 {
        with_law!(*self, law => law.creep_cap())
    }
    #[inline]
    fn spring_energy(&self, z: f64, mu_s: f64, mu_k: f64) -> f64 {
        with_law!(*self, law => law.spring_energy(z, mu_s, mu_k))
    }
    fn follows_sliding_velocity(&self) -> bool {
        with_law!(*self, law => law.follows_sliding_velocity())
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// `law`'s partials `(dmu/dv_T, dmu/dz)` at (v, z) against central
    /// differences of its coefficient (steps 1e-9 m/s and 1e-10 m: the
    /// laws' scales dv, Delta_max are >= 1e-5 m/s, 1e-4 m in the tests, so
    /// truncation is ~1e-8 relative and rounding ~1e-16 / 1e-10 = 1e-6
    /// absolute against slopes of 1e3-1e4), within 1e-5 of the partial or
    /// of 1; and mu itself equal to `coefficient`'s.
    pub(crate) fn assert_partials<L: Law + std::fmt::Debug>(
        f: &L,
        v: f64,
        z: f64,
        ms: f64,
        mk: f64,
    ) {
        let (mu, dv, dz) = f.coefficient_jac(v, z, ms, mk);
        assert_eq!(mu, f.coefficient(v, z, ms, mk));
        let (ev, ez) = (1e-9, 1e-10);
        let fv = (f.coefficient(v + ev, z, ms, mk) - f.coefficient(v - ev, z, ms, mk)) / (2.0 * ev);
        let fz = (f.coefficient(v, z + ez, ms, mk) - f.coefficient(v, z - ez, ms, mk)) / (2.0 * ez);
        assert!(
            (dv - fv).abs() <= 1e-5 * fv.abs().max(1.0),
            "{f:?} v={v} z={z}: dmu/dv {dv} vs {fv}"
        );
        assert!(
            (dz - fz).abs() <= 1e-5 * fz.abs().max(1.0),
            "{f:?} v={v} z={z}: dmu/dz {dz} vs {fz}"
        );
    }

    #[test]
    fn s_curve_shape() {
        assert_eq!(s_curve(0.0), 0.0);
        assert_eq!(s_curve(1.0), 1.0);
        assert_eq!(s_curve(-1.0), -1.0);
        assert_eq!(s_curve(2.0), 1.0);
        // slope 3/2 at the origin, 0 at the ends
        let h = 1e-6;
        assert!(((s_curve(h) - s_curve(-h)) / (2.0 * h) - 1.5).abs() < 1e-9);
        assert!((s_curve(1.0) - s_curve(1.0 - h)).abs() < 1e-11);
    }

    #[test]
    fn coefficient_derivatives_match_differences() {
        let (ms, mk) = (1.05, 0.9);
        for law in [FrictionLaw::Creep, FrictionLaw::Kubas2014] {
            let f = Friction::new(law, 1e-3, 1e-4, 2e-4);
            for &v in &[-2e-3, -1.2e-3, -4e-4, 3e-4, 1.3e-3, 0.05] {
                for &z in &[-1.3e-4, -5e-5, 2e-5, 9e-5, 1.2e-4, 1.45e-4] {
                    let (mu, dv, dz) = f.coefficient_jac(v, z, ms, mk);
                    assert_eq!(mu, f.coefficient(v, z, ms, mk));
                    let (ev, ez) = (1e-9, 1e-10);
                    let fv = (f.coefficient(v + ev, z, ms, mk) - f.coefficient(v - ev, z, ms, mk))
                        / (2.0 * ev);
                    let fz = (f.coefficient(v, z + ez, ms, mk) - f.coefficient(v, z - ez, ms, mk))
                        / (2.0 * ez);
                    assert!(
                        (dv - fv).abs() <= 1e-5 * fv.abs().max(1.0),
                        "{law:?} v={v} z={z}: {dv} vs {fv}"
                    );
                    assert!(
                        (dz - fz).abs() <= 1e-5 * fz.abs().max(1.0),
                        "{law:?} v={v} z={z}: {dz} vs {fz}"
                    );
                }
            }
        }
    }

    /// The slip loss is never negative and is the friction power less the
    /// creep spring's: for the creep law exactly (no clipping), on a grid
    /// through the elastic range, the damper's clamp, the sliding band and
    /// the cap, both signs.
    #[test]
    fn slip_loss_is_friction_power_less_the_creep_spring() {
        let (ms, mk, n) = (1.05, 0.9, 80.0);
        for law in [FrictionLaw::Creep, FrictionLaw::Kubas2014] {
            let f = Friction::new(law, 1e-3, 1e-4, 3e-4);
            let cap = f.creep_cap();
            for &v in &[-0.3, -2e-3, -4e-4, 0.0, 3e-4, 1.3e-3, 0.05, 2.0] {
                for &z in &[-cap, -1.3e-4, -9e-5, -2e-5, 0.0, 2e-5, 9e-5, 1.2e-4, cap] {
                    let loss = f.slip_loss(v, z, ms, mk, n);
                    assert!(loss >= 0.0, "{law:?} v={v} z={z}: {loss}");
                    let power = f.coefficient(v, z, ms, mk) * n * v;
                    let spring = f.coefficient(0.0, z, ms, mk) * n * f.creep_rate(v, z);
                    if law == FrictionLaw::Creep {
                        let d = power - spring;
                        assert!(
                            (loss - d).abs() <= 1e-12 * (power.abs() + spring.abs()),
                            "{law:?} v={v} z={z}: {loss} vs {d}"
                        );
                    }
                }
            }
        }
    }

    /// The spring energy's slope is the force the law gives at rest,
    /// mu(0, z) (central differences through the elastic range, the
    /// softening band and beyond the cap, both signs), and it is even and
    /// zero at z = 0.
    #[test]
    fn spring_energy_is_the_integral_of_the_force_at_rest() {
        let (ms, mk) = (1.05, 0.9);
        for law in [FrictionLaw::Creep, FrictionLaw::Kubas2014] {
            let f = Friction::new(law, 1e-3, 1e-4, 3e-4);
            assert_eq!(f.spring_energy(0.0, ms, mk), 0.0);
            for &z in &[2e-5, 7e-5, 9.9e-5, 1.1e-4, 1.3e-4, 1.49e-4, 1.6e-4] {
                let e = 1e-9;
                let slope =
                    (f.spring_energy(z + e, ms, mk) - f.spring_energy(z - e, ms, mk)) / (2.0 * e);
                let mu0 = f.coefficient(0.0, z, ms, mk);
                assert!(
                    (slope - mu0).abs() < 1e-6,
                    "{law:?} z={z}: {slope} vs {mu0}"
                );
                assert_eq!(f.spring_energy(-z, ms, mk), f.spring_energy(z, ms, mk));
            }
        }
    }

    /// Along a contact history (creep, normal force and slip velocity
    /// varying in time, through the elastic range, the softening band and
    /// the cap, loading and unloading), the friction work equals the
    /// dissipated power integrated plus the change of the spring energy
    /// N_e Phi(z), to the quadrature's error: nothing counted twice or left
    /// out.
    #[test]
    fn dissipated_power_and_spring_energy_account_for_the_friction_work() {
        let (ms, mk) = (1.05, 0.9);
        for law in [FrictionLaw::Creep, FrictionLaw::Kubas2014] {
            let f = Friction::new(law, 1e-3, 1e-4, 3e-4);
            // N_e(t) loading and unloading; N = N_e + a damper share
            let ne = |t: f64| 60.0 + 50.0 * (7.0 * t).sin();
            let ne_rate = |t: f64| 350.0 * (7.0 * t).cos();
            let normal = |t: f64| (ne(t) + 0.002 * ne_rate(t)).max(0.0);
            let v_t = |t: f64| 1e-3 * (5.0 * t).cos() + 2e-4 * (13.0 * t).sin();
            let (mut z, mut work, mut loss) = (0.0_f64, 0.0, 0.0);
            let h = 1e-6;
            let e0 = ne(0.0) * f.spring_energy(z, ms, mk);
            let mut t = 0.0;
            let mut reached = false;
            for _ in 0..2_000_000 {
                // midpoint rule for the integrals and for z
                let tm = t + 0.5 * h;
                let zm = z + 0.5 * h * f.creep_rate(v_t(t), z);
                let (v, n) = (v_t(tm), normal(tm));
                work += h * f.coefficient(v, zm, ms, mk) * n * v;
                loss += h * f.dissipated_power(v, zm, ms, mk, n, ne(tm), ne_rate(tm));
                z += h * f.creep_rate(v, zm);
                z = z.clamp(-f.creep_cap(), f.creep_cap());
                reached |= z.abs() >= 0.999 * f.creep_cap();
                t += h;
            }
            assert!(reached, "{law:?}: the history reaches the cap");
            let stored = ne(t) * f.spring_energy(z, ms, mk) - e0;
            let gap = work - loss - stored;
            println!(
                "{law:?}: work {work:.6e}, loss {loss:.6e}, stored {stored:.3e}, gap {gap:.1e}"
            );
            assert!(loss > 0.0);
            // midpoint rule at h = 1e-6 over 2 s: error ~1e-6 of the work
            assert!(gap.abs() < 1e-5 * work.abs(), "{law:?}: {gap}");
        }
    }
}
