//! Belt-pulley penalty contact, eq. 4-11 of section 2.2, and the contact
//! force with its friction part (eq. 19) and partial derivatives. The
//! geometry of a body centre against a pulley circle ([`kinematics`]), the
//! normal force law ([`ContactLaw`]) and the force with its partials
//! ([`force_partials`]) live here and nowhere else; the contact along a
//! straight body at several points (`contact.points`: [`point`],
//! [`segment`]) in `segment.rs`.

use crate::model::matmul::mm;
use nalgebra::{Matrix2, RowVector2, Vector2};

/// Smoothstep of eq. 10-11 on [0, 1]: 0 below, x^2 (3 - 2x) inside, 1 above.
#[inline(always)]
pub fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// Penalty law of one body (constants already multiplied by the body
/// length). The damping ramp's length p_max (eq. 10-11) belongs to the
/// pulley (each wrap has its own equilibrium penetration, see
/// [`auto_p_max`]): the methods take its inverse `inv_p_max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLaw {
    /// Quadratic stiffness [N/m^2].
    pub c1: f64,
    /// Linear stiffness [N/m].
    pub c2: f64,
    /// Damping [N s/m].
    pub b: f64,
}

/// The damping ramp's length p_max when `contact.pMax` = 0 (automatic):
/// this multiple of the pulley's equilibrium penetration p0 under the
/// preload (docs/model.md, "Contact"). 0.5 puts the full damping b at the
/// mounted penetration and keeps half of it down to a quarter of the
/// preload's normal force (linear stiffness), i.e. on the slack side of a
/// loaded drive too, while the ramp still spans the range of penetrations a
/// body passes through when it lands.
pub const AUTO_P_MAX_PER_PENETRATION: f64 = 0.5;

/// p_max [m] of a wrap with equilibrium penetration `p0` [m] for the
/// user's `contact.pMax` `p_max`: the user's value, or with 0 the automatic
/// [`AUTO_P_MAX_PER_PENETRATION`] x p0 (at least 1e-9 m, for a wrap that
/// carries no force at mounting).
pub fn auto_p_max(p_max: f64, p0: f64) -> f64 {
    if p_max > 0.0 {
        p_max
    } else {
        (AUTO_P_MAX_PER_PENETRATION * p0).max(1e-9)
    }
}

/// The friction lever of a pulley of `radius` on a chain of straight bodies
/// of length `body_length` whose centres rest at the penetration
/// `penetration` (docs/model.md, "Chordal effect"): r atan(h) / h with
/// h = l / (2 (r - p0)). On the wrap the centres lie on the circle
/// rho = r - p0 and each body spans the angle 2 atan(h), so bodies whose
/// centres move at v pass at the rate v / (2 rho atan h) and carry the belt
/// on at v h / atan(h) (each takes the length l on a span). With the
/// surface speed omega times this lever a chain in stick runs its spans at
/// omega r on any mesh, like a continuous belt, and the lever tends to r as
/// l -> 0. The pulley's friction moment uses the same lever, so the
/// friction power stays f v_T (eq. 14, 24).
pub fn chordal_lever(radius: f64, penetration: f64, body_length: f64) -> f64 {
    let h = body_length / (2.0 * (radius - penetration));
    if h > 0.0 && h.is_finite() {
        radius * h.atan() / h
    } else {
        radius
    }
}

/// Derivative of [`smoothstep`].
#[inline(always)]
pub fn smoothstep_slope(x: f64) -> f64 {
    if x <= 0.0 || x >= 1.0 {
        0.0
    } else {
        6.0 * x * (1.0 - x)
    }
}

impl ContactLaw {
    /// Normal force for penetration `p` > 0 and penetration rate `p_dot`
    /// (eq. 9) on a pulley whose damping ramp is `1 / inv_p_max` long, never
    /// negative (the belt cannot pull on the pulley), and its elastic part.
    #[inline(always)]
    pub fn normal_force(&self, p: f64, p_dot: f64, inv_p_max: f64) -> (f64, f64) {
        let elastic = (self.c1 * p + self.c2) * p;
        let n = elastic + smoothstep(p * inv_p_max) * self.b * p_dot;
        (n.max(0.0), elastic)
    }

    /// Rate of the elastic part of the normal force, dN_e/dt = (2 c1 p + c2)
    /// p_dot, for the energy its creep spring stores (elements::friction).
    #[inline(always)]
    pub fn elastic_rate(&self, p: f64, p_dot: f64) -> f64 {
        (2.0 * self.c1 * p + self.c2) * p_dot
    }

    /// Elastic part of the normal force at penetration `p` > 0.
    #[inline(always)]
    pub fn elastic_force(&self, p: f64) -> f64 {
        (self.c1 * p + self.c2) * p
    }

    /// Tangent stiffness of the elastic part at penetration `p`, dN_e/dp =
    /// 2 c1 p + c2 (eq. 9).
    pub fn stiffness(&self, p: f64) -> f64 {
        2.0 * self.c1 * p + self.c2
    }

    /// The penetration at which the elastic part carries the normal force
    /// `n`: the positive root of c1 p^2 + c2 p = n (eq. 9 in equilibrium),
    /// 0 for `n` <= 0.
    pub fn penetration_for(&self, n: f64) -> f64 {
        let (c1, c2) = (self.c1, self.c2);
        if n <= 0.0 {
            0.0
        } else if c1 == 0.0 {
            n / c2
        } else {
            // Stable form of (-c2 + sqrt(c2^2 + 4 c1 n)) / (2 c1).
            2.0 * n / (c2 + (c2 * c2 + 4.0 * c1 * n).sqrt())
        }
    }

    /// Damping ratio of a body of `mass` bouncing on the pulley at
    /// penetration `p`: delta(p) b / (2 sqrt(k m)) with the tangent
    /// stiffness k ([`Self::stiffness`], eq. 9-11).
    pub fn damping_ratio(&self, p: f64, mass: f64, inv_p_max: f64) -> f64 {
        let k = self.stiffness(p);
        smoothstep(p * inv_p_max) * self.b / (2.0 * (k * mass).sqrt())
    }

    /// [`normal_force`](Self::normal_force) with its partial derivatives
    /// `(N, dN/dp, dN/dp_dot)` (zero where the clamp at 0 is active), for the
    /// Jacobian of the implicit integrator.
    #[inline(always)]
    pub fn normal_force_jac(&self, p: f64, p_dot: f64, inv_p_max: f64) -> (f64, f64, f64) {
        let x = p * inv_p_max;
        let s = smoothstep(x);
        let n = (self.c1 * p + self.c2) * p + s * self.b * p_dot;
        if n <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        let dn_dp = 2.0 * self.c1 * p + self.c2 + smoothstep_slope(x) * inv_p_max * self.b * p_dot;
        (n, dn_dp, s * self.b)
    }

    /// Elastic energy stored at penetration `p` (the integral of the elastic part).
    pub fn energy(&self, p: f64) -> f64 {
        if p <= 0.0 {
            0.0
        } else {
            p * p * (self.c1 * p / 3.0 + 0.5 * self.c2)
        }
    }
}

/// A body centre relative to a pulley (eq. 4-8, 14-18): the squared and
/// plain distance from the pulley centre, the outward normal `n` and the
/// tangent `t` (n turned by +90 degrees), the penetration `p = r_p - dist`
/// and its rate, and the relative tangential velocity `v_T` of the pulley
/// surface over the body (`v_T = omega r_c - v.t`, r_c the pulley's friction lever).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactKin {
    /// Squared distance of the body centre from the pulley centre [m^2].
    pub d2: f64,
    /// Distance [m].
    pub dist: f64,
    /// 1 / max(dist, 1e-12) [1/m].
    pub inv_dist: f64,
    /// Outward unit normal.
    pub n: [f64; 2],
    /// Unit tangent, the direction of positive pulley rotation.
    pub t: [f64; 2],
    /// Penetration [m] (positive inside the circle).
    pub p: f64,
    /// Penetration rate [m/s].
    pub p_dot: f64,
    /// Tangential velocity of the pulley surface relative to the body [m/s].
    pub v_t: f64,
}

/// Squared distance of a point at `r` from the pulley centre [m^2]
/// (eq. 4-8).
#[inline(always)]
pub fn distance2(r: [f64; 2]) -> f64 {
    r[0] * r[0] + r[1] * r[1]
}

/// Penetration p = r_p - |r| of a point at `r` from the centre of a
/// contact circle of `radius` [m], positive inside (eq. 8): the
/// [`ContactKin::p`] of [`kinematics`], for code that needs no more.
#[inline(always)]
pub fn penetration(r: [f64; 2], radius: f64) -> f64 {
    radius - distance2(r).sqrt()
}

/// [`ContactKin`] of a body at `r` from the centre of a pulley of `radius`
/// whose surface moves at `surface` (= omega times the friction lever),
/// body velocity `v`.
#[inline(always)]
pub fn kinematics(r: [f64; 2], v: [f64; 2], radius: f64, surface: f64) -> ContactKin {
    let [rx, ry] = r;
    let [vx, vy] = v;
    let d2 = distance2(r);
    let dist = d2.sqrt();
    let inv_dist = 1.0 / dist.max(1e-12);
    let (nx, ny) = (rx * inv_dist, ry * inv_dist);
    let p = penetration(r, radius);
    let p_dot = -(vx * nx + vy * ny);
    let (tx, ty) = (-ny, nx);
    let v_t = surface - (vx * tx + vy * ty);
    ContactKin {
        d2,
        dist,
        inv_dist,
        n: [nx, ny],
        t: [tx, ty],
        p,
        p_dot,
        v_t,
    }
}

/// Force on the body: the normal force `normal` along n plus the friction
/// force `f = mu N` along t (eq. 19).
#[inline(always)]
pub fn force(k: &ContactKin, normal: f64, f: f64) -> [f64; 2] {
    [normal * k.n[0] + f * k.t[0], normal * k.n[1] + f * k.t[1]]
}

/// Power dissipated by one contact: the normal damper ([`damper_loss`])
/// plus friction (f v_T).
#[inline(always)]
pub fn dissipation(k: &ContactKin, normal: f64, elastic: f64, f: f64) -> f64 {
    damper_loss(k, normal, elastic) + f * k.v_t
}

/// Power dissipated by the contact's normal damper: the normal force
/// beyond its elastic part `elastic` times the penetration rate.
#[inline(always)]
pub fn damper_loss(k: &ContactKin, normal: f64, elastic: f64) -> f64 {
    (normal - elastic) * k.p_dot
}

/// Partial derivatives of one contact's force ([`force`]) on a body, for
/// the Jacobian.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPartials {
    /// Friction force f = mu N along the tangent [N].
    pub f: f64,
    /// dF/dx (2 x 2) of the body centre position.
    pub f_x: Matrix2<f64>,
    /// dF/dv (2 x 2) of the body centre velocity.
    pub f_v: Matrix2<f64>,
    /// df/dx and df/dv of the friction force alone (the pulley's torque -r f).
    pub fric_x: RowVector2<f64>,
    /// See `fric_x`.
    pub fric_v: RowVector2<f64>,
    /// df/dz: the friction force's slope in the creep displacement.
    pub fric_z: f64,
    /// df/d(omega_p): its slope in the pulley speed (through v_T = omega r_c - ...).
    pub fric_w: f64,
    /// dv_T/dx and dv_T/dv (the creep rate's slopes).
    pub vt_x: RowVector2<f64>,
    /// See `vt_x`.
    pub vt_v: RowVector2<f64>,
}

/// Partial derivatives of the contact force `F = N n + mu N t` of a body
/// at `k` ([`kinematics`]) with velocity `v`, given the normal force and
/// its partials `(N, dN/dp, dN/dp')` ([`ContactLaw::normal_force_jac`]) and
/// the friction coefficient with its partials `(mu, dmu/dv_T, dmu/dz)`
/// (the friction law's `coefficient_jac`), on a pulley whose friction has
/// the lever `lever` (the surface speed is omega times it).
/// With dn/dx = t t^T / dist and dt/dx = -n t^T / dist.
#[inline(always)]
pub fn force_partials(
    k: &ContactKin,
    v: [f64; 2],
    normal: (f64, f64, f64),
    mu: (f64, f64, f64),
    lever: f64,
) -> ContactPartials {
    let (n_force, dn_dp, dn_dpd) = normal;
    let (mu, dmu_dv, dmu_dz) = mu;
    let v = Vector2::from(v);
    let nrm = Vector2::from(k.n);
    let tau = Vector2::from(k.t);
    let inv = k.inv_dist;
    let f = mu * n_force;
    // gradients of p, p_dot, v_T with respect to x and v
    let dpd_dx = -(v.dot(&tau) * inv) * tau.transpose();
    let vt_x = (v.dot(&nrm) * inv) * tau.transpose();
    let vt_v = -tau.transpose();
    let dn_dx = -dn_dp * nrm.transpose() + dn_dpd * dpd_dx;
    let dn_dv = -dn_dpd * nrm.transpose();
    let fric_x = mu * dn_dx + n_force * dmu_dv * vt_x;
    let fric_v = mu * dn_dv + n_force * dmu_dv * vt_v;
    let f_x = mm(&nrm, &dn_dx) + mm(&((n_force * inv) * tau), &tau.transpose()) + mm(&tau, &fric_x)
        - mm(&((f * inv) * nrm), &tau.transpose());
    let f_v = mm(&nrm, &dn_dv) + mm(&tau, &fric_v);
    ContactPartials {
        f,
        f_x,
        f_v,
        fric_x,
        fric_v,
        fric_z: n_force * dmu_dz,
        fric_w: n_force * dmu_dv * lever,
        vt_x,
        vt_v,
    }
}

mod segment;
pub use segment::*;

#[cfg(test)]
mod tests;
