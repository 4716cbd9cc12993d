//! Belt path construction and refusal of impossible drives.

use belt_drive::fmu::names;
use belt_drive::model::layout::Layout;
use belt_drive::model::params::PulleyParams;
use belt_drive::{Drive, DriveParams};
use std::f64::consts::PI;

fn err_of(p: &DriveParams) -> (String, String) {
    let e = Drive::new(p, 0.0).expect_err("must be refused");
    // as the FMU names them
    (names::param_name(e.parameter), names::render(&e.message))
}

#[test]
fn two_pulleys_open_belt_length_and_wraps() {
    // Unequal radii: wraps pi +- 2 asin((R - r)/D), length 2 sqrt(D^2 - (R-r)^2) + arcs.
    let mut p = DriveParams::kubas_section4();
    p.pulleys[1].radius = 0.06;
    p.pulleys[1].x = 0.4;
    p.belt.preload = 0.0; // pure geometry: no penetration
    let l = Layout::new(&p).unwrap();
    let (r1, r2, d): (f64, f64, f64) = (0.027, 0.06, 0.4);
    let beta = ((r2 - r1) / d).asin();
    let w1 = l.wrap_of(0).unwrap().angle;
    let w2 = l.wrap_of(1).unwrap().angle;
    assert!((w1 - (PI - 2.0 * beta)).abs() < 1e-12, "wrap 1 {w1}");
    assert!((w2 - (PI + 2.0 * beta)).abs() < 1e-12, "wrap 2 {w2}");
    let len = 2.0 * (d * d - (r2 - r1) * (r2 - r1)).sqrt() + r1 * w1 + r2 * w2;
    assert!(
        (l.path_length - len).abs() < 1e-12,
        "{} vs {len}",
        l.path_length
    );
    // Unstretched length n l is shorter by the preload strain (here 0).
    let natural = l.body_length * p.belt.n_bodies as f64;
    assert!((natural - len).abs() < 1e-3 * len);
}

/// A front-end-accessory-like drive with a back-side idler, listed
/// clockwise: the path is found, the idler wrapped the other way, and the
/// total turning of the loop is one revolution.
#[test]
fn back_side_idler_and_either_listing_direction() {
    let mut p = DriveParams::kubas_section4();
    let mk = |x: f64, y: f64, r: f64| {
        let mut q = PulleyParams::paper_5pk(x, y);
        q.radius = r;
        q
    };
    let mut idler = mk(0.15, 0.09, 0.03);
    idler.back_side = true;
    // crank (0,0), alternator (0.25, 0.12), idler between them on the top span's outside
    p.pulleys = vec![
        mk(0.0, 0.0, 0.07),
        idler,
        mk(0.3, 0.12, 0.03),
        mk(0.3, -0.05, 0.05),
    ];
    p.belt.n_bodies = 200;
    let l = Layout::new(&p).expect("valid accessory drive");
    let turning: f64 = l.wraps.iter().map(|w| w.side * w.angle).sum();
    assert!((turning - 2.0 * PI).abs() < 1e-9);
    let idler = l.wrap_of(1).unwrap();
    assert_eq!(idler.side, -1.0);
    assert!(idler.angle > 0.1 && idler.angle < PI);
    // Reversed listing gives the same path length.
    let mut q = p.clone();
    q.pulleys.reverse();
    let l2 = Layout::new(&q).unwrap();
    assert!((l.path_length - l2.path_length).abs() < 1e-12);
    // and it runs
    let mut d = Drive::new(&p, 0.0).unwrap();
    d.advance(0.002).unwrap();
    let o = d.outputs();
    assert!(o.min_tension > 0.95 * p.belt.preload && o.max_tension < 1.05 * p.belt.preload);
}

#[test]
fn impossible_drives_are_refused_with_the_parameter_named() {
    let base = DriveParams::kubas_section4();

    let mut p = base.clone();
    p.pulleys[1].x = 0.04;
    let (name, msg) = err_of(&p);
    assert_eq!(name, "pulley[2].x");
    assert!(msg.contains("overlaps"), "{msg}");

    let mut p = base.clone();
    p.belt.n_bodies = 20;
    p.probe_body = 0;
    let (name, msg) = err_of(&p);
    assert_eq!(name, "belt.nBodies");
    assert!(msg.contains("use belt.nBodies >="), "{msg}");

    // Bodies longer than the pulley diameter (no pitch angle at all): the
    // advice is still a body count that works (was "use belt.nBodies >= 0").
    for n in [3, 4, 6] {
        let mut p = base.clone();
        p.belt.n_bodies = n;
        p.probe_body = 0;
        let (name, msg) = err_of(&p);
        assert_eq!(name, "belt.nBodies");
        let advice: usize = msg
            .rsplit("use belt.nBodies >= ")
            .next()
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("{msg}"));
        p.belt.n_bodies = advice;
        assert!(
            Layout::new(&p).is_ok(),
            "{n} bodies: advice {advice} fails: {msg}"
        );
    }

    let mut p = base.clone();
    p.pulleys[0].radius = -0.01;
    assert_eq!(err_of(&p).0, "pulley[1].radius");

    let mut p = base.clone();
    p.pulleys[1].mu_kinetic = 1.2;
    let (name, msg) = err_of(&p);
    assert_eq!(name, "pulley[2].muKinetic");
    assert!(msg.contains("muStatic"), "{msg}");

    let mut p = base.clone();
    p.belt.mass_per_length = 0.0;
    assert_eq!(err_of(&p).0, "belt.massPerLength");

    let mut p = base.clone();
    p.belt.ea = f64::NAN;
    assert_eq!(err_of(&p).0, "belt.EA");

    let mut p = base.clone();
    p.pulleys.truncate(1);
    assert_eq!(err_of(&p).0, "nPulleys");

    // Both pulleys back-side: no loop can be wrapped.
    let mut p = base.clone();
    p.pulleys[0].back_side = true;
    p.pulleys[1].back_side = true;
    let (name, msg) = err_of(&p);
    assert!(name.ends_with(".backSide"), "{name}: {msg}");

    // A third pulley in the middle of a span.
    let mut p = base;
    let mut mid = PulleyParams::paper_5pk(0.25, -0.01);
    mid.radius = 0.02;
    p.pulleys.push(mid);
    p.pulleys.swap(1, 2);
    assert!(Drive::new(&p, 0.0).is_err());
}
