//! The structured solves against dense Gaussian elimination, and the
//! builds against each other.

use super::*;
use crate::drive::Drive;
use crate::model::params::{DecouplerParams, DriveParams, PulleyParams, TensionerArm};
use crate::model::state::BodyIndex;

/// Gaussian elimination with partial pivoting (row-major `a`), the
/// reference for the structured solves.
pub(crate) fn dense_solve(mut a: Vec<f64>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for k in 0..n {
        let p = (k..n)
            .max_by(|&i, &j| a[i * n + k].abs().total_cmp(&a[j * n + k].abs()))
            .unwrap();
        for j in 0..n {
            a.swap(k * n + j, p * n + j);
        }
        b.swap(k, p);
        for i in k + 1..n {
            let l = a[i * n + k] / a[k * n + k];
            if l != 0.0 {
                for j in k..n {
                    a[i * n + j] -= l * a[k * n + j];
                }
                b[i] -= l * b[k];
            }
        }
    }
    for k in (0..n).rev() {
        let mut s = b[k];
        for j in k + 1..n {
            s -= a[k * n + j] * b[j];
        }
        b[k] = s / a[k * n + k];
    }
    b
}

#[test]
fn solves_like_dense_gaussian_elimination() {
    for (speed_driven, three, dec, arms) in [
        (false, false, false, false),
        (true, false, false, false),
        (false, true, false, false),
        (false, false, true, false),
        (true, true, true, false),
        (false, false, false, true),
        (true, true, true, true),
    ] {
        let mut p = DriveParams::kubas_section4();
        p.belt.n_bodies = 40;
        p.belt.preload = 300.0;
        let mut p1 = PulleyParams::paper_5pk(0.0, 0.0);
        p1.radius = 0.05;
        let mut p2 = p1.clone();
        p2.x = 0.25;
        p2.load_damping = 0.3;
        p.pulleys = vec![p1, p2];
        if three {
            let mut p3 = PulleyParams::paper_5pk(0.12, 0.2);
            p3.radius = 0.04;
            p.pulleys.push(p3);
            p.belt.n_bodies = 60;
        }
        p.pulleys[0].speed_driven = speed_driven;
        p.probe_body = 0;
        if dec {
            // decouplers on a free hub and on hub 1 (speed-driven in one case)
            p.pulleys[0].decoupler = Some(DecouplerParams::default());
            p.pulleys[1].decoupler = Some(DecouplerParams {
                clockwise: true,
                ..Default::default()
            });
        }
        if arms {
            // an arm on pulley 2 (and on pulley 3 of three), pivots
            // 80 mm off the centres
            for (j, pivot) in [(1, [0.3, 0.06]), (2, [0.2, 0.25])] {
                if let Some(t) = p.pulleys.get_mut(j) {
                    t.arm = Some(TensionerArm {
                        pivot,
                        friction: 1.5,
                        damping: 0.05,
                        ..Default::default()
                    });
                }
            }
        }
        let d = Drive::new(&p, 0.0).unwrap();
        let sys = d.system();
        let mut y = d.state().to_vec();
        for j in 0..2 {
            if dec {
                // engaged on hub 1, overrunning on hub 2
                let o = sys.state_layout.decoupler(j);
                y[o.twist] = [0.05, 0.02][j];
                y[o.rotor_speed] = [-3.0, -40.0][j];
            }
        }
        for i in 0..sys.n {
            let o = BodyIndex::of(i);
            y[o.vx] = 0.3 * (i as f64).sin();
            y[o.spin] = 10.0 * (i as f64).cos();
            y[o.creep] = 4e-5 * (i as f64 * 0.3).sin();
        }
        for (k, pc) in sys.pulleys[..sys.np].iter().enumerate() {
            if pc.arm.is_some() {
                let o = sys.state_layout.arm(k);
                y[o.angle] = 2e-4 * (k as f64 + 1.0);
                y[o.rate] = [0.004, -0.3, 1.0][k];
            }
        }
        assert_eq!(
            sys.state_layout.n_arms(),
            usize::from(arms) * if three { 2 } else { 1 }
        );
        let dim = sys.dim();
        let mut jac = Jacobian::new(sys);
        sys.jacobian(0.01, &y, &mut jac);
        let dense = jac.to_dense(sys);
        let mut im = IterationMatrix::new(sys);
        for c in [1e-7, 1e-5, 1e-4, 1e-3] {
            let mut a = vec![0.0; dim * dim];
            for r in 0..dim {
                for k in 0..dim {
                    a[r * dim + k] = f64::from(u8::from(r == k)) - c * dense[r * dim + k];
                }
            }
            let b: Vec<f64> = (0..dim).map(|k| ((k * 7919) % 13) as f64 - 6.0).collect();
            let x_ref = dense_solve(a.clone(), b.clone());
            assert!(im.factor(sys, &jac, c));
            let mut x = b.clone();
            im.solve(sys, &jac, &mut x);
            // residual of the structured solution in the dense system
            let scale = x_ref.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for k in 0..dim {
                assert!(
                    (x[k] - x_ref[k]).abs() <= 1e-8 * scale,
                    "speed_driven {speed_driven}, 3 pulleys {three}, decouplers {dec}, \
                     arms {arms}, c {c:e}: x[{k}] = {} vs {}",
                    x[k],
                    x_ref[k]
                );
            }
        }
    }
}

/// The AVX2 builds of factor and solve give the baseline's numbers to
/// the last bit (no FMA).
#[test]
fn avx2_build_matches_baseline_to_the_bit() {
    if !Isa::Avx2.available() {
        return;
    }
    let mut p = DriveParams::kubas_section4();
    p.belt.n_bodies = 120;
    let d = Drive::new(&p, 0.0).unwrap();
    let sys = d.system();
    let mut y = d.state().to_vec();
    for i in 0..sys.n {
        let o = BodyIndex::of(i);
        y[o.vx] += 0.3 * (i as f64).sin();
        y[o.spin] += 10.0 * (i as f64).cos();
        y[o.creep] = 4e-5 * (i as f64 * 0.3).sin();
    }
    let mut jac = Jacobian::new(sys);
    sys.jacobian(0.01, &y, &mut jac);
    assert!(jac.bodies.iter().any(|b| b.touching != 0));
    let rhs: Vec<f64> = (0..sys.dim())
        .map(|k| ((k * 7919) % 13) as f64 - 6.0)
        .collect();
    let (mut base, mut wide) = (IterationMatrix::new(sys), IterationMatrix::new(sys));
    for c in [1e-6, 1e-4] {
        assert!(base.factor_with(Isa::Baseline, sys, &jac, c));
        assert!(wide.factor_with(Isa::Avx2, sys, &jac, c));
        assert_eq!(base, wide);
        let (mut xb, mut xw) = (rhs.clone(), rhs.clone());
        base.solve_with(Isa::Baseline, sys, &jac, &mut xb);
        wide.solve_with(Isa::Avx2, sys, &jac, &mut xw);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&xb), bits(&xw), "c = {c:e}");
    }
}
