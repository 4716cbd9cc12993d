//! The tension, normal force, friction force, creep displacement and
//! relative velocity along every wrap of a drive (the 5PK drive of section
//! 4, the 2:1 drive or the accessory drive of docs/validation.md), averaged
//! over snapshots in steady running and binned by the angle travelled from
//! the tangent point where the belt arrives on the pulley. Shows where a
//! coarse mesh's excess slip comes from, and feeds the reduced model
//! `examples/creep_wrap.py` (docs/validation.md, "Why a coarse mesh slips
//! more").
//!
//! `cargo run --profile ci --example wrap_profile -- [5pk|2to1|accessory|sixty|heavy]
//! [bodies] [bin width, degrees] [contact.points] [solver.method] [solver.relTol]
//! [NAME*FACTOR...] [off]` (NAME one of friction.creepMax, contact.c1, contact.c2; relTol `-`:
//! the default)
//! (the drive's own `contact.points` when not given or 0; the stiff method
//! (2) at relTol 1e-5, absTol 1e-7 when not given; a given relTol keeps the
//! default absTol, as the tests run; `off` runs the stiff method without
//! its energy check). `sixty` is the 60-body drive of
//! `tests/defaults.rs` (`integrators_agree_on_a_sixty_body_drive`), `heavy`
//! the heavy-belt drive of `tests/python/test_mean_forces.py`.
//!
//! Signs follow the belt: f > 0 pulls the belt along its travel, z > 0 and
//! v_T > 0 mean the pulley surface runs ahead of the belt (the belt lags).

use std::f64::consts::TAU;

use belt_drive::model::params::Method;
use belt_drive::model::state::body;
use belt_drive::model::system::{Recorder, Workspace};
use belt_drive::{Drive, DriveParams};

#[path = "common/two_to_one.rs"]
mod drives;
use drives::two_to_one;
#[path = "common/ssv.rs"]
mod ssv;
use ssv::from_ssv;

#[derive(Default)]
struct Snap {
    /// (body, pulley, N, f, v_T)
    contacts: Vec<(usize, usize, f64, f64, f64)>,
    /// (tension, midpoint)
    sdes: Vec<(f64, [f64; 2])>,
}

impl Recorder for Snap {
    const ACTIVE: bool = true;
    fn sde(&mut self, _k: usize, tension: f64, mid: [f64; 2]) {
        self.sdes.push((tension, mid));
    }
    fn contact(&mut self, body: usize, pulley: usize, n: f64, f: f64, v_t: f64, _p: f64) {
        if n > 0.0 {
            self.contacts.push((body, pulley, n, f, v_t));
        }
    }
}

/// One wrap as the profile sees it: its pulley, the angle about the pulley
/// centre of the tangent point where the belt arrives, and the sense in
/// which the belt travels round it (+1 counterclockwise).
struct WrapFrame {
    pulley: usize,
    arrive: f64,
    sense: f64,
    angle: f64,
}

#[path = "common/sixty_body.rs"]
mod sixty_body;
use sixty_body::sixty_body_drive;

#[path = "common/heavy_belt.rs"]
mod heavy_belt;
use heavy_belt::heavy_belt_drive;

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, d: &str| a.get(i).cloned().unwrap_or_else(|| d.to_string());
    let which = arg(0, "5pk");
    let n: usize = arg(1, "150").parse().unwrap();
    let bin: f64 = arg(2, "10").parse::<f64>().unwrap().to_radians();
    let points: usize = arg(3, "0").parse().unwrap();
    let method = match arg(4, "2").as_str() {
        "1" => Method::Rkf45,
        _ => Method::Rosenbrock,
    };
    // given: with the default absTol, as the tests run it
    let tol: Option<f64> = a.get(5).filter(|v| *v != "-").map(|v| v.parse().unwrap());
    let (mut p, (t0, t1)) = match which.as_str() {
        "2to1" => (two_to_one(), (0.5, 0.8)),
        "accessory" => (from_ssv("accessory-drive-4.ssv"), (0.8, 1.1)),
        "sixty" => (sixty_body_drive(), (0.3, 0.5)),
        "heavy" => (heavy_belt_drive(), (0.2, 0.3)),
        _ => (DriveParams::kubas_section4(), (0.5, 0.8)),
    };
    p.belt.n_bodies = n;
    if points > 0 {
        p.contact.points = points;
    }
    p.probe_body = 0;
    p.solver.method = method;
    match tol {
        Some(t) => p.solver.rel_tol = t,
        None => {
            p.solver.rel_tol = 1e-5;
            p.solver.abs_tol = 1e-7;
        }
    }
    p.solver.max_steps = u64::MAX;
    // NAME*FACTOR after the tolerance: a creep-law parameter scaled
    for scaling in a.iter().skip(6).filter(|v| v.as_str() != "off") {
        let (name, factor) = scaling.split_once('*').expect("NAME*FACTOR");
        let factor: f64 = factor.parse().expect("FACTOR");
        match name {
            "friction.creepMax" => p.friction.creep_max *= factor,
            "contact.c1" => p.contact.c1 *= factor,
            "contact.c2" => p.contact.c2 *= factor,
            _ => panic!("{name}: not one of friction.creepMax, contact.c1, contact.c2"),
        }
    }
    let np = p.pulleys.len();
    let mut d = Drive::new(&p, 0.0).expect("parameters");
    d.set_energy_check(!a.iter().skip(6).any(|v| v == "off"));
    let l = d.layout().body_length;
    d.advance(t0).expect("advance");
    let o0 = d.outputs();
    // the belt runs in the layout's loop order when the first wrap's pulley
    // turns in that wrap's sense (+1 inside the loop: counterclockwise)
    let layout = d.layout().clone();
    let w0 = &layout.wraps[0];
    let forward = o0.pulleys[w0.pulley].omega * w0.side > 0.0;
    let ns = layout.spans.len();
    let frames: Vec<WrapFrame> = (0..ns)
        .map(|m| {
            let w = &layout.wraps[m];
            let q = &p.pulleys[w.pulley];
            // wraps[m] lies between spans[m] (arriving in loop order) and
            // spans[m + 1]
            let t = if forward {
                layout.spans[m].end
            } else {
                layout.spans[(m + 1) % ns].start
            };
            WrapFrame {
                pulley: w.pulley,
                arrive: (t[1] - q.y).atan2(t[0] - q.x),
                sense: if forward { w.side } else { -w.side },
                angle: w.angle,
            }
        })
        .collect();
    let nb = (TAU / bin).ceil() as usize;
    // per wrap and bin: tension sum/count, N, f, z, v_T sums and count
    let mut ten = vec![[0.0f64; 2]; ns * nb];
    let mut con = vec![[0.0f64; 5]; ns * nb];
    let samples = 60;
    // per pulley: the sum of the mean belt torques over the snapshots'
    // equal intervals (their mean is the window's mean)
    let mut belt_torque = vec![0.0f64; np];
    // travel angle from the arrival on wrap m of a point near its pulley
    let travel = |m: usize, c: [f64; 2], x: f64, y: f64| -> Option<usize> {
        let f = &frames[m];
        let (dx, dy) = (x - c[0], y - c[1]);
        let r = p.pulleys[f.pulley].radius + 2.0 * l;
        if dx * dx + dy * dy > r * r {
            return None;
        }
        let s = (f.sense * (dy.atan2(dx) - f.arrive)).rem_euclid(TAU);
        Some(((s / bin) as usize).min(nb - 1))
    };
    for k in 1..=samples {
        d.advance(t0 + (t1 - t0) * k as f64 / samples as f64)
            .expect("advance");
        for (j, t) in belt_torque.iter_mut().enumerate() {
            *t += d.outputs().pulleys[j].mean_belt_torque / samples as f64;
        }
        let sys = d.system().clone();
        let y = d.state().to_vec();
        let centres: Vec<[f64; 2]> = (0..np).map(|j| sys.pulley_centre(j, &y).0).collect();
        let mut s = Snap::default();
        let mut dy = vec![0.0; y.len()];
        sys.rhs(&mut Workspace::new(), d.time(), &y, &mut dy, &mut s);
        for &(t, [x, yy]) in &s.sdes {
            for (m, f) in frames.iter().enumerate() {
                if let Some(b) = travel(m, centres[f.pulley], x, yy) {
                    ten[m * nb + b][0] += t;
                    ten[m * nb + b][1] += 1.0;
                }
            }
        }
        for &(i, j, nn, f, vt) in &s.contacts {
            let bi = body(&y, i);
            let [bx, by] = bi.position();
            for (m, fr) in frames.iter().enumerate().filter(|(_, fr)| fr.pulley == j) {
                if let Some(b) = travel(m, centres[j], bx, by) {
                    // the model's f, z and v_T point along the pulley's
                    // counterclockwise tangent, the belt travels along
                    // fr.sense times it
                    let sign = fr.sense;
                    let c = &mut con[m * nb + b];
                    c[0] += nn;
                    c[1] += sign * f;
                    c[2] += sign * bi.creep();
                    c[3] += sign * vt;
                    c[4] += 1.0;
                }
            }
        }
    }
    let o1 = d.outputs();
    let w: Vec<f64> = (0..np)
        .map(|j| (o1.pulleys[j].angle - o0.pulleys[j].angle) / (t1 - t0))
        .collect();
    let losses: Vec<String> = (1..np)
        .map(|j| {
            let loss =
                1.0 - (w[j] * p.pulleys[j].radius).abs() / (w[0] * p.pulleys[0].radius).abs();
            format!("{:.4}", 100.0 * loss)
        })
        .collect();
    println!(
        "{which}, {n} bodies (l = {:.3} mm), contact.points {}: speed loss against pulley 1 [%] {}",
        l * 1e3,
        p.contact.points,
        losses.join(" / ")
    );
    // the belt's loss: the power it takes from the pulleys less the power it
    // gives them, from the window's mean belt torques and speeds
    let loss: f64 = -(0..np).map(|j| belt_torque[j] * w[j]).sum::<f64>();
    println!(
        "mean belt torque [N m] {}, mean speed [rad/s] {}, belt loss {:.3} W, {} steps",
        belt_torque
            .iter()
            .map(|t| format!("{t:.4}"))
            .collect::<Vec<_>>()
            .join(" / "),
        w.iter()
            .map(|v| format!("{v:.4}"))
            .collect::<Vec<_>>()
            .join(" / "),
        loss,
        d.stats().steps
    );
    // the constants of the reduced model (examples/creep_wrap.py)
    println!(
        "belt EA {} N, friction.creepMax {} m, friction.creepDampingTime {} s, belt speed {:.4} m/s, massPerLength {} kg/m",
        p.belt.ea,
        p.friction.creep_max,
        p.friction.creep_damping_time,
        (w[0] * p.pulleys[0].radius).abs(),
        p.belt.mass_per_length
    );
    for (m, f) in frames.iter().enumerate() {
        println!(
            "\npulley {} (radius {} m, wrap {:.4} deg, muStatic {}, muKinetic {}; travel from arrival [deg], mean SDE tension [N], per contact: N [N], f [N], z [um], v_T [mm/s], contacts per snapshot)",
            f.pulley + 1,
            p.pulleys[f.pulley].radius,
            f.angle.to_degrees(),
            p.pulleys[f.pulley].mu_static,
            p.pulleys[f.pulley].mu_kinetic
        );
        for b in 0..nb {
            let t = ten[m * nb + b];
            let c = con[m * nb + b];
            if c[4] == 0.0 && t[1] == 0.0 {
                continue;
            }
            let cnt = c[4].max(1.0);
            println!(
                "{:6.1} {:8.1} | {:7.1} {:8.2} {:8.2} {:8.3} {:5.2}",
                (b as f64 + 0.5) * bin.to_degrees(),
                t[0] / t[1].max(1.0),
                c[0] / cnt,
                c[1] / cnt,
                1e6 * c[2] / cnt,
                1e3 * c[3] / cnt,
                c[4] / samples as f64
            );
        }
    }
}
