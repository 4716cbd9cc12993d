//! The body-passing component of a drive's instantaneous outputs (shared by
//! examples/body_passing.rs and tests/mesh.rs, included with `#[path]`; the
//! including crate declares `mod ssv` and `mod accessory` from
//! examples/common/).

use belt_drive::model::params::Method;
use belt_drive::{Drive, DriveParams};
use std::f64::consts::PI;

/// Sampling interval [s] and window [s].
const DT: f64 = 20e-6;
const WINDOW: f64 = 0.2;

/// Amplitude of the component at frequency `f` of samples `x` taken every
/// `DT`, Hann-windowed (the window's coherent gain 1/2 corrected).
pub fn amplitude(x: &[f64], f: f64) -> f64 {
    let n = x.len();
    let (mut re, mut im) = (0.0, 0.0);
    for (k, v) in x.iter().enumerate() {
        let w = 0.5 - 0.5 * (2.0 * PI * k as f64 / (n - 1) as f64).cos();
        let ph = 2.0 * PI * f * k as f64 * DT;
        re += w * v * ph.cos();
        im += w * v * ph.sin();
    }
    2.0 * (re * re + im * im).sqrt() / (0.5 * n as f64)
}

/// The largest amplitude within 5 % of `f` and the frequency it is at.
pub fn line_near(x: &[f64], f: f64) -> (f64, f64) {
    (-50..=50)
        .map(|k| {
            let g = f * (1.0 + 1e-3 * k as f64);
            (amplitude(x, g), g)
        })
        .fold((0.0, f), |a, b| if b.0 > a.0 { b } else { a })
}

/// One signal's mean, peak-to-peak swing and spectral lines.
#[derive(Clone, Debug)]
#[allow(dead_code)] // tests/mesh.rs reads the mean and the line at f_bp only
pub struct Signal {
    /// What it is, with its unit.
    pub name: String,
    /// Mean over the window.
    pub mean: f64,
    /// Largest less smallest sample.
    pub peak_to_peak: f64,
    /// Amplitude of the largest line within 5 % of f_bp, and its frequency.
    pub at_f_bp: (f64, f64),
    /// ... of 2 f_bp.
    pub at_2f_bp: f64,
    /// ... of f_bp / 2.
    pub at_half_f_bp: f64,
}

/// The accessory set `set` (`acc4`: parameters/accessory-drive-4.ssv,
/// `tens`: parameters/accessory-drive-tensioner.ssv) with the crank at
/// `rpm` (load damping scaled by 800 / rpm: the idle load torques) and
/// `method` at relTol 1e-4, settled 0.1 s after its speed ramp, sampled
/// every `DT` over `WINDOW`: the body-passing frequency f_bp = v / l [Hz]
/// and the alternator's (pulley 3) belt torque, then each span's tension.
#[allow(dead_code)] // examples/body_passing.rs calls measure_with
pub fn measure(set: &str, rpm: f64, method: Method) -> (DriveParams, f64, Vec<Signal>) {
    measure_with(set, rpm, method, &[])
}

/// `measure` with the parameters `overrides` (FMU variable name, value) set
/// after the file's (e.g. `belt.nBodies`, `contact.points`).
pub fn measure_with(
    set: &str,
    rpm: f64,
    method: Method,
    overrides: &[(String, String)],
) -> (DriveParams, f64, Vec<Signal>) {
    let p: DriveParams = crate::accessory::at_rpm_with(set, rpm, method, overrides);
    let np = p.pulleys.len();
    let ramp = p.pulleys.iter().map(|q| q.ramp_time).fold(0.0, f64::max);
    let t0 = ramp + 0.1;
    let mut d = Drive::new(&p, 0.0).expect("valid drive");
    let mut t = 0.0;
    while t < t0 - 1e-12 {
        t += 1e-3;
        d.advance(t).expect("runs");
    }
    let n = (WINDOW / DT).round() as usize;
    let mut sig = vec![Vec::with_capacity(n); 1 + np];
    for k in 1..=n {
        d.advance(t0 + k as f64 * DT).expect("runs");
        let o = d.outputs();
        sig[0].push(o.pulleys[2].belt_torque);
        for j in 0..np {
            sig[1 + j].push(o.span_tension[j]);
        }
    }
    // belt speed from the crank's speed, body length from the belt's
    let v = p.pulleys[0].omega_ramp.abs() * p.pulleys[0].radius;
    let f_bp = v / (2.0 * d.system().half_length());
    let signals = sig
        .iter()
        .enumerate()
        .map(|(i, x)| {
            let (lo, hi) = x
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                });
            Signal {
                name: if i == 0 {
                    "alternator belt torque [N m]".into()
                } else {
                    format!("span {i} tension [N]")
                },
                mean: x.iter().sum::<f64>() / x.len() as f64,
                peak_to_peak: hi - lo,
                at_f_bp: line_near(x, f_bp),
                at_2f_bp: line_near(x, 2.0 * f_bp).0,
                at_half_f_bp: line_near(x, 0.5 * f_bp).0,
            }
        })
        .collect();
    (p, f_bp, signals)
}
