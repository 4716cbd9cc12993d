//! The belt's own rows of the Jacobian: the SDEs between neighbouring
//! bodies (eq. 20-23), the relaxation's damping and the transverse damping.

use super::{perp, Jacobian, NEXT, PREV, SELF};
use crate::model::elements::sde::{self, BodyEnd};
use crate::model::matmul::mm;
use crate::model::state::BodyIndex;
use crate::model::system::BeltSystem;
use crate::model::trig;
use nalgebra::{Matrix3, SMatrix, Vector2};

impl BeltSystem {
    /// The rows of the SDEs between neighbouring bodies (eq. 20-23).
    #[inline(always)]
    pub(super) fn sde_rows(&self, y: &[f64], jac: &mut Jacobian) {
        let n = self.n;
        let hl = self.half_length;
        let (inv_m, inv_i) = (self.inv_mass, self.inv_inertia);
        let row_scale = [inv_m, inv_m, inv_i];
        // SDE k joins the right end of body p = k-1 to the left end of body
        // c = k. Gap d = J_d q-ish, generalized forces Q = -J_d^T F (eq. 20-23).
        let (kt, bt) = self.bend.partials();
        // sin/cos of each body angle once: body k's is body k+1's "previous"
        let mut prev_sc = trig::sin_cos(y[BodyIndex::of(n - 1).angle]);
        for k in 0..n {
            let p = if k == 0 { n - 1 } else { k - 1 };
            let (op, oc) = (BodyIndex::of(p), BodyIndex::of(k));
            let (sp, cp) = prev_sc;
            let (sc, cc) = trig::sin_cos(y[oc.angle]);
            prev_sc = (sc, cc);
            let hp = Vector2::new(hl * cp, hl * sp);
            let hc = Vector2::new(hl * cc, hl * sc);
            let (hpp, hcp) = (perp(hp), perp(hc));
            let (wp, wc) = (y[op.spin], y[oc.spin]);
            let end = |o: BodyIndex, h: Vector2<f64>| BodyEnd {
                x: y[o.x],
                y: y[o.y],
                hx: h.x,
                hy: h.y,
                vx: y[o.vx],
                vy: y[o.vy],
                w: y[o.spin],
            };
            let (d, dd) = sde::gap(end(op, hp), end(oc, hc));
            let (force, f_d, f_dd) = self.axial.partials(d, dd);
            // dF/dq and dF/dv (2 x 6 over x_p, y_p, phi_p, x_c, y_c, phi_c)
            // column by column: the gap's Jacobian is J_d = [-I, -h_p^perp,
            // I, -h_c^perp], and d(dd)/dq acts only through the angles
            // (columns w_p h_p and w_c h_c).
            let mut dfq = SMatrix::<f64, 2, 6>::zeros();
            let mut dfv = SMatrix::<f64, 2, 6>::zeros();
            dfq.fixed_view_mut::<2, 2>(0, 0).copy_from(&(-f_d));
            dfq.fixed_view_mut::<2, 2>(0, 3).copy_from(&f_d);
            dfq.set_column(2, &(mm(&f_dd, &(wp * hp)) - mm(&f_d, &hpp)));
            dfq.set_column(5, &(mm(&f_dd, &(wc * hc)) - mm(&f_d, &hcp)));
            dfv.fixed_view_mut::<2, 2>(0, 0).copy_from(&(-f_dd));
            dfv.fixed_view_mut::<2, 2>(0, 3).copy_from(&f_dd);
            dfv.set_column(2, &(-mm(&f_dd, &hpp)));
            dfv.set_column(5, &(-mm(&f_dd, &hcp)));
            // generalized forces Q = -J_d^T F: rows dF, h_p^perp . dF, -dF,
            // h_c^perp . dF
            let q_of = |df: &SMatrix<f64, 2, 6>| {
                let mut k = SMatrix::<f64, 6, 6>::zeros();
                k.fixed_view_mut::<2, 6>(0, 0).copy_from(df);
                k.set_row(2, &mm(&hpp.transpose(), df));
                k.fixed_view_mut::<2, 6>(3, 0).copy_from(&(-df));
                k.set_row(5, &mm(&hcp.transpose(), df));
                k
            };
            let mut kq = q_of(&dfq);
            let mut kv = q_of(&dfv);
            // explicit angle dependence of the lever arms: d(h_perp . F)/dphi = -h . F
            kq[(2, 2)] -= hp.dot(&force);
            kq[(5, 5)] -= hc.dot(&force);
            // torsional SDE: m = kt (phi_c - phi_p) + bt (w_c - w_p), +m on p, -m on c
            kq[(2, 5)] += kt;
            kq[(2, 2)] -= kt;
            kq[(5, 5)] -= kt;
            kq[(5, 2)] += kt;
            kv[(2, 5)] += bt;
            kv[(2, 2)] -= bt;
            kv[(5, 5)] -= bt;
            kv[(5, 2)] += bt;
            // a 3 x 3 block of Q divided by the mass, mass, inertia of its rows
            let blk = |m: &SMatrix<f64, 6, 6>, r: usize, c: usize| -> Matrix3<f64> {
                Matrix3::from_fn(|i, j| row_scale[i] * m[(r + i, c + j)])
            };
            {
                let bp = &mut jac.bodies[p];
                bp.accel_by_position[SELF] += blk(&kq, 0, 0);
                bp.accel_by_velocity[SELF] += blk(&kv, 0, 0);
                bp.accel_by_position[NEXT] += blk(&kq, 0, 3);
                bp.accel_by_velocity[NEXT] += blk(&kv, 0, 3);
            }
            let bc = &mut jac.bodies[k];
            bc.accel_by_position[SELF] += blk(&kq, 3, 3);
            bc.accel_by_velocity[SELF] += blk(&kv, 3, 3);
            bc.accel_by_position[PREV] += blk(&kq, 3, 0);
            bc.accel_by_velocity[PREV] += blk(&kv, 3, 0);
        }
    }

    /// The bodies' damping: the relaxation's, and the transverse (span)
    /// damping of the body centres.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // indices run over several parallel arrays
    pub(super) fn damping_rows(&self, y: &[f64], jac: &mut Jacobian) {
        let damping = self.relaxation.damping;
        if damping != 0.0 {
            for b in jac.bodies.iter_mut() {
                for r in 0..3 {
                    b.accel_by_velocity[SELF][(r, r)] -= damping;
                }
            }
        }
        // transverse damping of the body centres (elements::transverse)
        let transverse = self.transverse();
        if transverse.acts() {
            for (i, b) in jac.bodies.iter_mut().enumerate() {
                let o = BodyIndex::of(i);
                let (d_v, d_phi) = transverse.partials(y[o.angle], [y[o.vx], y[o.vy]]);
                for r in 0..2 {
                    b.accel_by_position[SELF][(r, 2)] += d_phi[r];
                    for c in 0..2 {
                        b.accel_by_velocity[SELF][(r, c)] += d_v[r][c];
                    }
                }
            }
        }
    }
}
