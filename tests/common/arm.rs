//! The three-pulley tensioner drive and the closed form of its arm's
//! stiffness on the belt, shared by the tensioner and modal-analysis tests.

use super::small_drive;
use belt_drive::model::layout::Layout;
use belt_drive::model::params::{PulleyParams, TensionerArm};
use belt_drive::{DriveParams, FrictionLaw};

/// Three-pulley drive unlike the paper's: crank (r 60 mm) at the origin,
/// load pulley (r 40 mm) 0.32 m to its right, idler (r 35 mm) above between
/// them. A clockwise crank pays the belt out towards the idler: the idler
/// sits on the slack side, its two spans (`span[2]` from the load pulley,
/// `span[3]` to the crank) are slack spans, `span[1]` (crank to load) is
/// the tight one. With `tensioner` the idler rides on an 80 mm arm whose
/// pivot lies level with it towards the load pulley (the belt's hub force,
/// pointing down, turns the arm clockwise), spring 40 N m/rad.
pub fn three_pulley(tensioner: bool) -> DriveParams {
    let mut p = small_drive(FrictionLaw::Creep);
    p.belt.n_bodies = 90;
    let mut crank = PulleyParams::paper_5pk(0.0, 0.0);
    crank.radius = 0.06;
    let mut load = PulleyParams::paper_5pk(0.32, 0.0);
    load.radius = 0.04;
    let mut idler = PulleyParams::paper_5pk(0.16, 0.18);
    idler.radius = 0.035;
    idler.inertia = 1e-4;
    idler.arm = tensioner.then_some(TensionerArm {
        pivot: [0.24, 0.18],
        inertia: 1e-3,
        stiffness: 40.0,
        damping: 0.05,
        friction: 0.0,
        ..Default::default()
    });
    p.pulleys = vec![crank, load, idler];
    p
}

/// The drive of the closed-form arm tests: the three-pulley drive with
/// every pulley free and unloaded, no gravity and no friction (the belt
/// slides over the pulleys: its tension is the same all round the loop, at
/// rest and in the arm's slow swing, the closed form's assumption; with
/// friction the wraps hold part of the belt and the pulleys' inertia enters),
/// a heavy arm (2e-2 kg m2, 3.1 kg at the
/// 80 mm pulley centre, against the belt's 0.1 kg and the pulleys'
/// J / r^2 <= 0.08 kg, which swing with a fraction of the arm's motion:
/// < 0.3 % on the frequency).
pub fn free_loop() -> DriveParams {
    let mut p = three_pulley(true);
    p.gravity = 0.0;
    for q in p.pulleys.iter_mut() {
        q.speed_driven = false;
        q.load_damping = 0.0;
        q.torque_ramp = 0.0;
    }
    p.pulleys[2].arm.as_mut().unwrap().inertia = 2e-2;
    for q in p.pulleys.iter_mut() {
        q.mu_static = 0.0;
        q.mu_kinetic = 0.0;
    }
    p
}

/// Belt path length (spans plus wraps at the pulley radii) with pulley `j`
/// moved to `centre`.
pub fn path_length(p: &DriveParams, j: usize, centre: [f64; 2]) -> f64 {
    let mut q = p.clone();
    q.pulleys[j].x = centre[0];
    q.pulleys[j].y = centre[1];
    let l = Layout::new(&q).expect("layout");
    l.spans.iter().map(|s| s.length).sum::<f64>()
        + l.wraps
            .iter()
            .map(|w| w.angle * q.pulleys[w.pulley].radius)
            .sum::<f64>()
}

/// Closed-form stiffness of the arm on the belt, K_alpha = -d(M_spring +
/// M_hub)/d alpha at the mounted position.
///
/// The belt carries the same tension T all round (free pulleys, no
/// gravity). Virtual work: the hub force F = T (u_a + u_b) (unit vectors
/// along the two spans, away from the pulley) does the work the belt path
/// loses, F . dc = -T dL, so M_hub = (c - pivot) x F = -T dL/d alpha =: T g.
/// Rotating the arm lengthens the path by dL = -g d alpha; the belt takes
/// it up by stretching (L_belt / EA) and by sinking deeper into the wraps
/// (body centres at r - p, contact stiffness per length k_j = c2 + 2 c1 p_j
/// under the load T / r_j: dp_j = dT / (r_j k_j), the path shortens by
/// theta_j dp_j), so dT = K dL with 1 / K = L_belt / EA + sum theta_j /
/// (r_j k_j). Then dM_hub/d alpha = g dT/d alpha + T dg/d alpha = -K g^2 -
/// T L'' and
///
///   K_alpha = k + K g^2 + T L''(alpha),
///
/// g and L'' by central differences of the exact belt path (`path_length`,
/// steps of 1e-3 rad: truncation ~1e-6 relative).
pub fn arm_stiffness(p: &DriveParams, j: usize) -> f64 {
    let q = &p.pulleys[j];
    let arm = q.arm.expect("pulley j is on an arm");
    let (rx, ry) = (q.x - arm.pivot[0], q.y - arm.pivot[1]);
    let at = |a: f64| {
        let (s, c) = a.sin_cos();
        path_length(
            p,
            j,
            [
                arm.pivot[0] + c * rx - s * ry,
                arm.pivot[1] + s * rx + c * ry,
            ],
        )
    };
    let h = 1e-3;
    let (lm, l0, lp) = (at(-h), at(0.0), at(h));
    let g = -(lp - lm) / (2.0 * h);
    let l2 = (lp - 2.0 * l0 + lm) / (h * h);
    let layout = Layout::new(p).expect("layout");
    let l_belt = layout.body_length * p.belt.n_bodies as f64;
    let c = &p.contact;
    let wraps: f64 = layout
        .wraps
        .iter()
        .map(|w| {
            let r = p.pulleys[w.pulley].radius;
            w.angle / (r * (c.c2 + 2.0 * c.c1 * w.penetration))
        })
        .sum();
    let k_belt = 1.0 / (l_belt / p.belt.ea + wraps);
    let t = p.belt.preload;
    println!(
        "closed form: g {g:.5} m, L'' {l2:.5} m, K {k_belt:.4e} N/m (wraps {:.1} % of the \
         compliance), k {}, K g^2 {:.2}, T L'' {:.2} N m/rad",
        100.0 * wraps / (l_belt / p.belt.ea + wraps),
        arm.stiffness,
        k_belt * g * g,
        t * l2
    );
    arm.stiffness + k_belt * g * g + t * l2
}
