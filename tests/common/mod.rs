//! Shared helpers for the physics tests: small drives that reach steady
//! state quickly, and time averages of outputs.
#![allow(dead_code)]

pub mod arm;

use belt_drive::model::params::PulleyParams;
use belt_drive::{Drive, DriveParams, FrictionLaw, Inputs, Outputs};

/// A two-pulley drive with the paper's 5PK belt properties but longer
/// bodies (r = 50 mm, 0.25 m apart, 40 bodies): the same physics as the
/// section-4 drive at a fraction of the cost.
pub fn small_drive(law: FrictionLaw) -> DriveParams {
    let mut p = DriveParams::kubas_section4();
    p.belt.n_bodies = 40;
    p.belt.preload = 300.0;
    p.friction.law = law;
    p.probe_body = 0;
    let mut p1 = PulleyParams::paper_5pk(0.0, 0.0);
    p1.radius = 0.05;
    let mut p2 = p1.clone();
    p2.x = 0.25;
    p.pulleys = vec![p1, p2];
    p
}

/// The default drive re-meshed coarsely: 60 bodies on two 50 mm pulleys
/// 0.25 m apart under 300 N (13.6 mm bodies, l = 0.27 r), the pulleys'
/// torques and loads the defaults' (tests/defaults.rs, tests/modes.rs).
pub fn sixty_bodies() -> DriveParams {
    let mut p = DriveParams::default();
    p.belt.n_bodies = 60;
    p.belt.preload = 300.0;
    p.probe_body = 0;
    p.pulleys[0].radius = 0.05;
    p.pulleys[1].radius = 0.05;
    p.pulleys[1].x = 0.25;
    p
}

/// Pulley 1 speed-driven at `omega` (reached by a 0.05 s ramp), pulley 2
/// loaded by `load_damping * omega`.
pub fn speed_driven(mut p: DriveParams, omega: f64, load_damping: f64) -> DriveParams {
    p.pulleys[0].speed_driven = true;
    p.pulleys[0].omega_ramp = omega;
    p.pulleys[0].ramp_time = 0.05;
    p.pulleys[0].torque_ramp = 0.0;
    p.pulleys[1].load_damping = load_damping;
    p.pulleys[1].torque_ramp = 0.0;
    p
}

/// Time averages over a window.
#[derive(Debug, Default, Clone)]
pub struct Averages {
    /// Mean angular speeds from angle differences [rad/s].
    pub omega: Vec<f64>,
    /// Mean span tensions [N].
    pub span_tension: Vec<f64>,
    pub min_tension: f64,
    pub max_tension: f64,
    pub belt_torque: Vec<f64>,
    pub last: Outputs,
}

/// Runs `drive` to `t_start`, then averages over [t_start, t_end] sampled
/// every `dt`.
pub fn run_and_average(drive: &mut Drive, t_start: f64, t_end: f64, dt: f64) -> Averages {
    drive.advance(t_start).expect("run to the averaging window");
    let np = drive.params().pulleys.len();
    let o0 = drive.outputs();
    let mut sum_t = vec![0.0; np];
    let mut sum_bt = vec![0.0; np];
    let mut min_t = f64::INFINITY;
    let mut max_t = f64::NEG_INFINITY;
    let n = ((t_end - t_start) / dt).round() as usize;
    let mut last = o0.clone();
    for k in 1..=n {
        drive
            .advance(t_start + k as f64 * dt)
            .expect("run through the averaging window");
        last = drive.outputs();
        for j in 0..np {
            sum_t[j] += last.span_tension[j];
            sum_bt[j] += last.pulleys[j].belt_torque;
        }
        min_t = min_t.min(last.min_tension);
        max_t = max_t.max(last.max_tension);
    }
    let span = t_end - t_start;
    Averages {
        omega: (0..np)
            .map(|j| (last.pulleys[j].angle - o0.pulleys[j].angle) / span)
            .collect(),
        span_tension: sum_t.iter().map(|s| s / n as f64).collect(),
        min_tension: min_t,
        max_tension: max_t,
        belt_torque: sum_bt.iter().map(|s| s / n as f64).collect(),
        last,
    }
}

pub fn drive(p: &DriveParams) -> Drive {
    let mut d = Drive::new(p, 0.0).expect("valid parameters");
    d.set_inputs(Inputs::default());
    d
}
