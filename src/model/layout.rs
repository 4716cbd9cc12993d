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

/// The drive as installed: with `belt.natural_length` given (> 0), the
/// parameters with the preload replaced by the installation tension of a
/// belt of that natural length, and the length cleared; with a tensioner
/// spring given by its nominal torque (`TensionerArm::nominal`), the arm
/// turned to where that spring balances the belt; otherwise `params`
/// unchanged. `params` must have passed [`DriveParams::validate`].
///
/// The tension is the continuum's: T = EA (L_p(T) / L0 - 1), L_p the belt's
/// path at its pitch line ([`pitch_length`]: the pulleys' radii, each span
/// with its static sag, which shortens as T grows). It does not depend on
/// the mesh or the contact stiffness; the mounted chain then carries T
/// (docs/model.md "Layout and preload"). T - EA (L_p(T) / L0 - 1) grows
/// with T (an arm that yields shortens the path): bisection.
///
/// An arm on a nominal spring sits where its spring and stops balance the
/// moment of the belt's hub force T (u_out - u_in) about the pivot (u the
/// spans' directions of travel; the static sag's tilt of the spans, below
/// 1e-3 rad, left out), found by bisection at each tension (several such
/// arms: in turn until none moves). The installed parameters have the arm
/// drawn there: its pulley centre turned by the arm's angle, its stops and
/// nominal angle counted from it ([`installed_arm_angle`] recovers the
/// angle).
pub fn installed(params: &DriveParams) -> Result<std::borrow::Cow<'_, DriveParams>, ParamError> {
    let target = params.belt.natural_length;
    let mut arms = NominalArms::new(params)?;
    if target <= 0.0 && arms.0.is_empty() {
        return Ok(std::borrow::Cow::Borrowed(params));
    }
    // With an arm whose spring follows from the preload, the arm's angle
    // would be a second unknown without the spring to find it.
    if target > 0.0 {
        if let Some(j) = params
            .pulleys
            .iter()
            .position(|p| p.arm.is_some_and(|a| a.nominal.is_none()))
        {
            return Err(param_error(
                Param::BeltNaturalLength,
                msg![
                    "needs the tensioner's spring as built (",
                    Param::PulleyArmNominalTorque(j),
                    " at ",
                    Param::PulleyArmNominalAngle(j),
                    "): without it the spring's free angle follows from the installation \
                     tension, so ",
                    Param::BeltPreload,
                    " must set the tension",
                ],
            ));
        }
    }
    let mut p = params.clone();
    p.belt.natural_length = 0.0;
    if target <= 0.0 {
        arms.balance(&mut p, params.belt.preload)?;
        arms.draw_installed(&mut p);
        return Ok(std::borrow::Cow::Owned(p));
    }
    let ea = params.belt.ea;
    let fixed = if arms.0.is_empty() {
        Some(PitchPath::new(params)?)
    } else {
        None
    };
    // the belt path at tension t, the arms balanced at t; 0 when an arm
    // finds no balance at a tension above 0: the belt would push it beyond
    // any, so the belt's tension is lower
    let mut path_at = |q: &mut DriveParams, t: f64| -> Result<f64, ParamError> {
        match &fixed {
            Some(path) => Ok(path.length(params, t)),
            None => match arms.balance(q, t) {
                Ok(()) => Ok(PitchPath::new(q)?.length(q, t)),
                Err(_) if t > 0.0 => Ok(0.0),
                Err(e) => Err(e),
            },
        }
    };
    let straight = path_at(&mut p, 0.0)?;
    if straight <= target {
        return Err(param_error(
            Param::BeltNaturalLength,
            format!(
                "a belt of {target} m must be shorter than its path round the pulleys at their \
                 radii ({straight:.6} m), else it hangs slack: give a shorter belt or move the \
                 pulleys apart"
            ),
        ));
    }
    let (mut lo, mut hi) = (0.0, 0.5 * ea);
    if hi - ea * (path_at(&mut p, hi)? / target - 1.0) <= 0.0 {
        return Err(param_error(
            Param::BeltNaturalLength,
            msg![
                format!(
                    "a belt of {target} m stretched onto its {straight:.6} m path would carry \
                     more than half of "
                ),
                Param::BeltEa,
                ": it must be longer (lengths are in metres), or the pulleys closer",
            ],
        ));
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid - ea * (path_at(&mut p, mid)? / target - 1.0) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
        if hi - lo <= 1e-14 * ea {
            break;
        }
    }
    p.belt.preload = 0.5 * (lo + hi);
    if !arms.0.is_empty() {
        let t = p.belt.preload;
        arms.balance(&mut p, t)?;
        arms.draw_installed(&mut p);
    }
    Ok(std::borrow::Cow::Owned(p))
}

/// Angle of the installed arm of pulley `j` from where `params` draws it
/// (`pulley[j].arm.installedAngle`): the turn about the pivot from the
/// centre in `params` to the one in `installed` (their [`installed`]
/// parameters), counterclockwise positive; 0 without an arm.
pub fn installed_arm_angle(params: &DriveParams, installed: &DriveParams, j: usize) -> f64 {
    let (Some(a), Some(b)) = (params.pulleys.get(j), installed.pulleys.get(j)) else {
        return 0.0;
    };
    let Some(arm) = a.arm else {
        return 0.0;
    };
    let (u, v) = (
        [a.x - arm.pivot[0], a.y - arm.pivot[1]],
        [b.x - arm.pivot[0], b.y - arm.pivot[1]],
    );
    (u[0] * v[1] - u[1] * v[0]).atan2(u[0] * v[0] + u[1] * v[1])
}

/// Tensioner arms whose spring is given by its nominal torque: each one's
/// law in the frame of the arm as drawn (the spring's free angle set) and
/// its angle from there.
struct NominalArms(Vec<(usize, Arm, f64)>);

/// Step of the search for an arm's balance [rad].
const ARM_SEARCH_STEP: f64 = 0.01;

impl NominalArms {
    fn new(params: &DriveParams) -> Result<Self, ParamError> {
        let mut arms = Vec::new();
        for (j, q) in params.pulleys.iter().enumerate() {
            let Some(a) = q.arm.as_ref().filter(|a| a.nominal.is_some()) else {
                continue;
            };
            let mut law = Arm::new(a, [q.x, q.y]);
            // which way the belt turns the arm, from the drawn path: the
            // spring turns it back
            let m = Self::hub_moment(&mut params.clone(), j, &law, 0.0, 1.0)?;
            if m.abs() < 1e-9 * law.length {
                return Err(param_error(
                    Param::PulleyArmNominalTorque(j),
                    msg![
                        "cannot be applied: the belt's hub force on ",
                        Part::Pulley(j),
                        " passes through the arm's pivot (",
                        Param::PulleyArmPivotX(j),
                        ", ",
                        Param::PulleyArmPivotY(j),
                        "), so the spring has no side to press the pulley to",
                    ],
                ));
            }
            law.free_angle = law.free_angle_for(m);
            arms.push((j, law, 0.0));
        }
        Ok(Self(arms))
    }

    /// Moment about the pivot of the belt's hub force on pulley `j` at
    /// tension `t` with the arm at `angle` (`q`'s pulley `j` moved there).
    fn hub_moment(
        q: &mut DriveParams,
        j: usize,
        law: &Arm,
        angle: f64,
        t: f64,
    ) -> Result<f64, ParamError> {
        let (c, _) = law.centre(angle);
        q.pulleys[j].x = c[0];
        q.pulleys[j].y = c[1];
        let radii: Vec<f64> = q.pulleys.iter().map(|p| p.radius).collect();
        let (spans, _) = path_in_belt_order(q, &radii)?;
        let dir = |a: f64| [a.cos(), a.sin()];
        let (mut f_in, mut f_out) = ([0.0; 2], [0.0; 2]);
        for s in &spans {
            if s.to == j {
                f_in = dir(s.angle);
            }
            if s.from == j {
                f_out = dir(s.angle);
            }
        }
        let f = [t * (f_out[0] - f_in[0]), t * (f_out[1] - f_in[1])];
        Ok(law.moment(angle, f).0)
    }

    /// Turns each arm (in `q`) to where its spring and stops balance the
    /// belt at tension `t`, in turn until none moves.
    fn balance(&mut self, q: &mut DriveParams, t: f64) -> Result<(), ParamError> {
        for (j, law, angle) in &self.0 {
            let (c, _) = law.centre(*angle);
            q.pulleys[*j].x = c[0];
            q.pulleys[*j].y = c[1];
        }
        for _ in 0..100 {
            let mut moved: f64 = 0.0;
            for (j, law, angle) in &mut self.0 {
                let a = Self::balance_one(q, *j, law, *angle, t)?;
                moved = moved.max((a - *angle).abs());
                *angle = a;
            }
            if moved <= 1e-13 {
                break;
            }
        }
        Ok(())
    }

    /// The angle, searched from `from` in steps of [`ARM_SEARCH_STEP`] up
    /// to a quarter turn the way the net moment turns the arm, then
    /// bisected, where the arm's moment (spring and stops) balances the
    /// belt's at tension `t`; `q`'s pulley `j` left there.
    fn balance_one(
        q: &mut DriveParams,
        j: usize,
        law: &Arm,
        from: f64,
        t: f64,
    ) -> Result<f64, ParamError> {
        let net = |q: &mut DriveParams, a: f64| -> Result<f64, ParamError> {
            Ok(law.torque(a, 0.0).torque + Self::hub_moment(q, j, law, a, t)?)
        };
        let r0 = net(q, from)?;
        let dir = if r0 > 0.0 { 1.0 } else { -1.0 };
        let (mut a, mut b) = (from, from);
        let mut found = r0 == 0.0;
        let steps = (0.5 * std::f64::consts::PI / ARM_SEARCH_STEP).ceil() as usize;
        for k in 1..=steps {
            if found {
                break;
            }
            a = b;
            b = from + dir * ARM_SEARCH_STEP * k as f64;
            let r = net(q, b).map_err(|_| no_balance(j, t, None))?;
            found = r * dir <= 0.0;
        }
        if !found {
            return Err(no_balance(j, t, Some(b)));
        }
        // bisection on [a, b]: the net moment turns the arm towards b at a
        for _ in 0..200 {
            let mid = 0.5 * (a + b);
            if net(q, mid)? * dir > 0.0 {
                a = mid;
            } else {
                b = mid;
            }
            if (b - a).abs() <= 1e-15 {
                break;
            }
        }
        let angle = 0.5 * (a + b);
        Self::hub_moment(q, j, law, angle, t)?;
        Ok(angle)
    }

    /// `q` with each arm drawn where it is installed: its stops and nominal
    /// angle counted from there (its pulley centre is there already).
    fn draw_installed(&self, q: &mut DriveParams) {
        for (j, _, angle) in &self.0 {
            if let Some(a) = q.pulleys[*j].arm.as_mut() {
                if let Some(s) = a.stops.as_mut() {
                    s.min_angle -= angle;
                    s.max_angle -= angle;
                }
                if let Some(n) = a.nominal.as_mut() {
                    n.angle -= angle;
                }
            }
        }
    }
}

/// No balance of the arm of pulley `j` at tension `t` (searched up to
/// `reached`, or until the belt path broke).
fn no_balance(j: usize, t: f64, reached: Option<f64>) -> ParamError {
    let how = match reached {
        Some(a) => format!(
            "turned up to {:.0} deg from where it is drawn",
            a.to_degrees()
        ),
        None => "turned until the belt path breaks".to_string(),
    };
    param_error(
        Param::PulleyArmNominalTorque(j),
        msg![
            "the arm of ",
            Part::Pulley(j),
            format!(" finds no static balance at a belt tension of {t:.1} N ({how}): its spring ("),
            Param::PulleyArmStiffness(j),
            " and this torque at ",
            Param::PulleyArmNominalAngle(j),
            ") and stops never balance the belt's hub force; check the torque, the nominal angle \
             (counterclockwise positive) and the pivot",
        ],
    )
}

/// The belt's length at its pitch line under the tension `tension` [m]:
/// spans and wraps at the pulleys' radii, each span's static sag added
/// (the parabola of [`sag_shape`], longer than its chord by s^2 L^3 / 6).
pub fn pitch_length(params: &DriveParams, tension: f64) -> Result<f64, ParamError> {
    Ok(PitchPath::new(params)?.length(params, tension))
}

/// The natural length of the belt whose installation tension is
/// `params.belt.preload` (`belt.length`): L_p / (1 + T/EA), the inverse of
/// [`installed`].
pub fn natural_length(params: &DriveParams) -> Result<f64, ParamError> {
    let b = &params.belt;
    Ok(pitch_length(params, b.preload)? / (1.0 + b.preload / b.ea))
}

/// The belt path at the pulleys' radii.
struct PitchPath {
    spans: Vec<Span>,
    wrapped: f64,
}

impl PitchPath {
    fn new(params: &DriveParams) -> Result<Self, ParamError> {
        let radii: Vec<f64> = params.pulleys.iter().map(|p| p.radius).collect();
        let (spans, wraps) = path_in_belt_order(params, &radii)?;
        let wrapped = wraps.iter().map(|w| w.angle * radii[w.pulley]).sum();
        Ok(Self { spans, wrapped })
    }

    fn length(&self, params: &DriveParams, tension: f64) -> f64 {
        let b = &params.belt;
        let rho = b.mass_per_length / (1.0 + tension / b.ea);
        let spans: f64 = self
            .spans
            .iter()
            .map(|sp| {
                let (s, _) = sag_shape(params, sp, rho, tension);
                sp.length * (1.0 + s * s * sp.length * sp.length / 6.0)
            })
            .sum();
        spans + self.wrapped
    }
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

fn solve_body_length(
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
fn place_bodies(
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
