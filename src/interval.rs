//! Interval outputs: means and extrema over the last communication interval
//! (the last [`crate::Drive::advance`] call) of each span's tension, of the
//! smallest tension anywhere in the belt and of each tensioner arm's spring
//! torque, taken over the integrator's own steps, not over samples at the
//! communication points.
//!
//! At the interval's start and at the end of every accepted step the
//! accumulator evaluates the quantities at the step's end state (the
//! endpoint values the integrator itself produced; no interpolation
//! between them):
//!
//! * the **means** integrate them by the trapezoidal rule over the steps
//!   (second order in the step: for a ripple of frequency f its error is
//!   about (2 pi f h)^2 / 12 of the ripple's amplitude, 0.5 % of it for the
//!   stiff method's 53 us steps at the accessory drive's 740 Hz body-passing
//!   frequency, and far less for RKF45's microsecond steps);
//! * the **extrema** are the extrema over those endpoints: an extremum that
//!   falls between two endpoints is missed by at most the signal's change
//!   over half a step (for the same ripple 1 - cos(pi f h) of its
//!   amplitude, 0.7 % of it).
//!
//! The span's tension is that of the translational SDE whose middle lies
//! nearest the mid-point of the mounted free span (`span[k].tension`, the
//! same element the instantaneous output reads); the search starts from the
//! element found at the last endpoint, so it costs a few elements per step.

use crate::model::params::MAX_PULLEYS;
use crate::model::state;
use crate::model::system::BeltSystem;
use crate::model::trig;

/// Length of the data [`IntervalAccumulator::save`] writes.
pub const INTERVAL_DATA: usize = 5 * MAX_PULLEYS + 1;

/// The interval outputs of the last communication interval.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct IntervalOutputs {
    /// Mean tension of span k (from pulley k to k+1) [N].
    pub span_mean_tension: [f64; MAX_PULLEYS],
    /// Smallest tension of span k [N].
    pub span_min_tension: [f64; MAX_PULLEYS],
    /// Largest tension of span k [N].
    pub span_max_tension: [f64; MAX_PULLEYS],
    /// Smallest tension of any translational SDE of the belt [N].
    pub belt_min_tension: f64,
    /// Mean torque of the tensioner spring on the arm carrying pulley j
    /// (0 without an arm) [N m].
    pub arm_mean_spring_torque: [f64; MAX_PULLEYS],
}

/// The values at one step endpoint.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Sample {
    span: [f64; MAX_PULLEYS],
    /// The belt's smallest tension, None until taken (a communication
    /// point's is taken when it is read: [`IntervalAccumulator::settle`]).
    belt_min: Option<f64>,
    arm: [f64; MAX_PULLEYS],
}

/// The two states an interval's start may be kept in (the drive owns
/// them): the start of the interval before stays intact while a call that
/// may fail writes the other.
pub type StartStates = [Vec<f64>; 2];

/// Accumulates [`IntervalOutputs`] over the endpoints of the integrator's
/// steps. Allocates nothing.
#[derive(Clone, Debug, PartialEq)]
pub struct IntervalAccumulator {
    /// Mid-points of the mounted free spans (span k from pulley k to k+1).
    span_mid: [[f64; 2]; MAX_PULLEYS],
    /// Spans with a free length.
    has_span: [bool; MAX_PULLEYS],
    /// The SDE found nearest each span's mid-point at the last endpoint.
    hint: [usize; MAX_PULLEYS],
    /// Time and values at the last endpoint.
    last_t: f64,
    last: Sample,
    /// `last` is the sample of the drive's state at `last_t` (false once
    /// the state may have been replaced: [`Self::invalidate`], [`Self::load`]).
    last_valid: bool,
    /// The belt's smallest tension at the interval's start is not taken
    /// yet; the start's state is in the drive's `StartStates[start_slot]`.
    start_pending: bool,
    start_slot: usize,
    /// ... nor at the last endpoint, a communication point: the drive's
    /// state now.
    end_pending: bool,
    /// Trapezoidal integrals since the interval's start.
    span_integral: [f64; MAX_PULLEYS],
    arm_integral: [f64; MAX_PULLEYS],
    start: f64,
    out: IntervalOutputs,
}

impl IntervalAccumulator {
    /// An accumulator for the spans whose mid-points are `span_mid`
    /// (`None`: no free span between pulleys k and k+1).
    pub fn new(span_mid: &[Option<[f64; 2]>]) -> Self {
        let mut mid = [[0.0; 2]; MAX_PULLEYS];
        let mut has = [false; MAX_PULLEYS];
        for (k, m) in span_mid.iter().enumerate().take(MAX_PULLEYS) {
            if let Some(m) = m {
                mid[k] = *m;
                has[k] = true;
            }
        }
        Self {
            span_mid: mid,
            has_span: has,
            hint: [0; MAX_PULLEYS],
            last_t: 0.0,
            last: Sample::default(),
            last_valid: false,
            start_pending: false,
            start_slot: 0,
            end_pending: false,
            span_integral: [0.0; MAX_PULLEYS],
            arm_integral: [0.0; MAX_PULLEYS],
            start: 0.0,
            out: IntervalOutputs::default(),
        }
    }

    /// Starts an interval at time `t`, state `y`: the outputs of an empty
    /// interval are the values at this instant.
    pub fn begin(&mut self, sys: &BeltSystem, t: f64, y: &[f64]) {
        let s = self.sample(sys, y, true);
        self.start_with(t, s);
    }

    /// [`Self::begin`] for the interval that follows the last one: where
    /// that ended at `t` and the state has not been replaced since
    /// ([`Self::invalidate`]), its end's sample is taken again (the pass
    /// over the bodies for the belt's smallest tension is what a short
    /// communication step would otherwise pay twice). Where that sample's
    /// smallest tension was not taken (nobody read it), `y` is kept in
    /// `starts` for when it is.
    pub fn continue_at(&mut self, sys: &BeltSystem, t: f64, y: &[f64], starts: &mut StartStates) {
        let s = if self.last_valid && self.last_t == t {
            self.last
        } else {
            self.sample(sys, y, true)
        };
        self.start_with(t, s);
        if s.belt_min.is_none() {
            let slot = 1 - self.start_slot;
            starts[slot].copy_from_slice(y);
            self.start_slot = slot;
            self.start_pending = true;
        }
    }

    fn start_with(&mut self, t: f64, s: Sample) {
        self.last_valid = true;
        self.start_pending = false;
        self.end_pending = false;
        self.start = t;
        self.last_t = t;
        self.last = s;
        self.span_integral = [0.0; MAX_PULLEYS];
        self.arm_integral = [0.0; MAX_PULLEYS];
        self.out = IntervalOutputs {
            span_mean_tension: s.span,
            span_min_tension: s.span,
            span_max_tension: s.span,
            belt_min_tension: s.belt_min.unwrap_or(f64::INFINITY),
            arm_mean_spring_torque: s.arm,
        };
    }

    /// The integrator reached time `t` (> the last endpoint's) with state `y`
    /// at the end of an accepted step.
    pub fn step_end(&mut self, sys: &BeltSystem, t: f64, y: &[f64]) {
        self.endpoint(sys, t, y, true);
    }

    /// The drive reached a communication point at time `t` with state `y`
    /// (its state from now on): as [`Self::step_end`], but the belt's
    /// smallest tension there is taken only when asked for
    /// ([`Self::settle`]), since a pass over the belt at every point is
    /// what short communication steps would otherwise pay for.
    pub fn point_end(&mut self, sys: &BeltSystem, t: f64, y: &[f64]) {
        self.endpoint(sys, t, y, false);
    }

    fn endpoint(&mut self, sys: &BeltSystem, t: f64, y: &[f64], belt: bool) {
        let dt = t - self.last_t;
        if dt <= 0.0 {
            return;
        }
        let s = self.sample(sys, y, belt);
        let np = sys.np;
        for k in 0..np {
            self.span_integral[k] += 0.5 * dt * (self.last.span[k] + s.span[k]);
            self.arm_integral[k] += 0.5 * dt * (self.last.arm[k] + s.arm[k]);
            self.out.span_min_tension[k] = self.out.span_min_tension[k].min(s.span[k]);
            self.out.span_max_tension[k] = self.out.span_max_tension[k].max(s.span[k]);
        }
        if let Some(b) = s.belt_min {
            self.out.belt_min_tension = self.out.belt_min_tension.min(b);
        }
        self.end_pending = s.belt_min.is_none();
        self.last_t = t;
        self.last = s;
        let span = t - self.start;
        for k in 0..np {
            self.out.span_mean_tension[k] = self.span_integral[k] / span;
            self.out.arm_mean_spring_torque[k] = self.arm_integral[k] / span;
        }
    }

    /// The drive's state `y` is about to be replaced (set, restored or a
    /// prescribed speed jumped) or the springs moved: the smallest tension
    /// still owed by the interval is taken from the states as they are
    /// ([`Self::settle`]), and the next [`Self::continue_at`] samples
    /// afresh.
    pub fn invalidate(&mut self, sys: &BeltSystem, starts: &StartStates, y: &[f64]) {
        self.settle(sys, starts, y);
        self.last_valid = false;
    }

    /// Takes the belt's smallest tension where the interval still owes it:
    /// at its start (kept in `starts`) and at its last endpoint (the
    /// drive's state `y`).
    pub fn settle(&mut self, sys: &BeltSystem, starts: &StartStates, y: &[f64]) {
        self.out.belt_min_tension = self.belt_min_tension(sys, starts, y);
        if self.last.belt_min.is_none() {
            // the last endpoint is the drive's state (a point's end, or
            // the start of an empty interval)
            self.last.belt_min = Some(belt_min(sys, y));
        }
        self.start_pending = false;
        self.end_pending = false;
    }

    /// The belt's smallest tension over the interval so far, the values
    /// still owed taken from `starts` and `y` ([`Self::settle`] keeps them).
    pub fn belt_min_tension(&self, sys: &BeltSystem, starts: &StartStates, y: &[f64]) -> f64 {
        let mut m = self.out.belt_min_tension;
        if self.start_pending {
            m = m.min(belt_min(sys, &starts[self.start_slot]));
        }
        if self.end_pending {
            m = m.min(belt_min(sys, y));
        }
        m
    }

    /// The outputs of the interval so far; the belt's smallest tension
    /// leaves out the values not yet taken ([`Self::belt_min_tension`]).
    pub fn outputs(&self) -> IntervalOutputs {
        self.out
    }

    /// The state a saved FMU state carries: the outputs, with the belt's
    /// smallest tension `belt_min` ([`Self::belt_min_tension`]), and the
    /// search hints (the integrals are folded into the outputs at every
    /// endpoint).
    pub fn save(&self, out: &mut Vec<f64>, belt_min: f64) {
        let o = &self.out;
        for a in [
            &o.span_mean_tension,
            &o.span_min_tension,
            &o.span_max_tension,
            &o.arm_mean_spring_torque,
        ] {
            out.extend_from_slice(a);
        }
        out.push(belt_min);
        out.extend(self.hint.iter().map(|&h| h as f64));
    }

    /// Restores what [`Self::save`] wrote; false if it does not fit.
    pub fn load(&mut self, src: &[f64], n_bodies: usize) -> bool {
        if src.len() != INTERVAL_DATA {
            return false;
        }
        let (arrays, rest) = src.split_at(4 * MAX_PULLEYS);
        let hints = &rest[1..];
        if hints
            .iter()
            .any(|h| !(h.is_finite() && *h >= 0.0 && (*h as usize) < n_bodies.max(1)))
        {
            return false;
        }
        self.last_valid = false;
        self.start_pending = false;
        self.end_pending = false;
        let o = &mut self.out;
        for (a, v) in [
            &mut o.span_mean_tension,
            &mut o.span_min_tension,
            &mut o.span_max_tension,
            &mut o.arm_mean_spring_torque,
        ]
        .into_iter()
        .zip(arrays.chunks_exact(MAX_PULLEYS))
        {
            a.copy_from_slice(v);
        }
        o.belt_min_tension = rest[0];
        for (h, v) in self.hint.iter_mut().zip(hints) {
            *h = *v as usize;
        }
        true
    }

    /// Span tensions, the belt's smallest tension (if `belt`) and the arms'
    /// spring torques at state `y`.
    fn sample(&mut self, sys: &BeltSystem, y: &[f64], belt: bool) -> Sample {
        let mut s = Sample {
            belt_min: belt.then(|| belt_min(sys, y)),
            ..Sample::default()
        };
        for k in 0..sys.np {
            if self.has_span[k] {
                let i = nearest_sde(sys, y, self.span_mid[k], self.hint[k]);
                self.hint[k] = i;
                s.span[k] = sde_tension(sys, y, i).0;
            }
            if let Some(arm) = &sys.pulleys[k].arm {
                s.arm[k] = arm.spring_torque(y[sys.state_layout().arm(k).angle]);
            }
        }
        s
    }
}

/// The smallest tension of the belt's translational SDEs at state `y`: one
/// pass over the bodies, each body's ends once, SDE i joining body i - 1's
/// end to body i's start.
fn belt_min(sys: &BeltSystem, y: &[f64]) -> f64 {
    let n = sys.n;
    let axial = sys.axial;
    let mut m = f64::INFINITY;
    let (mut prev_p, mut prev_v) = body_end(sys, y, n - 1, 1.0);
    for i in 0..n {
        let (b, sn, cs) = body_trig(y, i);
        let (hx, hy) = (sys.half_length * cs, sys.half_length * sn);
        let ([x, yy], [vx, vy], w) = (b.position(), b.velocity(), b.spin());
        let start = [x - hx, yy - hy];
        let start_v = [vx + w * hy, vy - w * hx];
        let d = [start[0] - prev_p[0], start[1] - prev_p[1]];
        let dd = [start_v[0] - prev_v[0], start_v[1] - prev_v[1]];
        let (d2, rate) = axial.rate(d, dd);
        m = m.min(axial.tension(d2, rate));
        prev_p = [x + hx, yy + hy];
        prev_v = [vx - w * hy, vy + w * hx];
    }
    m
}

/// The end of body `i` towards body `i + 1` (`sign` +1) or towards body
/// `i - 1` (-1), and that point's velocity.
#[inline]
fn body_end(sys: &BeltSystem, y: &[f64], i: usize, sign: f64) -> ([f64; 2], [f64; 2]) {
    let (b, sn, cs) = body_trig(y, i);
    let (hx, hy) = (sign * sys.half_length * cs, sign * sys.half_length * sn);
    let ([x, yy], [vx, vy], w) = (b.position(), b.velocity(), b.spin());
    ([x + hx, yy + hy], [vx - w * hy, vy + w * hx])
}

/// Body `i` of state `y` and the sine and cosine of its angle.
#[inline]
fn body_trig(y: &[f64], i: usize) -> (state::Body<'_>, f64, f64) {
    let b = state::body(y, i);
    let (sn, cs) = trig::sin_cos(b.angle());
    (b, sn, cs)
}

/// Tension of SDE `i` (joining body i - 1's end to body i's start, as the
/// right-hand side numbers them) at state `y`, and its middle.
#[inline]
fn sde_tension(sys: &BeltSystem, y: &[f64], i: usize) -> (f64, [f64; 2]) {
    let n = sys.n;
    let (p, c) = ((i + n - 1) % n, i);
    let (pp, pv) = body_end(sys, y, p, 1.0);
    let (cp, cv) = body_end(sys, y, c, -1.0);
    let d = [cp[0] - pp[0], cp[1] - pp[1]];
    let dd = [cv[0] - pv[0], cv[1] - pv[1]];
    let axial = sys.axial;
    let (d2, rate) = axial.rate(d, dd);
    let mid = [0.5 * (cp[0] + pp[0]), 0.5 * (cp[1] + pp[1])];
    (axial.tension(d2, rate), mid)
}

/// Squared distance of SDE `i`'s middle from `m`.
#[inline]
fn distance2(sys: &BeltSystem, y: &[f64], i: usize, m: [f64; 2]) -> f64 {
    let n = sys.n;
    let (p, c) = ((i + n - 1) % n, i);
    let (pp, _) = body_end(sys, y, p, 1.0);
    let (cp, _) = body_end(sys, y, c, -1.0);
    let mid = [0.5 * (cp[0] + pp[0]) - m[0], 0.5 * (cp[1] + pp[1]) - m[1]];
    mid[0] * mid[0] + mid[1] * mid[1]
}

/// The SDE whose middle lies nearest `m`: a descent along the chain from
/// `hint` (the mid-points of a free span's elements lie on a line, their
/// distance from `m` falls to the nearest and rises after it), checked
/// against a full scan when the descent ends more than a body length off.
fn nearest_sde(sys: &BeltSystem, y: &[f64], m: [f64; 2], hint: usize) -> usize {
    let n = sys.n;
    let mut i = hint % n;
    let mut best = distance2(sys, y, i, m);
    for dir in [1, n - 1] {
        loop {
            let j = (i + dir) % n;
            let d = distance2(sys, y, j, m);
            if d < best {
                (i, best) = (j, d);
            } else {
                break;
            }
        }
    }
    let l = 2.0 * sys.half_length;
    if best <= l * l {
        return i;
    }
    (0..n)
        .map(|j| (j, distance2(sys, y, j, m)))
        .fold((i, best), |a, b| if b.1 < a.1 { b } else { a })
        .0
}
