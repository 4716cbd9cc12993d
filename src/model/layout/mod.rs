//! Belt path and initial assembly (the drive "as mounted").
//!
//! From pulley centres, radii and wrap sides: the common tangents (free
//! spans) and wrap arcs of the belt path, the body length that gives the
//! requested preload, and the bodies placed along the path in static
//! equilibrium (pitch stretched by the preload on spans and arcs, centres
//! pressed into the pulleys by the equilibrium penetration).
//!
//! The path is traversed counterclockwise around the loop. A pulley inside
//! the loop is wrapped counterclockwise (side s = +1), a back-side idler
//! clockwise (s = -1). A belt point on pulley j with travel direction t is
//! `c_j - s_j r_j n(t)`, n(t) the left normal of t.

use crate::model::elements::contact::{resting_force, ContactLaw};
use crate::model::elements::tensioner::Arm;
use crate::model::param_id::{msg, Param, Part};
use crate::model::params::{param_error, DriveParams, ParamError, MAX_BODIES};
use crate::model::system::wrap_angle;
use std::f64::consts::TAU;

mod bodies;
mod installation;

use bodies::{place_bodies, solve_body_length};
pub use installation::{installed, installed_arm_angle, natural_length, pitch_length};

/// A free span: the common tangent from one pulley to the next.
#[derive(Clone, Debug, PartialEq)]
pub struct Span {
    /// Pulley (index into `DriveParams::pulleys`) the span leaves and reaches.
    pub from: usize,
    /// Pulley the span reaches.
    pub to: usize,
    /// Tangent point where the span leaves `from` [m].
    pub start: [f64; 2],
    /// Tangent point where the span reaches `to` [m].
    pub end: [f64; 2],
    /// Direction angle of travel (loop order) [rad].
    pub angle: f64,
    /// Free length [m].
    pub length: f64,
}

impl Span {
    /// Mid-point of the span [m].
    pub fn midpoint(&self) -> [f64; 2] {
        [
            0.5 * (self.start[0] + self.end[0]),
            0.5 * (self.start[1] + self.end[1]),
        ]
    }
}

/// The wrap of the belt on one pulley.
#[derive(Clone, Debug, PartialEq)]
pub struct Wrap {
    /// The pulley (index into `DriveParams::pulleys`).
    pub pulley: usize,
    /// +1 inside the loop (counterclockwise wrap), -1 back-side idler.
    pub side: f64,
    /// Wrap angle [rad].
    pub angle: f64,
    /// Travel direction angle where the belt arrives on the pulley [rad].
    pub arrive: f64,
    /// Equilibrium penetration of a body under the preload [m].
    pub penetration: f64,
    /// Angle between neighbouring body centres on the arc [rad].
    pub pitch_angle: f64,
}

/// Initial pose of one body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyPose {
    /// Centre x [m].
    pub x: f64,
    /// Centre y [m].
    pub y: f64,
    /// Orientation, continuous along the loop (grows by 2*pi once around).
    pub phi: f64,
}

#[derive(Clone, Debug, PartialEq)]
/// The mounted belt: path around the pulleys and the bodies placed on it.
pub struct Layout {
    /// Spans in loop order; `spans[m]` leaves `wraps[m].pulley`... see `span_of_pair`.
    pub spans: Vec<Span>,
    /// Wraps in loop order: wraps[m] is the arc at the end of spans[m].
    pub wraps: Vec<Wrap>,
    /// Natural (unstretched) body length [m].
    pub body_length: f64,
    /// Length of the belt path through the contact line [m].
    pub path_length: f64,
    /// Mounted pose of every body, in belt order.
    pub bodies: Vec<BodyPose>,
    /// The line the body centres of each free span lie on, in the order of
    /// `spans`: the common tangent of the circles the body ends run on
    /// (radius sqrt(rho^2 + l^2/4), rho = r - p0 the body centres' radius on
    /// the arc), outside `spans` by about l^2 / (8 rho), the chordal offset
    /// of the bodies on the arcs. The span's deflection is measured from it.
    pub lines: Vec<Span>,
}

fn left_normal(a: f64) -> [f64; 2] {
    [-a.sin(), a.cos()]
}

fn dist_point_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1]];
    let ap = [p[0] - a[0], p[1] - a[1]];
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    let s = if len2 > 0.0 {
        ((ap[0] * ab[0] + ap[1] * ab[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (ap[0] - s * ab[0]).hypot(ap[1] - s * ab[1])
}

fn segments_cross(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let orient = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    };
    let (o1, o2) = (orient(a, b, c), orient(a, b, d));
    let (o3, o4) = (orient(c, d, a), orient(c, d, b));
    o1 * o2 < 0.0 && o3 * o4 < 0.0
}

/// Spans and wraps of a belt path, in loop order.
type BeltPath = (Vec<Span>, Vec<Wrap>);

/// Spans and wrap angles for pulleys visited in `order`; `None` if the
/// visiting order does not give a simple counterclockwise loop.
fn path_for_order(
    params: &DriveParams,
    radii: &[f64],
    order: &[usize],
) -> Result<Option<BeltPath>, ParamError> {
    let np = order.len();
    let side = |j: usize| {
        if params.pulleys[j].back_side {
            -1.0
        } else {
            1.0
        }
    };
    let mut spans = Vec::with_capacity(np);
    for m in 0..np {
        let (a, b) = (order[m], order[(m + 1) % np]);
        let (pa, pb) = (&params.pulleys[a], &params.pulleys[b]);
        let (ra, rb) = (radii[a], radii[b]);
        let d = [pb.x - pa.x, pb.y - pa.y];
        let dist = d[0].hypot(d[1]);
        let k = side(b) * rb - side(a) * ra;
        if k.abs() >= dist {
            return Err(param_error(
                Param::PulleyBackSide(b),
                msg![
                    "no common tangent from ",
                    Part::Pulley(a),
                    " to ",
                    Part::Pulley(b),
                    format!(
                        ": the belt path cannot be wrapped with these wrap sides (centre \
                         distance {dist:.4} m must exceed {:.4} m)",
                        k.abs()
                    ),
                ],
            ));
        }
        let angle = d[1].atan2(d[0]) - (k / dist).asin();
        let n = left_normal(angle);
        let start = [pa.x - side(a) * ra * n[0], pa.y - side(a) * ra * n[1]];
        let end = [pb.x - side(b) * rb * n[0], pb.y - side(b) * rb * n[1]];
        spans.push(Span {
            from: a,
            to: b,
            start,
            end,
            angle,
            length: (dist * dist - k * k).sqrt(),
        });
    }
    let mut wraps = Vec::with_capacity(np);
    let mut turning = 0.0;
    for m in 0..np {
        let j = spans[m].to;
        let s = side(j);
        let angle = (s * (spans[(m + 1) % np].angle - spans[m].angle)).rem_euclid(TAU);
        turning += s * angle;
        wraps.push(Wrap {
            pulley: j,
            side: s,
            angle,
            arrive: spans[m].angle,
            penetration: 0.0,
            pitch_angle: 0.0,
        });
    }
    // A simple loop traversed counterclockwise turns by exactly +2*pi.
    if (turning - TAU).abs() > 1e-6 {
        return Ok(None);
    }
    Ok(Some((spans, wraps)))
}

/// Spans and wraps for the pulleys in their listed belt order, taken
/// either way round the loop.
fn path_in_belt_order(
    params: &DriveParams,
    radii: &[f64],
) -> Result<(Vec<Span>, Vec<Wrap>), ParamError> {
    let np = params.pulleys.len();
    let forward: Vec<usize> = (0..np).collect();
    let backward: Vec<usize> = (0..np).rev().collect();
    let (spans, wraps) = match path_for_order(params, radii, &forward)? {
        Some(p) => p,
        None => path_for_order(params, radii, &backward)?.ok_or_else(|| {
            param_error(
                Param::PulleyBackSide(0),
                "the pulleys, in the listed order and wrap sides, do not form a simple closed \
                 belt loop (check the order and which pulleys are back-side idlers)",
            )
        })?,
    };
    for w in &wraps {
        if w.angle < 1e-3 {
            return Err(param_error(
                Param::PulleyBackSide(w.pulley),
                msg![
                    "the belt does not wrap ",
                    Part::Pulley(w.pulley),
                    format!(" (wrap angle {:.2e} rad)", w.angle),
                ],
            ));
        }
    }
    Ok((spans, wraps))
}

/// Spans must not run through other pulleys or cross each other.
fn check_spans(params: &DriveParams, spans: &[Span]) -> Result<(), ParamError> {
    for (m, s) in spans.iter().enumerate() {
        for (j, p) in params.pulleys.iter().enumerate() {
            if j != s.from && j != s.to && dist_point_segment([p.x, p.y], s.start, s.end) < p.radius
            {
                return Err(param_error(
                    Param::PulleyX(j),
                    msg![
                        "the span from ",
                        Part::Pulley(s.from),
                        " to ",
                        Part::Pulley(s.to),
                        " runs through ",
                        Part::Pulley(j),
                    ],
                ));
            }
        }
        for q in spans.iter().skip(m + 2) {
            if q.to != s.from && segments_cross(s.start, s.end, q.start, q.end) {
                return Err(param_error(
                    Param::PulleyX(q.from),
                    msg![
                        "the spans ",
                        Part::Pulley(s.from),
                        "->",
                        Part::Pulley(s.to),
                        " and ",
                        Part::Pulley(q.from),
                        "->",
                        Part::Pulley(q.to),
                        " cross",
                    ],
                ));
            }
        }
    }
    Ok(())
}

/// The refusal of a drive whose pulley centres look typed in millimetres:
/// read as millimetres, every centre coordinate of 1 m or more gives a drive
/// the mesh resolves. Names the largest coordinate; `None` if there is none
/// or the drive would still be refused.
fn millimetre_positions(params: &DriveParams, path_length: f64) -> Option<ParamError> {
    let mut scaled = params.clone();
    let mut largest: Option<(Param, f64)> = None;
    for (j, q) in scaled.pulleys.iter_mut().enumerate() {
        for (id, v) in [(Param::PulleyX(j), &mut q.x), (Param::PulleyY(j), &mut q.y)] {
            if v.abs() >= 1.0 {
                if largest.is_none_or(|(_, big)| v.abs() > big.abs()) {
                    largest = Some((id, *v));
                }
                *v *= 1e-3;
            }
        }
    }
    let (id, v) = largest?;
    Layout::build(&scaled, false).ok()?;
    Some(param_error(
        id,
        msg![format!(
            "{v} m makes a belt of {path_length:.1} m, which no mesh of at most {MAX_BODIES} bodies \
             resolves on these pulleys; positions are in metres: if {v} was meant in millimetres, \
             set {}",
            v * 1e-3
        )],
    ))
}

/// A span's static sag under gravity: the coefficient s of the parabola
/// w(d) = s d (L - d) (s = rho' g_n / (2 T), rho' the mass per stretched
/// length, g_n the part of gravity across the span; the catenary within
/// (sag / L)^2) and the span's normal on gravity's side. A span without
/// tension, or so slack that its sag exceeds a twentieth of the span
/// (beyond the shallow string), gets s = 0: it is mounted straight.
fn sag_shape(params: &DriveParams, sp: &Span, rho: f64, tension: f64) -> (f64, [f64; 2]) {
    let dir = [sp.angle.cos(), sp.angle.sin()];
    // the span's normal on gravity's side (gravity acts in -y)
    let down = if dir[0] >= 0.0 {
        [dir[1], -dir[0]]
    } else {
        [-dir[1], dir[0]]
    };
    let g_n = -params.gravity * down[1];
    let sag = rho * g_n / (2.0 * tension);
    let shallow = tension > 0.0 && sag * sp.length <= 0.2;
    (if shallow { sag } else { 0.0 }, down)
}

/// Two pulleys must not overlap; a radius that reaches the other pulley is
/// named as the likely mistake (millimetres).
fn check_overlaps(params: &DriveParams) -> Result<(), ParamError> {
    let np = params.pulleys.len();
    for a in 0..np {
        for b in a + 1..np {
            let (pa, pb) = (&params.pulleys[a], &params.pulleys[b]);
            let dist = (pb.x - pa.x).hypot(pb.y - pa.y);
            if dist <= pa.radius + pb.radius {
                // A radius that alone reaches the other pulley's centre
                // and is ten times the other's is the implausible number
                // (typically typed in millimetres), not the position.
                let (k, r, r_other) = if pa.radius >= pb.radius {
                    (a, pa.radius, pb.radius)
                } else {
                    (b, pb.radius, pa.radius)
                };
                if r >= dist && r >= 10.0 * r_other {
                    let other = if k == a { b } else { a };
                    let unit = if r >= 1.0 {
                        format!(
                            "; radii are in metres: if {r} was meant in millimetres, \
                             set {}",
                            r * 1e-3
                        )
                    } else {
                        String::new()
                    };
                    return Err(param_error(
                        Param::PulleyRadius(k),
                        msg![
                            format!("{r} m must be less than the centre distance {dist:.4} m to "),
                            Part::Pulley(other),
                            unit,
                        ],
                    ));
                }
                return Err(param_error(
                    Param::PulleyX(b),
                    msg![
                        Part::Pulley(b),
                        " overlaps ",
                        Part::Pulley(a),
                        format!(
                            ": centre distance {dist:.4} m must exceed the sum of radii \
                             {:.4} m",
                            pa.radius + pb.radius
                        ),
                    ],
                ));
            }
        }
    }
    Ok(())
}

impl Layout {
    /// Builds the belt path and the mounted belt. `params` must have passed
    /// [`DriveParams::validate`].
    pub fn new(params: &DriveParams) -> Result<Self, ParamError> {
        Self::build(params, true)
    }

    /// [`new`](Self::new); `diagnose` lets a refusal for a coarse mesh try
    /// the other wrap side of the pulley (once: not when called for that).
    fn build(params: &DriveParams, diagnose: bool) -> Result<Self, ParamError> {
        check_overlaps(params)?;
        // The path of the body centres runs around circles shrunk by the
        // equilibrium penetration (so spans and arcs meet without a step);
        // that penetration depends on the body length: iterate.
        let mut radii: Vec<f64> = params.pulleys.iter().map(|p| p.radius).collect();
        let mut result = None;
        for _ in 0..4 {
            let (spans, mut wraps) = path_in_belt_order(params, &radii)?;
            let path_length: f64 = spans.iter().map(|s| s.length).sum::<f64>()
                + wraps.iter().map(|w| w.angle * radii[w.pulley]).sum::<f64>();
            let body_length = solve_body_length(params, &spans, &mut wraps, path_length)?;
            for w in &wraps {
                radii[w.pulley] = params.pulleys[w.pulley].radius - w.penetration;
            }
            result = Some((spans, wraps, path_length, body_length));
        }
        let (spans, wraps, path_length, body_length) = result.expect("at least one iteration");
        check_spans(params, &spans)?;

        Self::check_wraps_resolved(params, &wraps, path_length, body_length, diagnose)?;
        // End points run on circles of radius sqrt(rho^2 + l^2/4) around the
        // pulleys, so body centres sit at the equilibrium radius rho = r - p0.
        let end_path = |l: f64| {
            let mut radii_e = vec![0.0; params.pulleys.len()];
            for w in &wraps {
                let rho = params.pulleys[w.pulley].radius - w.penetration;
                radii_e[w.pulley] = (rho * rho + 0.25 * l * l).sqrt();
            }
            let (spans_e, wraps_e) = path_in_belt_order(params, &radii_e)?;
            Ok((spans_e, wraps_e, radii_e))
        };
        let (body_length, bodies) = place_bodies(params, end_path, body_length)?;
        let (lines, _, _) = end_path(body_length)?;
        Ok(Self {
            spans,
            wraps,
            body_length,
            path_length,
            bodies,
            lines,
        })
    }

    /// Every wrap must be resolved by a few bodies and no body may span a
    /// large part of a pulley: the refusal names the likely mistake
    /// (millimetres, the wrap side, or the body count). `diagnose` as in
    /// [`build`](Self::build).
    fn check_wraps_resolved(
        params: &DriveParams,
        wraps: &[Wrap],
        path_length: f64,
        body_length: f64,
        diagnose: bool,
    ) -> Result<(), ParamError> {
        for w in wraps {
            let per_arc = w.angle / w.pitch_angle;
            // A body longer than the pulley's diameter has no pitch angle at
            // all (NaN or negative): also too coarse.
            let resolved = w.pitch_angle > 0.0 && w.pitch_angle <= 0.5 && per_arc >= 3.0;
            if !resolved {
                let n = params.belt.n_bodies;
                let r = params.pulleys[w.pulley].radius;
                // Longest body that meets both conditions on this wrap.
                let l_max = r * (w.angle / 3.0).min(0.5);
                let needed = (path_length / l_max).ceil();
                // More bodies than allowed: a belt far longer than its
                // pulleys are wide, typically centres typed in millimetres.
                // If the drive with every coordinate of 1 m or more read as
                // millimetres is one this mesh resolves, the largest of them
                // is named.
                if diagnose && needed > MAX_BODIES as f64 {
                    if let Some(e) = millimetre_positions(params, path_length) {
                        return Err(e);
                    }
                }
                // A small wrap may be an idler on the wrong side of the belt:
                // if the other wrap side gives a drive this mesh resolves,
                // the flag is the likely mistake.
                if diagnose {
                    let mut flipped = params.clone();
                    let q = &mut flipped.pulleys[w.pulley];
                    q.back_side = !q.back_side;
                    if let Ok(other) = Self::build(&flipped, false) {
                        let side = |b: bool| if b { "true" } else { "false" };
                        let back = params.pulleys[w.pulley].back_side;
                        let wrap = other.wrap_of(w.pulley).map_or(0.0, |w| w.angle);
                        return Err(param_error(
                            Param::PulleyBackSide(w.pulley),
                            msg![
                                format!("with backSide = {} the belt wraps ", side(back)),
                                Part::Pulley(w.pulley),
                                format!(
                                    " by only {:.0} deg, too little for {n} bodies of {:.1} mm; \
                                     with backSide = {} (the belt's {} on it) it wraps {:.0} deg \
                                     and the mesh resolves it. Check which side of the belt \
                                     touches ",
                                    w.angle.to_degrees(),
                                    body_length * 1e3,
                                    side(!back),
                                    if back { "inner side" } else { "back" },
                                    wrap.to_degrees(),
                                ),
                                Part::Pulley(w.pulley),
                                format!("; to keep backSide = {} use ", side(back)),
                                Param::BeltBodies,
                                format!(
                                    " >= {}",
                                    (path_length / (r * (w.angle / 3.0).min(0.5))).ceil() as usize
                                ),
                            ],
                        ));
                    }
                }
                return Err(param_error(
                    Param::BeltBodies,
                    msg![
                        format!(
                            "{n} bodies of {:.1} mm are too coarse for the {:.0} deg wrap of ",
                            body_length * 1e3,
                            w.angle.to_degrees(),
                        ),
                        Part::Pulley(w.pulley),
                        format!(
                            " (radius {:.1} mm): at least 3 bodies per wrap and at most 29 deg \
                             of arc each are needed: use ",
                            r * 1e3,
                        ),
                        Param::BeltBodies,
                        format!(" >= {}", needed as usize),
                    ],
                ));
            }
        }
        Ok(())
    }

    /// The free span from pulley `a` to pulley `b` in the listed belt order
    /// (the loop may have been traversed the other way round).
    pub fn span_between(&self, a: usize, b: usize) -> Option<&Span> {
        let forward = self.spans.iter().find(|s| s.from == a && s.to == b);
        forward.or_else(|| self.spans.iter().find(|s| s.from == b && s.to == a))
    }

    /// The line of the body centres in the free span from pulley `a` to
    /// pulley `b` ([`Self::lines`]), as [`Self::span_between`] finds spans.
    pub fn line_between(&self, a: usize, b: usize) -> Option<&Span> {
        let forward = self.lines.iter().find(|s| s.from == a && s.to == b);
        forward.or_else(|| self.lines.iter().find(|s| s.from == b && s.to == a))
    }

    /// The wrap on `pulley`, if the belt wraps it.
    pub fn wrap_of(&self, pulley: usize) -> Option<&Wrap> {
        self.wraps.iter().find(|w| w.pulley == pulley)
    }
}
