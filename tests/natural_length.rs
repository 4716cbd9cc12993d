//! Installation from the belt's natural length (`belt.naturalLength`)
//! through the C ABI (the built library via dlopen): the installed tension
//! against the closed form T = EA (L_path / L0 - 1) on two unequal pulleys,
//! the round trip preload -> `belt.length` -> `belt.naturalLength` -> the
//! same tension, and the refusals (a length beside a preload, a belt longer
//! than its path, a tensioner arm without its spring as built).
#![cfg(unix)]

mod abi;

use abi::*;
use std::f64::consts::PI;

const EA: f64 = 1.2e5;
const R1: f64 = 0.06;
const R2: f64 = 0.035;
const X2: f64 = 0.30;
const Y2: f64 = 0.11;

/// Two unequal pulleys (60 and 35 mm, centre distance 0.3195 m, the line
/// of centres 20 deg up), a 1.2e5 N belt of 0.12 kg/m under gravity: unlike
/// the paper's drive. `extra` on top.
fn drive<'a>(fmi: &'a Fmi, extra: &[(&str, f64)]) -> (Instance<'a>, i32) {
    let i = Instance::new(fmi);
    let base = [
        ("belt.EA", EA),
        ("belt.massPerLength", MASS),
        ("pulley[1].radius", R1),
        ("pulley[2].radius", R2),
        ("pulley[2].x", X2),
        ("pulley[2].y", Y2),
        // no torque: the drive stays at rest
        ("pulley[1].torqueRamp", 0.0),
    ];
    for (n, x) in base.iter().chain(extra) {
        assert_eq!(i.set_real(n, *x), OK, "{n}");
    }
    // SAFETY: live instance.
    let s = unsafe {
        assert_eq!((fmi.setup_experiment)(i.c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!((fmi.enter_init)(i.c), OK);
        (fmi.exit_init)(i.c)
    };
    (i, s)
}

const MASS: f64 = 0.12;
const G: f64 = 9.81;

/// The open two-pulley belt's length at the pitch line:
/// L = 2 C cos(a) + pi (r1 + r2) + 2 a (r1 - r2), sin(a) = (r1 - r2) / C.
fn open_belt_length() -> f64 {
    let c = X2.hypot(Y2);
    let a = ((R1 - R2) / c).asin();
    2.0 * c * a.cos() + PI * (R1 + R2) + 2.0 * a * (R1 - R2)
}

/// The same with each span's static sag under tension T: the parabola of
/// sag coefficient s = rho' g_n / (2 T) (rho' = m / (1 + T/EA), g_n the part
/// of gravity across the span) is longer than its chord by s^2 L^3 / 6.
/// Both spans are C cos(a) long and leave the centre line at +-a.
fn sagging_belt_length(t: f64) -> f64 {
    let c = X2.hypot(Y2);
    let a = ((R1 - R2) / c).asin();
    let (phi, span) = (Y2.atan2(X2), c * a.cos());
    let rho = MASS / (1.0 + t / EA);
    let sag: f64 = [phi + a, phi - a]
        .iter()
        .map(|angle| {
            let s = rho * G * angle.cos().abs() / (2.0 * t);
            s * s * span.powi(3) / 6.0
        })
        .sum();
    open_belt_length() + sag
}

/// T = EA (L_path(T) / L0 - 1) by fixed-point iteration (the sag term
/// changes L_path by 1e-8 m: it converges at once).
fn closed_form_tension(l0: f64) -> f64 {
    let mut t = EA * (open_belt_length() / l0 - 1.0);
    for _ in 0..20 {
        t = EA * (sagging_belt_length(t) / l0 - 1.0);
    }
    t
}

const TENSIONS: &[&str] = &[
    "belt.installedTension",
    "span[1].tension",
    "span[2].tension",
    "belt.minTension",
    "belt.maxTension",
];

/// A belt 3.5 mm shorter than its 0.9395 m path: T = EA (L_path / L0 - 1)
/// = 445 N. The installation tension reported must be the closed form
/// (1e-7: the FMU solves the same relation by bisection; the spans' sag
/// lengthens the path by 1.7e-8 m, 2e-3 N or 5e-6 of T, so the closed form
/// without it would fail), and the mounted belt must carry it: the span tensions and the
/// belt's min and max SDE tension within 1 % (the relaxation into the static
/// equilibrium leaves the tension uneven by up to 0.5 % round the loop,
/// docs/model.md "Layout and preload"; gravity and the contact's
/// penetration do not change the tension the chain was mounted at).
#[test]
fn natural_length_gives_the_closed_form_tension() {
    let fmi = Fmi::load();
    let path = open_belt_length();
    let l0 = 0.936;
    let closed = closed_form_tension(l0);
    let (i, s) = drive(&fmi, &[("belt.naturalLength", l0)]);
    assert_eq!(s, OK, "{:?}", i.log.borrow());
    let t = i.get(TENSIONS);
    eprintln!(
        "path {path:.6} m, L0 {l0} m: closed form {closed:.3} N; {TENSIONS:?} = {t:.3?}; \
         belt.length {:.6} m",
        i.get(&["belt.length"])[0]
    );
    assert!((t[0] / closed - 1.0).abs() < 1e-7, "{} vs {closed}", t[0]);
    for (name, x) in TENSIONS.iter().zip(&t).skip(1) {
        let err = x / closed - 1.0;
        assert!(
            err.abs() < 0.01,
            "{name} {x:.3} N vs {closed:.3} N ({err:+.4})"
        );
    }
    // the belt's length is the one given
    let length = i.get(&["belt.length"])[0];
    assert!((length / l0 - 1.0).abs() < 1e-9, "belt.length {length}");
    // and the drive runs: 20 ms at rest keep the tension (1 %, as above)
    for k in 0..20 {
        assert_eq!(i.step(f64::from(k) * 1e-3, 1e-3), OK);
    }
    let after = i.get(&["span[1].tension", "span[2].tension"]);
    for x in after {
        assert!(
            (x / closed - 1.0).abs() < 0.01,
            "after 20 ms: {x} vs {closed}"
        );
    }
}

/// Preload 300 N -> `belt.length` -> a second instance given that natural
/// length -> 300 N again (1e-9: the same continuum relation both ways), and
/// the two mounted belts carry the same tension (1e-6).
#[test]
fn preload_and_natural_length_round_trip() {
    let fmi = Fmi::load();
    let (a, s) = drive(&fmi, &[("belt.preload", 300.0)]);
    assert_eq!(s, OK, "{:?}", a.log.borrow());
    let length = a.get(&["belt.length"])[0];
    // the continuum's natural length: L_path / (1 + T/EA), the path with
    // the spans' sag (1e-12 m: rounding)
    let expected = sagging_belt_length(300.0) / (1.0 + 300.0 / EA);
    assert!((length - expected).abs() < 1e-12, "{length} vs {expected}");
    let (b, s) = drive(&fmi, &[("belt.naturalLength", length)]);
    assert_eq!(s, OK, "{:?}", b.log.borrow());
    let (ta, tb) = (a.get(TENSIONS), b.get(TENSIONS));
    eprintln!("belt.length {length:.9} m; preload: {ta:.4?}; from the length: {tb:.4?}");
    assert!((ta[0] - 300.0).abs() < 1e-12 && (tb[0] / 300.0 - 1.0).abs() < 1e-9);
    for (x, y) in ta.iter().zip(&tb).skip(1) {
        assert!((x / y - 1.0).abs() < 1e-6, "{ta:?} vs {tb:?}");
    }
}

/// The tension is never set twice, a belt longer than its path hangs slack,
/// and an arm's angle would need the spring's free angle: each refused at
/// initialization with the parameters named.
#[test]
fn contradictory_or_impossible_lengths_are_refused() {
    let fmi = Fmi::load();
    let (i, s) = drive(
        &fmi,
        &[("belt.naturalLength", 0.936), ("belt.preload", 400.0)],
    );
    i.assert_refused(s, "belt.naturalLength");
    assert!(i.logged(ERROR, "belt.preload"), "{:?}", i.log.borrow());
    let (i, s) = drive(&fmi, &[("belt.naturalLength", 0.95)]);
    i.assert_refused(s, "hangs slack");
    // millimetres typed for metres
    let (i, s) = drive(&fmi, &[("belt.naturalLength", 936.0)]);
    i.assert_refused(s, "belt.naturalLength");
    let (i, s) = drive(&fmi, &[("belt.naturalLength", 0.5)]);
    i.assert_refused(s, "belt.EA");
    let i = Instance::new(&fmi);
    assert_eq!(i.set_real("belt.naturalLength", 0.8), OK);
    assert_eq!(i.set_boolean("pulley[2].tensioner", true), OK);
    assert_eq!(i.set_real("pulley[2].arm.pivot.y", 0.08), OK);
    // SAFETY: live instance.
    let s = unsafe {
        assert_eq!((fmi.setup_experiment)(i.c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!((fmi.enter_init)(i.c), OK);
        (fmi.exit_init)(i.c)
    };
    // the spring as built is what a length with an arm needs
    i.assert_refused(s, "pulley[2].arm.nominalTorque");
}
