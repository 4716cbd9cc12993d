//! Slip against the mesh (docs/validation.md, "Slip against the mesh";
//! docs/model.md, "Chordal effect"): a chain of straight bodies on pulleys
//! of different radius runs at the radius ratio, and the slip of coarse
//! meshes lies within 10 % of the mesh-converged value
//! (examples/common/mesh_limits.rs, from the two contacts' fine-mesh runs;
//! the meshes are those of `cargo run --profile ci --example mesh_study`).
//!
//! Run with `cargo test --profile ci --test mesh` (35-65 s of wall time
//! on the shared machine: the stiff method at relTol 1e-5, as in the study).

use belt_drive::model::params::Method;
use belt_drive::{Drive, DriveParams};

#[path = "../examples/common/two_to_one.rs"]
mod drives;

#[path = "../examples/common/mesh_limits.rs"]
mod mesh_limits;

#[path = "../examples/common/ssv.rs"]
mod ssv;

#[path = "../examples/common/accessory.rs"]
mod accessory;

#[path = "../examples/common/body_passing.rs"]
mod body_passing;
use mesh_limits::{CONVERGED_2TO1, CONVERGED_5PK};

/// The 2:1 drive of the mesh study: 40 mm pulley speed-driven at -40 rad/s
/// (0.1 s ramp), 80 mm pulley 0.3 m away loaded by 1.5 N m s/rad (30 N m at
/// speed); 5PK belt at 500 N.
fn two_to_one(n_bodies: usize) -> DriveParams {
    let mut p = drives::two_to_one();
    p.belt.n_bodies = n_bodies;
    p.probe_body = 0;
    p
}

/// Speed loss of pulley 2 against pulley 1, 1 - |omega_2 r_2| / |omega_1
/// r_1|, from the mean speeds (pulley angles) over [t0, t1]; the stiff
/// method at relTol 1e-5 (the study's; it gives RKF45's slip within 0.0002
/// points on these drives, docs/validation.md).
fn speed_loss(p: &DriveParams, t0: f64, t1: f64) -> f64 {
    speed_loss_sampled(p, t0, t1, 1).0
}

/// [`speed_loss`] and the mean tensions of the two spans, tight first (50
/// samples over the window, as `mesh_study` takes them).
fn speed_loss_and_tensions(p: &DriveParams, t0: f64, t1: f64) -> (f64, [f64; 2]) {
    let (loss, [a, b]) = speed_loss_sampled(p, t0, t1, 50);
    (loss, [a.max(b), a.min(b)])
}

/// The speed loss over [t0, t1] and the two spans' tensions averaged over
/// `samples` communication points spread evenly over the window.
fn speed_loss_sampled(p: &DriveParams, t0: f64, t1: f64, samples: usize) -> (f64, [f64; 2]) {
    let mut p = p.clone();
    p.solver.method = Method::Rosenbrock;
    p.solver.rel_tol = 1e-5;
    p.solver.abs_tol = 1e-7;
    p.solver.max_steps = u64::MAX;
    let mut d = Drive::new(&p, 0.0).expect("valid drive");
    d.advance(t0).expect("runs");
    let a0 = [d.outputs().pulleys[0].angle, d.outputs().pulleys[1].angle];
    let mut tension = [0.0; 2];
    for k in 1..=samples {
        let t = if k == samples {
            t1
        } else {
            t0 + (t1 - t0) * k as f64 / samples as f64
        };
        d.advance(t).expect("runs");
        for (m, t) in tension.iter_mut().enumerate() {
            *t += d.outputs().span_tension[m] / samples as f64;
        }
    }
    let o = d.outputs();
    let w = [
        (o.pulleys[0].angle - a0[0]) / (t1 - t0),
        (o.pulleys[1].angle - a0[1]) / (t1 - t0),
    ];
    let loss = 1.0 - (w[1] * p.pulleys[1].radius).abs() / (w[0] * p.pulleys[0].radius).abs();
    (loss, tension)
}

/// Rigid-adhesion creep theory's speed loss from span tensions (tight,
/// slack): the belt arrives on each pulley in stick at the strain of the span
/// it comes from, 1 - (1 + T_s / EA) / (1 + T_t / EA).
fn creep_theory(p: &DriveParams, [tight, slack]: [f64; 2]) -> f64 {
    (tight - slack) / (p.belt.ea + tight)
}

/// How far below rigid creep theory the creep a belt brings onto its
/// driving pulley can put the slip (docs/validation.md, "A small Delta_max:
/// the creep the belt brings onto a wrap"). The penalty contact lets the
/// straight belt enter the pulley's circle over s_c = sqrt(2 rho p0) (p0
/// the penetration under the arriving tension T, rho = r - p0) at the angle
/// s / rho, so that it falls behind the surface by at most the integral of (s / rho)^2 / 2,
/// z_e = s_c^3 / (6 rho^2) (the straight line's value; the belt bends onto
/// the pulley over that length and was measured to bring 2.7-4.1 um of the
/// 8 um this gives on the 5PK drive). The creep law carries that as friction
/// from the entry on: the belt creeps back over the creep length
/// lambda = sqrt(EA Delta_max r / (1.5 mu_s T)) and sheds EA z_e / lambda
/// of tension before its adhesion arc, whose strain, lower by z_e / lambda,
/// sets the slip. Returns z_e / lambda.
fn entry_creep_margin(p: &DriveParams, driver: usize, arriving: f64) -> f64 {
    let q = &p.pulleys[driver];
    let r = q.radius;
    // the contact law per unit length: c1 p^2 + c2 p = T / r
    let (c1, c2) = (p.contact.c1, p.contact.c2);
    let n = arriving / r;
    let p0 = 2.0 * n / (c2 + (c2 * c2 + 4.0 * c1 * n).sqrt());
    let rho = r - p0;
    let z_e = (2.0 * rho * p0).powf(1.5) / (6.0 * rho * rho);
    let mu_s = if q.groove_angle > 0.0 {
        q.mu_static / (0.5 * q.groove_angle).sin()
    } else {
        q.mu_static
    };
    let lambda = (p.belt.ea * p.friction.creep_max * r / (1.5 * mu_s * arriving)).sqrt();
    z_e / lambda
}

/// The slip `loss` (and the drive's mesh-converged slip, when given) not
/// below rigid creep theory from the run's own span tensions by more than
/// [`entry_creep_margin`] of the driving pulley (pulley 1, onto which the
/// tight span runs).
fn assert_not_below_creep_theory(
    name: &str,
    p: &DriveParams,
    loss: f64,
    converged: Option<f64>,
    t: [f64; 2],
) {
    let theory = creep_theory(p, t);
    let margin = entry_creep_margin(p, 0, t[0]);
    println!(
        "{name}: span tensions {:.1} / {:.1} N, creep theory {:.4} %, entry-creep margin {:.4} points: \
         bound {:.4} %, slip {:.4} %",
        t[0],
        t[1],
        100.0 * theory,
        100.0 * margin,
        100.0 * (theory - margin),
        100.0 * loss
    );
    for (what, x) in [("slip", Some(loss)), ("converged slip", converged)] {
        let Some(x) = x else { continue };
        assert!(
            x >= theory - margin,
            "{name}: {what} {x} below creep theory {theory} by more than the entry creep's {margin}"
        );
    }
}

/// With no load the belt transmits no force, so a continuous belt turns the
/// pulleys at the radius ratio: omega_2 r_2 = omega_1 r_1. A chain of
/// straight bodies of length l = 0.2 x the small radius (120 bodies) with
/// the radius as the friction lever would run the small pulley's spans
/// 0.33 % and the large one's 0.08 % fast (v h / atan h, h = l / (2 r)) and
/// miss the ratio by 0.25 %; the chordal lever r atan(h)/h removes that
/// (measured 0.043 %). Bound 0.1 %: well inside the 0.25 % it removes, above
/// the residual of the landing (docs/model.md, "Chordal effect").
#[test]
fn unloaded_unequal_pulleys_turn_at_the_radius_ratio() {
    let mut p = two_to_one(120);
    p.pulleys[1].load_damping = 0.0;
    let loss = speed_loss(&p, 0.3, 0.6);
    println!(
        "unloaded 2:1 drive, 120 bodies: speed loss {:.4} %",
        100.0 * loss
    );
    assert!(loss.abs() < 1e-3, "speed loss {loss}");
}

/// The loaded 2:1 drive at 240 bodies (l = 0.10 x the small radius): slip
/// within 10 % of the mesh-converged value ([`CONVERGED_2TO1`]). With the
/// radius as the lever the chordal effect put it 22 % low (0.191 %).
#[test]
fn unequal_pulleys_slip_within_ten_percent_of_converged() {
    let converged = CONVERGED_2TO1;
    let p = two_to_one(240);
    let (loss, tensions) = speed_loss_and_tensions(&p, 0.4, 1.0);
    assert_not_below_creep_theory("2:1 drive, 240 bodies", &p, loss, Some(converged), tensions);
    println!(
        "2:1 drive, 240 bodies: speed loss {:.4} % against converged {:.3} %",
        100.0 * loss,
        100.0 * converged
    );
    assert!(
        (loss / converged - 1.0).abs() < 0.1,
        "{loss} vs {converged}"
    );
}

/// The paper's 5PK drive (equal 27 mm pulleys, 15 N m) at 300 bodies
/// (l = 0.15 x the radius): slip within 10 % of the mesh-converged value
/// ([`CONVERGED_5PK`]). At the paper's 150 bodies (l = 0.30 r) it is 24 %
/// high: the abrupt landing of docs/validation.md, "Why a coarse mesh slips
/// more".
#[test]
fn equal_pulleys_slip_within_ten_percent_of_converged() {
    let converged = CONVERGED_5PK;
    let mut p = DriveParams::kubas_section4();
    p.belt.n_bodies = 300;
    p.probe_body = 0;
    let (loss, tensions) = speed_loss_and_tensions(&p, 0.6, 1.2);
    assert_not_below_creep_theory("5PK drive, 300 bodies", &p, loss, Some(converged), tensions);
    println!(
        "5PK drive, 300 bodies: speed loss {:.4} % against converged {:.3} %",
        100.0 * loss,
        100.0 * converged
    );
    assert!(
        (loss / converged - 1.0).abs() < 0.1,
        "{loss} vs {converged}"
    );
}

/// The contact along the body (`contact.points` = 3, docs/model.md,
/// "Contact along the body") on the paper's 5PK drive at its 150 bodies
/// (l = 0.30 x the radius) and on the 2:1 drive at 120 bodies (l = 0.20 x
/// the small radius), the meshes of issue 16's goal: slip within 10 % of
/// the mesh-converged value ([`CONVERGED_5PK`], [`CONVERGED_2TO1`]). The
/// study measured +5.6 % and +9.0 % against them; the centre contact gives
/// +24.0 % and +23.7 % on these meshes. 10 % is the required bound, not a fit.
#[test]
fn contact_along_the_body_slip_within_ten_percent_at_practical_meshes() {
    for (name, mut p, (t0, t1), converged) in [
        (
            "5PK drive, 150 bodies",
            DriveParams::kubas_section4(),
            (0.6, 1.2),
            CONVERGED_5PK,
        ),
        (
            "2:1 drive, 120 bodies",
            two_to_one(120),
            (0.4, 1.0),
            CONVERGED_2TO1,
        ),
    ] {
        p.contact.points = 3;
        p.probe_body = 0;
        let loss = speed_loss(&p, t0, t1);
        println!(
            "{name}, 3 contact points: speed loss {:.4} % against converged {:.4} % ({:+.1} %)",
            100.0 * loss,
            100.0 * converged,
            100.0 * (loss / converged - 1.0)
        );
        assert!(
            (loss / converged - 1.0).abs() < 0.1,
            "{name}: {loss} vs {converged}"
        );
    }
}

/// The paper's 5PK drive with a tenth of its Delta_max (`friction.creepMax`
/// 10 um) at 1200 bodies, the landing resolved (docs/validation.md, "A
/// small Delta_max: the creep the belt brings onto a wrap"): the slip lies
/// 0.042 points (12 %) below rigid creep theory, all of it the creep the
/// belt brings through the contact's entry, and it must not lie lower than
/// [`entry_creep_margin`] (0.145 points) says that can put it. About 5 min
/// of wall time: `cargo test --profile ci --test mesh -- --ignored`.
#[test]
#[ignore]
fn small_creep_max_slip_not_below_creep_theory_beyond_the_entry_creep() {
    let mut p = DriveParams::kubas_section4();
    p.belt.n_bodies = 1200;
    p.probe_body = 0;
    p.friction.creep_max *= 0.1;
    let (loss, tensions) = speed_loss_and_tensions(&p, 0.6, 1.2);
    assert_not_below_creep_theory(
        "5PK drive, Delta_max / 10, 1200 bodies",
        &p,
        loss,
        None,
        tensions,
    );
}

/// The body-passing component of the accessory drive's instantaneous
/// outputs at idle (`parameters/accessory-drive-4.ssv`, 800 rpm, 160 bodies,
/// f_bp = v / l = 740 Hz; RKF45 at relTol 1e-4, 0.2 s sampled every 20 us
/// after 0.6 s; `cargo run --profile ci --example body_passing`), as the
/// model gives it today: the largest line within 5 % of f_bp (at 739.8 Hz)
/// of the alternator's belt torque 0.246 N m (8 % of its 3.0 N m mean), of
/// the span tensions 1.38 / 0.97 / 6.57 / 9.38 N (643 / 498 / 391 / 390 N
/// mean), at the default span damping (`belt.transverseDamping` 25 1/s).
/// Without span damping they were 0.507 N m and 5.6 / 2.3 / 16.3 / 23.7 N
/// (at 2 f_bp 0.39 N m and 1.7 / 1.1 / 9.7 / 2.9 N): the damper takes 2.1
/// (alternator) to 4 (span 1) times off the line, since the spans' response
/// to the body passing is resonant (span 3's second mode lies near f_bp / 2
/// and its fourth near f_bp, docs/modes.md). Issue 33 asks for these at
/// least 10 times smaller than without damping; until then this test holds
/// them at today's level (20 % over today's figures, the run-to-run spread
/// of a line measured over 150 periods being far below that), so that a
/// change that makes the artefact worse fails here.
#[test]
fn body_passing_ripple_no_larger_than_today_on_the_accessory_drive() {
    let (_, f_bp, signals) = body_passing::measure("acc4", 800.0, Method::Rkf45);
    let today = [0.246, 1.38, 0.969, 6.57, 9.38];
    for (s, t) in signals.iter().zip(today) {
        println!(
            "{}: mean {:.3}, at f_bp ({:.1} Hz) {:.4} (today {t})",
            s.name, s.mean, f_bp, s.at_f_bp.0
        );
        assert!(
            s.at_f_bp.0 <= 1.2 * t,
            "{}: body-passing line {} above today's {t}",
            s.name,
            s.at_f_bp.0
        );
    }
}

/// The mesh warning (src/drive/mesh_check.rs; docs/model.md, "Body passing:
/// when the mesh is too coarse"). The accessory drive at idle, 160 bodies:
/// the bodies pass at f_bp = 738 Hz, and f_bp / 2 = 369 Hz lies within the
/// 15 % band of the third mode of span 1 (386 Hz at the preload) and of the
/// second modes of spans 3 and 4 (414 and 394 Hz; the running state's
/// parametric resonance of docs/modes.md): the drive warns naming
/// `belt.nBodies` and proposes the count that puts f_bp / 2 above the third
/// mode of every span, n >= 160 x 3.45 / n*_min = 310. At that count, and at
/// 6000 rpm on the shipped mesh (f_bp / 2 7.5 times higher), it warns
/// about the mesh no more; a speed only given through the speed input is
/// not known at initialisation, so the crank's ramp set to 0 silences it.
#[test]
fn mesh_warning_names_belt_n_bodies_where_the_body_passing_meets_span_modes() {
    let mesh_warnings = |p: &DriveParams| -> Vec<String> {
        Drive::mounted(p, 0.0)
            .expect("valid drive")
            .warnings()
            .iter()
            .map(belt_drive::fmu::names::render)
            .filter(|w| w.starts_with("belt.nBodies"))
            .collect()
    };
    let acc4 = ssv::from_ssv("accessory-drive-4.ssv");
    let w = mesh_warnings(&acc4);
    println!("{w:?}");
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].starts_with("belt.nBodies = 160: at the belt speed 5.86 m/s"));
    assert!(w[0].contains("half of that, 369 Hz"), "{w:?}");
    assert!(w[0].contains("belt.nBodies >= 310 puts"), "{w:?}");
    let mut finer = acc4.clone();
    finer.belt.n_bodies = 310;
    assert!(mesh_warnings(&finer).is_empty());
    finer.belt.n_bodies = 309;
    assert_eq!(mesh_warnings(&finer).len(), 1);
    let mut fast = acc4.clone();
    fast.pulleys[0].omega_ramp *= 7.5;
    assert!(mesh_warnings(&fast).is_empty());
    let mut input_only = acc4.clone();
    input_only.pulleys[0].omega_ramp = 0.0;
    assert!(mesh_warnings(&input_only).is_empty());
    // a span too short for its mesh: the FMU's fast test drive (two 50 mm
    // pulleys 0.25 m apart, torque-driven, so only the second rule) at 40
    // bodies of 20 mm: each span holds 12.3, too few for mode 3 within 2 %;
    // 60 bodies give it 18.4
    let mut p = DriveParams::default();
    p.belt.preload = 300.0;
    p.pulleys[0].radius = 0.05;
    p.pulleys[1].radius = 0.05;
    p.pulleys[1].x = 0.25;
    p.probe_body = 0;
    p.belt.n_bodies = 60;
    assert!(mesh_warnings(&p).is_empty(), "{:?}", mesh_warnings(&p));
    p.belt.n_bodies = 40;
    let w = mesh_warnings(&p);
    println!("{w:?}");
    assert!(
        w.len() == 1
            && w[0].starts_with(
                "belt.nBodies = 40: 2 of the 2 free spans hold fewer than 13.6 bodies"
            )
            && w[0].contains("belt.nBodies >= 45 gives every span 13.6"),
        "{w:?}"
    );
}
