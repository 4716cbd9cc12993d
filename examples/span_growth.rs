//! The running drive's unstable span modes against the time domain
//! (docs/modes.md, "Checks against closed forms and the time domain"): the
//! drive run up, settled onto its periodic running state (optionally with
//! more settling cycles than the analysis' own), analysed by the Floquet
//! analysis at each substep count, then each of the most unstable span
//! modes of the first count followed in the time domain from a kick along
//! its eigenvector (examples/common/span_growth.rs).
//!
//! ```text
//! cargo run --profile ci --features modes --example span_growth -- \
//!     --ssv parameters/accessory-drive-4.ssv --set solver.method=2 [--speed W] [--at 0.8] \
//!     [--substeps 128,256] [--cycles 6] [--modes 3] [--kick 1e-6] [--run 0.2]
//! ```
//!
//! `--speed`: the crank's speed [rad/s] (default: the set's); `--at`: the
//! end of the run-up (default: the ramp time + 0.3 s); `--cycles`: most
//! extrapolations of the settling (at least the analysis' own);
//! `--kick`: the largest body displacement of the kick [m]; `--run`: how
//! long each mode is followed [s].
use belt_drive::modes::{adapter, floquet, params, Options, Part};

#[path = "common/span_growth.rs"]
mod span_growth;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (mut ssv, mut sets, mut speed, mut at) = (None, Vec::new(), None, None);
    let (mut subs, mut cycles, mut count, mut kick, mut run) =
        (vec![128usize], floquet::SETTLE_CYCLES, 3usize, 1e-6, 0.2);
    let mut i = 0;
    while i < args.len() {
        let v = &args[i + 1];
        match args[i].as_str() {
            "--ssv" => ssv = Some(std::path::PathBuf::from(v)),
            "--set" => sets.push(v.clone()),
            "--speed" => speed = Some(v.parse::<f64>().unwrap()),
            "--at" => at = Some(v.parse::<f64>().unwrap()),
            "--substeps" => subs = v.split(',').map(|x| x.parse().unwrap()).collect(),
            "--cycles" => cycles = v.parse().unwrap(),
            "--modes" => count = v.parse().unwrap(),
            "--kick" => kick = v.parse().unwrap(),
            "--run" => run = v.parse().unwrap(),
            a => panic!("unknown argument {a}"),
        }
        i += 2;
    }
    let mut p = params::drive_params(ssv.as_deref(), &sets).unwrap();
    // the crank's speed if given, in the direction the set drives it
    if let Some(w) = speed {
        p.pulleys[0].omega_ramp = w.copysign(p.pulleys[0].omega_ramp);
    }
    let at = at.unwrap_or(p.pulleys[0].ramp_time + 0.3);
    let t0 = std::time::Instant::now();
    let mut drive = adapter::build(&p).unwrap();
    adapter::run_to(&mut drive, at).unwrap();
    eprintln!("run-up to {at} s: {:.1} s", t0.elapsed().as_secs_f64());
    let (mut settled, defects) = floquet::settled(&drive).unwrap();
    let mut defects = defects;
    if cycles > floquet::SETTLE_CYCLES {
        defects.extend(
            floquet::settle(
                &mut settled,
                cycles - floquet::SETTLE_CYCLES,
                floquet::SETTLE_PERIODS,
            )
            .unwrap(),
        );
    }
    println!(
        "# settling defects {:?} ({:.1} s)",
        defects
            .iter()
            .map(|d| format!("{d:.2e}"))
            .collect::<Vec<_>>(),
        t0.elapsed().as_secs_f64()
    );
    let mut first = None;
    for &n in &subs {
        let t1 = std::time::Instant::now();
        let m =
            floquet::floquet_settled(&settled, defects.clone(), &Options::default(), n).unwrap();
        let o = m.orbit.clone().unwrap();
        println!(
            "# substeps {n}: {:.1} s, analysed period's defect {:.2e}, period {:.5e} s, span tensions {:.1?} N, belt speed {:.3} m/s",
            t1.elapsed().as_secs_f64(),
            o.defects[o.defects.len() - 1],
            o.period,
            o.span_tension,
            o.belt_speed
        );
        for x in m.modes.iter().filter(|x| x.damping_ratio < 0.1).take(24) {
            println!(
                "{n} {:9.3} Hz zeta {:+.4e} {} ({:.0} %)",
                x.frequency_hz,
                x.damping_ratio,
                x.describe(),
                100.0 * x.share
            );
        }
        let mut unstable: Vec<_> = m.modes.iter().filter(|x| x.damping_ratio < 0.0).collect();
        unstable.sort_by(|a, b| a.damping_ratio.total_cmp(&b.damping_ratio));
        for x in &unstable {
            println!(
                "{n} unstable {:9.3} Hz zeta {:+.4e} {} ({:.0} %)",
                x.frequency_hz,
                x.damping_ratio,
                x.describe(),
                100.0 * x.share
            );
        }
        if first.is_none() {
            first = Some(m);
        }
    }
    let m = first.unwrap();
    let mut spans: Vec<_> = m
        .modes
        .iter()
        .filter(|x| x.damping_ratio < 0.0 && matches!(x.part, Part::SpanTransverse(_)))
        .collect();
    spans.sort_by(|a, b| a.damping_ratio.total_cmp(&b.damping_ratio));
    for x in spans.into_iter().take(count) {
        let Part::SpanTransverse(k) = x.part else {
            unreachable!()
        };
        let t1 = std::time::Instant::now();
        let g = span_growth::kicked_growth(&settled, x, k, kick, run, 1e-4);
        println!(
            "growth of {:.3} Hz ({}), Floquet zeta {:+.4e}, rate {:.2} 1/s: {} ({:+.1} %; {:.1} s)",
            x.frequency_hz,
            x.describe(),
            x.damping_ratio,
            -x.damping_ratio * std::f64::consts::TAU * x.frequency_hz,
            g.describe(),
            100.0 * (g.zeta / x.damping_ratio - 1.0),
            t1.elapsed().as_secs_f64()
        );
    }
}
