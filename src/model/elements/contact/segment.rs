//! The contact along a straight body (`contact.points`, docs/model.md,
//! "Contact along the body"): the quadrature of the penalty law per unit
//! length, the points' contact radii and friction levers, one point's law
//! ([`point`]) and the body's sums and partials ([`segment`]).

use super::{
    chordal_lever, dissipation, force, force_partials, kinematics, ContactKin, ContactLaw,
};
use crate::model::elements::friction::Law;
use crate::model::matmul::mm;
use nalgebra::{Matrix2x3, RowVector2, RowVector3, Vector2};

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
/// (`model/layout/bodies.rs`).
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

/// Where the point at `xi` l/2 along a body lies relative to the pulley
/// centre: r + xi h, `r` the body centre's position relative to it and
/// `h` = l/2 (cos phi, sin phi). [`point`]'s geometry, and with
/// [`super::penetration`] the point's penetration wherever it is needed.
#[inline(always)]
pub fn point_position(r: [f64; 2], xi: f64, h: [f64; 2]) -> [f64; 2] {
    [r[0] + xi * h[0], r[1] + xi * h[1]]
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
    let rg = point_position(body.r, xi, body.h);
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
/// The tests' reference for [`segment_of`] and the right-hand side's lanes.
#[cfg_attr(not(test), allow(dead_code))]
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
            let fq = mm(&cp.f_x, &jr) + mm(&cp.f_v, &jv);
            let fu = mm(&cp.f_v, &jr);
            let tau = Vector2::from(kin.t);
            let paf = RowVector2::new(pa[0], pa[1]);
            d.force_q += fq;
            d.force_u += fu;
            d.force_z += cp.fric_z * tau;
            d.force_w += cp.fric_w * tau;
            // M = perp(a) . F, d perp(a) / dphi = -a
            d.moment_q += mm(&paf, &fq);
            d.moment_q[2] -= a[0] * force[0] + a[1] * force[1];
            d.moment_u += mm(&paf, &fu);
            d.moment_z += cp.fric_z * paf.dot(&tau.transpose());
            d.moment_w += cp.fric_w * paf.dot(&tau.transpose());
            d.torque_q += lever * (mm(&cp.fric_x, &jr) + mm(&cp.fric_v, &jv));
            d.torque_u += lever * mm(&cp.fric_v, &jr);
            d.torque_z += lever * cp.fric_z;
            d.torque_w += lever * cp.fric_w;
            let dp_dr = -RowVector2::from(kin.n);
            pe_q[g] = (2.0 * lw.c1 * kin.p + lw.c2) * mm(&dp_dr, &jr);
            pv_q[g] = mm(&cp.vt_x, &jr) + mm(&cp.vt_v, &jv);
            pv_u[g] = mm(&cp.vt_v, &jr);
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
