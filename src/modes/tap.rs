//! A tensioner arm's swing after a tap (docs/modes.md, "Frictional
//! tensioner arms"): the arm's rate kicked by one unit in the linearised
//! drive, and the time its angle takes to swing out, back through its rest
//! position and back again (its second zero crossing).
//!
//! This is the frequency the describing function of the arm's pivot
//! friction is taken at ([`super::describe_arms`]). For an arm whose swing
//! is one mode, x(t) ~ e^(-sigma t) sin(omega_d t) crosses zero at pi /
//! omega_d and 2 pi / omega_d: the swing is that mode's damped frequency.
//! A frictional arm is heavily damped, and its swing is shared by several
//! modes with the spans (in steady running) or the pulleys (at rest), none
//! of which is the arm's: the mode carrying the largest share of the arm's
//! energy can then change with the damper and be one a tap hardly rings.
//! The tap is what the friction feels. An angle that crosses zero at most
//! once within [`TAP_HORIZON`] creeps back: the arm does not swing
//! ([`Tap::Overdamped`]).

use super::adapter::Linearisation;
use super::floquet::{sdirk_step, sparse, SDIRK_GAMMA};
use crate::model::params::MAX_PULLEYS;
use faer::Mat;

/// A tensioner arm's free response to a tap of its rate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tap {
    /// The arm angle swings back through its rest position twice: the
    /// second crossing is one period of the swing, at this frequency [Hz].
    Swings(f64),
    /// The arm angle crosses its rest position at most once within
    /// [`TAP_HORIZON`]: the arm creeps back, it does not swing.
    Overdamped,
}

/// How long a tap is followed [s]: 0.25 s, four periods of a 16 Hz swing
/// (tensioner arms' modes lie at tens of Hz).
pub const TAP_HORIZON: f64 = 0.25;

/// Time step of the tap at rest [s]: 0.1 ms, a hundred steps per swing of
/// 100 Hz, where the second-order method's phase error is 1e-4 of a period.
pub const REST_STEP: f64 = 1e-4;

/// The tap at rest: x' = J x from x(0) = e (the arm's rate), J the
/// Jacobian of `lin`, in steps of [`REST_STEP`] by the two-stage SDIRK
/// method that integrates the running drive's variational equations
/// (L-stable: the contacts' and the bodies' fast modes die out instead of
/// ringing at the step), the arm angle sampled at every step.
pub fn at_rest(lin: &Linearisation) -> Result<[Option<Tap>; MAX_PULLEYS], String> {
    if lin.pulleys.iter().all(|p| p.arm.is_none()) {
        return Ok([None; MAX_PULLEYS]);
    }
    let h = REST_STEP;
    let lu = sparse(lin, -SDIRK_GAMMA * h, 1.0)?
        .sp_lu()
        .map_err(|e| format!("the tap's step matrix is singular: {e:?}"))?;
    Ok(each_arm(lin, h, |x| sdirk_step(x, &lu, &lu)))
}

/// The tap in steady running: the perturbation carried from period to
/// period by the monodromy `m` (x_k = M^k e, one product per `period`), the
/// arm angle sampled at the period ends (at idle a period is an eighth to
/// a tenth of a swing).
pub fn running(m: &Mat<f64>, lin: &Linearisation, period: f64) -> [Option<Tap>; MAX_PULLEYS] {
    each_arm(lin, period, |x| *x = m * &*x)
}

/// The swing of each arm of `lin`: its rate kicked by one unit and carried
/// by `step` (the state, one column, carried on by `dt`) for up to
/// [`TAP_HORIZON`].
fn each_arm(
    lin: &Linearisation,
    dt: f64,
    mut step: impl FnMut(&mut Mat<f64>),
) -> [Option<Tap>; MAX_PULLEYS] {
    let mut out = [None; MAX_PULLEYS];
    let steps = (TAP_HORIZON / dt).ceil() as usize;
    for (j, p) in lin.pulleys.iter().enumerate() {
        if p.arm.is_none() {
            continue;
        }
        let arm = lin.states.arm(j);
        let mut x = Mat::<f64>::zeros(lin.dim, 1);
        x[(arm.rate, 0)] = 1.0;
        out[j] = Some(swing(steps, dt, || {
            step(&mut x);
            x[(arm.angle, 0)]
        }));
    }
    out
}

/// The swing of the arm angles `next()` returns (one per step of `dt`
/// after the tap, up to `steps` of them): the second sign change after the
/// tap, placed by [`crossing`].
fn swing(steps: usize, dt: f64, mut next: impl FnMut() -> f64) -> Tap {
    // samples from the tap on, until one past the second sign change
    let mut a = Vec::with_capacity(steps + 1);
    a.push(0.0);
    let (mut changes, mut second) = (0, None);
    for k in 1..=steps {
        a.push(next());
        if second.is_some() {
            break;
        }
        if k > 1 && (a[k] < 0.0) != (a[k - 1] < 0.0) {
            changes += 1;
            if changes == 2 {
                second = Some(k);
            }
        }
    }
    match second {
        Some(k) => Tap::Swings(1.0 / (crossing(&a, k) * dt)),
        None => Tap::Overdamped,
    }
}

/// Where the samples `a` (at 0, 1, 2, ...) cross zero between `k - 1` and
/// `k`: the root of the cubic through samples k - 2 to k + 1, by Newton's
/// method from the straight line's root and kept within the interval (a
/// straight line alone where fewer than four samples exist). A damped sine
/// (zeta 0.4) sampled 8.3 times per swing, as the running tap at idle is:
/// the second crossing 0.13 % early on the cubic, 0.99 % on the straight
/// line (the unit test).
fn crossing(a: &[f64], k: usize) -> f64 {
    let linear = k as f64 - 1.0 + a[k - 1] / (a[k - 1] - a[k]);
    if k < 2 || k + 1 >= a.len() {
        return linear;
    }
    let xs = [k - 2, k - 1, k, k + 1].map(|i| i as f64);
    let ys = [a[k - 2], a[k - 1], a[k], a[k + 1]];
    // the Lagrange form's value and slope at t
    let cubic = |t: f64| {
        let (mut v, mut d) = (0.0, 0.0);
        for i in 0..4 {
            let (mut l, mut dl) = (1.0, 0.0);
            for m in (0..4).filter(|&m| m != i) {
                let f = (t - xs[m]) / (xs[i] - xs[m]);
                dl = dl * f + l / (xs[i] - xs[m]);
                l *= f;
            }
            v += ys[i] * l;
            d += ys[i] * dl;
        }
        (v, d)
    };
    let mut t = linear;
    for _ in 0..8 {
        let (v, d) = cubic(t);
        if d == 0.0 {
            break;
        }
        t = (t - v / d).clamp(k as f64 - 1.0, k as f64);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::{crossing, swing, Tap};

    /// A damped sine (zeta 0.4) sampled 8.3 times per swing: the second
    /// crossing at the damped period within 2e-3 (measured: the cubic
    /// -0.13 %, a straight line between the samples -0.99 %), a creeping
    /// response overdamped.
    #[test]
    fn swing_of_a_damped_sine_and_a_creep() {
        let (f, zeta): (f64, f64) = (80.0, 0.4);
        let wn = std::f64::consts::TAU * f / (1.0 - zeta * zeta).sqrt();
        let wd = std::f64::consts::TAU * f;
        let dt = 1.0 / (8.3 * f);
        let mut k = 0;
        let tap = swing(400, dt, || {
            k += 1;
            let t = k as f64 * dt;
            (-zeta * wn * t).exp() * (wd * t).sin()
        });
        let Tap::Swings(got) = tap else {
            panic!("{tap:?}")
        };
        assert!((got / f - 1.0).abs() < 2e-3, "{got}");
        // critically damped: t e^(-w t) never crosses
        let mut k = 0;
        let creep = swing(400, dt, || {
            k += 1;
            let t = k as f64 * dt;
            t * (-wn * t).exp()
        });
        assert_eq!(creep, Tap::Overdamped);
        // a straight line's root is the cubic's on straight samples
        let a = [0.0, 3.0, 1.0, -1.0, -3.0];
        assert!((crossing(&a, 3) - 2.5).abs() < 1e-12);
    }
}
