//! The mounted belt: the body length that carries the preload on the path,
//! each wrap's resting penetration, and the bodies placed as a closed chain
//! of chords along the path through their end points.

use super::*;

/// Arc pitch angle alpha at centre-path radius rho: the gap between body
/// ends on the arc, 2 rho sin(alpha/2) - l cos(alpha/2), carries the preload
/// (gap = l T0 / EA).
fn arc_pitch_angle(rho: f64, l: f64, strain: f64) -> f64 {
    let mut a = l * (1.0 + strain) / rho;
    for _ in 0..30 {
        let (s, c) = (0.5 * a).sin_cos();
        let f = 2.0 * rho * s - l * (c + strain);
        let df = rho * c + 0.5 * l * s;
        let step = f / df;
        a -= step;
        if step.abs() < 1e-15 * a.abs() {
            break;
        }
    }
    a
}

/// Sets each wrap's penetration and pitch angle for body length `l` and
/// returns the number of bodies the path holds.
fn bodies_on_path(params: &DriveParams, spans: &[Span], wraps: &mut [Wrap], l: f64) -> f64 {
    let b = &params.belt;
    let strain = b.preload / b.ea;
    let (c1, c2) = (params.contact.c1 * l, params.contact.c2 * l);
    // the contact law of one body (per-length stiffnesses times l)
    let law = ContactLaw { c1, c2, b: 0.0 };
    let mut count: f64 = spans.iter().map(|s| s.length / (l * (1.0 + strain))).sum();
    for w in wraps.iter_mut() {
        let r = params.pulleys[w.pulley].radius;
        let mut p = 0.0;
        let mut alpha = l / r;
        for _ in 0..8 {
            alpha = arc_pitch_angle(r - p, l, strain);
            // Radial resultant of the two neighbouring SDE forces (eq. 9 in equilibrium).
            let radial = 2.0 * b.preload * (0.5 * alpha).sin();
            p = law.penetration_for(radial).min(0.5 * r);
            if params.contact.points > 1 {
                // contact along the body: the centre sinks until the points'
                // radial resultant carries the load (elements::contact,
                // `resting_force`, monotonic in p), bracketed by the centre
                // contact's penetration (the outer points carry less)
                let points = params.contact.points;
                p = bracketed_root(
                    |q| resting_force(&law, r, q, 0.5 * l, points) - radial,
                    p,
                    0.5 * r,
                );
            }
        }
        w.penetration = p;
        w.pitch_angle = alpha;
        count += w.angle / alpha;
    }
    count
}

pub(super) fn solve_body_length(
    params: &DriveParams,
    spans: &[Span],
    wraps: &mut [Wrap],
    path_length: f64,
) -> Result<f64, ParamError> {
    let n = params.belt.n_bodies as f64;
    // The count of bodies the path holds falls monotonically with l.
    let l = bracketed_root(
        |l| bodies_on_path(params, spans, wraps, l) - n,
        0.25 * path_length / n,
        2.0 * path_length / n,
    );
    // Leave every wrap's penetration and pitch set for the final l.
    bodies_on_path(params, spans, wraps, l);
    if !(l.is_finite() && l > 0.0) {
        return Err(param_error(
            Param::BeltBodies,
            "no body length fits the belt path",
        ));
    }
    Ok(l)
}

/// The root of `f` between `lo` and `hi`, where `f` changes sign, to a few
/// ulps (Alefeld, Potra and Shi's algorithm 748, which converges in a handful
/// of evaluations where bisection needs fifty). Where `f` keeps its sign,
/// the end nearer a root (as bisection would end there); NaN where `f` is
/// not finite, which the callers refuse.
fn bracketed_root(f: impl FnMut(f64) -> f64, lo: f64, hi: f64) -> f64 {
    match root1d::toms748(f, lo, hi).atol(0.0).maxiter(200).root() {
        Ok(x) => x,
        Err(root1d::Error::NoSignChange { a, fa, b, fb }) => {
            if fa.abs() <= fb.abs() {
                a
            } else {
                b
            }
        }
        Err(_) => f64::NAN,
    }
}

/// The path through the body end points: spans and arcs in loop order, by
/// arc length. Every SDE gap and every body is a chord of this path, so the
/// mounted chain has no kink; on an arc of radius rho_e a body of length l
/// has its centre at sqrt(rho_e^2 - l^2/4), which is set to the equilibrium
/// radius r - p0.
struct EndPath {
    /// Per segment: start arc length, length, heading at start, and for arcs
    /// the centre, radius and side.
    segs: Vec<Segment>,
    length: f64,
}

#[derive(Clone, Copy)]
enum Segment {
    Line {
        s0: f64,
        heading: f64,
        start: [f64; 2],
        dir: [f64; 2],
        /// Free length L [m].
        len: f64,
        /// The static sag's shape under gravity: the point at d along the
        /// line lies `sag d (L - d)` off it along `down`.
        sag: f64,
        down: [f64; 2],
    },
    Arc {
        s0: f64,
        len: f64,
        heading: f64,
        centre: [f64; 2],
        radius: f64,
        side: f64,
    },
}

impl EndPath {
    fn new(params: &DriveParams, spans: &[Span], wraps: &[Wrap], radii: &[f64]) -> Self {
        let mut s = 0.0;
        let mut heading = spans[0].angle;
        let mut segs = Vec::new();
        // A string of mass per length rho' under tension T0 and the load
        // rho' g_n across it (g_n the part of gravity across the span)
        // hangs in the parabola w(d) = rho' g_n d (L - d) / (2 T0), the
        // catenary within (sag / L)^2: the bodies are placed on it, so the
        // belt starts at its static sag instead of falling at t = 0.
        let b = &params.belt;
        let rho = b.mass_per_length / (1.0 + b.preload / b.ea);
        for (sp, w) in spans.iter().zip(wraps) {
            // mid-span sag rho' g_n L^2 / (8 T0) (`sag_shape`)
            let (sag, down) = sag_shape(params, sp, rho, b.preload);
            segs.push(Segment::Line {
                s0: s,
                heading,
                start: sp.start,
                dir: [sp.angle.cos(), sp.angle.sin()],
                len: sp.length,
                sag,
                down,
            });
            s += sp.length;
            let p = &params.pulleys[w.pulley];
            let radius = radii[w.pulley];
            segs.push(Segment::Arc {
                s0: s,
                len: radius * w.angle,
                heading,
                centre: [p.x, p.y],
                radius,
                side: w.side,
            });
            s += radius * w.angle;
            heading += w.side * w.angle;
        }
        Self { segs, length: s }
    }

    /// Point and continuous heading at arc length `s` (periodic in s).
    fn at(&self, s: f64) -> ([f64; 2], f64) {
        let turns = (s / self.length).floor();
        let s = s - turns * self.length;
        let extra = turns * TAU;
        let k = self
            .segs
            .partition_point(|g| match *g {
                Segment::Line { s0, .. } | Segment::Arc { s0, .. } => s0 <= s,
            })
            .max(1)
            - 1;
        match self.segs[k] {
            Segment::Line {
                s0,
                heading,
                start,
                dir,
                len,
                sag,
                down,
            } => {
                let d = s - s0;
                let w = sag * d.clamp(0.0, len) * (len - d).clamp(0.0, len);
                (
                    [
                        start[0] + d * dir[0] + w * down[0],
                        start[1] + d * dir[1] + w * down[1],
                    ],
                    heading + extra,
                )
            }
            Segment::Arc {
                s0,
                heading,
                centre,
                radius,
                side,
                len,
            } => {
                let a = heading + side * (s - s0).min(len) / radius;
                (
                    [
                        centre[0] + side * radius * a.sin(),
                        centre[1] - side * radius * a.cos(),
                    ],
                    a + extra,
                )
            }
        }
    }

    /// Arc length past `a` where the chord from the path point at `a` has
    /// length `chord` (monotonic for chords short against the radii).
    fn chord_end(&self, a: f64, chord: f64) -> f64 {
        let pa = self.at(a).0;
        bracketed_root(
            |s| {
                let ps = self.at(s).0;
                (ps[0] - pa[0]).hypot(ps[1] - pa[1]) - chord
            },
            a,
            a + 2.0 * chord + 1e-12,
        )
    }

    /// Chains `n` bodies of length l with gaps `gap` from arc length 0;
    /// writes (left, right) end arc lengths and returns the closing error:
    /// the arc length left for the last gap minus the one that gap needs.
    fn chain(&self, n: usize, l: f64, gap: f64, out: &mut Vec<(f64, f64)>) -> f64 {
        out.clear();
        let mut left = 0.0;
        for i in 0..n {
            let right = self.chord_end(left, l);
            out.push((left, right));
            if i + 1 < n {
                left = self.chord_end(right, gap);
            }
        }
        let last = out[n - 1].1;
        (self.length - last) - (self.chord_end(last, gap) - last)
    }
}

/// Places the bodies with end points on the end path, every body a chord of
/// length l and every gap a chord carrying exactly the preload
/// (gap = l T0 / EA), adjusting l so the chain closes. Returns (l, poses).
pub(super) fn place_bodies(
    params: &DriveParams,
    spans_wraps: impl Fn(f64) -> Result<(Vec<Span>, Vec<Wrap>, Vec<f64>), ParamError>,
    l_guess: f64,
) -> Result<(f64, Vec<BodyPose>), ParamError> {
    let n = params.belt.n_bodies;
    let strain = params.belt.preload / params.belt.ea;
    let (spans, wraps, radii) = spans_wraps(l_guess)?;
    let path = EndPath::new(params, &spans, &wraps, &radii);
    let mut ends = Vec::with_capacity(n);
    // The closing error falls as l grows; bracket around the guess.
    let l = bracketed_root(
        |l| path.chain(n, l, l * strain, &mut ends),
        0.95 * l_guess,
        1.05 * l_guess,
    );
    path.chain(n, l, l * strain, &mut ends);
    let bodies = ends
        .iter()
        .map(|&(a, b)| {
            let (pa, pb) = (path.at(a).0, path.at(b).0);
            let h = path.at(0.5 * (a + b)).1;
            let chord = (pb[1] - pa[1]).atan2(pb[0] - pa[0]);
            let d = chord - h;
            BodyPose {
                x: 0.5 * (pa[0] + pb[0]),
                y: 0.5 * (pa[1] + pb[1]),
                phi: h + wrap_angle(d),
            }
        })
        .collect();
    Ok((l, bodies))
}
