//! Slip against the mesh (docs/validation.md, "Slip against the mesh";
//! docs/model.md, "Chordal effect"): a chain of straight bodies on pulleys
//! of different radius runs at the radius ratio, and the slip of coarse
//! meshes lies within 10 % of the mesh-converged value
//! (examples/common/mesh_limits.rs, from the two contacts' fine-mesh runs;
//! the meshes are those of `cargo run --profile ci --example mesh_study`).
//!
//! Run with `cargo test --profile ci --test mesh` (35-65 s of wall time
//! on the shared machine: the stiff method at relTol 1e-5, as in the study).

use belt_drive::belt::params::Method;
use belt_drive::belt::{Drive, DriveParams};

#[path = "../examples/common/two_to_one.rs"]
mod drives;

#[path = "../examples/common/mesh_limits.rs"]
mod mesh_limits;
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
    let mut p = p.clone();
    p.solver.method = Method::Rosenbrock;
    p.solver.rel_tol = 1e-5;
    p.solver.abs_tol = 1e-7;
    p.solver.max_steps = u64::MAX;
    let mut d = Drive::new(&p, 0.0).expect("valid drive");
    d.advance(t0).expect("runs");
    let a0 = [d.outputs().pulleys[0].angle, d.outputs().pulleys[1].angle];
    d.advance(t1).expect("runs");
    let o = d.outputs();
    let w = [
        (o.pulleys[0].angle - a0[0]) / (t1 - t0),
        (o.pulleys[1].angle - a0[1]) / (t1 - t0),
    ];
    1.0 - (w[1] * p.pulleys[1].radius).abs() / (w[0] * p.pulleys[0].radius).abs()
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
    let loss = speed_loss(&two_to_one(240), 0.4, 1.0);
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
    let loss = speed_loss(&p, 0.6, 1.2);
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
