//! Right answers at the defaults on drives unlike the paper's: the contact
//! damping ramp chosen automatically per pulley (`contact.pMax` = 0), and
//! the two integrators giving one model: RKF45 at its default tolerance
//! against the stiff method (`solver.method` = 2) at relTol 1e-4 and at the
//! 1e-3 importers commonly pass through fmi2SetupExperiment.
//!
//! Run with `cargo test --profile ci --test defaults` (each test runs its
//! drive three times; the longest, the 5PK drive's RKF45 run, takes about
//! half a minute).

mod common;

#[path = "../examples/common/ssv.rs"]
mod ssv;

#[path = "../examples/common/accessory.rs"]
mod accessory;

use belt_drive::model::params::{Method, PulleyParams};
use belt_drive::{Drive, DriveParams, Inputs};
use common::Averages;

/// The heavy belt of issue 16: 0.8 kg/m, EA 7.6 kN, two 100 mm (radius)
/// pulleys 0.4 m apart, 400 N preload, mu 0.5, pulley 1 speed-driven at
/// 12 rad/s, pulley 2 loaded with 25 N m plus 2 N m s/rad (47.6 N m at
/// speed: 476 N between the spans, tension ratio 3.6 against the capstan
/// limit e^(0.5 pi) = 4.8). Every contact and friction parameter at the
/// FMU's default. 100 bodies of 14 mm.
fn heavy_belt() -> DriveParams {
    let mut p = DriveParams::default();
    p.belt.mass_per_length = 0.8;
    p.belt.ea = 7600.0;
    p.belt.preload = 400.0;
    p.belt.n_bodies = 100;
    p.probe_body = 0;
    let mut p1 = PulleyParams::paper_5pk(0.0, 0.0);
    p1.radius = 0.1;
    p1.inertia = 0.01;
    p1.mu_static = 0.5;
    p1.mu_kinetic = 0.5;
    let mut p2 = p1.clone();
    p2.x = 0.4;
    p1.speed_driven = true;
    p1.omega_ramp = 12.0;
    p1.ramp_time = 0.1;
    p2.torque_ramp = -25.0;
    p2.ramp_time = 0.1;
    p2.load_damping = 2.0;
    p.pulleys = vec![p1, p2];
    p
}

/// Two unequal pulleys (40 and 80 mm, 2:1), 5PK belt at 300 N, 120 bodies
/// (body length 0.2 x the small radius), the small pulley speed-driven at
/// -40 rad/s, the large one loaded by 1 N m s/rad; the default contact.
fn two_to_one() -> DriveParams {
    let mut p = DriveParams::default();
    p.belt.n_bodies = 120;
    p.belt.preload = 300.0;
    p.probe_body = 0;
    let mut p1 = PulleyParams::paper_5pk(0.0, 0.0);
    p1.radius = 0.04;
    let mut p2 = p1.clone();
    p2.radius = 0.08;
    p2.x = 0.29;
    p1.speed_driven = true;
    p1.omega_ramp = -40.0;
    p1.ramp_time = 0.05;
    p2.load_damping = 1.0;
    p.pulleys = vec![p1, p2];
    p
}

/// One run's means over a window.
struct Run {
    averages: Averages,
    steps: u64,
    warnings: Vec<String>,
}

/// `p` with `method` at `rel_tol` (absTol stays the default 1e-6, as an
/// importer that only passes a tolerance leaves it), run to `t0`, with
/// `load` = (time, pulley, torque) stepped in through the torque input,
/// then averaged over [t0, t1].
fn run(
    p: &DriveParams,
    method: Method,
    rel_tol: f64,
    load: Option<(f64, usize, f64)>,
    t0: f64,
    t1: f64,
) -> Run {
    let mut p = p.clone();
    p.solver.method = method;
    p.solver.rel_tol = rel_tol;
    let mut d = Drive::new(&p, 0.0).expect("valid drive");
    d.set_inputs(Inputs::default());
    if let Some((t, j, torque)) = load {
        d.advance(t).expect("runs to the load step");
        let mut inputs = *d.inputs();
        inputs.torque[j] = torque;
        d.set_inputs(inputs);
    }
    let averages = common::run_and_average(&mut d, t0, t1, 1e-3);
    Run {
        averages,
        steps: d.stats().steps,
        warnings: d
            .warnings()
            .iter()
            .map(belt_drive::fmu::names::render)
            .collect(),
    }
}

/// Slip between pulley 1 and `j` from the mean speeds: 1 - v_j / v_1 with
/// v = s omega r (s = -1 on a back-side idler).
fn slip(p: &DriveParams, a: &Averages, j: usize) -> f64 {
    let v = |k: usize| {
        let side = if p.pulleys[k].back_side { -1.0 } else { 1.0 };
        side * a.omega[k] * p.pulleys[k].radius
    };
    1.0 - v(j) / v(0)
}

/// RKF45 at its default tolerance (the reference) against the stiff method
/// at relTol 1e-4 and 1e-3 on drive `p`. Bounds of issue 16: at 1e-4
/// speeds and span tensions within 0.5 %; at 1e-3 speeds within 0.5 %,
/// tensions within 2 %, the slip between pulley 1 and `slip_pulley` within
/// 25 %. Returns the three runs (RKF45, stiff 1e-4, stiff 1e-3).
fn integrators_agree(
    name: &str,
    p: &DriveParams,
    load: Option<(f64, usize, f64)>,
    t0: f64,
    t1: f64,
    slip_pulley: usize,
) -> [Run; 3] {
    agree_with_reference(name, p, 1e-4, load, t0, t1, slip_pulley)
}

/// [`integrators_agree`] with RKF45 at `reference_tol`.
fn agree_with_reference(
    name: &str,
    p: &DriveParams,
    reference_tol: f64,
    load: Option<(f64, usize, f64)>,
    t0: f64,
    t1: f64,
    slip_pulley: usize,
) -> [Run; 3] {
    let (reference, stiff) = std::thread::scope(|s| {
        let h = s.spawn(|| run(p, Method::Rkf45, reference_tol, load, t0, t1));
        let stiff = [1e-4, 1e-3].map(|tol| run(p, Method::Rosenbrock, tol, load, t0, t1));
        (h.join().expect("RKF45 run"), stiff)
    });
    let r = &reference.averages;
    let np = p.pulleys.len();
    for (s, (tol, tension_bound, slip_bound)) in stiff
        .iter()
        .zip([(1e-4, 5e-3, None), (1e-3, 2e-2, Some(0.25))])
    {
        let a = &s.averages;
        println!(
            "{name}: stiff at {tol:e} ({} steps) vs RKF45 ({} steps): speeds {:?} vs {:?}, \
             span tensions {:?} vs {:?} N, slip {:.4} % vs {:.4} %",
            s.steps,
            reference.steps,
            a.omega,
            r.omega,
            a.span_tension,
            r.span_tension,
            100.0 * slip(p, a, slip_pulley),
            100.0 * slip(p, r, slip_pulley)
        );
        for j in 0..np {
            let (x, y) = (a.omega[j], r.omega[j]);
            assert!(
                (x - y).abs() <= 5e-3 * y.abs(),
                "{name}, relTol {tol:e}: pulley {} speed {x} vs {y} rad/s",
                j + 1
            );
            let (x, y) = (a.span_tension[j], r.span_tension[j]);
            assert!(
                (x - y).abs() <= tension_bound * y.abs(),
                "{name}, relTol {tol:e}: span {} tension {x} vs {y} N",
                j + 1
            );
        }
        if let Some(bound) = slip_bound {
            let (x, y) = (slip(p, a, slip_pulley), slip(p, r, slip_pulley));
            assert!(
                (x - y).abs() <= bound * y.abs(),
                "{name}, relTol {tol:e}: slip {x} vs {y}"
            );
        }
    }
    let [a, b] = stiff;
    [reference, a, b]
}

/// Creep theory for a two-pulley drive: belt material is conserved, so in
/// steady running the flux v / (1 + eps) is the same in both spans (eps =
/// T / EA). On each pulley the belt adheres on the arc where it arrives and
/// creeps on the arc before it leaves, so it arrives on the driver with the
/// tight span's speed v_t = omega_1 r_1 and on the driven pulley with the
/// slack span's v_s = omega_2 r_2. Hence omega_2 r_2 / (omega_1 r_1) =
/// (1 + T_s/EA) / (1 + T_t/EA), the creep loss s = (T_t - T_s) / (EA + T_t)
/// ~ dT / EA.
fn creep_theory_speed_ratio(t_tight: f64, t_slack: f64, ea: f64) -> f64 {
    (1.0 + t_slack / ea) / (1.0 + t_tight / ea)
}

/// The heavy belt with every contact parameter at its default: both
/// integrators give the creep-theory speed ratio within 1 % (the slip
/// itself, ~6 %, within 5 %), with no warning. With the paper's 1 mm ramp
/// the radial contact mode is undamped (damping ratio 0.01) and RKF45
/// slips grossly (measured 12.9 % instead of 5.8 %) while the stiff method
/// damps the rattle numerically: the defaults are what makes them agree.
#[test]
fn heavy_belt_at_the_defaults_creeps_as_theory_says() {
    let p = heavy_belt();
    let runs = integrators_agree("heavy belt", &p, None, 0.6, 1.0, 1);
    for (name, r) in ["RKF45", "stiff 1e-4", "stiff 1e-3"].iter().zip(&runs) {
        assert!(r.warnings.is_empty(), "{name}: {:?}", r.warnings);
        let a = &r.averages;
        let (t_tight, t_slack) = (a.span_tension[1], a.span_tension[0]);
        assert!(t_tight > t_slack, "{name}: span 2 is the tight one");
        let theory = creep_theory_speed_ratio(t_tight, t_slack, p.belt.ea);
        let ratio = a.omega[1] / a.omega[0];
        println!("{name}: speed ratio {ratio:.5}, creep theory {theory:.5}");
        // 1 % of the ratio (0.17 of the 5.8 % slip); measured within 0.07 %
        assert!(
            (ratio / theory - 1.0).abs() < 0.01,
            "{name}: {ratio} vs {theory}"
        );
        // the slip itself within 5 %: the 100-body chain's polygon excess
        // on equal pulleys (docs/model.md: ~1/n), measured 1 %
        let (s, s_theory) = (1.0 - ratio, 1.0 - theory);
        assert!(
            (s / s_theory - 1.0).abs() < 0.05,
            "{name}: slip {s} vs {s_theory}"
        );
    }
    // the paper's ramp and centre contact on this belt: RKF45 resolves the
    // undamped contact mode, rattles and slips far beyond creep theory
    let mut paper = p.clone();
    paper.contact.p_max = 1e-3;
    paper.contact.points = 1;
    let r = run(&paper, Method::Rkf45, 1e-4, None, 0.6, 1.0);
    assert!(r
        .warnings
        .iter()
        .any(|w| w.starts_with("contact.pMax = 1e-3 m")));
    let a = &r.averages;
    let s = 1.0 - a.omega[1] / a.omega[0];
    println!("RKF45 with the paper's 1 mm ramp: slip {:.2} %", 100.0 * s);
    assert!(s > 0.1, "the paper's ramp on the heavy belt: slip {s}");
}

/// The paper's 5PK drive at the FMU's defaults (torque-driven, ramped over
/// 0.3 s; means over 0.35-0.6 s).
#[test]
fn integrators_agree_on_the_default_drive() {
    let p = DriveParams::default();
    integrators_agree("5PK default drive", &p, None, 0.35, 0.6, 1);
}

/// The 2:1 drive with unequal pulleys.
#[test]
fn integrators_agree_on_unequal_pulleys() {
    integrators_agree("2:1 drive", &two_to_one(), None, 0.25, 0.45, 1);
}

/// The heavy section-3 belt (1.036 kg/m on 81.25 mm pulleys) with the
/// paper's 10 N m load step at 0.3 s and the default (automatic) contact
/// damping ramp, means over 1-2 s. The driven pulley then rings in its
/// ~20 Hz torsional mode against the spans, a physical mode damped only by
/// the belt (docs/validation.md): the stiff method must resolve it, not
/// damp it away, so the mean of |omega_2 - its mean| over 0.3-0.5 s after
/// the step must be RKF45's within 15 %.
///
/// The section-3 parameter set itself (contact.pMax = 1e-5 m, which leaves
/// a third of the damping on the slack side of the driven wrap) is compared
/// with RKF45 at its default relTol 1e-4 and at 1e-7: the slack-span tension
/// (means over 1-2 s) is 90.83 N with RKF45 at 1e-4, 90.76 N at 1e-7 and
/// 90.65 N with the stiff method at 1e-4 (0.21 % and 0.12 % off).
#[test]
fn integrators_agree_on_the_section3_load_step() {
    let load = Some((0.3, 1, 10.0));
    let set = DriveParams::kubas_section3();
    agree_with_reference("section-3 set, pMax 1e-5", &set, 1e-7, load, 1.0, 2.0, 1);
    integrators_agree("section-3 set at the defaults", &set, load, 1.0, 2.0, 1);
    let mut p = set.clone();
    p.contact.p_max = 0.0;
    integrators_agree("section-3 drive", &p, load, 1.0, 2.0, 1);
    let ringing = |method: Method| {
        let mut q = p.clone();
        q.solver.method = method;
        let mut d = Drive::new(&q, 0.0).expect("valid drive");
        d.advance(0.3).expect("runs to the step");
        let mut inputs = *d.inputs();
        inputs.torque[1] = 10.0;
        d.set_inputs(inputs);
        let w: Vec<f64> = (1..=200)
            .map(|k| {
                d.advance(0.3 + 1e-3 * f64::from(k)).expect("runs");
                d.outputs().pulleys[1].omega
            })
            .collect();
        let tail = &w[w.len() / 2..];
        let mean = tail.iter().sum::<f64>() / tail.len() as f64;
        tail.iter().map(|x| (x - mean).abs()).sum::<f64>() / tail.len() as f64
    };
    let (a, b) = (ringing(Method::Rkf45), ringing(Method::Rosenbrock));
    println!("section 3: ringing of omega_2 0.4-0.5 s: RKF45 {a:.4}, stiff {b:.4} rad/s");
    assert!(a > 1e-3, "the load step excites the torsional mode: {a}");
    assert!((b - a).abs() < 0.15 * a, "ringing {b} vs {a} rad/s");
}

/// The 4-pulley accessory drive (parameters/accessory-drive-4.ssv, which
/// spells out the paper's 1 mm contact ramp), the crank ramp shortened to
/// 0.2 s to keep the RKF45 run short; means over 0.4-0.6 s. The slip
/// compared is the alternator's (the fastest pulley).
#[test]
fn integrators_agree_on_the_accessory_drive() {
    let mut p = ssv::from_ssv("accessory-drive-4.ssv");
    p.solver.max_steps = DriveParams::default().solver.max_steps;
    for q in &mut p.pulleys {
        q.ramp_time = 0.2;
    }
    integrators_agree("accessory drive", &p, None, 0.4, 0.6, 2);
}

/// The accessory drive's decoupler and tensioner sets
/// (parameters/accessory-drive-decoupler.ssv, accessory-drive-tensioner.ssv)
/// as the plain accessory drive above: the crank ramp shortened to 0.2 s,
/// means over 0.4-0.6 s, the alternator's slip (pulley 2, behind its
/// one-way clutch: the slip is the belt's over its pulley, not the
/// rotor's).
#[test]
fn integrators_agree_on_the_decoupler_and_tensioner_sets() {
    for file in [
        "accessory-drive-decoupler.ssv",
        "accessory-drive-tensioner.ssv",
    ] {
        let mut p = ssv::from_ssv(file);
        p.solver.max_steps = DriveParams::default().solver.max_steps;
        for q in &mut p.pulleys {
            q.ramp_time = 0.2;
        }
        integrators_agree(file, &p, None, 0.4, 0.6, 2);
    }
}

/// The tensioner set (parameters/accessory-drive-tensioner.ssv) at 6,000
/// rpm crank speed (belt at 44 m/s) with the load torques held at their
/// idle values (load damping scaled by 800/6000): the stiff method at
/// relTol 1e-4 against RKF45 at relTol 1e-6 (tight: RKF45 is held by its
/// stability limit at 1e-4 already, so 1e-6 tightens what it resolves), the
/// bounds of `agree_with_reference` at 1e-4: pulley speeds and span
/// tensions within 0.5 %. The crank ramp shortened to 0.2 s, means over
/// 0.3-0.4 s. Measured (`cargo test --profile ci --test defaults
/// tensioner_set_at_6000 -- --nocapture`): span tensions within 0.16 %
/// (919.18 / 774.10 / 661.81 / 659.29 N against 917.92 / 772.89 / 660.81 /
/// 658.27 N), pulley speeds within 0.007 %, the alternator's slip 0.1071 %
/// against 0.1132 %; 40 767 stiff steps against 171 468.
#[test]
fn integrators_agree_on_the_tensioner_set_at_6000_rpm() {
    let mut p = accessory::at_rpm("tens", 6000.0, Method::Rosenbrock);
    p.solver.max_steps = DriveParams::default().solver.max_steps;
    for q in &mut p.pulleys {
        q.ramp_time = 0.2;
    }
    let (t0, t1) = (0.3, 0.4);
    let (reference, stiff) = std::thread::scope(|s| {
        let h = s.spawn(|| run(&p, Method::Rkf45, 1e-6, None, t0, t1));
        let stiff = run(&p, Method::Rosenbrock, 1e-4, None, t0, t1);
        (h.join().expect("RKF45 run"), stiff)
    });
    let (a, r) = (&stiff.averages, &reference.averages);
    println!(
        "tensioner set at 6000 rpm: stiff at 1e-4 ({} steps) vs RKF45 at 1e-6 ({} steps): \
         speeds {:?} vs {:?}, span tensions {:?} vs {:?} N, slip {:.4} % vs {:.4} %",
        stiff.steps,
        reference.steps,
        a.omega,
        r.omega,
        a.span_tension,
        r.span_tension,
        100.0 * slip(&p, a, 2),
        100.0 * slip(&p, r, 2)
    );
    assert!(
        (a.omega[0] / r.omega[0] - 1.0).abs() < 1e-6,
        "the crank is speed-driven: {} vs {} rad/s",
        a.omega[0],
        r.omega[0]
    );
    for j in 0..p.pulleys.len() {
        let (x, y) = (a.omega[j], r.omega[j]);
        assert!(
            (x - y).abs() <= 5e-3 * y.abs(),
            "pulley {} speed {x} vs {y} rad/s",
            j + 1
        );
        let (x, y) = (a.span_tension[j], r.span_tension[j]);
        assert!(
            (x - y).abs() <= 5e-3 * y.abs(),
            "span {} tension {x} vs {y} N",
            j + 1
        );
    }
}

/// The paper's section-4 set as it ships (parameters/kubas2014-section4.ssv:
/// the paper's 1 mm contact ramp, the 5PK drive of the default otherwise),
/// means over 0.35-0.6 s as on the default drive.
#[test]
fn integrators_agree_on_the_section4_set() {
    let mut p = ssv::from_ssv("kubas2014-section4.ssv");
    // the set's step guard is the FMU's per-communication-step bound
    p.solver.max_steps = DriveParams::default().solver.max_steps;
    integrators_agree("section-4 set", &p, None, 0.35, 0.6, 1);
}

/// A 60-body drive (two 50 mm pulleys 0.25 m apart, 300 N preload, every
/// other parameter at its default, the probe chosen automatically): pulley
/// 1 driven by -2 N m ramped over 0.05 s, pulley 2 loaded by 0.05 N m s/rad;
/// means over 0.3-0.5 s.
///
/// A fast, lightly loaded drive: the speeds follow the power balance
/// 2 N m omega_1 = 0.05 omega_2^2 + the belt's loss, and the loss is 0.6 %
/// of the power (RKF45: 0.0120 N m of the 2 N m). The stiff method's error
/// norm does not see an error of that loss (a bias of ~0.5 % of the belt
/// torque in every step, coherent over all bodies, far below each body's
/// tolerance); its energy check does: a step whose energy residual (input
/// work less dissipated less the change of the stored energy) exceeds
/// relTol times the belt's stored energy is rejected (docs/model.md,
/// "Integrators"). Without the check the stiff method at relTol 1e-4 was
/// 0.67 % off (omega_2 40.027 against 39.760 rad/s: it fed the belt's
/// fast motion with 1.5 W); with it 0.08 %, 0.31 % at 1e-3. RKF45 is the
/// right one: the stiff method converges to its answer as relTol tightens
/// (`sixty_body_drive_converged` below).
#[test]
fn integrators_agree_on_a_sixty_body_drive() {
    integrators_agree("60-body drive", &sixty_body_drive(), None, 0.3, 0.5, 1);
}

/// The 60-body drive of the test above.
fn sixty_body_drive() -> DriveParams {
    let mut p = common::sixty_bodies();
    p.pulleys[0].torque_ramp = -2.0;
    p.pulleys[0].ramp_time = 0.05;
    p.pulleys[1].load_damping = 0.05;
    p.pulleys[1].ramp_time = 0.05;
    p
}

/// Which method is right on the 60-body drive: both converge to one answer,
/// RKF45's at its default tolerance. RKF45 at relTol 1e-7 and the stiff
/// method at 1e-6 (measured: mean speeds 0.003 % apart, span tensions
/// 0.004 %; RKF45 at 1e-4 is within 0.0001 % of its 1e-7 run, the stiff
/// method at 1e-4 0.67 % off; with the paper's SDE, `belt.shearDampingFactor`
/// 0: 0.003 and 0.006 %, the stiff method at 1e-5 0.04 % and at 1e-4 0.69 %
/// off) agree within 0.05 %, a tenth of the bound and ten times the
/// measured difference.
#[test]
fn sixty_body_drive_converged() {
    let p = sixty_body_drive();
    let (reference, stiff) = std::thread::scope(|s| {
        let h = s.spawn(|| run(&p, Method::Rkf45, 1e-7, None, 0.3, 0.5));
        let stiff = run(&p, Method::Rosenbrock, 1e-6, None, 0.3, 0.5);
        (h.join().expect("RKF45 run"), stiff)
    });
    let (a, r) = (&stiff.averages, &reference.averages);
    println!(
        "60-body drive: stiff at 1e-6 ({} steps) vs RKF45 at 1e-7 ({} steps): speeds {:?} vs \
         {:?}, span tensions {:?} vs {:?} N",
        stiff.steps, reference.steps, a.omega, r.omega, a.span_tension, r.span_tension
    );
    for j in 0..2 {
        let (x, y) = (a.omega[j], r.omega[j]);
        assert!(
            (x - y).abs() <= 5e-4 * y.abs(),
            "pulley {} speed {x} vs {y}",
            j + 1
        );
        let (x, y) = (a.span_tension[j], r.span_tension[j]);
        assert!(
            (x - y).abs() <= 5e-4 * y.abs(),
            "span {} tension {x} vs {y}",
            j + 1
        );
    }
}
