//! A drawing of the mounted drive (`cargo xtask layout`, docs/layout.md): an
//! SVG of the pulleys with their names and radii, the belt path of the
//! core's own mounted layout ([`Layout`]), the running direction, the span
//! numbers with their free lengths, the wrap angles, the span tensions at the
//! loads given (tight and slack side) and the tensioner arms.
//!
//! The tensions are the quasi-static estimate of [`static_tensions`]: each
//! pulley's steady torque balance (eq. 24 with alpha = 0) sets the step of
//! the tension across it, and the belt's length (or a tensioner's spring)
//! sets their level. No centrifugal or dynamic part: the simulation gives
//! those (`span[k].tension`).

use crate::model::layout::Layout;
use crate::model::params::DriveParams;
use crate::ParamError;
use std::f64::consts::{PI, TAU};
use std::fmt::Write;

/// One free span as drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct SpanFigure {
    /// The FMU's span number (1-based): span k runs from pulley k to k+1
    /// (the last one back to pulley 1).
    pub number: usize,
    /// Free length [m] (the layout's).
    pub length: f64,
    /// Quasi-static tension at the loads given [N] ([`static_tensions`]).
    pub tension: f64,
    /// Tight (tension above the preload), slack (below) or at the preload.
    pub side: Side,
}

/// Where a span's tension is against the preload.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Above the preload.
    Tight,
    /// Below the preload.
    Slack,
    /// At the preload (no load), within 1e-6 of it.
    Preload,
}

impl Side {
    /// The word in the drawing.
    pub fn word(self) -> &'static str {
        match self {
            Side::Tight => "tight",
            Side::Slack => "slack",
            Side::Preload => "at preload",
        }
    }

    fn colour(self) -> &'static str {
        match self {
            Side::Tight => "#c0392b",
            Side::Slack => "#2471a3",
            Side::Preload => "#555555",
        }
    }
}

/// One wrap as drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct WrapFigure {
    /// The pulley (0-based).
    pub pulley: usize,
    /// Wrap angle [rad] (the layout's).
    pub angle: f64,
}

/// The drawing and the numbers it shows.
#[derive(Clone, Debug, PartialEq)]
pub struct Drawing {
    /// The SVG document.
    pub svg: String,
    /// Spans in FMU order (span 1 first).
    pub spans: Vec<SpanFigure>,
    /// Wraps in pulley order.
    pub wraps: Vec<WrapFigure>,
    /// Length of the belt path through the contact line [m].
    pub path_length: f64,
}

/// A pulley's role, for its default name: `driver` (speed-driven, or its
/// torque puts power in at the steady speed of [`loop_speed`]), `tensioner`,
/// `back idler`, `decoupler`, `driven` (a load torque or damping), else
/// `idler`.
pub fn role(params: &DriveParams, layout: &Layout, j: usize) -> &'static str {
    let p = &params.pulleys[j];
    let side = layout.wrap_of(j).map_or(1.0, |w| w.side);
    let omega = side * loop_speed(params, layout) / p.radius;
    if p.speed_driven || p.torque_ramp * omega > 0.0 {
        "driver"
    } else if p.arm.is_some() {
        "tensioner"
    } else if p.back_side {
        "back idler"
    } else if p.decoupler.is_some() {
        "decoupler"
    } else if p.torque_ramp != 0.0 || p.load_damping != 0.0 {
        "driven"
    } else {
        "idler"
    }
}

/// Signed steady belt speed along the layout's loop order [m/s] (positive:
/// the belt runs in loop order). A pulley turns at omega_j = s_j u / r_j.
/// With a speed-driven pulley, its speed (`omega_ramp`, the first one's)
/// sets u; without one, the torques balance the speed-proportional loads:
/// the tension steps of [`static_tensions`] sum to zero around the loop,
/// sum_j (d_j s_j u / r_j - T_j) / (s_j r_j) = 0, so
/// u = sum_j T_j s_j / r_j / sum_j d_j / r_j^2 (0 without load damping).
pub fn loop_speed(params: &DriveParams, layout: &Layout) -> f64 {
    let side = |j: usize| layout.wrap_of(j).map_or(1.0, |w| w.side);
    if let Some(d) = params.pulleys.iter().position(|p| p.speed_driven) {
        return params.pulleys[d].omega_ramp * params.pulleys[d].radius / side(d);
    }
    let (mut num, mut den) = (0.0, 0.0);
    for (j, p) in params.pulleys.iter().enumerate() {
        num += p.torque_ramp * side(j) / p.radius;
        den += p.load_damping / (p.radius * p.radius);
    }
    if den > 0.0 {
        num / den
    } else {
        0.0
    }
}

/// Quasi-static span tensions at the loads given, per span of
/// `layout.spans` (loop order) [N].
///
/// In loop order the belt's torque on pulley j (counterclockwise positive)
/// is s_j r_j (T_next - T_prev), whichever way the belt runs; at steady speed
/// it balances the load, eq. 24 with alpha = 0: T_next - T_prev = (d_load
/// omega_j - T_applied) / (s_j r_j), omega_j = s_j u / r_j. The first
/// speed-driven pulley supplies what the others take (further speed-driven
/// pulleys are taken as carrying no torque). The level: with a tensioner
/// arm, its spring holds the mean of its two spans at the preload (the
/// mounting sets the spring for the preload; the arm's travel under load is
/// neglected); without one, the belt's stretch is conserved, so the
/// length-weighted mean tension (each arc counted half to each of its
/// spans) stays the preload.
pub fn static_tensions(params: &DriveParams, layout: &Layout) -> Vec<f64> {
    let n = layout.spans.len();
    let u = loop_speed(params, layout);
    let driver = params.pulleys.iter().position(|p| p.speed_driven);
    // wraps[m] sits at the end of spans[m], so spans[(m + 1) % n] leaves it.
    let mut t = vec![0.0; n];
    let start = driver
        .and_then(|d| layout.wraps.iter().position(|w| w.pulley == d))
        .unwrap_or(n - 1);
    for i in 1..n {
        let m = (start + i) % n; // wrap between spans[m] and spans[m + 1]
        let prev = t[m];
        let w = &layout.wraps[m];
        let p = &params.pulleys[w.pulley];
        let step = if p.speed_driven {
            0.0
        } else {
            let omega = w.side * u / p.radius;
            (p.load_damping * omega - p.torque_ramp) / (w.side * p.radius)
        };
        t[(m + 1) % n] = prev + step;
    }
    let level = match params.pulleys.iter().position(|p| p.arm.is_some()) {
        Some(a) => {
            let m = layout
                .wraps
                .iter()
                .position(|w| w.pulley == a)
                .expect("every pulley is wrapped");
            0.5 * (t[m] + t[(m + 1) % n])
        }
        None => {
            let arc = |m: usize| {
                let w = &layout.wraps[m];
                w.angle * params.pulleys[w.pulley].radius
            };
            let (mut sum, mut len) = (0.0, 0.0);
            for (m, (span, tm)) in layout.spans.iter().zip(&t).enumerate() {
                // spans[m] ends on wraps[m] and starts on wraps[m - 1]
                let wgt = span.length + 0.5 * (arc(m) + arc((m + n - 1) % n));
                sum += wgt * tm;
                len += wgt;
            }
            sum / len
        }
    };
    t.iter().map(|x| x - level + params.belt.preload).collect()
}

/// Maps metres to drawing pixels (y up in the drive, down in SVG).
struct View {
    scale: f64,
    x0: f64,
    y1: f64,
    margin: f64,
    /// Extra room above the drive (title lines) [px].
    top: f64,
}

impl View {
    fn p(&self, q: [f64; 2]) -> [f64; 2] {
        [
            self.margin + (q[0] - self.x0) * self.scale,
            self.top + self.margin + (self.y1 - q[1]) * self.scale,
        ]
    }
}

/// Escapes text for SVG.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The drawing being made: the drive, its layout and the mapping to pixels.
struct Sketch<'a> {
    params: &'a DriveParams,
    layout: Layout,
    view: View,
    /// [`static_tensions`] per span of `layout.spans`.
    tensions: Vec<f64>,
    /// [`loop_speed`].
    u: f64,
    width: f64,
    height: f64,
    centroid: [f64; 2],
    svg: String,
}

/// Draws the mounted drive of `params` (which must have passed
/// [`DriveParams::validate`]); `names` overrides the pulleys' default names
/// ([`role`]) where given and non-empty; `title` heads the drawing.
pub fn draw(params: &DriveParams, names: &[String], title: &str) -> Result<Drawing, ParamError> {
    // With `belt.naturalLength` the preload is the installation tension.
    let installed = crate::model::layout::installed(params)?;
    let params: &DriveParams = &installed;
    let layout = Layout::new(params)?;
    let mut k = Sketch::new(params, layout);
    k.header(title);
    k.arms();
    k.pulleys();
    let spans = k.belt();
    let wraps = k.labels(names);
    k.marks();
    k.svg.push_str("</svg>\n");
    Ok(Drawing {
        svg: k.svg,
        spans,
        wraps,
        path_length: k.layout.path_length,
    })
}

// Writing into a String cannot fail: the `let _ = writeln!` below.
impl<'a> Sketch<'a> {
    fn new(params: &'a DriveParams, layout: Layout) -> Self {
        let np = params.pulleys.len();
        let tensions = static_tensions(params, &layout);
        let u = loop_speed(params, &layout);
        // Extent: pulleys and arm pivots.
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &params.pulleys {
            let mut grow = |c: [f64; 2], r: f64| {
                for i in 0..2 {
                    lo[i] = lo[i].min(c[i] - r);
                    hi[i] = hi[i].max(c[i] + r);
                }
            };
            grow([p.x, p.y], p.radius);
            if let Some(arm) = &p.arm {
                grow(arm.pivot, 0.0);
            }
        }
        let size = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-6);
        let scale = 720.0 / size;
        // Room for the labels beside the drive.
        let margin = 130.0;
        let n = np as f64;
        Self {
            params,
            view: View {
                scale,
                x0: lo[0],
                y1: hi[1],
                margin,
                top: 80.0,
            },
            tensions,
            u,
            width: (hi[0] - lo[0]) * scale + 2.0 * margin,
            height: (hi[1] - lo[1]) * scale + 2.0 * margin + 80.0,
            centroid: [
                params.pulleys.iter().map(|p| p.x).sum::<f64>() / n,
                params.pulleys.iter().map(|p| p.y).sum::<f64>() / n,
            ],
            layout,
            svg: String::new(),
        }
    }

    fn header(&mut self, title: &str) {
        let (width, height) = (self.width, self.height);
        let w = &mut self.svg;
        let _ = writeln!(
            w,
            r##"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.2} {height:.2}" font-family="DejaVu Sans, Arial, sans-serif" font-size="13">"##
        );
        let _ = writeln!(
            w,
            r##"<rect width="100%" height="100%" fill="white"/>
    <defs><marker id="run" viewBox="0 0 10 10" refX="5" refY="5" markerWidth="7" markerHeight="7" orient="auto"><path d="M0,0 L10,5 L0,10 z" fill="black"/></marker></defs>"##
        );
        let _ = writeln!(
            w,
            r##"<text x="12" y="22" font-size="16" font-weight="bold">{}</text>"##,
            esc(title)
        );
        let _ = writeln!(
            w,
            r##"<text x="12" y="42">belt path {:.1} mm (contact line), preload {:.0} N, {} bodies; span tensions: quasi-static estimate at the loads given</text>"##,
            self.layout.path_length * 1e3,
            self.params.belt.preload,
            self.params.belt.n_bodies
        );
    }

    /// Tensioner arms, under the pulleys.
    fn arms(&mut self) {
        let w = &mut self.svg;
        for (j, p) in self.params.pulleys.iter().enumerate() {
            let Some(arm) = &p.arm else {
                continue;
            };
            let a = self.view.p(arm.pivot);
            let b = self.view.p([p.x, p.y]);
            let _ = writeln!(
                w,
                r##"<g class="arm" data-pulley="{}"><line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="#777" stroke-width="9" stroke-linecap="round"/><circle cx="{:.2}" cy="{:.2}" r="6" fill="white" stroke="black" stroke-width="2"/><text x="{:.2}" y="{:.2}" font-size="11" fill="#555">pivot</text></g>"##,
                j + 1,
                a[0],
                a[1],
                b[0],
                b[1],
                a[0],
                a[1],
                a[0] + 9.0,
                a[1] - 9.0
            );
        }
    }

    fn pulleys(&mut self) {
        let w = &mut self.svg;
        for (j, p) in self.params.pulleys.iter().enumerate() {
            let c = self.view.p([p.x, p.y]);
            let fill = if p.back_side { "#eef3f8" } else { "#f2f2f2" };
            let _ = writeln!(
                w,
                r##"<g class="pulley" data-pulley="{}"><circle cx="{:.3}" cy="{:.3}" r="{:.3}" fill="{fill}" stroke="#444" stroke-width="1.5"/><circle cx="{:.2}" cy="{:.2}" r="2.5" fill="#444"/></g>"##,
                j + 1,
                c[0],
                c[1],
                p.radius * self.view.scale,
                c[0],
                c[1]
            );
        }
    }

    /// The belt: spans (coloured by tight and slack side, with the running
    /// direction and their labels) and wrap arcs.
    fn belt(&mut self) -> Vec<SpanFigure> {
        let np = self.params.pulleys.len();
        let w = &mut self.svg;
        let mut spans = Vec::with_capacity(np);
        for (m, s) in self.layout.spans.iter().enumerate() {
            let number = if s.to == (s.from + 1) % np {
                s.from + 1
            } else {
                s.to + 1
            };
            let t0 = self.params.belt.preload;
            let side = if (self.tensions[m] - t0).abs() <= 1e-6 * t0 {
                Side::Preload
            } else if self.tensions[m] > t0 {
                Side::Tight
            } else {
                Side::Slack
            };
            let colour = side.colour();
            let (a, b) = (self.view.p(s.start), self.view.p(s.end));
            let _ = writeln!(
                w,
                r##"<line class="span" data-span="{number}" x1="{:.3}" y1="{:.3}" x2="{:.3}" y2="{:.3}" stroke="{colour}" stroke-width="{}"/>"##,
                a[0],
                a[1],
                b[0],
                b[1],
                if side == Side::Tight { 4.5 } else { 3.0 }
            );
            // Running direction: an arrow at the span's middle.
            if self.u != 0.0 {
                let dir = if self.u > 0.0 { s.angle } else { s.angle + PI };
                let mid = self.view.p(s.midpoint());
                let (dx, dy) = (dir.cos() * 10.0, -dir.sin() * 10.0);
                let _ = writeln!(
                    w,
                    r##"<line class="run" x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="black" stroke-width="1.5" marker-end="url(#run)"/>"##,
                    mid[0] - dx,
                    mid[1] - dy,
                    mid[0] + dx,
                    mid[1] + dy
                );
            }
            // Label outside the loop: the right normal of the loop direction.
            let out = [s.angle.sin(), -s.angle.cos()];
            let mid = self.view.p(s.midpoint());
            let lx = mid[0] + out[0] * 26.0;
            let ly = mid[1] - out[1] * 26.0;
            let anchor = if out[0] > 0.3 {
                "start"
            } else if out[0] < -0.3 {
                "end"
            } else {
                "middle"
            };
            let _ = writeln!(
                w,
                r##"<text class="span-label" data-span="{number}" x="{lx:.1}" y="{ly:.1}" text-anchor="{anchor}" fill="{colour}"><tspan font-weight="bold">span {number}</tspan> {:.1} mm, {:.0} N {}</text>"##,
                s.length * 1e3,
                self.tensions[m],
                side.word()
            );
            spans.push(SpanFigure {
                number,
                length: s.length,
                tension: self.tensions[m],
                side,
            });
        }
        spans.sort_by_key(|s| s.number);
        let n = self.layout.spans.len();
        for (m, wr) in self.layout.wraps.iter().enumerate() {
            let j = wr.pulley;
            // The belt's contact line: the pulley's radius less the
            // mounted penetration (the layout's spans end on it).
            let r = (self.params.pulleys[j].radius - wr.penetration) * self.view.scale;
            let (a, b) = (
                self.view.p(self.layout.spans[m].end),
                self.view.p(self.layout.spans[(m + 1) % n].start),
            );
            // The drawing shows the drive as seen (y up), so counterclockwise
            // in the drive is counterclockwise on the screen: SVG's sweep
            // flag 0 (flag 1 turns towards growing angle in SVG's y-down
            // frame, clockwise as seen).
            let large = u8::from(wr.angle > PI);
            let sweep = u8::from(wr.side < 0.0);
            let _ = writeln!(
                w,
                r##"<path class="wrap" data-pulley="{}" d="M {:.3} {:.3} A {r:.3} {r:.3} 0 {large} {sweep} {:.3} {:.3}" fill="none" stroke="black" stroke-width="3"/>"##,
                j + 1,
                a[0],
                a[1],
                b[0],
                b[1]
            );
        }
        spans
    }

    /// Pulley labels (name, radius, wrap angle), away from the drive's centre.
    fn labels(&mut self, names: &[String]) -> Vec<WrapFigure> {
        let centroid = self.centroid;
        let w = &mut self.svg;
        let mut wraps = Vec::with_capacity(self.params.pulleys.len());
        for (j, p) in self.params.pulleys.iter().enumerate() {
            let wrap = self.layout.wrap_of(j).map_or(0.0, |w| w.angle);
            wraps.push(WrapFigure {
                pulley: j,
                angle: wrap,
            });
            let c = self.view.p([p.x, p.y]);
            let (dx, dy) = (p.x - centroid[0], p.y - centroid[1]);
            let d = dx.hypot(dy);
            let dir = if d > 1e-9 {
                [dx / d, -dy / d]
            } else {
                [0.0, 1.0]
            };
            let reach = p.radius * self.view.scale + 18.0;
            let (lx, ly) = (c[0] + dir[0] * reach, c[1] + dir[1] * reach);
            let anchor = if dir[0] > 0.3 {
                "start"
            } else if dir[0] < -0.3 {
                "end"
            } else {
                "middle"
            };
            let name = names.get(j).filter(|s| !s.trim().is_empty()).map_or_else(
                || role(self.params, &self.layout, j).to_string(),
                |s| s.trim().to_string(),
            );
            let _ = writeln!(
                w,
                r##"<text class="pulley-label" data-pulley="{}" x="{lx:.1}" y="{:.1}" text-anchor="{anchor}"><tspan x="{lx:.1}" font-weight="bold">{} {}</tspan><tspan x="{lx:.1}" dy="15">r {:.1} mm</tspan><tspan class="wrap-label" x="{lx:.1}" dy="15">wrap {:.1} deg</tspan></text>"##,
                j + 1,
                ly - 8.0 + dir[1] * 12.0,
                j + 1,
                esc(&name),
                p.radius * 1e3,
                wrap.to_degrees()
            );
        }
        wraps
    }

    /// Body 1, the axes and the legend.
    fn marks(&mut self) {
        let (width, height) = (self.width, self.height);
        let w = &mut self.svg;
        // Body 1 (the start of the belt's numbering) and the axes.
        let b1 = self
            .view
            .p([self.layout.bodies[0].x, self.layout.bodies[0].y]);
        let _ = writeln!(
            w,
            r##"<g class="body1"><circle cx="{:.2}" cy="{:.2}" r="4.5" fill="#c00"/><text x="{:.1}" y="{:.1}" fill="#c00" font-size="12">body 1</text></g>"##,
            b1[0],
            b1[1],
            b1[0] + 7.0,
            b1[1] + 16.0
        );
        let (ax, ay) = (width - 250.0, height - 50.0);
        let _ = writeln!(
            w,
            r##"<g class="axes" font-size="12"><line x1="{ax:.1}" y1="{ay:.1}" x2="{:.1}" y2="{ay:.1}" stroke="black" marker-end="url(#run)"/><text x="{:.1}" y="{:.1}">x</text><line x1="{ax:.1}" y1="{ay:.1}" x2="{ax:.1}" y2="{:.1}" stroke="black" marker-end="url(#run)"/><text x="{:.1}" y="{:.1}">y</text><text x="{:.1}" y="{:.1}">+ angle, speed, torque:</text><text x="{:.1}" y="{:.1}">counterclockwise</text></g>"##,
            ax + 32.0,
            ax + 36.0,
            ay + 4.0,
            ay - 32.0,
            ax - 4.0,
            ay - 36.0,
            ax + 50.0,
            ay - 18.0,
            ax + 50.0,
            ay - 4.0
        );

        // Legend.
        let ly = height - 22.0;
        let _ = writeln!(
            w,
            r##"<g class="legend"><line x1="12" y1="{y:.1}" x2="42" y2="{y:.1}" stroke="#c0392b" stroke-width="4.5"/><text x="48" y="{t:.1}">tight span (above preload)</text><line x1="250" y1="{y:.1}" x2="280" y2="{y:.1}" stroke="#2471a3" stroke-width="3"/><text x="286" y="{t:.1}">slack span</text><line x1="390" y1="{y:.1}" x2="420" y2="{y:.1}" stroke="black" stroke-width="1.5" marker-end="url(#run)"/><text x="428" y="{t:.1}">{}</text></g>"##,
            if self.u != 0.0 {
                "running direction"
            } else {
                "no speed-driven pulley: running direction not shown"
            },
            y = ly,
            t = ly + 4.0
        );
    }
}

/// Wrap angle of an SVG arc `M ax ay A r r 0 large sweep bx by` around the
/// centre `c` (screen coordinates) [rad]: the angle swept from a to b in
/// the arc's direction. For checking a drawing (tests, tools).
pub fn arc_angle(a: [f64; 2], b: [f64; 2], c: [f64; 2], sweep: bool) -> f64 {
    let ta = (a[1] - c[1]).atan2(a[0] - c[0]);
    let tb = (b[1] - c[1]).atan2(b[0] - c[0]);
    // Sweep 1 runs towards growing screen angle (clockwise on the screen).
    let d = if sweep { tb - ta } else { ta - tb };
    d.rem_euclid(TAU)
}
