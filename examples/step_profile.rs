//! What limits the integrators' step on a running drive: accepted and
//! rejected steps per simulated second, the step sizes, the Jacobians and
//! factorizations of the stiff method, and for every trial step the state
//! component whose weighted error is largest (grouped: body positions,
//! angles, velocities, spins, creep states, pulleys, decouplers, tensioner
//! arms), for a body where it lies (on a wrap, in a free span, or within a
//! body or two of a landing or leaving point), and the steps the stiff
//! method's energy check rejected; on drives that have them, what the
//! tensioner arms (their rate against the pivot friction's band) and the
//! decouplers (clutch engaged, in its band or overrunning) do over the
//! accepted steps.
//!
//! `cargo run --profile ci --example step_profile -- [DRIVE RPM METHOD ...]`
//! with DRIVE one of `5pk` (the FMU's default drive), `acc4`
//! (`parameters/accessory-drive-4.ssv`), `tens`
//! (`parameters/accessory-drive-tensioner.ssv`), RPM the crank speed (the
//! accessory sets' load torques held at their idle values: the load damping
//! scaled by 800 / RPM; ignored for `5pk`), METHOD `stiff` or `rkf45`
//! (relTol 1e-4). Without arguments it runs the table of docs/benchmarks.md
//! ("What limits the step on the accessory drives"). Each run settles for 0.1 s after the speed
//! ramp (0.5 s) and measures 0.1 s in 1 ms communication steps; the
//! real-time factor is the CPU time of the plain `Drive::advance` over the
//! same window (a clone of the drive; this machine's, not a benchmark).

#[path = "common/ssv.rs"]
mod ssv;

#[path = "common/accessory.rs"]
mod accessory;

#[path = "../benches/common/mod.rs"]
#[allow(dead_code)] // median
mod timing;
use timing::cpu_time;

use belt_drive::drive::Integrator;
use belt_drive::model::params::Method;
use belt_drive::model::state::{bodies_len, body_component, BodyComponent};
use belt_drive::model::system::{BeltSystem, Workspace};
use belt_drive::solver::knobs::TUNING;
use belt_drive::solver::rkf45::Rkf45;
use belt_drive::solver::step_control::Trial;
use belt_drive::{Drive, DriveParams};

/// The measured window after the settling [s].
const WINDOW: f64 = 0.1;
/// Communication step [s].
const COMM: f64 = 1e-3;

/// The drive `name` at crank speed `rpm` with `method` at relTol 1e-4.
fn drive(name: &str, rpm: f64, method: Method) -> DriveParams {
    if name == "5pk" {
        let mut p = DriveParams::default();
        p.solver.method = method;
        p.solver.rel_tol = 1e-4;
        return p;
    }
    accessory::at_rpm(name, rpm, method)
}

/// Where the worst component of a trial lies.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Group {
    BodyPosition,
    BodyAngle,
    BodyVelocity,
    BodySpin,
    Creep,
    Pulley,
    Decoupler,
    ArmAngle,
    ArmRate,
    Energy,
    Other,
}

const GROUPS: [Group; 11] = [
    Group::BodyPosition,
    Group::BodyAngle,
    Group::BodyVelocity,
    Group::BodySpin,
    Group::Creep,
    Group::Pulley,
    Group::Decoupler,
    Group::ArmAngle,
    Group::ArmRate,
    Group::Energy,
    Group::Other,
];

/// A body's place: bodies from the nearest change of contact (0: the body
/// itself lands or leaves: it touches and a neighbour does not, or the other
/// way round; 1, 2: its neighbours; 3: farther), and whether it touches.
fn place(sys: &BeltSystem, y: &[f64], k: usize) -> (usize, bool) {
    let n = sys.n_bodies();
    let centres: Vec<[f64; 2]> = (0..sys.n_pulleys())
        .map(|j| sys.pulley_centre(j, y).0)
        .collect();
    let touch = |i: usize| sys.touching((i + n) % n, y, &centres);
    let here = touch(k);
    for d in 0..3 {
        for i in [k + n - d, k + d] {
            let (a, b) = (touch(i), touch(i + 1));
            if a != b {
                return (d, here.is_some());
            }
        }
    }
    (3, here.is_some())
}

#[derive(Default)]
struct Profile {
    accepted: u64,
    rejected: u64,
    /// Worst group of accepted / rejected trials (energy: rejected by the
    /// energy check alone).
    acc_group: [u64; 11],
    rej_group: [u64; 11],
    /// Bodies' worst components by distance to a contact change (0..=3),
    /// accepted and rejected.
    acc_place: [u64; 4],
    rej_place: [u64; 4],
    /// Step sizes of accepted steps, decades from 1e-8 s.
    h_hist: [u64; 6],
    h_sum: f64,
    /// Trials over which some body lands or leaves (its contact changes
    /// from start to end) [accepted, rejected on the norm, rejected on the
    /// energy], and all of each kind.
    with_change: [u64; 3],
    of_kind: [u64; 3],
    /// Accepted steps whose energy error exceeds the norm (the energy check
    /// sets the next step).
    energy_limited: u64,
}

/// What the tensioner arms and decouplers do over the accepted steps of the
/// observed run: how often an arm's pivot friction holds (its presliding
/// deflection below 90 % of the presliding angle, the sliding one under
/// the mounted hub force), its mean
/// and rms rate and how often it changes sign, and
/// whether a decoupler's clutch is engaged beyond its band, in it or
/// overrunning.
#[derive(Default)]
struct Hardware {
    arm_steps: u64,
    arm_held: u64,
    arm_deflection_sum: f64,
    arm_deflection_max: f64,
    arm_sum: f64,
    arm_sum2: f64,
    arm_sign_changes: u64,
    arm_last: Vec<f64>,
    dec_steps: u64,
    dec_engaged: u64,
    dec_overrunning: u64,
}

impl Hardware {
    fn record(&mut self, sys: &BeltSystem, y: &[f64]) {
        let s = sys.state_layout();
        let pulleys = sys.pulleys();
        self.arm_last.resize(pulleys.len(), 0.0);
        for (j, pc) in pulleys.iter().enumerate() {
            if let Some(arm) = &pc.arm {
                let o = s.arm(j);
                let w = y[o.rate];
                self.arm_steps += 1;
                let u = y[o.deflection].abs() / arm.presliding_angle;
                self.arm_held += u64::from(u < 0.9);
                self.arm_deflection_sum += u;
                self.arm_deflection_max = self.arm_deflection_max.max(u);
                self.arm_sum += w;
                self.arm_sum2 += w * w;
                self.arm_sign_changes += u64::from(w * self.arm_last[j] < 0.0);
                self.arm_last[j] = w;
            }
            if let Some(dc) = &pc.decoupler {
                let d = s.decoupler(j);
                let w = dc.relative_rate(y[s.pulley(j).speed], y[d.rotor_speed]);
                let law = dc.law(y[d.twist], w);
                self.dec_steps += 1;
                // beyond the band the clutch's slope is 1, overrunning it
                // carries nothing
                self.dec_engaged += u64::from(law.rate_d_rate == 1.0);
                self.dec_overrunning += u64::from(law.torque == 0.0);
            }
        }
    }

    fn print(&self) {
        if self.arm_steps > 0 {
            let n = self.arm_steps as f64;
            println!(
                "  tensioner arm over the accepted steps: pivot friction holding (presliding) \
                 on {:.1} %, deflection over the presliding angle mean {:.2} max {:.2}, mean rate \
                 {:.2e} rad/s, rms {:.2e} rad/s, {:.0} sign changes per simulated s",
                100.0 * self.arm_held as f64 / n,
                self.arm_deflection_sum / n,
                self.arm_deflection_max,
                self.arm_sum / n,
                (self.arm_sum2 / n).sqrt(),
                self.arm_sign_changes as f64 / WINDOW
            );
        }
        if self.dec_steps > 0 {
            let n = self.dec_steps as f64;
            let overrunning = self.dec_overrunning as f64 / n;
            let engaged = self.dec_engaged as f64 / n;
            println!(
                "  decoupler over the accepted steps: clutch engaged beyond its band {:.1} %, in the band \
                 {:.1} %, overrunning {:.1} %",
                100.0 * engaged,
                100.0 * (1.0 - engaged - overrunning),
                100.0 * overrunning
            );
        }
    }
}

/// Bodies whose contact changes between states `a` and `b`.
fn contact_changes(sys: &BeltSystem, a: &[f64], b: &[f64]) -> usize {
    let centres = |y: &[f64]| -> Vec<[f64; 2]> {
        (0..sys.n_pulleys())
            .map(|j| sys.pulley_centre(j, y).0)
            .collect()
    };
    let (ca, cb) = (centres(a), centres(b));
    (0..sys.n_bodies())
        .filter(|&i| sys.touching(i, a, &ca) != sys.touching(i, b, &cb))
        .count()
}

fn classify(sys: &BeltSystem, comps: &[f64]) -> (Group, usize) {
    let nb = bodies_len(sys.n_bodies());
    let (i, _) =
        comps[..sys.controlled_dim()]
            .iter()
            .enumerate()
            .fold((0, -1.0), |(bi, bv), (i, &v)| {
                if v.abs() > bv {
                    (i, v.abs())
                } else {
                    (bi, bv)
                }
            });
    if i < nb {
        let (body, c) = body_component(i);
        let g = match c {
            BodyComponent::X | BodyComponent::Y => Group::BodyPosition,
            BodyComponent::Angle => Group::BodyAngle,
            BodyComponent::Vx | BodyComponent::Vy => Group::BodyVelocity,
            BodyComponent::Spin => Group::BodySpin,
            BodyComponent::Creep => Group::Creep,
        };
        return (g, body);
    }
    let s = sys.state_layout();
    let pulleys = sys.pulleys();
    let g = if i < s.energy().work_in {
        Group::Pulley
    } else if (0..pulleys.len()).any(|j| {
        let d = s.decoupler(j);
        pulleys[j].decoupler.is_some() && (i == d.twist || i == d.rotor_speed)
    }) {
        Group::Decoupler
    } else if (0..pulleys.len()).any(|j| pulleys[j].arm.is_some() && i == s.arm(j).angle) {
        Group::ArmAngle
    } else if (0..pulleys.len()).any(|j| pulleys[j].arm.is_some() && i == s.arm(j).rate) {
        Group::ArmRate
    } else {
        Group::Other
    };
    (g, usize::MAX)
}

impl Profile {
    fn record(&mut self, sys: &BeltSystem, tr: &Trial, comps: &[f64], end: &[f64], energy: f64) {
        let ok = tr.err <= 1.0;
        let (mut g, body) = classify(sys, comps);
        // the norm without the energy check
        let q = sys.controlled_dim();
        let norm = (comps[..q].iter().map(|c| c * c).sum::<f64>() / q as f64).sqrt();
        if !ok && tr.err.is_finite() && norm <= 1.0 && energy > 1.0 {
            g = Group::Energy;
        }
        let kind = match (ok, g) {
            (true, _) => 0,
            (false, Group::Energy) => 2,
            _ => 1,
        };
        self.of_kind[kind] += 1;
        if tr.err.is_finite() && contact_changes(sys, tr.y, end) > 0 {
            self.with_change[kind] += 1;
        }
        if ok && energy > norm {
            self.energy_limited += 1;
        }
        let gi = GROUPS.iter().position(|&x| x == g).unwrap();
        if ok {
            self.accepted += 1;
            self.acc_group[gi] += 1;
            let d = ((tr.h.log10() + 8.0).floor().clamp(0.0, 5.0)) as usize;
            self.h_hist[d] += 1;
            self.h_sum += tr.h;
        } else {
            self.rejected += 1;
            self.rej_group[gi] += 1;
        }
        if body != usize::MAX && g != Group::Energy {
            let (d, _) = place(sys, tr.y, body);
            if ok {
                self.acc_place[d] += 1;
            } else {
                self.rej_place[d] += 1;
            }
        }
    }
}

/// Options `key=value` after the runs: `pMax=<m>` (contact.pMax),
/// `energyCheck=0` (the stiff method's energy check off), `points=<n>`
/// (contact.points), `relTol=<x>`, `bodies=<n>` (belt.nBodies), `load=<x>`
/// (the load dampings times x), `jacobianAge=<n>` (the stiff method's
/// Jacobian kept for n accepted steps in the observed run;
/// `SolverTuning::jacobian_max_age` by default),
/// `armFriction=<x>` (the tensioner arms' pivot friction times x),
/// `comm=<s>` (the window's communication step; 1 ms by default).
#[derive(Clone, Copy, Default)]
struct Options {
    p_max: Option<f64>,
    no_energy: bool,
    points: Option<usize>,
    rel_tol: Option<f64>,
    bodies: Option<usize>,
    load: Option<f64>,
    jacobian_age: Option<u32>,
    arm_friction: Option<f64>,
    comm: Option<f64>,
}

/// Trials whose energy terms are compared with a tight reference step.
const TERM_SAMPLES: usize = 40;

/// The stiff method's energy residual over its tolerance, term by term:
/// each term of the balance at the trial's end state less its value at the
/// end of the same step taken by RKF45 at relTol 1e-10 (summed |.| /
/// tolerance: residual, input work, dissipated, kinetic, potential less
/// creep springs, creep springs).
#[derive(Default)]
struct Terms {
    samples: usize,
    err: [f64; 6],
}

impl Terms {
    fn add(&mut self, sys: &BeltSystem, tr: &Trial, end: &[f64], rel_tol: f64, ws: &mut Workspace) {
        let mut rk = Rkf45::new(tr.y.len(), 1e-10, 1e-12, tr.h / 16.0, 1_000_000);
        let (mut t, mut y) = (tr.t, tr.y.to_vec());
        if rk.advance(sys, ws, &mut t, &mut y, tr.t + tr.h).is_err() {
            return;
        }
        let o = sys.state_layout().energy();
        let parts = |y: &[f64]| {
            let e = sys.stored_energy(y);
            let b = sys.balance_of(y, e);
            [
                b.balance,
                y[o.work_in],
                y[o.dissipated],
                e.kinetic,
                e.potential - e.creep,
                e.creep,
            ]
        };
        let tol = TUNING.energy_tolerance * rel_tol * sys.stored_energy(tr.y).belt;
        let (a, r) = (parts(end), parts(&y));
        for (k, e) in self.err.iter_mut().enumerate() {
            *e += (a[k] - r[k]).abs() / tol;
        }
        self.samples += 1;
    }
}

fn run(name: &str, rpm: f64, method: Method, o: Options) {
    let mut p = drive(name, rpm, method);
    if let Some(x) = o.p_max {
        p.contact.p_max = x;
    }
    if let Some(x) = o.points {
        p.contact.points = x;
    }
    if let Some(x) = o.rel_tol {
        p.solver.rel_tol = x;
    }
    if let Some(x) = o.bodies {
        p.belt.n_bodies = x;
    }
    if let Some(x) = o.arm_friction {
        for arm in p.pulleys.iter_mut().filter_map(|q| q.arm.as_mut()) {
            arm.friction *= x;
        }
    }
    if let Some(x) = o.load {
        for q in &mut p.pulleys {
            q.load_damping *= x;
        }
    }
    let ramp = p.pulleys.iter().map(|q| q.ramp_time).fold(0.0, f64::max);
    let t0 = ramp + 0.1;
    let mut d = Drive::new(&p, 0.0).expect("valid drive");
    if o.no_energy {
        d.set_energy_check(false);
    }
    for w in d.warnings() {
        println!("  warning: {w}");
    }
    let mut t = 0.0;
    while t < t0 - 1e-12 {
        t += COMM;
        d.advance(t).expect("runs");
    }
    // the plain run's cost over the window (the advance calls alone), its
    // span tensions and arm angles sampled at the communication points
    let mut plain = d.clone();
    let s0 = plain.stats();
    let np = p.pulleys.len();
    let (mut cpu, mut tension, mut arm) = (0.0, vec![0.0; np], 0.0);
    let mut tt = t;
    let comm = o.comm.unwrap_or(COMM);
    let samples = (WINDOW / comm).round() as usize;
    for k in 1..=samples {
        tt = t + k as f64 * comm;
        let c0 = cpu_time();
        plain.advance(tt).expect("runs");
        cpu += cpu_time() - c0;
        let o = plain.outputs();
        for (m, x) in tension.iter_mut().zip(&o.span_tension) {
            *m += x / samples as f64;
        }
        arm += o.pulleys[..np].iter().map(|q| q.arm_angle).sum::<f64>() / samples as f64;
    }
    let s1 = plain.stats();
    // the observed run
    let sys = d.system().clone();
    let mut y = d.state().to_vec();
    let mut ws = Workspace::new();
    let mut prof = Profile::default();
    let mut hw = Hardware::default();
    let mut terms = Terms::default();
    let mut ws_ref = Workspace::new();
    let mut comps = vec![0.0; y.len()];
    let mut end = vec![0.0; y.len()];
    let mut tc = t;
    let (jac, fac) = match d.integrator().clone() {
        Integrator::Rosenbrock(mut ros) => {
            if let Some(n) = o.jacobian_age {
                ros.jacobian_max_age = n;
            }
            let (j0, f0) = (ros.jacobians, ros.factorizations);
            for k in 1..=samples {
                ros.advance_observed(
                    &sys,
                    &mut ws,
                    &mut tc,
                    &mut y,
                    t + k as f64 * comm,
                    &mut |m, tr| {
                        let energy = m.error_components(tr.y, &mut comps, &mut end);
                        prof.record(&sys, &tr, &comps, &end, energy);
                        if tr.err <= 1.0 {
                            hw.record(&sys, &end);
                        }
                        if energy > 1.0 && terms.samples < TERM_SAMPLES {
                            terms.add(&sys, &tr, &end, m.rel_tol, &mut ws_ref);
                        }
                    },
                )
                .expect("runs");
            }
            (ros.jacobians - j0, ros.factorizations - f0)
        }
        Integrator::Rkf45(mut rk) => {
            for k in 1..=samples {
                rk.advance_observed(
                    &sys,
                    &mut ws,
                    &mut tc,
                    &mut y,
                    t + k as f64 * comm,
                    &mut |m, tr| {
                        m.error_components(tr.y, tr.h, &mut comps, &mut end);
                        prof.record(&sys, &tr, &comps, &end, 0.0);
                        if tr.err <= 1.0 {
                            hw.record(&sys, &end);
                        }
                    },
                )
                .expect("runs");
            }
            (0, 0)
        }
    };
    assert!((tt - tc).abs() < 1e-12);
    let per_s = |x: u64| x as f64 / WINDOW;
    let out = plain.outputs();
    println!(
        "  means over the window: span tensions {} N, arm angle {:.5} rad",
        tension
            .iter()
            .map(|x| format!("{x:.2}"))
            .collect::<Vec<_>>()
            .join("/"),
        arm
    );
    println!(
        "{name} {rpm} rpm {method:?}: real-time factor {:.3} (cpu {:.2} s); belt speed {:.1} m/s, slips {} %; \
         plain run: {:.0} accepted/s, {:.0} rejected/s ({:.1} %); observed run: {:.0} accepted/s, \
         {:.0} rejected/s; mean step {:.2e} s; Jacobians {:.0}/s, factorizations {:.0}/s",
        WINDOW / cpu,
        cpu,
        out.pulleys[0].omega.abs() * p.pulleys[0].radius,
        (1..p.pulleys.len())
            .map(|j| format!("{:.3}", 100.0 * out.pulleys[j].slip))
            .collect::<Vec<_>>()
            .join("/"),
        per_s(s1.steps - s0.steps),
        per_s(s1.rejected - s0.rejected),
        100.0 * (s1.rejected - s0.rejected) as f64 / (s1.steps - s0.steps) as f64,
        per_s(prof.accepted),
        per_s(prof.rejected),
        prof.h_sum / prof.accepted as f64,
        per_s(jac),
        per_s(fac)
    );
    let pct = |a: &[u64]| {
        let s: u64 = a.iter().sum::<u64>().max(1);
        a.iter()
            .map(|&x| format!("{:.0}", 100.0 * x as f64 / s as f64))
            .collect::<Vec<_>>()
            .join("/")
    };
    println!(
        "  worst component [% of trials] pos/angle/vel/spin/creep/pulley/decoupler/arm angle/arm rate/energy/other: \
         accepted {}; rejected {}",
        pct(&prof.acc_group),
        pct(&prof.rej_group)
    );
    println!(
        "  worst body's distance to a landing or leaving [bodies 0/1/2/3+, %]: accepted {}; rejected {}",
        pct(&prof.acc_place),
        pct(&prof.rej_place)
    );
    let share = |k: usize| 100.0 * prof.with_change[k] as f64 / prof.of_kind[k].max(1) as f64;
    println!(
        "  trials over which a body lands or leaves [%]: accepted {:.0}, rejected on the norm {:.0} \
         (of {}), on the energy check {:.0} (of {}); accepted steps limited by the energy check {:.0} %",
        share(0),
        share(1),
        prof.of_kind[1],
        share(2),
        prof.of_kind[2],
        100.0 * prof.energy_limited as f64 / prof.accepted.max(1) as f64
    );
    if terms.samples > 0 {
        let k = terms.samples as f64;
        println!(
            "  energy residual of {} trials over the energy check's tolerance, term by term against \
             RKF45 at relTol 1e-10 over the same step (mean |error| / tolerance): residual {:.2}; \
             input work {:.2}, dissipated {:.2}, kinetic {:.2}, potential less creep springs {:.2} \
             (creep springs {:.2})",
            terms.samples,
            terms.err[0] / k,
            terms.err[1] / k,
            terms.err[2] / k,
            terms.err[3] / k,
            terms.err[4] / k,
            terms.err[5] / k
        );
    }
    println!(
        "  accepted step sizes [% per decade 1e-8/1e-7/1e-6/1e-5/1e-4/1e-3 s]: {}",
        pct(&prof.h_hist)
    );
    hw.print();
}

fn main() {
    let (opts, args): (Vec<String>, Vec<String>) =
        std::env::args().skip(1).partition(|a| a.contains('='));
    let mut o = Options::default();
    for kv in &opts {
        let (k, v) = kv.split_once('=').unwrap();
        match k {
            "pMax" => o.p_max = Some(v.parse().expect("pMax")),
            "energyCheck" => o.no_energy = v == "0",
            "points" => o.points = Some(v.parse().expect("points")),
            "relTol" => o.rel_tol = Some(v.parse().expect("relTol")),
            "bodies" => o.bodies = Some(v.parse().expect("bodies")),
            "load" => o.load = Some(v.parse().expect("load")),
            "jacobianAge" => o.jacobian_age = Some(v.parse().expect("jacobianAge")),
            "armFriction" => o.arm_friction = Some(v.parse().expect("armFriction")),
            "comm" => o.comm = Some(v.parse().expect("comm")),
            _ => panic!("option {k}"),
        }
    }
    let method = |m: &str| match m {
        "stiff" => Method::Rosenbrock,
        "rkf45" => Method::Rkf45,
        _ => panic!("method {m}: stiff or rkf45"),
    };
    if args.is_empty() {
        for m in ["stiff", "rkf45"] {
            run("5pk", 0.0, method(m), o);
            for name in ["acc4", "tens"] {
                for rpm in [800.0, 6000.0] {
                    run(name, rpm, method(m), o);
                }
            }
        }
        return;
    }
    for a in args.chunks(3) {
        run(&a[0], a[1].parse().expect("rpm"), method(&a[2]), o);
    }
}
