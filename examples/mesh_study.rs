//! Slip against body count on three drives unlike each other (docs/validation.md,
//! "Slip against the mesh"): the paper's 5PK drive (equal 27 mm pulleys), a 2:1
//! drive (40 and 80 mm pulleys) and the four-pulley accessory drive
//! (`parameters/accessory-drive-4.ssv`, a back-side idler).
//!
//! Every run is the stiff method (`solver.method` = 2) at relTol 1e-5 unless
//! told otherwise; the speeds are means from the pulley angles over the
//! averaging window. The mesh-converged value is the Richardson extrapolation
//! of the two finest meshes (second order: the excess falls as n^-2).
//!
//! `cargo run --profile ci --example mesh_study -- [drive 5pk|2to1|accessory|all]
//! [method 1|2] [relTol] [bodies,...] [contact.points]` (the drive's own
//! `contact.points` when not given or 0).

use belt_drive::belt::params::Method;
use belt_drive::belt::{Drive, DriveParams};

#[path = "common/two_to_one.rs"]
mod drives;
use drives::two_to_one;
#[path = "common/ssv.rs"]
mod ssv;
use ssv::from_ssv;

/// A drive of the study: its parameters, the averaging window and the meshes.
struct Study {
    name: &'static str,
    params: DriveParams,
    window: (f64, f64),
    meshes: Vec<usize>,
    /// Pulleys whose speed loss against pulley 1 is reported.
    report: Vec<usize>,
}

/// Mean speeds over the window and mean span tensions.
fn run(p: &DriveParams, window: (f64, f64)) -> Result<(Vec<f64>, Vec<f64>, u64, f64), String> {
    let start = std::time::Instant::now();
    let mut d = Drive::new(p, 0.0).map_err(|e| e.to_string())?;
    let np = p.pulleys.len();
    d.advance(window.0).map_err(|e| format!("{e:?}"))?;
    let o0 = d.outputs();
    let steps = 50;
    let mut tens = vec![0.0; np];
    let mut last = o0.clone();
    for k in 1..=steps {
        let t = window.0 + (window.1 - window.0) * k as f64 / steps as f64;
        d.advance(t).map_err(|e| format!("{e:?}"))?;
        last = d.outputs();
        for (s, t) in tens.iter_mut().zip(&last.span_tension) {
            *s += t / steps as f64;
        }
    }
    let span = window.1 - window.0;
    let omega = (0..np)
        .map(|j| (last.pulleys[j].angle - o0.pulleys[j].angle) / span)
        .collect();
    Ok((omega, tens, d.stats().steps, start.elapsed().as_secs_f64()))
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, d: &str| a.get(i).cloned().unwrap_or_else(|| d.to_string());
    let which = arg(0, "all");
    let method: u32 = arg(1, "2").parse().unwrap();
    let rtol: f64 = arg(2, "1e-5").parse().unwrap();
    let meshes: Option<Vec<usize>> = a
        .get(3)
        .filter(|s| *s != "-")
        .map(|s| s.split(',').map(|x| x.parse().unwrap()).collect());
    let points: usize = arg(4, "0").parse().unwrap();

    let mut studies = vec![
        Study {
            name: "5pk",
            params: DriveParams::kubas_section4(),
            window: (0.6, 1.2),
            meshes: vec![100, 150, 225, 300, 600],
            report: vec![1],
        },
        Study {
            name: "2to1",
            params: two_to_one(),
            window: (0.4, 1.0),
            meshes: vec![80, 120, 180, 240, 480],
            report: vec![1],
        },
        Study {
            name: "accessory",
            params: from_ssv("accessory-drive-4.ssv"),
            window: (0.8, 1.4),
            meshes: vec![160, 240, 320, 480, 960],
            report: vec![1, 2, 3],
        },
    ];
    studies.retain(|s| which == "all" || which == s.name);
    for s in &mut studies {
        if let Some(m) = &meshes {
            s.meshes.clone_from(m);
        }
        let mut p = s.params.clone();
        p.probe_body = 0;
        p.solver.method = if method == 2 {
            Method::Rosenbrock
        } else {
            Method::Rkf45
        };
        p.solver.rel_tol = rtol;
        p.solver.abs_tol = rtol * 1e-2;
        p.solver.max_steps = u64::MAX;
        if points > 0 {
            p.contact.points = points;
        }
        let r_min = p
            .pulleys
            .iter()
            .map(|q| q.radius)
            .fold(f64::INFINITY, f64::min);
        println!(
            "## {} (method {method}, relTol {rtol:e}, contact.points {}, window {}-{} s)",
            s.name, p.contact.points, s.window.0, s.window.1
        );
        println!("| bodies | l / r_min | speed loss vs pulley 1 [%] | span tensions [N] | steps | wall [s] |");
        println!("|---|---|---|---|---|---|");
        let mut losses = Vec::new();
        for &n in &s.meshes {
            p.belt.n_bodies = n;
            match run(&p, s.window) {
                Ok((w, t, steps, wall)) => {
                    let l = Drive::mounted(&p, 0.0).unwrap().layout().body_length;
                    let loss: Vec<f64> = s
                        .report
                        .iter()
                        .map(|&j| {
                            100.0
                                * (1.0
                                    - (w[j] * p.pulleys[j].radius).abs()
                                        / (w[0] * p.pulleys[0].radius).abs())
                        })
                        .collect();
                    println!(
                        "| {n} | {:.3} | {} | {} | {steps} | {wall:.0} |",
                        l / r_min,
                        loss.iter()
                            .map(|x| format!("{x:.4}"))
                            .collect::<Vec<_>>()
                            .join(" / "),
                        t.iter()
                            .map(|x| format!("{x:.1}"))
                            .collect::<Vec<_>>()
                            .join(" / "),
                    );
                    losses.push((n, loss));
                }
                Err(e) => println!("| {n} | | {e} | | | |"),
            }
        }
        if losses.len() >= 2 {
            let (n1, s1) = &losses[losses.len() - 2];
            let (n2, s2) = &losses[losses.len() - 1];
            let q = (*n2 as f64 / *n1 as f64).powi(2);
            let rich: Vec<String> = s1
                .iter()
                .zip(s2)
                .map(|(a, b)| format!("{:.4}", (q * b - a) / (q - 1.0)))
                .collect();
            println!(
                "Richardson (n^-2) from {n1} and {n2} bodies: {} %\n",
                rich.join(" / ")
            );
        }
    }
}
