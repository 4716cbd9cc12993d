//! Modal analysis of a drive (`cargo xtask modes -- ...`, docs/modes.md):
//! natural frequencies, damping ratios and mode descriptions about the
//! mounted static state, or about the steady running state at each crank
//! (pulley 1) speed (the Floquet analysis about its periodic orbit), written
//! to `dist/modes.csv` (with the orbit's defect and whether it counts as
//! periodic per speed).
//!
//! ```text
//! cargo run --release --features modes --example modes -- [--ssv FILE] [--set NAME=VALUE ...]
//!     [--speeds FROM:TO:N] [--at TIME] [--fmax HZ] [--out FILE] [--frozen]
//!     [--arm-amplitude DEG] [--idle-loads] [--mesh-check BODIES]
//! ```
//!
//! `--arm-amplitude DEG` (default 0.5): the swing of the tensioner arms at
//! which their pivot friction is replaced by its describing function, at
//! rest, `--frozen` and in the Floquet analysis of steady running
//! (docs/modes.md, "Frictional tensioner arms"); 0 linearises the friction
//! law as it is.
//!
//! `--frozen`: at running speeds, the frozen-time approximation (one
//! instant's Jacobian with the belt's transport) instead of the Floquet
//! analysis. `--idle-loads`: at each speed every load damping is scaled by
//! the set's crank speed over the analysed one, so the loads keep the
//! torques they take at the set's speed (the set's loads grow with the
//! speed squared). At each running speed the console names the growing
//! modes' cause where the mesh explains it (`belt_drive::modes::mechanism`).
//! `--mesh-check BODIES`: at each running speed with a growing mode, the
//! analysis is repeated with `belt.nBodies` = BODIES (1.5 times the drive's
//! is a good choice) and each growing mode is said to grow there too (the
//! drive's) or not (the discrete belt's).

use belt_drive::modes::{
    adapter, analyse_drive, floquet, mechanism, params, Modes, Options, ARM_AMPLITUDE,
    FLOQUET_SUBSTEPS,
};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

struct Args {
    ssv: Option<PathBuf>,
    sets: Vec<String>,
    speeds: Option<(f64, f64, usize)>,
    at: Option<f64>,
    fmax: f64,
    out: PathBuf,
    frozen: bool,
    arm_amplitude: f64,
    idle_loads: bool,
    mesh_check: Option<usize>,
}

const USAGE: &str = "usage: modes [--ssv FILE] [--set NAME=VALUE ...] [--speeds FROM:TO:N] \
                     [--at TIME] [--fmax HZ] [--out FILE] [--frozen] [--arm-amplitude DEG] \
                     [--idle-loads] [--mesh-check BODIES]";

fn parse() -> Result<Args, String> {
    let mut a = Args {
        ssv: None,
        sets: Vec::new(),
        speeds: None,
        at: None,
        fmax: 2000.0,
        out: PathBuf::from("dist/modes.csv"),
        frozen: false,
        arm_amplitude: ARM_AMPLITUDE,
        idle_loads: false,
        mesh_check: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(k) = it.next() {
        let mut val = || {
            it.next()
                .ok_or_else(|| format!("{k} needs a value; {USAGE}"))
        };
        let num = |s: String, what: &str| -> Result<f64, String> {
            s.parse().map_err(|e| format!("{what} {s}: {e}"))
        };
        match k.as_str() {
            "--ssv" => a.ssv = Some(PathBuf::from(val()?)),
            "--set" => a.sets.push(val()?),
            "--at" => a.at = Some(num(val()?, "--at")?),
            "--fmax" => a.fmax = num(val()?, "--fmax")?,
            "--out" => a.out = PathBuf::from(val()?),
            "--frozen" => a.frozen = true,
            "--arm-amplitude" => {
                let deg = num(val()?, "--arm-amplitude")?;
                if !(deg >= 0.0 && deg.is_finite()) {
                    return Err(format!("--arm-amplitude {deg}: degrees >= 0"));
                }
                a.arm_amplitude = deg.to_radians();
            }
            "--idle-loads" => a.idle_loads = true,
            "--mesh-check" => {
                let s = val()?;
                let n: usize = s
                    .parse()
                    .map_err(|e| format!("--mesh-check {s}: BODIES: {e}"))?;
                a.mesh_check = Some(n);
            }
            "--speeds" => {
                let s = val()?;
                let p: Vec<&str> = s.split(':').collect();
                if p.len() != 3 {
                    return Err(format!("--speeds {s}: expected FROM:TO:N (rad/s)"));
                }
                let n: usize = p[2].parse().map_err(|e| format!("--speeds {s}: N: {e}"))?;
                let (from, to) = (num(p[0].into(), "--speeds")?, num(p[1].into(), "--speeds")?);
                if n == 0 || from < 0.0 || to < from {
                    return Err(format!(
                        "--speeds {s}: need 0 <= FROM <= TO (crank speed magnitudes, rad/s) and N >= 1"
                    ));
                }
                a.speeds = Some((from, to, n));
            }
            "-h" | "--help" => return Err(USAGE.into()),
            _ => return Err(format!("unknown argument {k}; {USAGE}")),
        }
    }
    if a.frozen && a.mesh_check.is_some() {
        return Err(
            "--mesh-check repeats the Floquet analysis of steady running, which --frozen \
             replaces: drop one of them"
                .into(),
        );
    }
    Ok(a)
}

fn run() -> Result<(), String> {
    let a = parse()?;
    let base = params::drive_params(a.ssv.as_deref(), &a.sets)?;
    let mut rows: Vec<(f64, Modes)> = Vec::new();
    let opts = Options {
        max_frequency_hz: a.fmax,
        arm_amplitude: a.arm_amplitude,
        ..Options::default()
    };
    let speeds: Vec<Option<f64>> = match a.speeds {
        None => vec![None],
        Some((from, to, n)) => (0..n)
            .map(|k| {
                Some(if n == 1 {
                    from
                } else {
                    from + (to - from) * k as f64 / (n - 1) as f64
                })
            })
            .collect(),
    };
    for speed in speeds {
        let mut p = base.clone();
        let mut at = a.at.unwrap_or(0.0);
        let mut o = opts;
        if let Some(w) = speed {
            let start = params::at_crank_speed(&mut p, w, a.idle_loads)
                .map_err(|e| format!("--speeds: {e}"))?;
            at = a.at.unwrap_or(start);
            o.transport = w > 0.0;
        }
        let t0 = Instant::now();
        let mut drive = adapter::build(&p)?;
        adapter::run_to(&mut drive, at)?;
        let t_run = t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        let modes = if !a.frozen && o.transport {
            floquet(&drive, &o, FLOQUET_SUBSTEPS)?
        } else {
            analyse_drive(&drive, &o)?
        };
        let t_modes = t1.elapsed().as_secs_f64();
        for s in &modes.arms {
            if s.stuck {
                eprintln!(
                    "arm {}: pivot friction {:.3} N m sticks it at a swing of {:.3} deg \
                     (a tap of the arm creeps back: no swing)",
                    s.pulley,
                    s.friction_torque,
                    o.arm_amplitude.to_degrees()
                );
            } else {
                eprintln!(
                    "arm {}: pivot friction {:.3} N m at a swing of {:.3} deg and {:.2} Hz \
                     ({}) acts as a damper of {:.4} N m s/rad (describing function{})",
                    s.pulley,
                    s.friction_torque,
                    o.arm_amplitude.to_degrees(),
                    s.frequency_hz,
                    if a.frozen && o.transport {
                        "the arm mode's damped frequency"
                    } else {
                        "a tap's swing"
                    },
                    s.equivalent_damping,
                    if s.converged {
                        ""
                    } else {
                        "; the swing did not settle within the iteration's steps: \
                         the damper is the last step's"
                    }
                );
            }
        }
        let w = speed.unwrap_or(0.0);
        if let Some(orbit) = &modes.orbit {
            eprintln!(
                "speed {w:.1} rad/s: running state analysed, period {:.4e} s, defect {:.1e} (settling: {})",
                orbit.period,
                orbit.defect(),
                orbit
                    .defects
                    .iter()
                    .map(|d| format!("{d:.1e}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
            if !periodic(orbit) {
                eprintln!(
                    "speed {w:.1} rad/s: WARNING: the drive did not settle onto a periodic running \
                     state (defect {:.1e}): its steady running is not periodic (docs/modes.md, \
                     \"When the running state is not periodic\"); these modes are about a trajectory \
                     near it, marked periodic=false in the CSV and drawn apart in the Campbell diagram",
                    orbit.defect()
                );
            }
        }
        if let Some(orbit) = &modes.orbit {
            // why the running state grows, where the mesh explains it
            for (mode, cause) in mechanism::growing(&modes) {
                eprintln!(
                    "speed {w:.1} rad/s: {}",
                    mechanism::explain(mode, cause, orbit.period)
                );
            }
            let growing = mechanism::growing(&modes);
            if let (Some(bodies), false) = (a.mesh_check, growing.is_empty()) {
                // the same analysis with another mesh: does the growth stay?
                let mut q = p.clone();
                q.belt.n_bodies = bodies;
                let finer = floquet::after_run_up(&q, at, &o)?;
                if let Some(orbit) = finer.orbit.as_ref().filter(|o| !periodic(o)) {
                    eprintln!(
                        "speed {w:.1} rad/s: mesh check: WARNING: with {bodies} bodies the drive \
                         did not settle onto a periodic running state (defect {:.1e}): the \
                         comparison below is about a trajectory near it",
                        orbit.defect()
                    );
                }
                for (mode, _) in &growing {
                    eprintln!(
                        "speed {w:.1} rad/s: mesh check: {}",
                        mechanism::explain_finer(
                            mode,
                            mechanism::on_finer_mesh(mode, &finer),
                            bodies
                        )
                    );
                }
                for (mode, cause) in mechanism::growing(&finer) {
                    if let Some(orbit) = &finer.orbit {
                        eprintln!(
                            "speed {w:.1} rad/s: mesh check: with {bodies} bodies, {}",
                            mechanism::explain(mode, cause, orbit.period)
                        );
                    }
                }
            }
            for line in mechanism::mesh_resonances(&drive) {
                eprintln!("speed {w:.1} rad/s: mesh check: {line}");
            }
        }
        eprintln!(
            "speed {w:.1} rad/s at t = {at} s: {} modes up to {} Hz, {} above; {} zero modes, \
             {} overdamped, {} states split off, eigenproblem {}x{} in {:.2} s (run {:.1} s)",
            modes.modes.len(),
            a.fmax,
            modes.above_limit,
            modes.zero_modes,
            modes.overdamped,
            modes.removed_states,
            modes.reduced_dim,
            modes.reduced_dim,
            t_modes,
            t_run
        );
        rows.push((w, modes));
    }
    if let Some(dir) = a.out.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let mut f = std::io::BufWriter::new(
        std::fs::File::create(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?,
    );
    let mut text = String::from(
        "speed_rad_s,mode,frequency_hz,damping_ratio,description,orbit_defect,periodic\n",
    );
    for (w, m) in &rows {
        // at rest: no orbit (the analysis is about the static state)
        let (defect, periodic) = match &m.orbit {
            Some(o) => (format!("{:.2e}", o.defect()), periodic(o)),
            None => (String::new(), true),
        };
        for (k, mode) in m.modes.iter().enumerate() {
            text.push_str(&format!(
                "{w},{},{:.4},{:.5},{},{defect},{periodic}\n",
                k + 1,
                mode.frequency_hz,
                mode.damping_ratio,
                mode.describe()
            ));
        }
    }
    f.write_all(text.as_bytes())
        .map_err(|e| format!("{}: {e}", a.out.display()))?;
    eprintln!("wrote {}", a.out.display());
    Ok(())
}

/// Whether the settling reached the periodic running state: the analysed
/// period's defect within twice the settling's aim (`ORBIT_TOL`; the
/// analysed period is integrated once more after the settling).
fn periodic(orbit: &belt_drive::modes::Orbit) -> bool {
    orbit.defect() <= 2.0 * belt_drive::modes::floquet::ORBIT_TOL
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("modes: {e}");
            ExitCode::FAILURE
        }
    }
}
