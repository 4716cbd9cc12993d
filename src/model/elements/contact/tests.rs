//! Unit tests of the contact laws: partials against central differences,
//! the chain in stick, the smoothstep ramp.

use super::*;
use crate::model::elements::friction::{Friction, Law};
use crate::model::params::FrictionLaw;
use nalgebra::{Matrix2x3, RowVector3};

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
                    let row = |q: &RowVector3<f64>, u: &RowVector3<f64>, zz: f64, ww: f64| match c {
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
