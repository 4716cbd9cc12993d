//! Slip against body count on three drives unlike each other (docs/validation.md,
//! "Slip against the mesh"): the paper's 5PK drive (equal 27 mm pulleys), a 2:1
//! drive (40 and 80 mm pulleys) and the four-pulley accessory drive
//! (`parameters/accessory-drive-4.ssv`, a back-side idler).
//!
//! Every run is the stiff method (`solver.method` = 2) at relTol 1e-5 unless
//! told otherwise; the speeds are means from the pulley angles over the
//! averaging window. The error column is the slip's relative error against
//! the drive's reference in examples/common/mesh_limits.rs: the 5PK and 2:1
//! drives' mesh-converged slips, which both contacts share (the values
//! tests/mesh.rs checks against), and for the accessory drive the centre
//! contact's n^-2 Richardson value from 480 and 960 bodies (a reference, not
//! an established limit). Beside it the run prints the n^-2 Richardson
//! value of its own two finest meshes.
//!
//! `cargo run --profile ci --example mesh_study -- [drive 5pk|2to1|accessory|all]
//! [method 1|2] [relTol] [bodies,...|-] [contact.points] [mu scale]
//! [NAME*FACTOR...]` (the centre contact, `contact.points` 1, when not given or 0;
//! every pulley's static and kinetic friction coefficients times the scale,
//! default 1; each NAME*FACTOR multiplies one belt or contact parameter, by
//! its FMU name: belt.massPerLength, belt.bendingStiffness,
//! belt.axialDamping, contact.c1, contact.c2, contact.damping,
//! friction.creepMax).
//!
//! `cargo run --profile ci --example mesh_study -- errors DRIVE ROW...` prints
//! the same table's error column for slips measured before, each ROW
//! `bodies=loss` in % (`loss/loss/loss` for the accessory drive's three
//! pulleys).

use belt_drive::model::params::Method;
use belt_drive::{Drive, DriveParams};

#[path = "common/two_to_one.rs"]
mod drives;
use drives::two_to_one;
#[path = "common/ssv.rs"]
mod ssv;
use ssv::from_ssv;
#[path = "common/mesh_limits.rs"]
mod mesh_limits;
use mesh_limits::{CONVERGED_2TO1, CONVERGED_5PK, REFERENCE_ACCESSORY};

/// A drive of the study: its parameters, the averaging window and the meshes.
struct Study {
    name: &'static str,
    params: DriveParams,
    window: (f64, f64),
    meshes: Vec<usize>,
    /// Pulleys whose speed loss against pulley 1 is reported.
    report: Vec<usize>,
    /// The speed loss of each reported pulley the errors are taken against
    /// [%], and what it is.
    reference: (Vec<f64>, &'static str),
}

/// The n^-2 Richardson extrapolation of the two finest meshes' speed losses
/// (`rows` ordered by body count).
fn richardson(rows: &[(usize, Vec<f64>)]) -> Option<Vec<f64>> {
    let [(n1, s1), (n2, s2)] = rows.get(rows.len().checked_sub(2)?..)? else {
        return None;
    };
    let q = (*n2 as f64 / *n1 as f64).powi(2);
    Some(
        s1.iter()
            .zip(s2)
            .map(|(a, b)| (q * b - a) / (q - 1.0))
            .collect(),
    )
}

/// The speed losses of a row and their relative errors against `reference`,
/// as the study's tables print them.
fn loss_and_error(loss: &[f64], reference: &[f64]) -> (String, String) {
    let join = |v: Vec<String>| v.join(" / ");
    (
        join(loss.iter().map(|x| format!("{x:.4}")).collect()),
        join(
            loss.iter()
                .zip(reference)
                .map(|(x, r)| format!("{:+.1} %", 100.0 * (x / r - 1.0)))
                .collect(),
        ),
    )
}

/// The reference of a drive's errors, printed with what it is, and beside
/// it the n^-2 Richardson value of the two finest of `rows`.
fn reference(s: &Study, rows: &[(usize, Vec<f64>)]) -> Vec<f64> {
    let join = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.4}"))
            .collect::<Vec<_>>()
            .join(" / ")
    };
    if let Some(r) = richardson(rows) {
        let (n1, n2) = (rows[rows.len() - 2].0, rows[rows.len() - 1].0);
        println!(
            "Richardson (n^-2) from {n1} and {n2} bodies: {} %",
            join(&r)
        );
    }
    let (r, what) = &s.reference;
    println!("errors against {what}: {} %", join(r));
    r.clone()
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

/// Rigid-adhesion creep theory's speed loss of a two-pulley drive from the
/// run's own mean span tensions, (T_t - T_s) / (EA + T_t) in % (the belt
/// arrives on each pulley in stick, at the strain of the span it comes
/// from); "-" on a drive of more pulleys.
fn creep_theory(tensions: &[f64], ea: f64) -> String {
    let [a, b] = tensions else {
        return "-".into();
    };
    let (t, s) = (a.max(*b), a.min(*b));
    format!("{:.4}", 100.0 * (t - s) / (ea + t))
}

/// The three drives of the study, with their averaging windows and meshes.
fn studies() -> Vec<Study> {
    vec![
        Study {
            name: "5pk",
            params: DriveParams::kubas_section4(),
            window: (0.6, 1.2),
            meshes: vec![100, 150, 225, 300, 600],
            report: vec![1],
            reference: (vec![100.0 * CONVERGED_5PK], "the mesh-converged slip"),
        },
        Study {
            name: "2to1",
            params: two_to_one(),
            window: (0.4, 1.0),
            meshes: vec![80, 120, 180, 240, 480],
            report: vec![1],
            reference: (vec![100.0 * CONVERGED_2TO1], "the mesh-converged slip"),
        },
        Study {
            name: "accessory",
            // the centre contact, as on the other two drives (the paper's
            // set they derive from pins it); the FMU's default, 4 points, is
            // the study's `contact.points` 4
            params: {
                let mut p = from_ssv("accessory-drive-4.ssv");
                p.contact.points = 1;
                p
            },
            window: (0.8, 1.4),
            meshes: vec![160, 240, 320, 480, 960],
            report: vec![1, 2, 3],
            reference: (
                REFERENCE_ACCESSORY.iter().map(|x| 100.0 * x).collect(),
                "the reference slips (the centre contact's Richardson value from 480 and 960 bodies)",
            ),
        },
    ]
}

/// The parameter a `NAME*FACTOR` argument scales, by its FMU name.
fn scaled<'a>(p: &'a mut DriveParams, name: &str) -> &'a mut f64 {
    match name {
        "belt.massPerLength" => &mut p.belt.mass_per_length,
        "belt.bendingStiffness" => &mut p.belt.bending_stiffness,
        "belt.axialDamping" => &mut p.belt.axial_damping,
        "contact.c1" => &mut p.contact.c1,
        "contact.c2" => &mut p.contact.c2,
        "contact.damping" => &mut p.contact.damping,
        "friction.creepMax" => &mut p.friction.creep_max,
        _ => panic!("{name}: not one of the parameters mesh_study scales"),
    }
}

/// Body length over the smallest pulley radius of the drive at `n` bodies.
fn length_ratio(p: &DriveParams, n: usize) -> f64 {
    let mut p = p.clone();
    p.belt.n_bodies = n;
    p.probe_body = 0;
    let r_min = p
        .pulleys
        .iter()
        .map(|q| q.radius)
        .fold(f64::INFINITY, f64::min);
    Drive::mounted(&p, 0.0).unwrap().layout().body_length / r_min
}

/// `errors DRIVE ROW...`: the error column for slips measured before.
fn errors(a: &[String]) {
    let s = studies()
        .into_iter()
        .find(|s| Some(s.name) == a.first().map(String::as_str))
        .expect("drive: 5pk, 2to1 or accessory");
    let parse = |v: &str| -> Vec<f64> { v.split('/').map(|x| x.parse().unwrap()).collect() };
    let rows: Vec<(usize, Vec<f64>, &str)> = a[1..]
        .iter()
        .map(|row| {
            let (n, value) = row.split_once('=').expect("ROW is bodies=loss");
            (n.parse().expect("bodies"), parse(value), value)
        })
        .collect();
    println!("## {} (speed losses given)", s.name);
    let mut sorted: Vec<(usize, Vec<f64>)> = rows.iter().map(|r| (r.0, r.1.clone())).collect();
    sorted.sort_by_key(|r| r.0);
    let reference = reference(&s, &sorted);
    println!("| bodies | l / r_min | speed loss [%] | error |");
    println!("|---|---|---|---|");
    // The losses as given (their digits), the errors computed as for a run.
    for (n, loss, given) in &rows {
        let (_, e) = loss_and_error(loss, &reference);
        println!(
            "| {n} | {:.3} | {} | {e} |",
            length_ratio(&s.params, *n),
            given.replace('/', " / ")
        );
    }
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    if a.first().map(String::as_str) == Some("errors") {
        return errors(&a[1..]);
    }
    let arg = |i: usize, d: &str| a.get(i).cloned().unwrap_or_else(|| d.to_string());
    let which = arg(0, "all");
    let method: u32 = arg(1, "2").parse().unwrap();
    let rtol: f64 = arg(2, "1e-5").parse().unwrap();
    let meshes: Option<Vec<usize>> = a
        .get(3)
        .filter(|s| *s != "-")
        .map(|s| s.split(',').map(|x| x.parse().unwrap()).collect());
    let points: usize = arg(4, "0").parse().unwrap();
    let mu_scale: f64 = arg(5, "1").parse().unwrap();

    let mut studies = studies();
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
        for q in &mut p.pulleys {
            q.mu_static *= mu_scale;
            q.mu_kinetic *= mu_scale;
        }
        for scaling in a.iter().skip(6) {
            let (name, factor) = scaling.split_once('*').expect("NAME*FACTOR");
            let factor: f64 = factor.parse().expect("FACTOR");
            *scaled(&mut p, name) *= factor;
            println!("{name} x {factor}");
        }
        println!(
            "## {} (method {method}, relTol {rtol:e}, contact.points {}, mu x {mu_scale}, window {}-{} s)",
            s.name, p.contact.points, s.window.0, s.window.1
        );
        // Each run as it ends (stderr), the table with the errors once the
        // reference is known (stdout).
        let mut rows = Vec::new();
        for &n in &s.meshes {
            p.belt.n_bodies = n;
            match run(&p, s.window) {
                Ok((w, t, steps, wall)) => {
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
                    let tensions = t
                        .iter()
                        .map(|x| format!("{x:.1}"))
                        .collect::<Vec<_>>()
                        .join(" / ");
                    let theory = creep_theory(&t, p.belt.ea);
                    eprintln!(
                        "{} {n} bodies: {loss:.4?} %, span tensions {tensions} N, creep theory {theory} %, {steps} steps, {wall:.0} s",
                        s.name
                    );
                    rows.push((n, loss, tensions, theory, steps, wall));
                }
                Err(e) => println!("{n} bodies: {e}"),
            }
        }
        let losses: Vec<(usize, Vec<f64>)> = rows.iter().map(|r| (r.0, r.1.clone())).collect();
        // with the friction or a parameter scaled the drive's references do
        // not apply: its own n^-2 Richardson value (two meshes at least)
        let reference = if mu_scale == 1.0 && a.len() <= 6 {
            reference(s, &losses)
        } else if let Some(r) = richardson(&losses) {
            println!("errors against the run's own Richardson (n^-2) value: {r:.4?} %");
            r
        } else {
            continue;
        };
        println!(
            "| bodies | l / r_min | speed loss vs pulley 1 [%] | error | span tensions [N] | creep theory [%] | steps | wall [s] |"
        );
        println!("|---|---|---|---|---|---|---|---|");
        for (n, loss, tensions, theory, steps, wall) in &rows {
            let (l, e) = loss_and_error(loss, &reference);
            println!(
                "| {n} | {:.3} | {l} | {e} | {tensions} | {theory} | {steps} | {wall:.0} |",
                length_ratio(&p, *n)
            );
        }
        println!();
    }
}
