//! Tests of the method on small dense systems: order, stiff decay, the
//! tolerance, the energy check, the observer, the AVX2 build.

use super::*;
use crate::solver::step_control::OdeSystem;

/// Small dense test systems: the Jacobian is a dense matrix, the
/// iteration matrix solved by Gaussian elimination.
#[derive(Clone)]
struct Dense<F: Fn(f64, &[f64], &mut [f64]) + Clone> {
    n: usize,
    f: F,
    /// Jacobian used by the method: exact (finite differences), or zero
    /// (the W-method then degenerates to an explicit Runge-Kutta method).
    exact: bool,
}

impl<F: Fn(f64, &[f64], &mut [f64]) + Clone> OdeSystem for Dense<F> {
    type Workspace = ();
    fn dim(&self) -> usize {
        self.n
    }
    fn workspace(&self) {}
    fn rhs(&self, _: &mut (), t: f64, y: &[f64], dy: &mut [f64]) {
        (self.f)(t, y, dy)
    }
}

impl<F: Fn(f64, &[f64], &mut [f64]) + Clone> StiffSystem for Dense<F> {
    type Jacobian = Vec<f64>;
    type Matrix = Vec<f64>;
    fn new_jacobian(&self) -> Vec<f64> {
        vec![0.0; self.n * self.n]
    }
    fn new_matrix(&self) -> Vec<f64> {
        vec![0.0; self.n * self.n]
    }
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut Vec<f64>) {
        jac.iter_mut().for_each(|v| *v = 0.0);
        if !self.exact {
            return;
        }
        let n = self.n;
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        for j in 0..n {
            let mut yp = y.to_vec();
            let e = 1e-7 * y[j].abs().max(1.0);
            yp[j] += e;
            (self.f)(t, &yp, &mut a);
            yp[j] -= 2.0 * e;
            (self.f)(t, &yp, &mut b);
            for i in 0..n {
                jac[i * n + j] = (a[i] - b[i]) / (2.0 * e);
            }
        }
    }
    fn factor(&self, jac: &Vec<f64>, c: f64, m: &mut Vec<f64>) -> bool {
        let n = self.n;
        for i in 0..n {
            for j in 0..n {
                m[i * n + j] = f64::from(u8::from(i == j)) - c * jac[i * n + j];
            }
        }
        true
    }
    fn save_jacobian(&self, jac: &Vec<f64>, out: &mut Vec<f64>) {
        out.extend_from_slice(jac);
    }
    fn load_jacobian(&self, jac: &mut Vec<f64>, src: &[f64]) -> bool {
        jac.copy_from_slice(src);
        true
    }
    fn solve(&self, _jac: &Vec<f64>, m: &mut Vec<f64>, b: &mut [f64]) {
        let x = crate::solver::iteration_matrix::tests::dense_solve(m.clone(), b.to_vec());
        b.copy_from_slice(&x);
    }
}

/// Error at t = 1 of fixed steps h on y' = -y + sin(t) y^2-ish smooth
/// nonlinear non-autonomous problem, against a fine reference.
fn fixed_step_error(exact: bool, h: f64) -> f64 {
    let f = |t: f64, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -y[0] - 0.5 * y[1] * y[1] + (2.0 * t).cos();
    };
    let run = |h: f64| {
        let sys = Dense { n: 2, f, exact };
        // tolerance so loose that every step is accepted: fixed steps
        let mut ros = Rosenbrock::new(&sys, 1e3, 1e3, h, 1_000_000);
        let mut y = vec![1.0, 0.0];
        let mut t = 0.0;
        let steps = (1.0 / h).round() as usize;
        for k in 1..=steps {
            ros.control.h = h;
            ros.advance(&sys, &mut (), &mut t, &mut y, k as f64 * h)
                .unwrap();
        }
        y
    };
    let reference = run(1e-4);
    let y = run(h);
    (y[0] - reference[0]).abs() + (y[1] - reference[1]).abs()
}

#[test]
fn order_three_with_exact_or_zero_jacobian() {
    // The W-method property: order 3 whatever matrix stands for J.
    for exact in [true, false] {
        let (e1, e2) = (fixed_step_error(exact, 0.02), fixed_step_error(exact, 0.01));
        let order = (e1 / e2).log2();
        assert!(
            (2.7..3.4).contains(&order),
            "exact J = {exact}: observed order {order} ({e1:e}, {e2:e})"
        );
    }
}

#[test]
fn stiff_problem_with_large_steps() {
    // Prothero-Robinson: y' = -1e6 (y - cos t) - sin t, y = cos t.
    let f = |t: f64, y: &[f64], dy: &mut [f64]| {
        dy[0] = -1e6 * (y[0] - t.cos()) - t.sin();
    };
    let sys = Dense {
        n: 1,
        f,
        exact: true,
    };
    let mut ros = Rosenbrock::new(&sys, 1e-6, 1e-8, 1e-3, 100_000);
    let mut y = vec![1.0];
    let mut t = 0.0;
    ros.advance(&sys, &mut (), &mut t, &mut y, 2.0).unwrap();
    assert_eq!(t, 2.0);
    assert!((y[0] - 2f64.cos()).abs() < 1e-6, "{}", y[0]);
    // An explicit method would need ~1e6 steps (stability h < 2.8e-6).
    assert!(ros.control.stats.steps < 2000, "{:?}", ros.control.stats);
}

#[test]
fn tolerance_controls_error_and_failure_restores() {
    let f = |_t: f64, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -y[0];
    };
    let sys = Dense {
        n: 2,
        f,
        exact: true,
    };
    let mut prev = f64::INFINITY;
    for tol in [1e-4, 1e-6, 1e-8] {
        let mut ros = Rosenbrock::new(&sys, tol, tol, 1e-3, 1_000_000);
        let mut y = vec![1.0, 0.0];
        let mut t = 0.0;
        for k in 1..=100 {
            ros.advance(&sys, &mut (), &mut t, &mut y, k as f64 * 0.1)
                .unwrap();
            assert_eq!(t, k as f64 * 0.1);
        }
        let err = (y[0] - 10f64.cos()).abs() + (y[1] + 10f64.sin()).abs();
        assert!(err < 1000.0 * tol && err < prev, "tol {tol}: {err}");
        prev = err;
    }
    let mut ros = Rosenbrock::new(&sys, 1e-12, 1e-12, 1e-3, 3);
    let mut y = vec![1.0, 0.0];
    let mut t = 0.25;
    assert!(ros.advance(&sys, &mut (), &mut t, &mut y, 50.0).is_err());
    assert_eq!((t, y), (0.25, vec![1.0, 0.0]));
}

/// x'' = -x with its energy balance -(x^2 + v^2)/2 (no input, no
/// dissipation) and both states left out of the error norm, so that
/// the energy check alone controls the step (`check`: the balance is
/// given; otherwise the system books no energy).
#[derive(Clone)]
struct Oscillator {
    check: bool,
}

impl OdeSystem for Oscillator {
    type Workspace = ();
    fn dim(&self) -> usize {
        2
    }
    fn workspace(&self) {}
    fn rhs(&self, _: &mut (), _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = -y[0];
    }
}

impl StiffSystem for Oscillator {
    type Jacobian = [f64; 4];
    type Matrix = [f64; 4];
    fn new_jacobian(&self) -> [f64; 4] {
        [0.0; 4]
    }
    fn new_matrix(&self) -> [f64; 4] {
        [0.0; 4]
    }
    fn jacobian(&self, _t: f64, _y: &[f64], jac: &mut [f64; 4]) {
        *jac = [0.0, 1.0, -1.0, 0.0];
    }
    fn factor(&self, jac: &[f64; 4], c: f64, m: &mut [f64; 4]) -> bool {
        *m = [1.0 - c * jac[0], -c * jac[1], -c * jac[2], 1.0 - c * jac[3]];
        true
    }
    fn solve(&self, _jac: &[f64; 4], m: &mut [f64; 4], b: &mut [f64]) {
        let det = m[0] * m[3] - m[1] * m[2];
        let (b0, b1) = (b[0], b[1]);
        b[0] = (m[3] * b0 - m[1] * b1) / det;
        b[1] = (m[0] * b1 - m[2] * b0) / det;
    }
    fn error_mask(&self, _rel_tol: f64, mask: &mut [f64]) {
        mask.fill(0.0);
    }
    fn energy_balance(&self, y: &[f64]) -> Option<EnergyBalance> {
        let e = 0.5 * (y[0] * y[0] + y[1] * y[1]);
        self.check.then_some(EnergyBalance {
            balance: -e,
            scale: e,
            magnitude: e,
        })
    }
    fn save_jacobian(&self, jac: &[f64; 4], out: &mut Vec<f64>) {
        out.extend_from_slice(jac);
    }
    fn load_jacobian(&self, jac: &mut [f64; 4], src: &[f64]) -> bool {
        jac.copy_from_slice(src);
        true
    }
}

/// The energy check holds each step's energy residual to relTol times
/// the stored energy: over ten periods of an oscillator whose states are
/// left out of the error norm the energy drifts by at most relTol per
/// step (measured 6.5e-7 per step at relTol 1e-6, 1056 steps). Without
/// the check nothing limits the steps and the L-stable method's
/// numerical damping takes most of the energy.
#[test]
fn energy_check_bounds_the_energy_residual_per_step() {
    // `check`: the system books its energy; `switch`: the integrator's
    // energy check is on
    let run_with = |check: bool, switch: bool| {
        let sys = Oscillator { check };
        let mut ros = Rosenbrock::new(&sys, 1e-6, 1e-6, 1e-3, 1_000_000);
        ros.energy_check = switch;
        let (mut t, mut y) = (0.0, vec![1.0, 0.0]);
        let t_end = 20.0 * std::f64::consts::PI;
        ros.advance(&sys, &mut (), &mut t, &mut y, t_end).unwrap();
        let drift = 1.0 - (y[0] * y[0] + y[1] * y[1]);
        (drift, ros.control.stats.steps, ros.energy_rejections)
    };
    let run = |check: bool| run_with(check, true);
    let (drift, steps, rejections) = run(true);
    assert!(
        drift.abs() <= 1e-6 * steps as f64,
        "with the check: drift {drift:e} over {steps} steps ({rejections} rejected on energy)"
    );
    let (unchecked, unchecked_steps, _) = run(false);
    assert!(
        unchecked > 0.5 && unchecked_steps < steps / 10,
        "without the check: drift {unchecked:e} over {unchecked_steps} steps"
    );
    // the switch off: the error norm's step control alone, step for step
    assert_eq!(run_with(true, false), (unchecked, unchecked_steps, 0));
}

/// The observer sees every trial with the error norm the step control
/// used: the RMS of the components it is given, and the energy error
/// where that was larger (the oscillator's states are out of the norm,
/// so with the check on the energy error alone sets the step).
#[test]
fn observer_sees_every_trial_and_its_error_components() {
    let f = |t: f64, y: &[f64], dy: &mut [f64]| {
        dy[0] = y[1];
        dy[1] = -y[0] - 0.5 * y[1] * y[1] + (2.0 * t).cos();
    };
    let sys = Dense {
        n: 2,
        f,
        exact: true,
    };
    let mut ros = Rosenbrock::new(&sys, 1e-8, 1e-8, 0.5, 1_000_000);
    let (mut y, mut t) = (vec![1.0, 0.0], 0.0);
    let (mut trials, mut max_gap) = (0u64, 0.0f64);
    let (mut comps, mut end) = (vec![0.0; 2], vec![0.0; 2]);
    ros.advance_observed(&sys, &mut (), &mut t, &mut y, 1.0, &mut |m, tr| {
        trials += 1;
        assert_eq!(m.error_components(tr.y, &mut comps, &mut end), 0.0);
        let rms = ((comps[0] * comps[0] + comps[1] * comps[1]) / 2.0).sqrt();
        max_gap = max_gap.max((rms - tr.err).abs() / tr.err.max(1e-300));
    })
    .unwrap();
    let s = ros.control.stats;
    assert!(s.rejected > 0, "the first step (0.5 s) is rejected: {s:?}");
    assert_eq!(trials, s.steps + s.rejected);
    assert!(max_gap < 1e-12, "{max_gap:e}");
    assert_eq!(end, y, "the last trial's end state is the result");

    let sys = Oscillator { check: true };
    let mut ros = Rosenbrock::new(&sys, 1e-6, 1e-6, 1e-3, 1_000_000);
    let (mut y, mut t) = (vec![1.0, 0.0], 0.0);
    let mut energy_set = 0u64;
    ros.advance_observed(&sys, &mut (), &mut t, &mut y, 1.0, &mut |m, tr| {
        let e = m.error_components(tr.y, &mut comps, &mut end);
        assert_eq!(comps, [0.0, 0.0], "masked out of the norm");
        if tr.err <= 1.0 {
            assert_eq!(e, tr.err);
            energy_set += 1;
        }
    })
    .unwrap();
    assert_eq!(energy_set, ros.control.stats.steps);
}

/// The AVX2 build of a trial step gives the baseline's state and error
/// norm to the last bit (no FMA).
#[test]
fn avx2_build_matches_baseline_to_the_bit() {
    if !Isa::Avx2.available() {
        return;
    }
    let f = |t: f64, y: &[f64], dy: &mut [f64]| {
        for (k, d) in dy.iter_mut().enumerate() {
            let (a, b) = (y[k], y[(k + 1) % y.len()]);
            *d = -(k as f64 + 1.0) * a + 0.3 * b * b + (t * (k as f64 + 2.0)).sin();
        }
    };
    let sys = Dense {
        n: 11,
        f,
        exact: true,
    };
    let y: Vec<f64> = (0..11).map(|k| (k as f64 * 0.37).cos()).collect();
    let mut base = Rosenbrock::new(&sys, 1e-6, 1e-8, 1e-3, 100);
    let mut wide = base.clone();
    let e_base = base.trial_with(Isa::Baseline, &sys, &mut (), 0.1, &y, 0.05);
    let e_wide = wide.trial_with(Isa::Avx2, &sys, &mut (), 0.1, &y, 0.05);
    assert!(e_base > 0.0 && e_base.is_finite());
    assert_eq!(e_base.to_bits(), e_wide.to_bits());
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&base.stage), bits(&wide.stage));
    assert_ne!(base.stage, y);
}
