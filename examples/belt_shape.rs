//! Belt shape over a run of the default drive, for the animation the main job
//! writes (`dist/default_drive.html`). The FMU outputs pulley and span
//! quantities, not the position of every belt body, so this runs the same
//! physics core (`Drive`) with the FMU's default parameters
//! (`DriveParams::default()`, the FMU's start values: checked in
//! tests/parameter_sets.rs) and the same integrator settings, and writes one
//! frame per `--frame-step`: every body's position, every SDE's tension, the
//! pulley angles and the outputs the page plots. The main job compares the
//! frames' span tensions with the FMU run's (the two runs agree to the
//! integration tolerance, not bit for bit: the FMU is stepped by FMPy's
//! communication points, this by the frame times).
//!
//! `cargo run --release --example belt_shape -- OUT.json [--stop-time 2]
//! [--frame-step 0.01] [--method 1|2] [--rel-tol 1e-4] [--probe 127]`
//!
//! Prints `progress <t>` after every frame, for the caller's progress line.

use std::fmt::Write as _;
use std::io::Write as _;

use belt_drive::model::params::Method;
use belt_drive::model::state::body;
use belt_drive::model::system::{Recorder, Workspace};
use belt_drive::{Drive, DriveParams};

/// SDE tensions of one right-hand-side evaluation.
struct Tensions(Vec<f64>);

impl Recorder for Tensions {
    const ACTIVE: bool = true;
    fn sde(&mut self, k: usize, tension: f64, _mid: [f64; 2]) {
        self.0[k] = tension;
    }
}

fn fail(msg: &str) -> ! {
    eprintln!("belt_shape: {msg}");
    std::process::exit(2)
}

fn push_list(s: &mut String, xs: impl Iterator<Item = f64>, digits: usize) {
    s.push('[');
    for (i, x) in xs.enumerate() {
        if i > 0 {
            s.push(',');
        }
        let _ = write!(s, "{x:.digits$}");
    }
    s.push(']');
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let out = args
        .first()
        .filter(|a| !a.starts_with("--"))
        .unwrap_or_else(|| fail("usage: belt_shape OUT.json [--stop-time T] [--frame-step H] [--method 1|2] [--rel-tol R] [--probe N]"))
        .clone();
    let opt = |name: &str, default: f64| -> f64 {
        match args.iter().position(|a| a == name) {
            Some(i) => args
                .get(i + 1)
                .and_then(|v| v.parse().ok())
                .unwrap_or_else(|| fail(&format!("{name} needs a number"))),
            None => default,
        }
    };
    let stop = opt("--stop-time", 2.0);
    let frame = opt("--frame-step", 0.01);
    let method = opt("--method", 1.0);
    let probe = opt("--probe", 108.0) as usize;
    let mut p = DriveParams::default();
    p.solver.rel_tol = opt("--rel-tol", p.solver.rel_tol);
    p.solver.method = match method as i32 {
        1 => Method::Rkf45,
        2 => Method::Rosenbrock,
        _ => fail("--method must be 1 (RKF45) or 2 (stiff)"),
    };
    if probe == 0 || probe > p.belt.n_bodies {
        fail("--probe must be a body number from 1 to belt.nBodies");
    }
    p.probe_body = probe - 1;
    if !(stop > 0.0 && frame > 0.0) {
        fail("--stop-time and --frame-step must be positive");
    }
    let mut d =
        Drive::new(&p, 0.0).unwrap_or_else(|e| fail(&belt_drive::fmu::names::render_error(&e)));
    let n = p.belt.n_bodies;
    let np = p.pulleys.len();

    let mut s = String::new();
    let _ = write!(
        s,
        "{{\"bodies\":{n},\"probe\":{probe},\"method\":{},\"relTol\":{:e},\"frameStep\":{frame},\"pulleys\":[",
        method as i32, p.solver.rel_tol
    );
    for (j, q) in p.pulleys.iter().enumerate() {
        if j > 0 {
            s.push(',');
        }
        let _ = write!(
            s,
            "{{\"x\":{},\"y\":{},\"r\":{},\"backSide\":{}}}",
            q.x, q.y, q.radius, q.back_side
        );
    }
    s.push_str("],\"frames\":[");
    let mut dy = vec![0.0; d.state().len()];
    let mut tensions = Tensions(vec![0.0; n]);
    let mut ws = Workspace::new();
    let frames = (stop / frame).round() as usize;
    let stdout = std::io::stdout();
    for i in 0..=frames {
        let t = if i == frames { stop } else { i as f64 * frame };
        if t > d.time() {
            d.advance(t).unwrap_or_else(|e| {
                fail(&format!("integration failed at t = {}: {e:?}", d.time()))
            });
        }
        let sys = d.system().clone();
        sys.rhs(&mut ws, d.time(), d.state(), &mut dy, &mut tensions);
        let o = d.outputs();
        let y = d.state();
        if i > 0 {
            s.push(',');
        }
        let _ = write!(s, "{{\"t\":{t:.6},\"x\":");
        push_list(&mut s, (0..n).map(|b| body(y, b).position()[0]), 6);
        s.push_str(",\"y\":");
        push_list(&mut s, (0..n).map(|b| body(y, b).position()[1]), 6);
        s.push_str(",\"T\":");
        push_list(&mut s, tensions.0.iter().copied(), 1);
        s.push_str(",\"angle\":");
        push_list(
            &mut s,
            (0..np).map(|j| y[sys.state_layout().pulley(j).angle]),
            5,
        );
        s.push_str(",\"omega\":");
        push_list(&mut s, o.pulleys[..np].iter().map(|q| q.omega), 5);
        s.push_str(",\"span\":");
        push_list(&mut s, o.span_tension[..np].iter().copied(), 2);
        s.push('}');
        let _ = writeln!(stdout.lock(), "progress {t}");
    }
    s.push_str("]}\n");
    std::fs::write(&out, s).unwrap_or_else(|e| fail(&format!("{out}: {e}")));
}
