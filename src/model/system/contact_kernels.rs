//! The contact kernels of the right-hand side: contact and friction
//! (eq. 4-19) of a run of bodies with one pulley, at the body centre
//! ([`contact_arc`]) or at points along the body ([`contact_along_arc`]),
//! written over columns so that the loop over the bodies vectorises.

use super::{BeltSystem, PulleyConst};
use crate::model::elements::contact::{self, ContactLaw};
use crate::model::elements::friction::Law;

/// Contact and friction (eq. 4-19) of a run of bodies with pulley `pc`
/// (surface speed `surface`, friction law `friction`).
/// `body` holds the columns x, y, vx, vy, z and friction zone factor of the
/// run (the first `valid` bodies, then padding that is ignored); the
/// contact forces and creep rates are added to `ofx`, `ofy`, `dz`, the
/// moments r f about the pulley axis and the dissipated powers stored in
/// `torque`, `diss`, and, if given, the recorded values in `rec`. Bodies
/// outside the circle (between two contacts of the run) add nothing.
/// Separate slices of one length: the loop has no aliasing and no bounds
/// checks and vectorises.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn contact_arc<const ENERGY: bool>(
    sys: &BeltSystem,
    pc: &PulleyConst,
    centre: &[f64; 4],
    surface: f64,
    friction: &impl Law,
    valid: usize,
    body: [&[f64]; 6],
    ofx: &mut [f64],
    ofy: &mut [f64],
    dz: &mut [f64],
    torque: &mut [f64],
    diss: &mut [f64],
    energy: [&mut [f64]; 2],
    mut rec: Option<&mut [[f64; 9]]>,
) {
    let k = ofx.len();
    let [en, cr] = energy;
    let (en, cr) = (&mut en[..k], &mut cr[..k]);
    let [xs, ys, vxs, vys, zs, zfs] = body;
    let (xs, ys, vxs, vys, zs, zfs) = (
        &xs[..k],
        &ys[..k],
        &vxs[..k],
        &vys[..k],
        &zs[..k],
        &zfs[..k],
    );
    let (ofy, dz, torque, diss) = (
        &mut ofy[..k],
        &mut dz[..k],
        &mut torque[..k],
        &mut diss[..k],
    );
    // constants in locals: the compiler need not prove that the stores
    // below leave them alone
    let PulleyConst {
        radius,
        radius2,
        lever,
        mu_s,
        mu_k,
        inv_p_max,
        ..
    } = *pc;
    // the centre and its velocity: the contact sees the body's motion
    // relative to it (a tensioner's pulley moves with its arm)
    let [cx, cy, cvx, cvy] = *centre;
    let law = sys.contact;
    for i in 0..k {
        let z = zs[i];
        let kin = contact::kinematics(
            [xs[i] - cx, ys[i] - cy],
            [vxs[i] - cvx, vys[i] - cvy],
            radius,
            surface,
        );
        let (normal, elastic) = law.normal_force(kin.p, kin.p_dot, inv_p_max);
        let zf = zfs[i];
        let f = friction.coefficient(kin.v_t, z, mu_s * zf, mu_k * zf) * normal; // eq. 19, along +tau
        let [fx, fy] = contact::force(&kin, normal, f);
        let inside = (kin.d2 < radius2) & (i < valid);
        let keep = |v: f64| if inside { v } else { 0.0 };
        ofx[i] = keep(fx);
        ofy[i] = keep(fy);
        dz[i] = keep(friction.creep_rate(kin.v_t, z));
        torque[i] = keep(lever * f); // eq. 24
        diss[i] = keep(contact::dissipation(&kin, normal, elastic, f));
        if ENERGY {
            // the contact's elastic energy beside its force, and its creep
            // spring's: the elastic normal force times the spring energy
            // per newton (elements::friction)
            en[i] = keep(law.energy(kin.p));
            cr[i] = keep(elastic * friction.spring_energy(z, mu_s * zf, mu_k * zf));
        }
        if let Some(r) = rec.as_deref_mut() {
            // the contact's share of the belt's loss: its normal damper and
            // friction slip; and the power its creep spring stores (the
            // friction power less what it dissipates, elements::friction)
            let (ms, mk) = (mu_s * zf, mu_k * zf);
            let loss = contact::damper_loss(&kin, normal, elastic)
                + friction.slip_loss(kin.v_t, z, ms, mk, normal);
            let stored = f * kin.v_t
                - friction.dissipated_power(
                    kin.v_t,
                    z,
                    ms,
                    mk,
                    normal,
                    elastic,
                    law.elastic_rate(kin.p, kin.p_dot),
                );
            r[i] = [
                normal,
                f,
                kin.v_t,
                kin.p,
                fx,
                fy,
                f64::from(u8::from(inside)),
                loss,
                stored,
            ];
        }
    }
}

/// Where [`contact_along_arc`] writes, per body of the run: the contact
/// force, creep rate, moment about the body centre, moment about the
/// pulley axis, dissipated power and, if given, the recorded values.
pub(super) struct ArcOut<'a> {
    pub(super) fx: &'a mut [f64],
    pub(super) fy: &'a mut [f64],
    pub(super) dz: &'a mut [f64],
    pub(super) moment: &'a mut [f64],
    pub(super) torque: &'a mut [f64],
    pub(super) diss: &'a mut [f64],
    /// With the stored energy: the contacts' elastic energy and the creep
    /// spring's.
    pub(super) energy: [&'a mut [f64]; 2],
    pub(super) rec: Option<&'a mut [[f64; 9]]>,
}

/// [`contact_arc`] with the contact along the body at `K` points
/// ([`contact::point`] at each, the sums and the body's one creep rate as
/// [`contact::segment`] forms them): `body` holds the columns x, y, vx, vy,
/// omega, z, the half body vector hx, hy and the friction zone factor of
/// the run (the first `valid` bodies, then padding that is ignored); pulley
/// speed `omega`. Every lane computes all its points and keeps those
/// inside their circles, so the loop over the bodies vectorises; a body
/// with no point inside writes zeros.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn contact_along_arc<const K: usize, const ENERGY: bool>(
    sys: &BeltSystem,
    pc: &PulleyConst,
    centre: &[f64; 4],
    omega: f64,
    friction: &impl Law,
    valid: usize,
    body: [&[f64]; 9],
    out: ArcOut,
) {
    let ArcOut {
        fx: ofx,
        fy: ofy,
        dz,
        moment,
        torque,
        diss,
        energy: [en, cr],
        mut rec,
    } = out;
    let k = ofx.len();
    let (en, cr) = (&mut en[..k], &mut cr[..k]);
    let [xs, ys, vxs, vys, ws, zs, hxs, hys, zfs] = body;
    let (xs, ys, vxs, vys, ws, zs, hxs, hys, zfs) = (
        &xs[..k],
        &ys[..k],
        &vxs[..k],
        &vys[..k],
        &ws[..k],
        &zs[..k],
        &hxs[..k],
        &hys[..k],
        &zfs[..k],
    );
    let (ofy, dz, moment, torque, diss) = (
        &mut ofy[..k],
        &mut dz[..k],
        &mut moment[..k],
        &mut torque[..k],
        &mut diss[..k],
    );
    // the points' constants in locals (unrolled over K)
    let quad: [(f64, f64); K] = contact::quadrature(K).try_into().expect("K points");
    let radii: [f64; K] = pc.radii[..K].try_into().expect("K radii");
    let levers: [f64; K] = pc.levers[..K].try_into().expect("K levers");
    let law = sys.contact;
    let laws: [ContactLaw; K] = std::array::from_fn(|g| law.share(quad[g].1));
    let PulleyConst {
        mu_s,
        mu_k,
        inv_p_max,
        ..
    } = *pc;
    let [cx, cy, cvx, cvy] = *centre;
    for i in 0..k {
        let zf = zfs[i];
        let pulley = contact::PulleySide {
            radii: &radii,
            omega,
            levers: &levers,
            mu_s: mu_s * zf,
            mu_k: mu_k * zf,
            inv_p_max,
        };
        let b = contact::BodySide {
            r: [xs[i] - cx, ys[i] - cy],
            v: [vxs[i] - cvx, vys[i] - cvy],
            h: [hxs[i], hys[i]],
            w: ws[i],
            z: zs[i],
        };
        // the sums of contact::segment over the points inside
        let mut sums = PointSums::new();
        // the points unrolled by hand (LLVM keeps a loop over four or five
        // of them, and a loop inside stops the lanes' loop vectorising)
        macro_rules! at {
            ($g:literal) => {
                if $g < K {
                    let g = $g;
                    let pt = contact::point(
                        &laws[g], friction, quad[g].0, radii[g], levers[g], &pulley, &b,
                    );
                    sums.add::<ENERGY>(&pt, levers[g], &laws[g]);
                }
            };
        }
        at!(0);
        at!(1);
        at!(2);
        at!(3);
        at!(4);
        let v_t = contact::body_sliding_velocity(sums.e, sums.ev, sums.count, sums.v);
        let creep_rate = friction.creep_rate(v_t, b.z);
        let inside = (sums.count > 0.0) & (i < valid);
        let keep = |v: f64| if inside { v } else { 0.0 };
        ofx[i] = keep(sums.fx);
        ofy[i] = keep(sums.fy);
        dz[i] = keep(creep_rate);
        moment[i] = keep(sums.moment);
        torque[i] = keep(sums.torque); // eq. 24
        diss[i] = keep(sums.diss);
        if ENERGY {
            // the creep spring's energy: the elastic normal force summed
            // over the points times the spring energy per newton
            en[i] = keep(sums.energy);
            cr[i] = keep(sums.elastic * friction.spring_energy(b.z, pulley.mu_s, pulley.mu_k));
        }
        if let Some(r) = rec.as_deref_mut() {
            // the contact's share of the belt's loss (normal dampers and
            // friction slip) and the power its creep spring stores
            // (elements::friction, with the body's one creep rate)
            let (ms, mk) = (pulley.mu_s, pulley.mu_k);
            let mu0 = friction.coefficient(0.0, b.z, ms, mk);
            let phi = friction.spring_energy(b.z, ms, mk);
            let slip = sums.slip - sums.normal * mu0 * creep_rate;
            let stored = sums.elastic * mu0 * creep_rate + sums.elastic_rate * phi;
            let damper = sums.diss - (slip + sums.normal * mu0 * creep_rate);
            r[i] = [
                sums.normal,
                sums.friction,
                v_t,
                sums.p_max,
                sums.fx,
                sums.fy,
                f64::from(u8::from(inside)),
                damper + slip.max(0.0),
                stored,
            ];
        }
    }
}

/// The sums of [`contact::segment`] over the points of a body inside their
/// circles, as [`contact_along_arc`] forms them point by point.
#[derive(Clone, Copy)]
struct PointSums {
    fx: f64,
    fy: f64,
    moment: f64,
    torque: f64,
    diss: f64,
    normal: f64,
    friction: f64,
    elastic: f64,
    elastic_rate: f64,
    /// Friction power f v_T.
    slip: f64,
    /// Elastic normal force and its product with v_T, the number of points
    /// inside and their v_T: the body's sliding velocity
    /// ([`contact::body_sliding_velocity`]).
    e: f64,
    ev: f64,
    count: f64,
    v: f64,
    /// With the stored energy: the points' elastic energy.
    energy: f64,
    /// Largest penetration of the body's points (inside or not).
    p_max: f64,
}

impl PointSums {
    #[inline(always)]
    fn new() -> Self {
        Self {
            fx: 0.0,
            fy: 0.0,
            moment: 0.0,
            torque: 0.0,
            diss: 0.0,
            normal: 0.0,
            friction: 0.0,
            elastic: 0.0,
            elastic_rate: 0.0,
            slip: 0.0,
            e: 0.0,
            ev: 0.0,
            count: 0.0,
            v: 0.0,
            energy: 0.0,
            p_max: f64::MIN,
        }
    }

    /// Adds point `pt` (lever `lever`, its share of the law `law`) if it is
    /// inside its circle.
    #[inline(always)]
    fn add<const ENERGY: bool>(
        &mut self,
        pt: &contact::PointContact,
        lever: f64,
        law: &ContactLaw,
    ) {
        self.p_max = self.p_max.max(pt.kin.p);
        let inside = pt.kin.p > 0.0;
        let keep = |v: f64| if inside { v } else { 0.0 };
        self.fx += keep(pt.force[0]);
        self.fy += keep(pt.force[1]);
        self.moment += keep(pt.moment);
        self.torque += keep(lever * pt.f);
        self.diss += keep(pt.dissipation);
        self.normal += keep(pt.normal);
        self.friction += keep(pt.f);
        self.elastic += keep(pt.elastic);
        self.elastic_rate += keep(pt.elastic_rate);
        self.slip += keep(pt.f * pt.kin.v_t);
        self.e += keep(pt.elastic);
        self.ev += keep(pt.elastic * pt.kin.v_t);
        self.count += keep(1.0);
        self.v += keep(pt.kin.v_t);
        if ENERGY {
            // the point's elastic energy beside its force
            self.energy += keep(law.energy(pt.kin.p));
        }
    }
}
