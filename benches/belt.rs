//! `cargo bench --bench belt -- <what> [--method N] [--quick]`: the
//! benchmark suite of docs/benchmarks.md. Plain timing, no harness; every
//! time is the CPU time of the benchmark's thread (on an idle core equal to
//! the wall time; on the shared development machine it leaves out the time
//! other processes hold the core).
//!
//! * `rhs`: cost of one right-hand-side evaluation per body at 60, 150, 600
//!   and 1200 bodies (median of 7 repeats);
//! * `accuracy`: real-time factor of the paper's 5PK drive and of the
//!   section-3 drive (10 N m load stepped on at 0.3 s) over 6 and 10 s (`creep`
//!   law) at several tolerances, and the
//!   deviation of the headline outputs (driven speed, slip, tight and slack
//!   span tension, means over 1.5-6 s and 1.25-10 s) from a tight-tolerance RKF45
//!   reference (also when `--method 2` benchmarks the stiff method);
//! * `kubas`: the `kubas2014` law at dv = 1e-2, 1e-3, 1e-4 m/s, steps per
//!   simulated second and real-time factor, with the extrapolation to the
//!   paper's 1e-5;
//! * `fmu`: the default drive stepped at 1 ms communication steps through
//!   the C API against one long doStep over the same horizon;
//! * `scaling`: cost per body per simulated second from 60 to 1200 bodies;
//! * `default`: the FMU's default drive (`DriveParams::default()`) over 0-0.4 s at its default tolerance;
//! * `speeds`: real-time factor against crank speed on the accessory sets
//!   at 800-6000 rpm and on the default 5PK drive, both methods
//!   (benches/speeds/mod.rs);
//! * `all`: everything (takes tens of minutes).
//!
//! `--method N` sets `solver.method` (1 = RKF45) for the integrator runs.
//! `--quick` shortens the horizons (a smoke test of the command).
//! `accuracy` also takes `--rtol 1e-4,5e-5` (the tolerances to run),
//! `--window 1.5,4` (averaging window, simulated from 0),
//! `--drive 5pk|s3` (one of the two drives) and `--atol 1e-6` (the absTol of
//! the runs benchmarked instead of relTol/100; 1e-6 is the FMU's default).
//!
//! `cargo bench --bench belt -- count-rhs <n> <reps> [baseline|avx2|avx512|dispatch] [contact.points] [belt.shearDampingFactor]`
//! evaluates the right-hand side `reps` times (as dispatched, or that build) at a running state of `n` bodies inside
//! `rhs_loop` (no timing) for instruction counts:
//! `valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*rhs_loop*' <bench binary> count-rhs 150 2000`.

mod common;
mod speeds;
use belt_drive::model::params::Method;
use belt_drive::model::simd::Isa as SimdBuild;
use belt_drive::model::system::{NoRecord, Workspace};
use belt_drive::{Drive, DriveParams, FrictionLaw, Inputs, Outputs};
use common::{cpu_time, median};

/// Options of the integrator runs.
#[derive(Clone, Copy)]
struct Opts {
    method: Method,
    quick: bool,
    /// `accuracy`: tolerances to run (None: 1e-3 to 1e-6).
    rtols: Option<&'static [f64]>,
    /// `accuracy`: averaging window (t_avg, t_end) instead of 1.5-2 s.
    window: Option<(f64, f64)>,
    /// `accuracy`: only the drive whose name starts with this.
    drive: Option<&'static str>,
    /// `accuracy`: absTol of the runs benchmarked (None: relTol/100).
    atol: Option<f64>,
}

impl Opts {
    fn apply(&self, p: &mut DriveParams) {
        p.solver.method = self.method;
    }
}

/// A drive of `n` bodies at a running state (contacts, creep): 60 bodies
/// cannot resolve the 5PK drive's 27 mm pulleys, so below 100 bodies the
/// section-3 drive (its own mesh) is used.
fn running_drive(n: usize, points: usize, shear: Option<f64>) -> Drive {
    let mut p = if n < 100 {
        DriveParams::kubas_section3()
    } else {
        DriveParams::kubas_section4()
    };
    p.belt.n_bodies = n;
    p.contact.points = points;
    if let Some(f) = shear {
        p.belt.shear_damping_factor = f;
    }
    p.probe_body = 0;
    let mut d = Drive::new(&p, 0.0).expect("valid drive");
    d.advance(0.01).expect("runs");
    d
}

/// `reps` evaluations of the right-hand side, by the run-time dispatch
/// (`None`) or one build; false if the CPU lacks that build's instructions.
#[inline(never)]
fn rhs_loop(d: &Drive, y: &[f64], dy: &mut [f64], reps: usize, build: Option<SimdBuild>) -> bool {
    let sys = d.system();
    let mut ws = Workspace::new();
    for _ in 0..reps {
        let y = std::hint::black_box(y);
        match build {
            None => sys.rhs(&mut ws, 0.01, y, dy, &mut NoRecord),
            Some(b) => {
                if !sys.rhs_build(b, &mut ws, 0.01, y, dy, &mut NoRecord) {
                    return false;
                }
            }
        }
        std::hint::black_box(&mut *dy);
    }
    true
}

/// Median CPU time per body per evaluation [s], None if the CPU lacks the build.
fn rhs_cost(d: &Drive, build: Option<SimdBuild>) -> Option<f64> {
    let n = d.system().n_bodies();
    let y = d.state().to_vec();
    let mut dy = vec![0.0; y.len()];
    let reps = (2_000_000 / n).max(200);
    let mut samples = Vec::new();
    for _ in 0..7 {
        let t = cpu_time();
        if !rhs_loop(d, &y, &mut dy, reps, build) {
            return None;
        }
        samples.push((cpu_time() - t) / reps as f64);
    }
    Some(median(samples) / n as f64)
}

fn bench_rhs() {
    println!("## Right-hand side");
    println!("ns per body per evaluation: as dispatched (the widest instruction set the CPU has), and each build");
    println!();
    println!("| bodies | drive | dispatched | AVX-512 | AVX2 | baseline (SSE2) |");
    println!("|---|---|---|---|---|---|");
    for n in [60usize, 150, 600, 1200] {
        let drive = if n < 100 { "section 3" } else { "5PK" };
        let d = running_drive(n, 1, None);
        let cell = |b: Option<SimdBuild>| match rhs_cost(&d, b) {
            Some(c) => format!("{:.2}", c * 1e9),
            None => "-".to_string(),
        };
        println!(
            "| {n} | {drive} | {} | {} | {} | {} |",
            cell(None),
            cell(Some(SimdBuild::Avx512)),
            cell(Some(SimdBuild::Avx2)),
            cell(Some(SimdBuild::Baseline))
        );
    }
}

/// Result of one integrator run.
struct Run {
    cpu: f64,
    sim: f64,
    steps: u64,
    rejected: u64,
    rhs: u64,
}

impl Run {
    fn rtf(&self) -> f64 {
        self.sim / self.cpu
    }
}

/// Means over the averaging window of the headline outputs.
#[derive(Clone, Copy, Debug, Default)]
struct Headline {
    driven_speed: f64,
    slip: f64,
    tight: f64,
    slack: f64,
}

impl Headline {
    fn deviation(&self, r: &Headline) -> [f64; 4] {
        let rel = |a: f64, b: f64| ((a - b) / b).abs();
        [
            rel(self.driven_speed, r.driven_speed),
            rel(self.slip, r.slip),
            rel(self.tight, r.tight),
            rel(self.slack, r.slack),
        ]
    }
}

/// Runs `p` from 0 to `t_end` (outputs sampled every ms from `t_avg`) and
/// returns the cost and the headline means (pulley 2 is the driven one).
/// `load`: (time, torque) stepped onto pulley 2's torque input.
fn run_drive(p: &DriveParams, t_avg: f64, t_end: f64, load: Option<(f64, f64)>) -> (Run, Headline) {
    let mut d = Drive::new(p, 0.0).expect("valid drive");
    d.set_inputs(Inputs::default());
    let start = d.stats();
    let c0 = cpu_time();
    let dt = 1e-3;
    let n_out = ((t_end - t_avg) / dt).round() as usize;
    if let Some((t_load, torque)) = load {
        d.advance(t_load).expect("runs");
        let mut inputs = *d.inputs();
        inputs.torque[1] = torque;
        d.set_inputs(inputs);
    }
    d.advance(t_avg).expect("runs");
    let mut sum = Headline::default();
    let mut acc = |o: &Outputs| {
        sum.driven_speed += o.pulleys[1].omega;
        sum.slip += o.pulleys[1].slip;
        let (a, b) = (o.span_tension[0], o.span_tension[1]);
        sum.tight += a.max(b);
        sum.slack += a.min(b);
    };
    for k in 1..=n_out {
        d.advance(t_avg + k as f64 * dt).expect("runs");
        acc(&d.outputs());
    }
    let cpu = cpu_time() - c0;
    let s = d.stats();
    let k = n_out as f64;
    let h = Headline {
        driven_speed: sum.driven_speed / k,
        slip: sum.slip / k,
        tight: sum.tight / k,
        slack: sum.slack / k,
    };
    let run = Run {
        cpu,
        sim: t_end,
        steps: s.steps - start.steps,
        rejected: s.rejected - start.rejected,
        rhs: s.rhs_evals - start.rhs_evals,
    };
    (run, h)
}

fn bench_accuracy(o: Opts) {
    println!(
        "## Real-time factor at converged accuracy (`creep` law, method {:?})",
        o.method
    );
    println!(
        "headline outputs are means over the window given per drive, sampled every 1 ms; reference: RKF45 at rtol 1e-7, atol 1e-9, whatever the method benchmarked."
    );
    // Long windows: the slip is a small difference of two speeds (0.5 % on
    // the 5PK drive, so a 0.5 % deviation is 2e-5 of the speed) and drifts
    // slowly; its 0.5 s window means move by ~1 % with the phase of that drift.
    // The section-3 drive runs under the validation's load step (10 N m at 0.3 s).
    for (name, base, load, window) in [
        (
            "paper's 5PK drive (section-4 set)",
            DriveParams::kubas_section4(),
            None,
            (1.5, 6.0),
        ),
        (
            "section-3 drive, 10 N m load stepped on at 0.3 s",
            DriveParams::kubas_section3(),
            Some((if o.quick { 0.01 } else { 0.3 }, 10.0)),
            (1.25, 10.0),
        ),
    ] {
        if o.drive.is_some_and(|d| !name.starts_with(d)) {
            continue;
        }
        let (t_avg, t_end) = match (o.quick, o.window) {
            (true, _) => (0.04, 0.05),
            (false, Some(w)) => w,
            (false, None) => window,
        };
        println!("### {name}, 0-{t_end} s, means over {t_avg}-{t_end} s");
        let with_tol = |rtol: f64, atol: Option<f64>| {
            let mut p = base.clone();
            o.apply(&mut p);
            p.solver.rel_tol = rtol;
            p.solver.abs_tol = atol.unwrap_or(rtol * 1e-2);
            p
        };
        let mut reference = with_tol(1e-7, None);
        reference.solver.method = Method::Rkf45;
        let (r_ref, h_ref) = run_drive(&reference, t_avg, t_end, load);
        println!(
            "reference: driven speed {:.4} rad/s, slip {:.5}, tight {:.2} N, slack {:.2} N ({} steps, RTF {:.4})",
            h_ref.driven_speed,
            h_ref.slip,
            h_ref.tight,
            h_ref.slack,
            r_ref.steps,
            r_ref.rtf()
        );
        let atol = o
            .atol
            .map_or("relTol/100".to_string(), |a| format!("{a:e}"));
        println!("| relTol (absTol = {atol}) | real-time factor | steps/simulated s | rejected | RHS evaluations | dev. driven speed | dev. slip | dev. tight | dev. slack | max dev. |");
        println!("|---|---|---|---|---|---|---|---|---|---|");
        for &rtol in o.rtols.unwrap_or(&[1e-3, 1e-4, 1e-5, 1e-6]) {
            let (r, h) = run_drive(&with_tol(rtol, o.atol), t_avg, t_end, load);
            let dev = h.deviation(&h_ref);
            let max = dev.iter().copied().fold(0.0, f64::max);
            println!(
                "| {rtol:.0e} | {:.4} | {:.0} | {} | {} | {:.3} % | {:.3} % | {:.3} % | {:.3} % | {:.3} % |",
                r.rtf(),
                r.steps as f64 / r.sim,
                r.rejected,
                r.rhs,
                dev[0] * 100.0,
                dev[1] * 100.0,
                dev[2] * 100.0,
                dev[3] * 100.0,
                max * 100.0
            );
        }
    }
}

/// The first benchmark's figure: the default drive over 0-0.4 s at its
/// default tolerance (before/after comparisons).
fn bench_default(o: Opts) {
    let horizon = if o.quick { 0.02 } else { 0.4 };
    // the FMU's default drive: the paper's section-4 drive with the
    // automatic contact damping ramp and the damper across the SDE gaps
    let mut p = DriveParams::default();
    o.apply(&mut p);
    let c0 = cpu_time();
    let mut d = Drive::new(&p, 0.0).expect("valid drive");
    let c1 = cpu_time();
    d.advance(horizon).expect("runs");
    let cpu = cpu_time() - c1;
    let s = d.stats();
    println!(
        "default 5PK drive 0-{horizon} s, rtol 1e-4: mounting {:.3} s, real-time factor {:.4}, {} steps, {} rejected, {} RHS, {:.2} ns per body per RHS incl. integrator",
        c1 - c0,
        horizon / cpu,
        s.steps,
        s.rejected,
        s.rhs_evals,
        cpu / s.rhs_evals as f64 / p.belt.n_bodies as f64 * 1e9
    );
}

fn bench_kubas(o: Opts) {
    let (ramp, t_end) = if o.quick {
        (0.002, 0.004)
    } else {
        (0.01, 0.03)
    };
    println!(
        "## `kubas2014` friction law (the paper's 5PK drive, section-4 set, method {:?}, rtol 1e-4)",
        o.method
    );
    println!(
        "Drive torque ramped over {ramp} s instead of 0.3 s; steps and time counted over {ramp}-{t_end} s (the loaded drive after the ramp)."
    );
    println!("| dv [m/s] | steps per simulated s | rejected per simulated s | real-time factor |");
    println!("|---|---|---|---|");
    let mut fit = Vec::new();
    for dv in [1e-2, 1e-3, 1e-4] {
        let mut p = DriveParams::kubas_section4();
        o.apply(&mut p);
        p.friction.law = FrictionLaw::Kubas2014;
        p.friction.dv = dv;
        p.pulleys[0].ramp_time = ramp;
        let mut d = Drive::new(&p, 0.0).expect("valid drive");
        d.set_inputs(Inputs::default());
        d.advance(ramp).expect("runs");
        let s0 = d.stats();
        let c0 = cpu_time();
        d.advance(t_end).expect("runs");
        let cpu = cpu_time() - c0;
        let s = d.stats();
        let span = t_end - ramp;
        let steps = (s.steps - s0.steps) as f64 / span;
        let rtf = span / cpu;
        println!(
            "| {dv:.0e} | {steps:.3e} | {:.3e} | {rtf:.2e} |",
            (s.rejected - s0.rejected) as f64 / span
        );
        fit.push((dv.ln(), steps.ln(), rtf.ln()));
    }
    // least squares ln(steps) = a + b ln(dv)
    let lsq = |sel: fn(&(f64, f64, f64)) -> f64| {
        let k = fit.len() as f64;
        let mx = fit.iter().map(|f| f.0).sum::<f64>() / k;
        let my = fit.iter().map(sel).sum::<f64>() / k;
        let sxy: f64 = fit.iter().map(|f| (f.0 - mx) * (sel(f) - my)).sum();
        let sxx: f64 = fit.iter().map(|f| (f.0 - mx).powi(2)).sum();
        let b = sxy / sxx;
        (my - b * mx, b)
    };
    let (a, b) = lsq(|f| f.1);
    let (ar, br) = lsq(|f| f.2);
    let x = 1e-5f64.ln();
    println!(
        "Fit over the three: steps per simulated s = {:.3e} * dv^{b:.3}; real-time factor = {:.3e} * dv^{br:.3}.",
        a.exp(),
        ar.exp()
    );
    let rtf5 = (ar + br * x).exp();
    println!(
        "Extrapolated to dv = 1e-5 m/s: {:.2e} steps per simulated s, real-time factor {rtf5:.2e} (2 s of the drive: {:.1} h of CPU time).",
        (a + b * x).exp(),
        2.0 / rtf5 / 3600.0
    );
}

fn bench_scaling(o: Opts) {
    let horizon = if o.quick { 0.002 } else { 0.05 };
    println!(
        "## Scaling (section-3 drive, `creep` law, method {:?}, rtol 1e-4)",
        o.method
    );
    println!("0-{horizon} s from the mounted state (drive speed ramping); the section-3 drive's 81 mm pulleys take every body count.");
    println!("| bodies | steps per simulated s | ns per body per RHS (incl. integrator) | CPU s per simulated s | µs per body per simulated s |");
    println!("|---|---|---|---|---|");
    for n in [60usize, 150, 300, 600, 1200] {
        let mut p = DriveParams::kubas_section3();
        o.apply(&mut p);
        p.belt.n_bodies = n;
        p.probe_body = 0;
        let mut d = Drive::new(&p, 0.0).expect("valid drive");
        d.set_inputs(Inputs::default());
        let s0 = d.stats();
        let c0 = cpu_time();
        d.advance(horizon).expect("runs");
        let cpu = cpu_time() - c0;
        let s = d.stats();
        let rhs = (s.rhs_evals - s0.rhs_evals) as f64;
        println!(
            "| {n} | {:.3e} | {:.2} | {:.1} | {:.1} |",
            (s.steps - s0.steps) as f64 / horizon,
            cpu / rhs / n as f64 * 1e9,
            cpu / horizon,
            cpu / horizon / n as f64 * 1e6
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("count-rhs") {
        let n = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(150);
        let reps = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1000);
        let build = match args.get(3).map(String::as_str) {
            None | Some("dispatch") => None,
            Some("baseline") => Some(SimdBuild::Baseline),
            Some("avx2") => Some(SimdBuild::Avx2),
            Some("avx512") => Some(SimdBuild::Avx512),
            Some(b) => panic!("count-rhs: unknown build {b} (baseline, avx2, avx512)"),
        };
        let points = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(1);
        // the paper's sets pin the damper across the gap to 0
        let shear = args.get(5).and_then(|s| s.parse().ok());
        let d = running_drive(n, points, shear);
        let y = d.state().to_vec();
        let mut dy = vec![0.0; y.len()];
        assert!(
            rhs_loop(&d, &y, &mut dy, reps, build),
            "the CPU lacks {build:?}"
        );
        println!(
            "{n} bodies, {points} contact points, shear damping factor {}, {reps} evaluations",
            d.system().axial().bt / d.system().axial().b
        );
        return;
    }
    let mut opts = Opts {
        method: Method::Rkf45,
        quick: false,
        rtols: None,
        window: None,
        drive: None,
        atol: None,
    };
    // a comma-separated list of numbers (leaked: parsed once per run)
    let numbers = |s: Option<&String>, what: &str| -> &'static [f64] {
        let v: Vec<f64> = s
            .map(|s| s.split(',').map(|x| x.parse().expect(what)).collect())
            .expect(what);
        Vec::leak(v)
    };
    let mut what = Vec::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--method" => {
                let code = it.next().and_then(|s| s.parse().ok()).unwrap_or(0);
                opts.method =
                    belt_drive::fmu::names::method(code).expect("--method: a solver.method code");
            }
            "--quick" => opts.quick = true,
            "--rtol" => opts.rtols = Some(numbers(it.next(), "--rtol: comma-separated tolerances")),
            "--atol" => {
                let a = numbers(it.next(), "--atol: an absolute tolerance");
                assert!(a.len() == 1 && a[0] > 0.0, "--atol: one tolerance > 0");
                opts.atol = Some(a[0]);
            }
            "--window" => {
                let w = numbers(it.next(), "--window: T_AVG,T_END");
                assert!(w.len() == 2 && w[0] < w[1], "--window: T_AVG,T_END");
                opts.window = Some((w[0], w[1]));
            }
            "--drive" => {
                opts.drive = Some(match it.next().map(String::as_str) {
                    Some("5pk") => "paper's 5PK",
                    Some("s3") => "section-3",
                    d => panic!("--drive: 5pk or s3, not {d:?}"),
                })
            }
            "--bench" => {} // passed by `cargo bench`
            w => what.push(w.to_string()),
        }
    }
    if what.is_empty() {
        what.push("rhs".into());
    }
    let all = what.iter().any(|w| w == "all");
    let run = |w: &str| all || what.iter().any(|x| x == w);
    if run("rhs") {
        bench_rhs();
    }
    if run("default") {
        bench_default(opts);
    }
    if run("fmu") {
        fmu::bench_fmu(opts);
    }
    if run("kubas") {
        bench_kubas(opts);
    }
    if run("scaling") {
        bench_scaling(opts);
    }
    if run("accuracy") {
        bench_accuracy(opts);
    }
    if run("speeds") {
        speeds::bench_speeds(opts.quick);
    }
}

/// The built FMU binary through its C API (as tests/fmi_abi.rs loads it).
mod fmu {
    use super::{cpu_time, Opts};
    use belt_drive::fmu::variables::{by_name, GUID};
    use std::ffi::{c_char, c_int, c_uint, c_void, CString};
    use std::ptr;

    type Component = *mut c_void;
    type Logger =
        unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);

    #[repr(C)]
    struct Callbacks {
        logger: Option<Logger>,
        allocate_memory: *const c_void,
        free_memory: *const c_void,
        step_finished: *const c_void,
        component_environment: *mut c_void,
    }

    unsafe extern "C" fn logger(
        _env: *mut c_void,
        _name: *const c_char,
        _status: c_int,
        _category: *const c_char,
        _message: *const c_char,
    ) {
    }

    struct Api {
        instantiate: unsafe extern "C" fn(
            *const c_char,
            c_int,
            *const c_char,
            *const c_char,
            *const Callbacks,
            c_int,
            c_int,
        ) -> Component,
        free_instance: unsafe extern "C" fn(Component),
        setup_experiment: unsafe extern "C" fn(Component, c_int, f64, f64, c_int, f64) -> c_int,
        enter_init: unsafe extern "C" fn(Component) -> c_int,
        exit_init: unsafe extern "C" fn(Component) -> c_int,
        get_real: unsafe extern "C" fn(Component, *const c_uint, usize, *mut f64) -> c_int,
        set_integer: unsafe extern "C" fn(Component, *const c_uint, usize, *const c_int) -> c_int,
        do_step: unsafe extern "C" fn(Component, f64, f64, c_int) -> c_int,
    }

    fn load() -> Api {
        let exe = std::env::current_exe().expect("bench executable");
        let deps = exe.parent().expect("deps directory");
        let path = [
            deps.join("libbelt_drive.so"),
            deps.join("../libbelt_drive.so"),
        ]
        .into_iter()
        .find(|p| p.exists())
        .expect("libbelt_drive.so next to the bench (cargo builds the cdylib with it)");
        let c = CString::new(path.to_string_lossy().as_bytes()).unwrap();
        // SAFETY: dlopen of our own library.
        let h = unsafe { libc::dlopen(c.as_ptr(), libc::RTLD_NOW | libc::RTLD_LOCAL) };
        assert!(!h.is_null(), "dlopen {path:?}");
        let sym = |name: &str| {
            let n = CString::new(name).unwrap();
            // SAFETY: valid handle and name.
            let p = unsafe { libc::dlsym(h, n.as_ptr()) };
            assert!(!p.is_null(), "{name}");
            p
        };
        fn f<F: Copy>(p: *mut c_void) -> F {
            // SAFETY: the FMI 2.0 function of that name, whose prototype F mirrors.
            unsafe { std::mem::transmute_copy(&p) }
        }
        Api {
            instantiate: f(sym("fmi2Instantiate")),
            free_instance: f(sym("fmi2FreeInstance")),
            setup_experiment: f(sym("fmi2SetupExperiment")),
            enter_init: f(sym("fmi2EnterInitializationMode")),
            exit_init: f(sym("fmi2ExitInitializationMode")),
            get_real: f(sym("fmi2GetReal")),
            set_integer: f(sym("fmi2SetInteger")),
            do_step: f(sym("fmi2DoStep")),
        }
    }

    fn vr(name: &str) -> c_uint {
        by_name(name).unwrap_or_else(|| panic!("{name}")).vr
    }

    /// Default drive from 0 to `t_end` in steps of `h`, reading `outputs`
    /// after every step. Returns (CPU s of the stepping, steps, RHS evals).
    fn run(api: &Api, method: i32, t_end: f64, h: f64, outputs: &[&str]) -> (f64, f64, f64) {
        let cb = Callbacks {
            logger: Some(logger),
            allocate_memory: ptr::null(),
            free_memory: ptr::null(),
            step_finished: ptr::null(),
            component_environment: ptr::null_mut(),
        };
        let guid = CString::new(GUID).unwrap();
        let vrs: Vec<c_uint> = outputs.iter().map(|n| vr(n)).collect();
        let mut out = vec![0.0; vrs.len()];
        let stats = [vr("solver.steps"), vr("solver.rhsEvaluations")];
        let mut st = [0.0; 2];
        // SAFETY: valid arguments throughout; the instance is freed at the end.
        unsafe {
            let c = (api.instantiate)(c"bench".as_ptr(), 1, guid.as_ptr(), ptr::null(), &cb, 0, 0);
            assert!(!c.is_null());
            assert_eq!((api.set_integer)(c, &vr("solver.method"), 1, &method), 0);
            // one long doStep takes more than the default work guard of
            // 1e5 steps per doStep
            let guard: c_int = 2_000_000_000;
            assert_eq!((api.set_integer)(c, &vr("solver.maxSteps"), 1, &guard), 0);
            assert_eq!((api.setup_experiment)(c, 0, 0.0, 0.0, 0, 0.0), 0);
            assert_eq!((api.enter_init)(c), 0);
            assert_eq!((api.exit_init)(c), 0);
            let n = (t_end / h).round() as usize;
            let c0 = cpu_time();
            for k in 0..n {
                let t = k as f64 * h;
                assert_eq!((api.do_step)(c, t, h, 1), 0);
                if !vrs.is_empty() {
                    assert_eq!(
                        (api.get_real)(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()),
                        0
                    );
                }
            }
            let cpu = cpu_time() - c0;
            assert_eq!((api.get_real)(c, stats.as_ptr(), 2, st.as_mut_ptr()), 0);
            (api.free_instance)(c);
            (cpu, st[0], st[1])
        }
    }

    pub fn bench_fmu(o: Opts) {
        let t_end = if o.quick { 0.01 } else { 0.2 };
        let api = load();
        let method = belt_drive::fmu::names::method_code(o.method);
        println!(
            "## FMU overhead (default drive through the C API, method {:?})",
            o.method
        );
        println!("0-{t_end} s after fmi2ExitInitializationMode; CPU time of the doStep (and GetReal) calls.");
        println!("| stepping | CPU s (median of 3) | accepted steps | RHS evaluations | overhead (CPU) | overhead (RHS evaluations) |");
        println!("|---|---|---|---|---|---|");
        let headline = [
            "pulley[2].omega",
            "pulley[2].slip",
            "span[1].tension",
            "span[2].tension",
        ];
        // Three rounds, the three ways alternating; medians of CPU time
        // (the counts are deterministic).
        let ways: [(&str, f64, &[&str]); 3] = [
            ("one doStep over the horizon", t_end, &[]),
            ("1 ms doSteps", 1e-3, &[]),
            (
                "1 ms doSteps + GetReal of 4 headline outputs",
                1e-3,
                &headline,
            ),
        ];
        let mut cpu = [[0.0; 3]; 3];
        let mut counts = [(0.0, 0.0); 3];
        #[allow(clippy::needless_range_loop)] // rounds alternate the three ways
        for round in 0..3 {
            for (w, (_, h, outs)) in ways.iter().enumerate() {
                let (c, s, r) = run(&api, method, t_end, *h, outs);
                cpu[w][round] = c;
                counts[w] = (s, r);
            }
        }
        let med = |w: usize| super::median(cpu[w].to_vec());
        for (w, (label, _, _)) in ways.iter().enumerate() {
            let (s, r) = counts[w];
            let (dc, dr) = if w == 0 {
                ("-".to_string(), "-".to_string())
            } else {
                (
                    format!("{:+.2} %", (med(w) / med(0) - 1.0) * 100.0),
                    format!("{:+.3} %", (r / counts[0].1 - 1.0) * 100.0),
                )
            };
            println!("| {label} | {:.3} | {s} | {r} | {dc} | {dr} |", med(w));
        }
    }
}
