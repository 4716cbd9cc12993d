//! Follows a drive from its periodic running state (as the Floquet analysis
//! settles it, `modes::floquet::settled`) over many body-passing periods
//! in the time domain and writes, 16 times per period, the pulley speeds,
//! the spans' mid-point deflections and tensions, the pulleys' slip, the
//! bodies sliding on each wrap (creep at its cap) and the contact on the
//! last pulley (docs/modes.md, "When the running state is not periodic").
//!
//! ```text
//! cargo run --profile ci --features modes --example orbit_probe -- \
//!     --ssv parameters/accessory-drive-4.ssv --set solver.method=2 --speed 84 --periods 400 --out FILE.csv
//! ```
use belt_drive::model::state::body;
use belt_drive::modes::{adapter, floquet, params};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut ssv = None;
    let mut sets = Vec::new();
    let mut speed = 240.0_f64;
    let mut periods = 400usize;
    let mut out = String::from("/tmp/probe.csv");
    let mut i = 0;
    while i < args.len() {
        match args[i].as_str() {
            "--ssv" => {
                ssv = Some(std::path::PathBuf::from(&args[i + 1]));
                i += 1;
            }
            "--set" => {
                sets.push(args[i + 1].clone());
                i += 1;
            }
            "--speed" => {
                speed = args[i + 1].parse().unwrap();
                i += 1;
            }
            "--periods" => {
                periods = args[i + 1].parse().unwrap();
                i += 1;
            }
            "--out" => {
                out = args[i + 1].clone();
                i += 1;
            }
            a => panic!("{a}"),
        }
        i += 1;
    }
    let mut p = params::drive_params(ssv.as_deref(), &sets).unwrap();
    // the crank's speed, in the direction the set drives it
    p.pulleys[0].omega_ramp = speed.copysign(p.pulleys[0].omega_ramp);
    let at = p.pulleys[0].ramp_time + 0.3;
    let t0 = std::time::Instant::now();
    let mut run = adapter::build(&p).unwrap();
    adapter::run_to(&mut run, at).unwrap();
    eprintln!("run-up {:.1} s", t0.elapsed().as_secs_f64());
    let (mut d, defects) = floquet::settled(&run).unwrap();
    eprintln!(
        "settle defects {defects:?} ({:.1} s)",
        t0.elapsed().as_secs_f64()
    );
    let lin = adapter::linearise(&d);
    let (period, _) = floquet::passing_period(&lin);
    let np = lin.pulleys.len();
    let n = lin.n;
    let cap = 1.5 * p.friction.creep_max;
    eprintln!("period {period:.5e} s; body rate {:.1} Hz", 1.0 / period);
    let dt = period / 16.0;
    let mut text = String::from("t");
    for j in 0..np {
        text += &format!(",w{}", j + 1);
    }
    for j in 0..np {
        text += &format!(",defl{}", j + 1);
    }
    for j in 0..np {
        text += &format!(",T{}", j + 1);
    }
    for j in 0..np {
        text += &format!(",slip{}", j + 1);
    }
    for j in 0..np {
        text += &format!(",slide_p{}", j + 1);
    }
    text += ",tmin,n4,slide4,z4max,vrel4\n";
    let start = d.time();
    for k in 0..=(periods * 16) {
        adapter::run_to(&mut d, start + k as f64 * dt).unwrap();
        let y = adapter::state(&d).to_vec();
        let sys = d.system();
        let centres: Vec<[f64; 2]> = (0..np).map(|j| sys.pulley_centre(j, &y).0).collect();
        let t = d.time();
        let ws: Vec<f64> = (0..np).map(|j| sys.pulley_speed(j, t, &y)).collect();
        let (mut cnt, mut slide, mut zmax, mut vrel) = (0, 0, 0.0f64, 0.0f64);
        let j4 = np - 1;
        for b in 0..n {
            if sys.touching(b, &y, &centres) == Some(j4) {
                cnt += 1;
                let z = body(&y, b).creep();
                zmax = zmax.max(z.abs() / cap);
                if z.abs() > 0.999 * cap {
                    slide += 1;
                }
                let [vx, vy] = body(&y, b).velocity();
                let v = vx.hypot(vy);
                vrel = vrel.max((v - ws[j4].abs() * lin.pulleys[j4].lever.abs()).abs());
            }
        }
        let mut sl = vec![0usize; np];
        for b in 0..n {
            if let Some(j) = sys.touching(b, &y, &centres) {
                if body(&y, b).creep().abs() > 0.999 * cap {
                    sl[j] += 1;
                }
            }
        }
        let o = d.outputs();
        text += &format!("{t:.9}");
        for w in &ws {
            text += &format!(",{w:.9}");
        }
        for j in 0..np {
            text += &format!(",{:.9e}", o.span_mid_deflection[j]);
        }
        for j in 0..np {
            text += &format!(",{:.3}", o.span_tension[j]);
        }
        for j in 0..np {
            text += &format!(",{:.5e}", o.pulleys[j].slip);
        }
        for x in &sl {
            text += &format!(",{x}");
        }
        text += &format!(",{:.3}", o.min_tension);
        text += &format!(",{cnt},{slide},{zmax:.4},{vrel:.5e}\n");
    }
    std::fs::write(&out, text).unwrap();
    eprintln!("wrote {out} ({:.1} s)", t0.elapsed().as_secs_f64());
}
