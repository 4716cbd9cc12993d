//! Belt-pulley penalty contact, eq. 4-11 of section 2.2, and the contact
//! force with its friction part (eq. 19) and partial derivatives. The
//! geometry of a body centre against a pulley circle ([`kinematics`]), the
//! normal force law ([`ContactLaw`]) and the force with its partials
//! ([`force_partials`]) live here and nowhere else.

use super::friction::Law;
use nalgebra::{Matrix2, Matrix2x3, RowVector2, RowVector3, Vector2};

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

/// [`ContactKin`] of a body at `r` from the centre of a pulley of `radius`
/// whose surface moves at `surface` (= omega times the friction lever),
/// body velocity `v`.
#[inline(always)]
pub fn kinematics(r: [f64; 2], v: [f64; 2], radius: f64, surface: f64) -> ContactKin {
    let [rx, ry] = r;
    let [vx, vy] = v;
    let d2 = rx * rx + ry * ry;
    let dist = d2.sqrt();
    let inv_dist = 1.0 / dist.max(1e-12);
    let (nx, ny) = (rx * inv_dist, ry * inv_dist);
    let p = radius - dist;
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

/// Power dissipated by one contact: the normal damper (the normal force
/// beyond its elastic part `elastic` times the penetration rate) plus
/// friction (f v_T).
#[inline(always)]
pub fn dissipation(k: &ContactKin, normal: f64, elastic: f64, f: f64) -> f64 {
    (normal - elastic) * k.p_dot + f * k.v_t
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
    let f_x = nrm * dn_dx + (n_force * inv) * tau * tau.transpose() + tau * fric_x
        - (f * inv) * nrm * tau.transpose();
    let f_v = nrm * dn_dv + tau * fric_v;
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

/// Most contact points along a body (`contact.points`).
pub const MAX_POINTS: usize = 5;

/// The quadrature of the penalty law per unit length along a straight body
/// (`contact.points`): `(xi, w)` per point, the point at xi l/2 from the
/// body centre along the body, carrying the share w of the body's c1, c2
/// and b (the shares add up to 1). 1: the body centre, the paper's contact
/// (eq. 4-8); 2..=5: Gauss-Legendre on [-1, 1], weights halved (docs/model.md,
/// "Contact along the body"). `points` outside 1..=5 is a programming error
/// (the parameter's declared range).
pub fn quadrature(points: usize) -> &'static [(f64, f64)] {
    const G1: [(f64, f64); 1] = [(0.0, 1.0)];
    const A2: f64 = 0.577_350_269_189_625_8;
    const G2: [(f64, f64); 2] = [(-A2, 0.5), (A2, 0.5)];
    const A3: f64 = 0.774_596_669_241_483_4;
    const G3: [(f64, f64); 3] = [(-A3, 5.0 / 18.0), (0.0, 8.0 / 18.0), (A3, 5.0 / 18.0)];
    const A4: f64 = 0.339_981_043_584_856_3;
    const B4: f64 = 0.861_136_311_594_052_6;
    const WA4: f64 = 0.5 * 0.652_145_154_862_546_1;
    const WB4: f64 = 0.5 * 0.347_854_845_137_453_9;
    const G4: [(f64, f64); 4] = [(-B4, WB4), (-A4, WA4), (A4, WA4), (B4, WB4)];
    const A5: f64 = 0.538_469_310_105_683_1;
    const B5: f64 = 0.906_179_845_938_664;
    const W05: f64 = 0.5 * 0.568_888_888_888_888_9;
    const WA5: f64 = 0.5 * 0.478_628_670_499_366_5;
    const WB5: f64 = 0.5 * 0.236_926_885_056_189_1;
    const G5: [(f64, f64); 5] = [(-B5, WB5), (-A5, WA5), (0.0, W05), (A5, WA5), (B5, WB5)];
    match points {
        1 => &G1,
        2 => &G2,
        3 => &G3,
        4 => &G4,
        5 => &G5,
        _ => panic!("{points} contact points outside 1..={MAX_POINTS}"),
    }
}

/// Friction levers of the contact points of a pulley of `radius` whose
/// chain rests at the centre penetration `penetration`, bodies of length
/// `body_length` (docs/model.md, "Contact along the body"): the centre's
/// lever r_c = [`chordal_lever`] times sqrt(1 + s^2 / rho^2) for the point
/// at s = xi l/2, rho = r - p0. A body of a chain in stick turns about the
/// pulley axis with the angular speed omega r_c / rho, so the point at s,
/// at sqrt(rho^2 + s^2) from the axis, moves at omega r_c sqrt(1 + s^2 /
/// rho^2) along its own tangent: with these surface speeds no point of a
/// chain in stick slides, and the span still runs at omega r.
pub fn point_levers(
    radius: f64,
    penetration: f64,
    body_length: f64,
    points: usize,
) -> [f64; MAX_POINTS] {
    let lever = chordal_lever(radius, penetration, body_length);
    let rho = radius - penetration;
    let mut out = [0.0; MAX_POINTS];
    for (o, &(xi, _)) in out.iter_mut().zip(quadrature(points)) {
        let s = xi * 0.5 * body_length / rho;
        *o = if points == 1 {
            lever
        } else {
            lever * (1.0 + s * s).sqrt()
        };
    }
    out
}

/// Contact radii of the points of a body of length `body_length` on a
/// pulley of `radius` (docs/model.md, "Contact along the body"):
/// sqrt(r^2 + s^2) for the point at s = xi l/2, the distance from the axis
/// at which that point lies when the body touches the pulley circle at its
/// centre. A point's penetration is measured against its own circle, so a
/// body resting tangent to the pulley presses on it along its whole length
/// (as the belt it stands for, which is curved there), not only near its
/// centre; a body that lands tilted touches first with its leading end.
/// With one point: r.
pub fn point_radii(radius: f64, body_length: f64, points: usize) -> [f64; MAX_POINTS] {
    let mut out = [0.0; MAX_POINTS];
    for (o, &(xi, _)) in out.iter_mut().zip(quadrature(points)) {
        let s = xi * 0.5 * body_length;
        *o = if xi == 0.0 { radius } else { radius.hypot(s) };
    }
    out
}

/// Radial resultant of the elastic normal forces on a straight body (law
/// `law`, half length `hl`) lying tangent to the circle rho = r - p at its
/// centre, the centre at penetration `p` in a pulley of `radius`, with the
/// contact at `points` ([`quadrature`], [`point_radii`]): the point at
/// s = xi hl lies at d = sqrt(rho^2 + s^2) from the axis and pushes along
/// its own normal, rho / d of it radially. The mounting's static balance
/// (layout.rs).
pub fn resting_force(law: &ContactLaw, radius: f64, p: f64, hl: f64, points: usize) -> f64 {
    let rho = radius - p;
    let radii = point_radii(radius, 2.0 * hl, points);
    quadrature(points)
        .iter()
        .zip(radii)
        .map(|(&(xi, w), rg)| {
            let s = xi * hl;
            let d = if xi == 0.0 {
                rho
            } else {
                (rho * rho + s * s).sqrt()
            };
            let pg = rg - d;
            if pg > 0.0 {
                w * law.elastic_force(pg) * rho / d
            } else {
                0.0
            }
        })
        .sum()
}

/// A pulley as one contact along a body sees it: the points' contact radii
/// ([`point_radii`]), its speed, the friction levers of the points
/// ([`point_levers`]), the friction coefficients (the body's zone factor
/// applied) and the damping ramp.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PulleySide<'a> {
    /// Contact radius of each point [m].
    pub radii: &'a [f64],
    /// Pulley speed [rad/s].
    pub omega: f64,
    /// Friction lever of each point [m].
    pub levers: &'a [f64],
    /// Static friction coefficient.
    pub mu_s: f64,
    /// Kinetic friction coefficient.
    pub mu_k: f64,
    /// Inverse length of the damping ramp [1/m].
    pub inv_p_max: f64,
}

/// A straight body as its contact sees it: centre `r` and velocity `v`
/// relative to the pulley centre, half vector `h` = l/2 (cos phi, sin phi),
/// spin `w`, creep displacement `z`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodySide {
    /// Centre relative to the pulley centre [m].
    pub r: [f64; 2],
    /// Velocity relative to the pulley centre [m/s].
    pub v: [f64; 2],
    /// Half vector l/2 (cos phi, sin phi) [m].
    pub h: [f64; 2],
    /// Spin [rad/s].
    pub w: f64,
    /// Creep displacement [m].
    pub z: f64,
}

/// The contact of one body with one pulley, integrated along the body
/// ([`segment`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Segment {
    /// Contact force on the body [N].
    pub force: [f64; 2],
    /// Its moment about the body centre [N m].
    pub moment: f64,
    /// Moment of the friction about the pulley axis, sum of lever f [N m]
    /// (the pulley gets minus it, eq. 24).
    pub torque: f64,
    /// Creep rate dz/dt [m/s].
    pub creep_rate: f64,
    /// Power dissipated: normal dampers and friction [W].
    pub dissipation: f64,
    /// Sum of the normal forces [N].
    pub normal: f64,
    /// Sum of the friction forces along the tangents [N].
    pub friction: f64,
    /// Sum of the elastic normal forces [N].
    pub elastic: f64,
    /// Its rate [N/s].
    pub elastic_rate: f64,
    /// The body's sliding velocity v_T: the points' mean weighted by their
    /// elastic normal forces [m/s].
    pub v_t: f64,
    /// Largest penetration of a point [m].
    pub penetration: f64,
    /// Friction power less the normal-force-weighted creep power,
    /// sum N (mu v_T - mu(0, z) dz/dt) (the friction's share of the belt
    /// loss, before the clip at 0; see `Law::slip_loss`).
    pub slip_power: f64,
}

/// Partial derivatives of a [`Segment`] with respect to the body's
/// position q = (x, y, phi), velocity u = (vx, vy, omega), creep z and the
/// pulley speed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SegmentPartials {
    /// Of the force, by q.
    pub force_q: Matrix2x3<f64>,
    /// Of the force, by u.
    pub force_u: Matrix2x3<f64>,
    /// Of the force, by z.
    pub force_z: Vector2<f64>,
    /// Of the force, by the pulley speed.
    pub force_w: Vector2<f64>,
    /// Of the moment, by q.
    pub moment_q: RowVector3<f64>,
    /// Of the moment, by u.
    pub moment_u: RowVector3<f64>,
    /// Of the moment, by z.
    pub moment_z: f64,
    /// Of the moment, by the pulley speed.
    pub moment_w: f64,
    /// Of the torque on the pulley, by q.
    pub torque_q: RowVector3<f64>,
    /// Of the torque on the pulley, by u.
    pub torque_u: RowVector3<f64>,
    /// Of the torque on the pulley, by z.
    pub torque_z: f64,
    /// Of the torque on the pulley, by the pulley speed.
    pub torque_w: f64,
    /// Of the creep rate (zero while it is held at the cap), by q.
    pub creep_q: RowVector3<f64>,
    /// Of the creep rate, by u.
    pub creep_u: RowVector3<f64>,
    /// Of the creep rate, by the pulley speed.
    pub creep_w: f64,
}

impl ContactLaw {
    /// The share `w` of the law ([`quadrature`]'s weight of a point): c1,
    /// c2 and b times w.
    #[inline(always)]
    pub fn share(&self, w: f64) -> Self {
        Self {
            c1: self.c1 * w,
            c2: self.c2 * w,
            b: self.b * w,
        }
    }
}

/// One contact point of a body ([`point`]): its offset `a` = xi h from the
/// body centre and `pa` = a turned by +90 degrees, its velocity `vg`, its
/// [`ContactKin`] against its own contact circle, and its normal force
/// (with the elastic part and its rate), friction force `f` = mu N and
/// force on the body, the force's moment about the body centre and the
/// power the point dissipates. Meaningful where `kin.p` > 0 (the point
/// inside its circle); computed, not branched, elsewhere, so that a loop
/// over the bodies vectorises.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointContact {
    /// Offset xi h from the body centre [m].
    pub a: [f64; 2],
    /// `a` turned by +90 degrees [m].
    pub pa: [f64; 2],
    /// Velocity of the point [m/s].
    pub vg: [f64; 2],
    /// Geometry against the point's contact circle.
    pub kin: ContactKin,
    /// Normal force [N].
    pub normal: f64,
    /// Its elastic part [N].
    pub elastic: f64,
    /// The elastic part's rate [N/s].
    pub elastic_rate: f64,
    /// Friction force mu N along the tangent [N].
    pub f: f64,
    /// Contact force on the body [N].
    pub force: [f64; 2],
    /// Its moment about the body centre [N m].
    pub moment: f64,
    /// Power the point dissipates [W].
    pub dissipation: f64,
}

/// The law of [`segment`] at one point of a body: the point at `xi` l/2
/// along the body (`body.h` = l/2 (cos phi, sin phi)) with its share `lw`
/// of the penalty law ([`ContactLaw::share`]), its contact circle `radius`
/// ([`point_radii`]) and friction lever `lever` ([`point_levers`]): its
/// penetration, rate and sliding velocity from the body's rigid motion
/// (v + omega x a), the normal force (eq. 9-11), the friction force
/// mu(v_T, z) N with the body's one creep z (eq. 19) and the force's
/// moment about the body centre. Branch-free (see [`PointContact`]): the
/// scalar [`segment`] and the right-hand side's loop over lanes of bodies
/// both evaluate the contact along the body through it.
#[inline(always)]
pub fn point(
    lw: &ContactLaw,
    fr: &impl Law,
    xi: f64,
    radius: f64,
    lever: f64,
    pulley: &PulleySide,
    body: &BodySide,
) -> PointContact {
    let [hx, hy] = body.h;
    let a = [xi * hx, xi * hy];
    let pa = [-a[1], a[0]];
    let rg = [body.r[0] + a[0], body.r[1] + a[1]];
    let vg = [body.v[0] + body.w * pa[0], body.v[1] + body.w * pa[1]];
    let kin = kinematics(rg, vg, radius, pulley.omega * lever);
    let (normal, elastic) = lw.normal_force(kin.p, kin.p_dot, pulley.inv_p_max);
    let mu = fr.coefficient(kin.v_t, body.z, pulley.mu_s, pulley.mu_k);
    let f = mu * normal; // eq. 19
    let force = force(&kin, normal, f);
    PointContact {
        a,
        pa,
        vg,
        kin,
        normal,
        elastic,
        elastic_rate: lw.elastic_rate(kin.p, kin.p_dot),
        f,
        force,
        moment: pa[0] * force[0] + pa[1] * force[1],
        dissipation: dissipation(&kin, normal, elastic, f),
    }
}

/// A body's sliding velocity from its points inside the circle: the mean
/// of their v_T weighted by their elastic normal forces, `sev / se` (sums
/// of N_e v_T and N_e), or the plain mean `sv / count` if they carry none
/// (`count` of them, at least one). Branch-free.
#[inline(always)]
pub fn body_sliding_velocity(se: f64, sev: f64, count: f64, sv: f64) -> f64 {
    if se > 0.0 {
        sev / se
    } else {
        sv / count.max(1.0)
    }
}

/// The contact of a straight body with a pulley, the penalty law per unit
/// length integrated at the points of [`quadrature`] (eq. 9-19 at each
/// point): each point has its own penetration, penetration rate and
/// sliding velocity from the body's rigid motion, a share w of the body's
/// law (`law`, the constants already times l), and the friction force
/// mu(v_T, z) N of its own sliding velocity and the body's one creep z;
/// the forces act at the points (a moment about the body centre). The
/// creep rate is that of the body's sliding velocity, the points' mean
/// weighted by their elastic normal forces. `None` if no point is inside
/// the circle. With `partials` the derivatives too (for the Jacobian).
/// `points` in 1..=5 ([`quadrature`]); [`segment_of`] with the count fixed.
pub fn segment(
    law: &ContactLaw,
    fr: &impl Law,
    points: usize,
    pulley: &PulleySide,
    body: &BodySide,
    partials: bool,
) -> Option<(Segment, SegmentPartials)> {
    match points {
        1 => segment_of::<1>(law, fr, pulley, body, partials),
        2 => segment_of::<2>(law, fr, pulley, body, partials),
        3 => segment_of::<3>(law, fr, pulley, body, partials),
        4 => segment_of::<4>(law, fr, pulley, body, partials),
        5 => segment_of::<5>(law, fr, pulley, body, partials),
        _ => panic!("{points} contact points outside 1..={MAX_POINTS}"),
    }
}

/// [`segment`] with K points, unrolled: the Jacobian inlines it into its
/// build per friction law, point count and instruction set.
#[inline(always)]
pub fn segment_of<const K: usize>(
    law: &ContactLaw,
    fr: &impl Law,
    pulley: &PulleySide,
    body: &BodySide,
    partials: bool,
) -> Option<(Segment, SegmentPartials)> {
    let quad: [(f64, f64); K] = quadrature(K).try_into().expect("K points");
    let levers: [f64; K] = pulley.levers[..K].try_into().expect("K levers");
    let radii: [f64; K] = pulley.radii[..K].try_into().expect("K radii");
    let mut s = Segment {
        penetration: f64::MIN,
        ..Segment::default()
    };
    let mut d = SegmentPartials::default();
    // per point: elastic force, sliding velocity and their partials, for
    // the weighted mean
    let mut pe = [0.0; K];
    let mut pv = [0.0; K];
    let mut pe_q = [RowVector3::zeros(); K];
    let mut pv_q = [RowVector3::zeros(); K];
    let mut pv_u = [RowVector3::zeros(); K];
    let mut pv_w = [0.0; K];
    let mut inside = [false; K];
    let mut any = false;
    for g in 0..K {
        let ((xi, wg), lever, radius) = (quad[g], levers[g], radii[g]);
        let lw = law.share(wg);
        let pt = point(&lw, fr, xi, radius, lever, pulley, body);
        let PointContact {
            a,
            pa,
            vg,
            kin,
            normal,
            elastic,
            f,
            force,
            ..
        } = pt;
        s.penetration = s.penetration.max(kin.p);
        if kin.p <= 0.0 {
            continue;
        }
        any = true;
        inside[g] = true;
        s.force[0] += force[0];
        s.force[1] += force[1];
        s.moment += pt.moment;
        s.torque += lever * f;
        s.dissipation += pt.dissipation;
        s.normal += normal;
        s.friction += f;
        s.elastic += elastic;
        s.elastic_rate += pt.elastic_rate;
        s.slip_power += f * kin.v_t; // less sum N mu(0, z) dz/dt below
        pe[g] = elastic;
        pv[g] = kin.v_t;
        if partials {
            let nj = lw.normal_force_jac(kin.p, kin.p_dot, pulley.inv_p_max);
            let mj = fr.coefficient_jac(kin.v_t, body.z, pulley.mu_s, pulley.mu_k);
            let cp = force_partials(&kin, vg, nj, mj, lever);
            // d r_g / dq = [I | perp(a)], d v_g / dq = [0 | -w a],
            // d v_g / du = [I | perp(a)]
            let jr = Matrix2x3::new(1.0, 0.0, pa[0], 0.0, 1.0, pa[1]);
            let jv = Matrix2x3::new(0.0, 0.0, -body.w * a[0], 0.0, 0.0, -body.w * a[1]);
            let fq = cp.f_x * jr + cp.f_v * jv;
            let fu = cp.f_v * jr;
            let tau = Vector2::from(kin.t);
            let paf = RowVector2::new(pa[0], pa[1]);
            d.force_q += fq;
            d.force_u += fu;
            d.force_z += cp.fric_z * tau;
            d.force_w += cp.fric_w * tau;
            // M = perp(a) . F, d perp(a) / dphi = -a
            d.moment_q += paf * fq;
            d.moment_q[2] -= a[0] * force[0] + a[1] * force[1];
            d.moment_u += paf * fu;
            d.moment_z += cp.fric_z * paf.dot(&tau.transpose());
            d.moment_w += cp.fric_w * paf.dot(&tau.transpose());
            d.torque_q += lever * (cp.fric_x * jr + cp.fric_v * jv);
            d.torque_u += lever * (cp.fric_v * jr);
            d.torque_z += lever * cp.fric_z;
            d.torque_w += lever * cp.fric_w;
            let dp_dr = -RowVector2::from(kin.n);
            pe_q[g] = (2.0 * lw.c1 * kin.p + lw.c2) * (dp_dr * jr);
            pv_q[g] = cp.vt_x * jr + cp.vt_v * jv;
            pv_u[g] = cp.vt_v * jr;
            pv_w[g] = lever;
        }
    }
    if !any {
        return None;
    }
    // the body's sliding velocity: the elastic-force-weighted mean (the
    // plain mean of the points inside if they carry no elastic force)
    let (mut se, mut sev, mut count, mut sv) = (0.0, 0.0, 0.0, 0.0);
    for g in 0..K {
        if inside[g] {
            se += pe[g];
            sev += pe[g] * pv[g];
            count += 1.0;
            sv += pv[g];
        }
    }
    let weighted = se > 0.0;
    s.v_t = body_sliding_velocity(se, sev, count, sv);
    s.creep_rate = fr.creep_rate(s.v_t, body.z);
    let mu0 = fr.coefficient(0.0, body.z, pulley.mu_s, pulley.mu_k);
    s.slip_power -= s.normal * mu0 * s.creep_rate;
    if partials && fr.creep_rate_slope(s.v_t, body.z) != 0.0 {
        for g in 0..K {
            if !inside[g] {
                continue;
            }
            if weighted {
                let k = 1.0 / se;
                d.creep_q += k * ((pv[g] - s.v_t) * pe_q[g] + pe[g] * pv_q[g]);
                d.creep_u += (k * pe[g]) * pv_u[g];
                d.creep_w += k * pe[g] * pv_w[g];
            } else {
                let k = 1.0 / count;
                d.creep_q += k * pv_q[g];
                d.creep_u += k * pv_u[g];
                d.creep_w += k * pv_w[g];
            }
        }
    }
    Some((s, d))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::elements::friction::{Friction, Law};
    use crate::model::params::FrictionLaw;

    /// 1 / p_max of the tests: a 0.1 mm ramp, so that the test points lie
    /// on it and beyond it.
    const INV_P_MAX: f64 = 1e4;

    /// The contact force of a body at (x, v, z) on a pulley turning at w,
    /// evaluated as the right-hand side does, and its friction force.
    fn contact(
        law: &ContactLaw,
        fr: &Friction,
        x: [f64; 2],
        v: [f64; 2],
        z: f64,
        w: f64,
    ) -> ([f64; 2], f64) {
        let (radius, lever) = (0.05, 0.0497);
        let k = kinematics(x, v, radius, w * lever);
        let (normal, _) = law.normal_force(k.p, k.p_dot, INV_P_MAX);
        let f = fr.coefficient(k.v_t, z, 1.05, 0.9) * normal;
        (force(&k, normal, f), f)
    }

    /// [`force_partials`] against central differences of [`force`] through
    /// [`kinematics`], [`ContactLaw::normal_force`] and both friction laws,
    /// in slip and in stick. Steps of 1e-9 m (penetrations are ~1e-5 m:
    /// truncation ~(1e-4)^2 relative), 1e-7 m/s and 1e-7 rad/s for the speeds
    /// (v_T's scale dv = 1e-3: ~1e-8 relative); 1e-5 relative of the entry's
    /// row scale covers truncation and rounding (~1e-16 N / 1e-9 m against
    /// slopes of ~1e6 N/m).
    #[test]
    fn force_partials_match_differences() {
        let law = ContactLaw {
            c1: 3.0e9 * 0.01,
            c2: 6.5e5 * 0.01,
            b: 300.0 * 0.01,
        };
        for fl in [FrictionLaw::Kubas2014, FrictionLaw::Creep] {
            let fr = Friction::new(fl, 1e-3, 1e-4, 2e-4);
            // (x, v, z, w): slip, stick, near the cap
            for &(x, v, z, w) in &[
                ([0.03, 0.0399], [-1.2, 0.9], 2e-5, 30.01),
                ([-0.0248, 0.0433], [-0.86676, -0.4999], -4e-5, 19.99),
                ([0.049_99, 0.0001], [0.01, 1.0], 1.2e-4, 20.1),
            ] {
                let (radius, lever) = (0.05, 0.0497);
                let k = kinematics(x, v, radius, w * lever);
                assert!(k.p > 0.0);
                let nj = law.normal_force_jac(k.p, k.p_dot, INV_P_MAX);
                let mj = fr.coefficient_jac(k.v_t, z, 1.05, 0.9);
                let cp = force_partials(&k, v, nj, mj, lever);
                assert_eq!(cp.f, contact(&law, &fr, x, v, z, w).1);
                let check = |m: &[[f64; 2]; 2], fd: &dyn Fn(usize, usize) -> f64, what: &str| {
                    for (r, row) in m.iter().enumerate() {
                        let scale = row[0].abs().max(row[1].abs()).max(1e-3);
                        for (c, &entry) in row.iter().enumerate() {
                            let d = fd(r, c);
                            assert!(
                                (entry - d).abs() <= 1e-5 * scale,
                                "{fl:?} {what}[{r}{c}]: {entry} vs {d}"
                            );
                        }
                    }
                };
                let (hx, hv) = (1e-9, 1e-7);
                let dx = |r: usize, c: usize| {
                    let (mut a, mut b) = (x, x);
                    a[c] += hx;
                    b[c] -= hx;
                    (contact(&law, &fr, a, v, z, w).0[r] - contact(&law, &fr, b, v, z, w).0[r])
                        / (2.0 * hx)
                };
                let dv = |r: usize, c: usize| {
                    let (mut a, mut b) = (v, v);
                    a[c] += hv;
                    b[c] -= hv;
                    (contact(&law, &fr, x, a, z, w).0[r] - contact(&law, &fr, x, b, z, w).0[r])
                        / (2.0 * hv)
                };
                let m = |m: &Matrix2<f64>| [[m[(0, 0)], m[(0, 1)]], [m[(1, 0)], m[(1, 1)]]];
                check(&m(&cp.f_x), &dx, "F_x");
                check(&m(&cp.f_v), &dv, "F_v");
                // friction force in z and in the pulley speed
                let (hz, hw) = (1e-10, 1e-7);
                let fz = (contact(&law, &fr, x, v, z + hz, w).1
                    - contact(&law, &fr, x, v, z - hz, w).1)
                    / (2.0 * hz);
                let fw = (contact(&law, &fr, x, v, z, w + hw).1
                    - contact(&law, &fr, x, v, z, w - hw).1)
                    / (2.0 * hw);
                assert!(
                    (cp.fric_z - fz).abs() <= 1e-5 * fz.abs().max(1.0),
                    "{fl:?} {} {fz}",
                    cp.fric_z
                );
                assert!(
                    (cp.fric_w - fw).abs() <= 1e-5 * fw.abs().max(1e-3),
                    "{fl:?} {} {fw}",
                    cp.fric_w
                );
                // friction force alone in x and v (the pulley torque's slopes)
                for c in 0..2 {
                    let (mut a, mut b) = (x, x);
                    a[c] += hx;
                    b[c] -= hx;
                    let fx = (contact(&law, &fr, a, v, z, w).1 - contact(&law, &fr, b, v, z, w).1)
                        / (2.0 * hx);
                    let (mut a, mut b) = (v, v);
                    a[c] += hv;
                    b[c] -= hv;
                    let fv = (contact(&law, &fr, x, a, z, w).1 - contact(&law, &fr, x, b, z, w).1)
                        / (2.0 * hv);
                    let s = cp.fric_x.abs().max().max(1e-3);
                    assert!(
                        (cp.fric_x[c] - fx).abs() <= 1e-5 * s,
                        "{fl:?} {} {fx}",
                        cp.fric_x[c]
                    );
                    let s = cp.fric_v.abs().max().max(1e-3);
                    assert!(
                        (cp.fric_v[c] - fv).abs() <= 1e-5 * s,
                        "{fl:?} {} {fv}",
                        cp.fric_v[c]
                    );
                }
            }
        }
    }

    /// [`segment`]'s partials against central differences of its values,
    /// for 1, 3 and 5 points, both friction laws, a body landing with its
    /// leading end (some points outside) and one resting across the wrap,
    /// in slip and near stick. State x = (x, y, phi, vx, vy, omega, z,
    /// pulley speed); steps as in `force_partials_match_differences` (1e-9
    /// m, 1e-9 rad on a 5 mm half length, 1e-7 m/s, 1e-7 rad/s, 1e-11 m of
    /// creep), tolerance 1e-5 of the row's scale.
    #[test]
    fn segment_partials_match_differences() {
        let law = ContactLaw {
            c1: 3.0e9 * 0.01,
            c2: 6.5e5 * 0.01,
            b: 300.0 * 0.01,
        };
        let (radius, hl, p0) = (0.05, 0.005, 1e-4);
        for fl in [FrictionLaw::Kubas2014, FrictionLaw::Creep] {
            let fr = Friction::new(fl, 1e-3, 1e-4, 2e-4);
            for points in [1, 3, 5] {
                let levers = point_levers(radius, p0, 2.0 * hl, points);
                let radii = point_radii(radius, 2.0 * hl, points);
                // (angle of the centre, tilt of the body from the tangent,
                // penetration of the centre, v, w, z, pulley speed)
                for &(ang, tilt, p, v, w, z, om) in &[
                    (0.3, 0.02, 3e-5, [-1.2, 0.9], 40.0, 2e-5, 30.01),
                    (1.1, -0.004, 1.2e-4, [-0.86, 0.5], -19.0, -4e-5, 20.0),
                    (2.0, 0.0, 8e-5, [0.3, -1.0], 5.0, 1.2e-4, -20.1),
                ] {
                    let eval = |x: &[f64; 8]| {
                        let pulley = PulleySide {
                            radii: &radii,
                            omega: x[7],
                            levers: &levers,
                            mu_s: 1.05,
                            mu_k: 0.9,
                            inv_p_max: 1e4,
                        };
                        let body = BodySide {
                            r: [x[0], x[1]],
                            v: [x[3], x[4]],
                            h: [hl * x[2].cos(), hl * x[2].sin()],
                            w: x[5],
                            z: x[6],
                        };
                        segment(&law, &fr, points, &pulley, &body, true).unwrap()
                    };
                    let rr = radius - p;
                    let phi = ang + std::f64::consts::FRAC_PI_2 + tilt;
                    let x0 = [rr * ang.cos(), rr * ang.sin(), phi, v[0], v[1], w, z, om];
                    let (s0, d) = eval(&x0);
                    let steps = [1e-9, 1e-9, 2e-7, 1e-7, 1e-7, 1e-5, 1e-11, 1e-7];
                    // rows: force x, force y, moment, torque, creep rate
                    let value =
                        |s: &Segment| [s.force[0], s.force[1], s.moment, s.torque, s.creep_rate];
                    let analytic = |c: usize| -> [f64; 5] {
                        let col = |q: &Matrix2x3<f64>,
                                   u: &Matrix2x3<f64>,
                                   zz: &Vector2<f64>,
                                   ww: &Vector2<f64>,
                                   r: usize| match c {
                            0..=2 => q[(r, c)],
                            3..=5 => u[(r, c - 3)],
                            6 => zz[r],
                            _ => ww[r],
                        };
                        let row =
                            |q: &RowVector3<f64>, u: &RowVector3<f64>, zz: f64, ww: f64| match c {
                                0..=2 => q[c],
                                3..=5 => u[c - 3],
                                6 => zz,
                                _ => ww,
                            };
                        [
                            col(&d.force_q, &d.force_u, &d.force_z, &d.force_w, 0),
                            col(&d.force_q, &d.force_u, &d.force_z, &d.force_w, 1),
                            row(&d.moment_q, &d.moment_u, d.moment_z, d.moment_w),
                            row(&d.torque_q, &d.torque_u, d.torque_z, d.torque_w),
                            row(&d.creep_q, &d.creep_u, 0.0, d.creep_w),
                        ]
                    };
                    let mut rows = [[0.0; 8]; 5];
                    let mut fds = [[0.0; 8]; 5];
                    for c in 0..8 {
                        let (mut a, mut b) = (x0, x0);
                        a[c] += steps[c];
                        b[c] -= steps[c];
                        let (va, vb) = (value(&eval(&a).0), value(&eval(&b).0));
                        let an = analytic(c);
                        for r in 0..5 {
                            fds[r][c] = (va[r] - vb[r]) / (2.0 * steps[c]);
                            rows[r][c] = an[r];
                        }
                    }
                    // the creep rate's z column: dz/dt does not depend on z
                    // off the cap
                    for r in 0..5 {
                        // scale per column group: positions, velocities, z, speed
                        for c in 0..8 {
                            let scale = rows[r]
                                .iter()
                                .zip(&fds[r])
                                .map(|(a, b)| a.abs().max(b.abs()))
                                .fold(0.0, f64::max)
                                .max(1e-9);
                            assert!(
                                (rows[r][c] - fds[r][c]).abs() <= 1e-5 * scale,
                                "{fl:?} points {points} ang {ang} row {r} col {c}: analytic {} differences {} (scale {scale})",
                                rows[r][c],
                                fds[r][c]
                            );
                        }
                    }
                    assert!(s0.normal > 0.0);
                }
            }
        }
    }

    /// One point is the paper's centre contact: [`segment`] with 1 point
    /// gives the force, creep rate and pulley moment of [`kinematics`],
    /// [`ContactLaw::normal_force`] and [`force`] at the centre, no moment;
    /// the Gauss weights add up to 1 and integrate a quadratic penalty
    /// exactly.
    #[test]
    fn segment_with_one_point_is_the_centre_contact() {
        for points in 1..=MAX_POINTS {
            let q = quadrature(points);
            let w: f64 = q.iter().map(|p| p.1).sum();
            assert!((w - 1.0).abs() < 1e-15, "{points}");
            // the integral over [-1, 1] / 2 of xi^2 is 1/3 (exact from 2 points)
            let m2: f64 = q.iter().map(|p| p.1 * p.0 * p.0).sum();
            if points > 1 {
                assert!((m2 - 1.0 / 3.0).abs() < 1e-15, "{points}");
            }
        }
        let law = ContactLaw {
            c1: 3.0e7,
            c2: 6.5e3,
            b: 3.0,
        };
        let fr = Friction::new(FrictionLaw::Creep, 1e-3, 1e-4, 2e-4);
        let levers = point_levers(0.05, 1e-4, 0.01, 1);
        assert_eq!(levers[0], chordal_lever(0.05, 1e-4, 0.01));
        let pulley = PulleySide {
            radii: &[0.05],
            omega: 20.0,
            levers: &levers,
            mu_s: 1.05,
            mu_k: 0.9,
            inv_p_max: 1e4,
        };
        let body = BodySide {
            r: [0.03, 0.0399],
            v: [-1.2, 0.9],
            h: [0.004, 0.003],
            w: 17.0,
            z: 3e-5,
        };
        let (s, _) = segment(&law, &fr, 1, &pulley, &body, false).unwrap();
        let k = kinematics(body.r, body.v, 0.05, 20.0 * levers[0]);
        let (n, _) = law.normal_force(k.p, k.p_dot, 1e4);
        let f = fr.coefficient(k.v_t, body.z, 1.05, 0.9) * n;
        assert_eq!(s.force, force(&k, n, f));
        assert_eq!(s.moment, 0.0);
        assert_eq!(s.torque, levers[0] * f);
        assert_eq!(s.creep_rate, fr.creep_rate(k.v_t, body.z));
        assert_eq!(
            s.dissipation,
            dissipation(&k, n, law.normal_force(k.p, k.p_dot, 1e4).1, f)
        );
    }

    /// A chain in stick on the wrap, every body tangent to rho = r - p0 at
    /// its centre and turning about the pulley axis with omega r_c / rho
    /// (the chain's stick speed, [`chordal_lever`]): with the points'
    /// levers ([`point_levers`]) no point of a body slides; and a body
    /// resting at its centre's penetration carries [`resting_force`].
    #[test]
    fn points_of_a_chain_in_stick_do_not_slide() {
        let law = ContactLaw {
            c1: 3.0e7,
            c2: 6.5e3,
            b: 3.0,
        };
        let fr = Friction::new(FrictionLaw::Creep, 1e-3, 1e-4, 2e-4);
        let (r, p0, l, omega) = (0.04, 2.0e-4, 0.008, 30.0);
        let rho = r - p0;
        for points in 1..=MAX_POINTS {
            let levers = point_levers(r, p0, l, points);
            let radii = point_radii(r, l, points);
            let big = omega * chordal_lever(r, p0, l) / rho;
            for ang in [0.1, 1.0, 2.5] {
                let (s, c) = f64::sin_cos(ang);
                let body = BodySide {
                    r: [rho * c, rho * s],
                    v: [-big * rho * s, big * rho * c],
                    h: [-0.5 * l * s, 0.5 * l * c],
                    w: big,
                    z: 0.0,
                };
                let pulley = PulleySide {
                    radii: &radii,
                    omega,
                    levers: &levers,
                    mu_s: 1.05,
                    mu_k: 0.9,
                    inv_p_max: 1e4,
                };
                let (seg, _) = segment(&law, &fr, points, &pulley, &body, false).unwrap();
                assert!(seg.v_t.abs() < 1e-14, "{points}: {}", seg.v_t);
                assert!(seg.friction.abs() < 1e-12, "{points}: {}", seg.friction);
                // at rest the radial force is the resting force
                let rest = BodySide {
                    v: [0.0; 2],
                    w: 0.0,
                    ..body
                };
                let still = PulleySide {
                    omega: 0.0,
                    ..pulley
                };
                let (seg, _) = segment(&law, &fr, points, &still, &rest, false).unwrap();
                let radial = seg.force[0] * c + seg.force[1] * s;
                let want = resting_force(&law, r, p0, 0.5 * l, points);
                assert!(
                    (radial - want).abs() < 1e-12 * want,
                    "{points}: {radial} {want}"
                );
                assert!(
                    seg.moment.abs() < 1e-12 * want * l,
                    "{points}: {}",
                    seg.moment
                );
            }
        }
    }

    /// A closed chain of straight bodies laid on the circle rho = r - p0,
    /// each tangent at its centre and the next one's end on its own end
    /// (zero gaps): its pitch angle is 2 atan(h), checked from the body
    /// ends; with the centres carried at omega times the lever, one body
    /// (length l of span) passes per pitch time, so the span runs at omega r
    /// to rounding; and the lever tends to r as l -> 0 (the second-order
    /// term r h^2 / 3).
    #[test]
    fn chordal_lever_runs_the_chain_at_the_radius() {
        let (r, p0, omega) = (0.027, 1.5e-4, 25.0);
        let rho = r - p0;
        for l in [0.02, 0.008, 0.002] {
            let lever = chordal_lever(r, p0, l);
            let h = l / (2.0 * rho);
            let pitch = 2.0 * h.atan();
            // end of body 0 (centre at angle 0) and start of body 1
            let end0 = [rho, 0.5 * l];
            let (s, c) = pitch.sin_cos();
            let start1 = [rho * c + 0.5 * l * s, rho * s - 0.5 * l * c];
            assert!((end0[0] - start1[0]).abs() < 1e-15 && (end0[1] - start1[1]).abs() < 1e-15);
            let v_span = l / (rho * pitch / (omega * lever));
            assert!((v_span / (omega * r) - 1.0).abs() < 1e-14, "{l}: {v_span}");
            assert!((lever / r - (1.0 - h * h / 3.0)).abs() < h.powi(4) / 5.0 + 1e-15);
        }
        assert_eq!(chordal_lever(r, p0, 0.0), r);
    }

    #[test]
    fn smoothstep_ends_and_midpoint() {
        assert_eq!(smoothstep(-1.0), 0.0);
        assert_eq!(smoothstep(0.0), 0.0);
        assert_eq!(smoothstep(0.5), 0.5);
        assert_eq!(smoothstep(1.0), 1.0);
        assert_eq!(smoothstep(3.0), 1.0);
    }

    #[test]
    fn normal_force_derivatives_match_differences() {
        let law = ContactLaw {
            c1: 3.0e9,
            c2: 6.5e5,
            b: 300.0,
        };
        let nf = |p: f64, pd: f64| law.normal_force(p, pd, INV_P_MAX).0;
        for &(p, pd) in &[(2e-5, 0.01), (5e-5, -0.02), (2e-4, 0.3), (1e-4, 0.0)] {
            let (n, dp, dpd) = law.normal_force_jac(p, pd, INV_P_MAX);
            assert_eq!(n, nf(p, pd));
            let (e1, e2) = (1e-10, 1e-7);
            let fp = (nf(p + e1, pd) - nf(p - e1, pd)) / (2.0 * e1);
            let fpd = (nf(p, pd + e2) - nf(p, pd - e2)) / (2.0 * e2);
            assert!((dp - fp).abs() <= 1e-6 * fp.abs().max(1.0), "{dp} {fp}");
            assert!(
                (dpd - fpd).abs() <= 1e-6 * fpd.abs().max(1.0),
                "{dpd} {fpd}"
            );
        }
        // clamped: no force, no slope
        assert_eq!(
            law.normal_force_jac(1e-6, -100.0, INV_P_MAX),
            (0.0, 0.0, 0.0)
        );
    }

    #[test]
    fn normal_force_is_elastic_at_rest_and_never_pulls() {
        let law = ContactLaw {
            c1: 3.0e9,
            c2: 6.5e5,
            b: 300.0,
        };
        let inv_p_max = 1e3;
        let p = 1e-4;
        let (n, e) = law.normal_force(p, 0.0, inv_p_max);
        assert_eq!(n, e);
        assert!((e - (3.0e9 * p * p + 6.5e5 * p)).abs() < 1e-9);
        // Fast separation: damping would pull; the force is clamped at 0.
        assert_eq!(law.normal_force(p, -100.0, inv_p_max).0, 0.0);
        // Energy is the integral of the elastic force (Simpson, exact for cubics).
        let (f0, fm, f1) = (0.0, law.normal_force(p / 2.0, 0.0, inv_p_max).1, e);
        assert!((law.energy(p) - p / 6.0 * (f0 + 4.0 * fm + f1)).abs() < 1e-15);
        // the tangent stiffness is the elastic force's slope (central
        // difference, exact for a quadratic up to rounding), and the
        // penetration that carries a force inverts it, with and without
        // the quadratic term
        let h = 1e-7;
        let slope = (law.elastic_force(p + h) - law.elastic_force(p - h)) / (2.0 * h);
        assert!((law.stiffness(p) - slope).abs() < 1e-6 * slope, "{slope}");
        for law in [law, ContactLaw { c1: 0.0, ..law }] {
            for q in [1e-6, 1e-4, 3e-3] {
                let back = law.penetration_for(law.elastic_force(q));
                assert!((back - q).abs() < 1e-12 * q, "{q} {back}");
            }
            assert_eq!(law.penetration_for(0.0), 0.0);
            assert_eq!(law.penetration_for(-1.0), 0.0);
        }
    }
}
