//! Belt-pulley friction, section 2.2: the paper's law (eq. 12-19) and the
//! elastic-plastic creep law of its ref. [11], both driven by the creep
//! displacement `z` of each body, integrated as a state (dz/dt = v_T).
//!
//! The creep law's elastic range is a Kelvin-Voigt element: the creep
//! spring mu_s S(z / Delta_max) N plus a damper of relaxation time tau on
//! it, so the tangential modes of the bodies on a wrap decay (the paper's
//! law gets this damping from its viscous slope mu_s / dv; docs/model.md).
//!
//! Both laws use the paper's transition curve of eq. 10 (Fig. 4). "Half of
//! this course" is read as the upper half of the odd S-curve that the
//! smoothstep makes on [-1, 1]: S(u) = (3u - u^3)/2, S(0) = 0, S'(0) = 3/2,
//! S(1) = 1, S'(1) = 0 (docs/model.md, "Friction").

use super::contact::{smoothstep, smoothstep_slope};
use crate::belt::params::FrictionLaw;
use crate::belt::solver_params::TUNING;

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

/// Friction law with its constants.
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

/// Creep displacement at which the creep law slides at mu_k (1.5 Delta_max:
/// the static-to-kinetic transition spans Delta_max..1.5 Delta_max, as the
/// paper's spans dv..1.5 dv).
const SLIDE_AT: f64 = 1.5;

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

    /// Largest |z| the creep state takes.
    #[inline(always)]
    pub fn creep_cap(&self) -> f64 {
        match self.law {
            FrictionLaw::Kubas2014 => self.creep_max,
            FrictionLaw::Creep => SLIDE_AT * self.creep_max,
        }
    }

    /// Weight of the body velocities in the stiff method's error norm at
    /// relative tolerance `rel_tol`. With the creep law the body velocities
    /// carry the damped artificial modes, but also the creep velocities that
    /// set the slip: weight 1e-2 (1e-3 let the 5PK slip drift 5 % from
    /// RKF45's, 1e-2 0.3 %, for 28 % more steps; docs/model.md), and never
    /// looser than a relative tolerance of 1e-2 on them: at relTol 1e-3 a
    /// weight of 1e-2 let the steps lose the creep arcs
    /// (`SolverTuning::creep_velocity_max_rel_tol`). With `kubas2014`
    /// friction follows the sliding velocity itself, and a step that jumps
    /// across the stick band |v_T| < dv lands on the sliding branch, whose
    /// linearisation has no friction slope: the velocities keep full weight.
    pub fn velocity_error_weight(&self, rel_tol: f64) -> f64 {
        match self.law {
            FrictionLaw::Creep => TUNING
                .weight_creep_velocities
                .max(rel_tol / TUNING.creep_velocity_max_rel_tol)
                .min(1.0),
            FrictionLaw::Kubas2014 => 1.0,
        }
    }

    /// Signed friction coefficient along the pulley's tangent for relative
    /// velocity `v_t` (pulley surface minus body, eq. 18) and creep `z`.
    #[inline(always)]
    pub fn coefficient(&self, v_t: f64, z: f64, mu_s: f64, mu_k: f64) -> f64 {
        match self.law {
            FrictionLaw::Creep => self.creep_coefficient(v_t, z, mu_s, mu_k),
            FrictionLaw::Kubas2014 => self.kubas_coefficient(v_t, z, mu_s, mu_k),
        }
    }

    /// [`Self::coefficient`] of the creep law. In the elastic range
    /// |z| <= Delta_max the creep rate is v_t, and the damper adds
    /// mu_s S'(u) tau du/dt, u = z / Delta_max; the sum stays within the
    /// static bound mu_s (Coulomb).
    #[inline(always)]
    pub fn creep_coefficient(&self, v_t: f64, z: f64, mu_s: f64, mu_k: f64) -> f64 {
        let u = z * self.inv_creep_max;
        let a = u.abs();
        // both branches evaluated and one selected: no jump, so that the
        // contact loop vectorises
        // elastic: the creep spring and its damper, within the static
        // bound +-mu_s (a clamp by comparisons, like f64::clamp without
        // its assertion, so that it vectorises)
        let damper = 1.5 * (1.0 - u * u) * self.damping_per_creep * v_t;
        let spring_damper = mu_s * (s_curve(u) + damper);
        let elastic = if spring_damper > mu_s {
            mu_s
        } else if spring_damper < -mu_s {
            -mu_s
        } else {
            spring_damper
        };
        let sliding = (mu_s + (mu_k - mu_s) * smoothstep((a - 1.0) * 2.0)).copysign(u);
        if a <= 1.0 {
            elastic
        } else {
            sliding
        }
    }

    /// [`Self::coefficient`] of the kubas2014 law.
    #[inline(always)]
    pub fn kubas_coefficient(&self, v_t: f64, z: f64, mu_s: f64, mu_k: f64) -> f64 {
        let w = v_t.abs() * self.inv_dv;
        // both branches evaluated and one selected (see creep_coefficient)
        // eq. 13: mu = (1 - beta) mu1(Delta) + beta mu_s
        let beta = s_curve(w);
        let mu1 = mu_s * s_curve(z * self.inv_creep_max);
        let stick = (1.0 - beta) * mu1 + (beta * mu_s).copysign(v_t);
        // Fig. 6c: mu_s -> mu_k over dv..1.5 dv, then mu_k.
        let slide = (mu_s + (mu_k - mu_s) * smoothstep((w - 1.0) * 2.0)).copysign(v_t);
        if w < 1.0 {
            stick
        } else {
            slide
        }
    }

    /// [`coefficient`](Self::coefficient) with its partial derivatives
    /// `(mu, dmu/dv_t, dmu/dz)`, for the Jacobian of the implicit integrator.
    #[inline(always)]
    pub fn coefficient_jac(&self, v_t: f64, z: f64, mu_s: f64, mu_k: f64) -> (f64, f64, f64) {
        let mu = self.coefficient(v_t, z, mu_s, mu_k);
        match self.law {
            FrictionLaw::Creep => {
                let u = z * self.inv_creep_max;
                let a = u.abs();
                if a <= 1.0 {
                    if mu.abs() >= mu_s {
                        // clamped at the static bound
                        return (mu, 0.0, 0.0);
                    }
                    let c = self.damping_per_creep;
                    let dmu_dv = mu_s * s_curve_slope(u) * c;
                    // d/du of S(u) + S'(u) c v_t, S''(u) = -3 u
                    let dmu_dz = mu_s * (s_curve_slope(u) - 3.0 * u * c * v_t) * self.inv_creep_max;
                    (mu, dmu_dv, dmu_dz)
                } else {
                    let dmu_dz = (mu_k - mu_s)
                        * smoothstep_slope((a - 1.0) * 2.0)
                        * 2.0
                        * self.inv_creep_max;
                    (mu, 0.0, dmu_dz)
                }
            }
            FrictionLaw::Kubas2014 => {
                let w = v_t.abs() * self.inv_dv;
                if w < 1.0 {
                    let beta = s_curve(w);
                    let u = z * self.inv_creep_max;
                    let mu1 = mu_s * s_curve(u);
                    let sign = if v_t < 0.0 { -1.0 } else { 1.0 };
                    let dmu_dv = s_curve_slope(w) * self.inv_dv * (mu_s - sign * mu1);
                    let dmu_dz = (1.0 - beta) * mu_s * s_curve_slope(u) * self.inv_creep_max;
                    (mu, dmu_dv, dmu_dz)
                } else {
                    let dmu_dv =
                        (mu_k - mu_s) * smoothstep_slope((w - 1.0) * 2.0) * 2.0 * self.inv_dv;
                    (mu, dmu_dv, 0.0)
                }
            }
        }
    }

    /// dz/dt: the creep displacement follows the relative velocity until it
    /// reaches its cap, where it holds while the motion keeps pushing outward.
    #[inline(always)]
    pub fn creep_rate(&self, v_t: f64, z: f64) -> f64 {
        if z.abs() >= self.creep_cap() && v_t * z > 0.0 {
            0.0
        } else {
            v_t
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
    pub fn slip_loss(&self, v_t: f64, z: f64, mu_s: f64, mu_k: f64, normal: f64) -> f64 {
        let mu = self.coefficient(v_t, z, mu_s, mu_k);
        let mu0 = self.coefficient(0.0, z, mu_s, mu_k);
        let dz = self.creep_rate(v_t, z);
        (normal * ((mu - mu0) * dz + mu * (v_t - dz))).max(0.0)
    }

    /// Energy stored in the creep spring per newton of normal force [m]:
    /// Phi(z) = integral from 0 to z of mu(0, z') dz', the work of the force
    /// the law gives at rest (the creep law's spring mu_s S(z / Delta_max)
    /// and its softening to mu_k beyond Delta_max; eq. 13's mu1 of
    /// kubas2014). Even in z, >= 0, and Phi'(z) = mu(0, z). With
    /// u = |z| / Delta_max: mu_s Delta_max (3u^2/4 - u^4/8) for u <= 1 (the
    /// integral of S), and beyond it the sliding coefficient's integral.
    #[inline(always)]
    pub fn spring_energy(&self, z: f64, mu_s: f64, mu_k: f64) -> f64 {
        let u = z.abs() * self.inv_creep_max;
        let elastic = |u: f64| 0.75 * u * u - 0.125 * u * u * u * u;
        let beyond = (u - 1.0).max(0.0);
        let slide = match self.law {
            // mu_s + (mu_k - mu_s) smoothstep(2 (u - 1)): the smoothstep's
            // integral over [0, x] is x^3 - x^4/2 (x <= 1), then 1/2 + (x - 1)
            FrictionLaw::Creep => {
                let x = 2.0 * beyond;
                let w = x.min(1.0);
                let ramp = w * w * w - 0.5 * w * w * w * w + (x - 1.0).max(0.0);
                mu_s * beyond + 0.5 * (mu_k - mu_s) * ramp
            }
            FrictionLaw::Kubas2014 => mu_s * beyond,
        };
        self.creep_max * (mu_s * elastic(u.min(1.0)) + slide)
    }

    /// What a contact's friction adds to the drive's dissipated energy:
    /// the friction power f v_T (f = mu N, `normal` = N >= 0) less the rate
    /// of change of the energy stored in its creep spring, `elastic`
    /// Phi(z) (`elastic` = N_e the elastic part of the normal force,
    /// `elastic_rate` its rate dN_e/dt; [`Self::spring_energy`]):
    ///   f v_T - N_e mu(0, z) dz/dt - dN_e/dt Phi(z)
    ///   = [`Self::slip_loss`] + (N - N_e) mu(0, z) dz/dt - dN_e/dt Phi(z).
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
    pub fn dissipated_power(
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

    /// Slope of [`Self::creep_rate`] in `v_t`: 1, or 0 while held at the cap.
    #[inline(always)]
    pub fn creep_rate_slope(&self, v_t: f64, z: f64) -> f64 {
        if z.abs() >= self.creep_cap() && v_t * z > 0.0 {
            0.0
        } else {
            1.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn creep_law_elastic_then_kinetic() {
        let f = Friction::new(FrictionLaw::Creep, 1e-5, 1e-4, 0.0);
        let (ms, mk) = (1.05, 1.0);
        assert_eq!(f.coefficient(0.3, 0.0, ms, mk), 0.0);
        assert!((f.coefficient(0.3, 1e-4, ms, mk) - ms).abs() < 1e-12);
        assert!((f.coefficient(0.3, -1.5e-4, ms, mk) + mk).abs() < 1e-12);
        assert!((f.coefficient(0.3, 1e-3, ms, mk) - mk).abs() < 1e-12);
        // independent of velocity
        assert_eq!(
            f.coefficient(1e-9, 5e-5, ms, mk),
            f.coefficient(10.0, 5e-5, ms, mk)
        );
        // creep holds at its cap while pushed outward, unloads freely
        let cap = f.creep_cap();
        assert_eq!(f.creep_rate(0.1, cap), 0.0);
        assert_eq!(f.creep_rate(-0.1, cap), -0.1);
        assert_eq!(f.creep_rate(0.1, 1e-4), 0.1);
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

    #[test]
    fn kubas_law_regularised_coulomb() {
        let f = Friction::new(FrictionLaw::Kubas2014, 1e-5, 1e-4, 1e-4);
        let (ms, mk) = (1.05, 1.0);
        assert!((f.coefficient(1e-5, 0.0, ms, mk) - ms).abs() < 1e-12);
        assert!((f.coefficient(-2e-5, 0.0, ms, mk) + mk).abs() < 1e-12);
        assert_eq!(f.coefficient(0.0, 0.0, ms, mk), 0.0);
        // at v = 0 the creep term alone acts (mu1 of eq. 13)
        assert!((f.coefficient(0.0, 1e-4, ms, mk) - ms).abs() < 1e-12);
        // continuous at dv
        let a = f.coefficient(1e-5 * (1.0 - 1e-9), 0.0, ms, mk);
        let b = f.coefficient(1e-5 * (1.0 + 1e-9), 0.0, ms, mk);
        assert!((a - b).abs() < 1e-6);
    }
}
