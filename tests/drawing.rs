//! The drive drawing (`cargo xtask layout`, `belt_drive::drawing`) on every
//! shipped parameter set: what the SVG draws and writes is checked against
//! the core's layout, read back from the SVG text itself.

use belt_drive::drawing::{arc_angle, draw, static_tensions, Side};
use belt_drive::model::layout::Layout;
use belt_drive::modes::params::drive_params;
use belt_drive::DriveParams;
use std::path::PathBuf;

/// The value of attribute `name` in the tag starting at `tag`.
fn attr(tag: &str, name: &str) -> Option<String> {
    let key = format!(" {name}=\"");
    let at = tag.find(&key)? + key.len();
    let end = tag[at..].find('"')? + at;
    Some(tag[at..end].to_string())
}

fn num(tag: &str, name: &str) -> f64 {
    attr(tag, name)
        .unwrap_or_else(|| panic!("no {name} in {tag}"))
        .parse()
        .unwrap()
}

/// Every element `<NAME class="CLASS" ...>` of the SVG, as its text up to
/// the end of its line.
fn elements<'a>(svg: &'a str, name: &str, class: &str) -> Vec<&'a str> {
    let head = format!("<{name} class=\"{class}\"");
    svg.lines()
        .filter_map(|l| l.find(&head).map(|i| &l[i..]))
        .collect()
}

/// The number in a label right before `unit` after `after`.
fn label_number(text: &str, after: &str, unit: &str) -> f64 {
    let rest = &text[text
        .find(after)
        .unwrap_or_else(|| panic!("{after} in {text}"))
        + after.len()..];
    let end = rest
        .find(unit)
        .unwrap_or_else(|| panic!("{unit} in {rest}"));
    let words: Vec<&str> = rest[..end].split_whitespace().collect();
    words.last().unwrap().parse().unwrap()
}

fn parameter_sets() -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("parameters");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ssv"))
        .collect();
    v.sort();
    assert!(v.len() >= 5, "parameter sets in {dir:?}: {v:?}");
    v
}

/// Pulley centres [px] and the scale [px/m], from the drawn circles.
fn circles(svg: &str, p: &DriveParams) -> (Vec<[f64; 2]>, Vec<f64>, f64) {
    let mut centres = vec![[f64::NAN; 2]; p.pulleys.len()];
    let mut radii = vec![f64::NAN; p.pulleys.len()];
    for g in elements(svg, "g", "pulley") {
        let j: usize = attr(g, "data-pulley").unwrap().parse::<usize>().unwrap() - 1;
        let c = &g[g.find("<circle").unwrap()..];
        centres[j] = [num(c, "cx"), num(c, "cy")];
        radii[j] = num(c, "r");
    }
    // The scale from the largest circle (radii are written to 0.001 px).
    let big = (0..radii.len())
        .max_by(|&a, &b| radii[a].total_cmp(&radii[b]))
        .unwrap();
    let scale = radii[big] / p.pulleys[big].radius;
    for (j, r) in radii.iter().enumerate() {
        assert!(
            (r / scale - p.pulleys[j].radius).abs() < 0.002 / scale,
            "pulley {} drawn with radius {} m, has {}",
            j + 1,
            r / scale,
            p.pulleys[j].radius
        );
    }
    (centres, radii, scale)
}

#[test]
fn drawing_shows_the_layouts_spans_and_wraps_on_every_parameter_set() {
    for path in parameter_sets() {
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
        let p = drive_params(Some(&path), &[]).unwrap_or_else(|e| panic!("{file}: {e}"));
        let layout = Layout::new(&p).unwrap();
        let d = draw(&p, &[], &file).unwrap();
        let svg = &d.svg;
        let np = p.pulleys.len();
        let (centres, radii, scale) = circles(svg, &p);

        // Spans: one line per span, tangent to both its pulleys (the belt's
        // straight run), as long as the layout's free span; its label says
        // that length (to 0.1 mm).
        let lines = elements(svg, "line", "span");
        assert_eq!(lines.len(), np, "{file}: spans drawn");
        for line in lines {
            let k: usize = attr(line, "data-span").unwrap().parse().unwrap();
            let (a, b) = (k - 1, k % np);
            let span = layout.span_between(a, b).unwrap();
            let (x1, y1, x2, y2) = (
                num(line, "x1"),
                num(line, "y1"),
                num(line, "x2"),
                num(line, "y2"),
            );
            let len = (x2 - x1).hypot(y2 - y1);
            // Coordinates are written to 0.001 px, the radius that gives the
            // scale too (relative error 0.0005 / radius in px).
            let r_big = radii.iter().copied().fold(0.0, f64::max);
            assert!(
                (len / scale - span.length).abs() < 0.003 / scale + span.length * 0.0005 / r_big,
                "{file}: span {k} drawn {} m long, layout {} m",
                len / scale,
                span.length
            );
            for j in [a, b] {
                let c = centres[j];
                let dist = ((x2 - x1) * (y1 - c[1]) - (x1 - c[0]) * (y2 - y1)).abs() / len;
                // The belt's contact line: radius less the mounted penetration.
                let rho = (p.pulleys[j].radius - layout.wrap_of(j).unwrap().penetration) * scale;
                assert!(
                    (dist - rho).abs() < 0.02,
                    "{file}: span {k} is {dist} px from the centre of pulley {} of contact radius {rho} px",
                    j + 1
                );
            }
            let label = elements(svg, "text", "span-label")
                .into_iter()
                .find(|t| attr(t, "data-span").as_deref() == Some(&k.to_string()))
                .unwrap_or_else(|| panic!("{file}: no label for span {k}"));
            let mm = label_number(label, &format!("span {k}</tspan>"), " mm");
            assert!(
                (mm - span.length * 1e3).abs() <= 0.05 + 1e-9,
                "{file}: span {k} labelled {mm} mm, layout {} mm",
                span.length * 1e3
            );
        }

        // Wraps: the arc drawn from span to span turns by the layout's wrap
        // angle, and the pulley's label says it (to 0.1 deg).
        let arcs = elements(svg, "path", "wrap");
        assert_eq!(arcs.len(), np, "{file}: wraps drawn");
        for arc in arcs {
            let j: usize = attr(arc, "data-pulley").unwrap().parse::<usize>().unwrap() - 1;
            let dpath = attr(arc, "d").unwrap();
            let f: Vec<&str> = dpath.split_whitespace().collect();
            // M ax ay A r r 0 large sweep bx by
            let v = |i: usize| f[i].parse::<f64>().unwrap();
            let (a, b) = ([v(1), v(2)], [v(9), v(10)]);
            // The belt's contact line, written to 0.001 px; the scale read
            // from the circles adds its share.
            let rho = (p.pulleys[j].radius - layout.wrap_of(j).unwrap().penetration) * scale;
            let r_big = radii.iter().copied().fold(0.0, f64::max);
            let tol = 0.0015 + rho * 0.0005 / r_big;
            assert!(
                (v(4) - rho).abs() < tol,
                "{file}: arc radius of pulley {}: {} px, contact line {rho} px",
                j + 1,
                v(4)
            );
            let angle = arc_angle(a, b, centres[j], f[8] == "1");
            let large = f[7] == "1";
            assert_eq!(
                large,
                angle > std::f64::consts::PI,
                "{file}: large-arc flag of pulley {}",
                j + 1
            );
            let wrap = layout.wrap_of(j).unwrap().angle;
            // The end points are written to 0.001 px on radii of 10 px and more.
            assert!(
                (angle - wrap).abs() < 2e-4,
                "{file}: pulley {} wrap drawn {angle} rad, layout {wrap} rad",
                j + 1
            );
            let label = elements(svg, "text", "pulley-label")
                .into_iter()
                .find(|t| attr(t, "data-pulley") == Some((j + 1).to_string()))
                .unwrap();
            let deg = label_number(label, "wrap", " deg");
            assert!(
                (deg - wrap.to_degrees()).abs() <= 0.05 + 1e-9,
                "{file}: pulley {} wrap labelled {deg} deg, layout {}",
                j + 1,
                wrap.to_degrees()
            );
        }
        // A tensioner's arm is drawn from its pivot to its pulley.
        let arms = elements(svg, "g", "arm");
        assert_eq!(
            arms.len(),
            p.pulleys.iter().filter(|q| q.arm.is_some()).count(),
            "{file}: arms"
        );
    }
}

/// Two pulleys of unequal size, the small one speed-driven, the large one
/// loaded with a torque Q: the quasi-static tensions are T0 +- Q / (2 r)
/// (equal free spans, so the length-weighted mean of the two is the
/// preload), the tight span the one the driver pulls the belt in from.
#[test]
fn static_tensions_of_a_two_pulley_drive_are_the_torque_balance() {
    let mut p = DriveParams::kubas_section3();
    p.pulleys.truncate(2);
    let (r1, r2) = (0.03, 0.06);
    p.pulleys[0].radius = r1;
    p.pulleys[1].radius = r2;
    p.pulleys[1].x = p.pulleys[0].x + 0.25;
    p.pulleys[1].y = p.pulleys[0].y;
    p.pulleys[0].speed_driven = true;
    p.pulleys[0].omega_ramp = 100.0;
    p.pulleys[1].speed_driven = false;
    p.pulleys[1].load_damping = 0.0;
    let q = 4.0;
    p.pulleys[1].torque_ramp = -q; // a load against counterclockwise rotation
    p.validate().unwrap();
    let layout = Layout::new(&p).unwrap();
    let t = static_tensions(&p, &layout);
    let t0 = p.belt.preload;
    let mut sorted = t.clone();
    sorted.sort_by(f64::total_cmp);
    // Closed form, exact for equal free spans (the arcs weigh in halves).
    let tol = 1e-9 * t0;
    assert!((sorted[0] - (t0 - q / (2.0 * r2))).abs() < tol, "{t:?}");
    assert!((sorted[1] - (t0 + q / (2.0 * r2))).abs() < tol, "{t:?}");
    // Counterclockwise pulleys: the belt runs from the top of the driver
    // (pulley 1, left) ... the tight span is the one arriving at the driver.
    let d = draw(&p, &[], "two").unwrap();
    for s in &d.spans {
        let span = layout.span_between(s.number - 1, s.number % 2).unwrap();
        let arrives_at_driver = if loop_runs_forward(&p, &layout) {
            span.to == 0
        } else {
            span.from == 0
        };
        assert_eq!(
            s.side == Side::Tight,
            arrives_at_driver,
            "span {}: {s:?}",
            s.number
        );
    }
}

fn loop_runs_forward(p: &DriveParams, layout: &Layout) -> bool {
    belt_drive::drawing::loop_speed(p, layout) > 0.0
}

/// The manual's drawing of the default drive (docs/layout/default-drive.svg,
/// inlined by `cargo xtask fmu`) is what the drawing gives today; if not,
/// regenerate it with the command in docs/layout.md.
#[test]
fn manuals_drawing_of_the_default_drive_is_current() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/layout/default-drive.svg");
    let committed = std::fs::read_to_string(&path).unwrap();
    let p = drive_params(None, &[]).unwrap();
    let d = draw(&p, &[], "The default drive").unwrap();
    // Same text; numbers within the last written digit (a body centre
    // rounded to 0.01 px may fall either side of a rounding boundary between
    // builds).
    let split = |s: &str| -> (String, Vec<f64>) {
        let mut text = String::new();
        let mut nums = Vec::new();
        let mut cur = String::new();
        for ch in s.chars() {
            if ch.is_ascii_digit() || ch == '.' || (ch == '-' && cur.is_empty()) {
                cur.push(ch);
            } else {
                if let Ok(v) = cur.parse::<f64>() {
                    nums.push(v);
                    text.push('#');
                } else {
                    text.push_str(&cur);
                }
                cur.clear();
                text.push(ch);
            }
        }
        (text, nums)
    };
    let stale = format!(
        "{path:?} is stale: cargo xtask layout -- --title \"The default drive\" \
         --out docs/layout/default-drive.svg"
    );
    let ((t1, n1), (t2, n2)) = (split(&committed), split(&d.svg));
    assert!(t1 == t2 && n1.len() == n2.len(), "{stale}");
    for (a, b) in n1.iter().zip(&n2) {
        assert!((a - b).abs() <= 0.011, "{stale}: {a} against {b}");
    }
}
