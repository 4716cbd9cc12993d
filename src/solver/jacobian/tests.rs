//! The Jacobian against finite differences of the right-hand side, and
//! its builds against each other.

use super::*;
use crate::drive::Drive;
use crate::model::params::{
    ArmStops, DecouplerParams, DriveParams, FrictionLaw, PulleyParams, TensionerArm,
};
use crate::model::state::{body_component, BodyComponent, BodyIndex};
use crate::model::system::{NoRecord, Workspace};

/// A small two-pulley drive (r = 50 and 45 mm) with 36 bodies at 120 N
/// and the automatic contact damping ramp, which differs between the
/// pulleys (p_max = 12.9 and 14.1 um, half their penetrations).
fn drive(law: FrictionLaw, speed_driven: bool) -> Drive {
    let mut p = DriveParams::default();
    p.belt.n_bodies = 36;
    p.belt.preload = 120.0;
    p.friction.law = law;
    p.friction.dv = 1e-2;
    p.probe_body = 0;
    let mut p1 = PulleyParams::paper_5pk(0.0, 0.0);
    p1.radius = 0.05;
    let mut p2 = p1.clone();
    p2.radius = 0.045;
    p2.x = 0.25;
    p2.load_damping = 0.3;
    p.pulleys = vec![p1, p2];
    if speed_driven {
        p.pulleys[0].speed_driven = true;
        p.pulleys[0].omega_ramp = -20.0;
        p.pulleys[0].ramp_time = 0.01;
        p.pulleys[0].torque_ramp = 0.0;
    }
    Drive::mounted(&p, 0.0).unwrap()
}

/// Compares the analytic Jacobian with central differences of the
/// right-hand side, column by column (the dissipated-energy row excluded:
/// the W-method leaves it out; the input-energy and impulse rows
/// included). Returns the number of
/// columns checked.
fn check(sys: &BeltSystem, t: f64, y: &[f64]) -> usize {
    check_rows(sys, t, y, None)
}

/// [`check`], with row `partial.0` compared in the columns `partial.1`
/// only: a row whose Jacobian leaves out some partials by design.
fn check_rows(sys: &BeltSystem, t: f64, y: &[f64], partial: Option<(usize, &[usize])>) -> usize {
    let dim = sys.dim();
    let mut jac = Jacobian::new(sys);
    sys.jacobian(t, y, &mut jac);
    let dense = jac.to_dense(sys);
    let e_rows = sys.state_layout.energy().work_in;
    // every state but the dissipated-energy accumulator
    let states: Vec<usize> = (0..=e_rows).chain(e_rows + 2..dim).collect();
    let (mut a, mut b) = (vec![0.0; dim], vec![0.0; dim]);
    let mut ws = Workspace::new();
    let mut yp = y.to_vec();
    let mut checked = 0;
    // a body's velocity: its column is held to the row's largest
    // velocity entry, not the row's largest (a spring's), so that the
    // dampers' partials (~1e-6 of the springs') are checked too
    let bodies = sys.state_layout.bodies_len();
    let component = |cc: usize| (cc < bodies).then(|| body_component(cc).1);
    let velocity = |cc: usize| {
        matches!(
            component(cc),
            Some(BodyComponent::Vx | BodyComponent::Vy | BodyComponent::Spin)
        )
    };
    for &c in &states {
        // relative steps: positions ~0.1 m, z ~1e-5 m; the bodies'
        // velocities ~1 m/s (spins ~30 rad/s) by 1e-6 of at least 1 (the
        // right-hand side is smooth in them at this scale: a step well
        // inside the friction law's dv = 1e-2 m/s; smaller steps lose
        // digits to rounding in the spin rows, I ~ 1e-7 kg m^2)
        let scale = if component(c) == Some(BodyComponent::Creep) {
            1e-11
        } else if velocity(c) {
            1e-6 * y[c].abs().max(1.0)
        } else {
            1e-8 * y[c].abs().max(1e-2)
        };
        yp[c] = y[c] + scale;
        sys.rhs(&mut ws, t, &yp, &mut a, &mut NoRecord);
        yp[c] = y[c] - scale;
        sys.rhs(&mut ws, t, &yp, &mut b, &mut NoRecord);
        yp[c] = y[c];
        for &r in &states {
            if partial.is_some_and(|(row, cols)| row == r && !cols.contains(&c)) {
                continue;
            }
            let fd = (a[r] - b[r]) / (2.0 * scale);
            let an = dense[r * dim + c];
            // tolerance relative to the row's largest entry (finite
            // differences lose digits on the small ones); in a velocity
            // column, the row's largest velocity entry
            let row_max = states
                .iter()
                .filter(|&&cc| !velocity(c) || velocity(cc))
                .map(|&cc| dense[r * dim + cc].abs())
                .fold(0.0, f64::max);
            assert!(
                (fd - an).abs() <= 1e-5 * row_max + 1e-6 * an.abs().max(fd.abs()),
                "d f[{r}] / d y[{c}]: analytic {an:e}, differences {fd:e} (row max {row_max:e})"
            );
        }
        checked += 1;
    }
    checked
}

/// Perturbs a mounted drive into a generic running state: velocities,
/// spins, creep at various levels, pulley speeds.
fn running_state(d: &Drive, creep: &[f64]) -> Vec<f64> {
    let sys = d.system();
    let mut y = d.state().to_vec();
    for i in 0..sys.n {
        let o = BodyIndex::of(i);
        let s = (i as f64 * 0.7).sin();
        y[o.x] += 1e-5 * s;
        y[o.y] -= 2e-5 * (i as f64 * 1.3).cos();
        y[o.angle] += 0.01 * s;
        y[o.vx] = 0.9 * s;
        y[o.vy] = -0.4 * (i as f64).cos();
        y[o.spin] = 30.0 * s;
        y[o.creep] = creep[i % creep.len()];
    }
    for j in 0..sys.np {
        y[sys.state_layout.pulley(j).speed] = -18.0 - j as f64;
    }
    // every third body in contact nearly sticks: v_T a fraction of dv
    for i in (0..sys.n).step_by(3) {
        let o = BodyIndex::of(i);
        for j in 0..sys.np {
            let pc = &sys.pulleys[j];
            let r = Vector2::new(y[o.x] - pc.cx, y[o.y] - pc.cy);
            if r.norm_squared() < pc.radius2 {
                let nrm = r.normalize();
                let tau = perp(nrm);
                let w = sys.pulley_speed(j, 0.02, &y);
                let v = (w * pc.lever - 3e-3) * tau + 0.01 * nrm;
                y[o.vx] = v.x;
                y[o.vy] = v.y;
            }
        }
    }
    y
}

#[test]
fn jacobian_matches_finite_differences_for_every_force_law() {
    // just beyond the cap, so that differences do not straddle it
    let cap_creep = 1.5e-4 * (1.0 + 1e-6);
    // the SDE's damper across the gap as along it (the default, 1) and
    // along the gap only (the paper's, 0)
    for (law, shear) in [
        (FrictionLaw::Creep, 0.0),
        (FrictionLaw::Creep, 1.0),
        (FrictionLaw::Kubas2014, 1.0),
        (FrictionLaw::Kubas2014, 0.0),
    ] {
        for speed_driven in [false, true] {
            let mut p = drive(law, speed_driven).params().clone();
            p.belt.shear_damping_factor = shear;
            let d = Drive::mounted(&p, 0.0).unwrap();
            assert_eq!(d.system().axial.bt, shear * d.system().axial.b);
            assert_eq!(d.system().friction.creep_max, 1e-4);
            // each pulley its own automatic ramp, half its penetration
            let sys = d.system();
            for j in 0..2 {
                let p0 = d.layout().wrap_of(j).unwrap().penetration;
                assert_eq!(sys.pulleys[j].inv_p_max, 1.0 / (0.5 * p0));
            }
            assert_ne!(sys.pulleys[0].inv_p_max, sys.pulleys[1].inv_p_max);
            // creep in the elastic range, in the softening range, at the
            // cap (sliding), and zero (stick at v_T ~ 0 for kubas2014)
            let y = running_state(&d, &[0.0, 3e-5, -7e-5, 1.2e-4, -1.3e-4, cap_creep]);
            // one body per pulley onto the middle of its pulley's ramp
            let mut y = y;
            for (j, pc) in sys.pulleys[..2].iter().enumerate() {
                let i = (0..sys.n)
                    .find(|&i| {
                        let o = BodyIndex::of(i);
                        let r = Vector2::new(y[o.x] - pc.cx, y[o.y] - pc.cy);
                        r.norm_squared() < pc.radius2
                    })
                    .unwrap_or_else(|| panic!("a body on pulley {j}"));
                let o = BodyIndex::of(i);
                let r = Vector2::new(y[o.x] - pc.cx, y[o.y] - pc.cy);
                let on_ramp =
                    Vector2::new(pc.cx, pc.cy) + r.normalize() * (pc.radius - 0.5 / pc.inv_p_max);
                y[o.x] = on_ramp.x;
                y[o.y] = on_ramp.y;
            }
            let cols = check(d.system(), 0.02, &y);
            assert_eq!(cols, d.system().dim() - 1);
        }
    }
}

/// The contact along the body (`contact.points` 2, 3 and 5): the body's
/// angle and spin columns and its moment row, the creep rate of the
/// weighted sliding velocity, both friction laws, on a torque-driven
/// and a speed-driven pulley, and on a tensioner arm's pulley.
#[test]
fn jacobian_covers_the_contact_along_the_body() {
    for (points, law, speed_driven, arm) in [
        (3, FrictionLaw::Creep, false, false),
        (3, FrictionLaw::Kubas2014, false, false),
        (3, FrictionLaw::Creep, true, false),
        (2, FrictionLaw::Creep, false, false),
        (5, FrictionLaw::Kubas2014, true, false),
        (3, FrictionLaw::Creep, false, true),
    ] {
        let mut p = drive(law, speed_driven).params().clone();
        p.contact.points = points;
        if arm {
            p.pulleys[1].arm = Some(TensionerArm {
                pivot: [0.3, 0.06],
                inertia: 2e-3,
                stiffness: 40.0,
                damping: 0.05,
                ..Default::default()
            });
        }
        let d = Drive::mounted(&p, 0.0).unwrap();
        let sys = d.system();
        assert_eq!(sys.points, points);
        let mut y = running_state(&d, &[0.0, 3e-5, -7e-5, 1.2e-4, -1.3e-4]);
        if arm {
            let o = sys.state_layout.arm(1);
            y[o.angle] = 2e-4;
            y[o.rate] = -0.3;
        }
        let mut jac = Jacobian::new(sys);
        sys.jacobian(0.02, &y, &mut jac);
        // the contact moment couples the angles of bodies on the wraps
        let touching = jac.bodies.iter().filter(|b| b.touching != 0).count();
        assert!(touching > 0);
        assert!(
            jac.bodies
                .iter()
                .any(|b| b.accel_by_position[SELF][(2, 0)] != 0.0),
            "moment row"
        );
        assert!(
            jac.impulse
                .iter()
                .any(|b| b[0].hub_by_position[(0, 2)] != 0.0),
            "angle column"
        );
        let cols = check(sys, 0.02, &y);
        assert_eq!(cols, sys.dim() - 1);
    }
}

/// The decoupler's rows and columns, on a torque-driven and on a
/// speed-driven hub, with the clutch engaged, in its band and
/// overrunning; the rest of the Jacobian stays right around it.
#[test]
fn jacobian_covers_the_decoupler() {
    for speed_driven in [false, true] {
        let mut p = drive(FrictionLaw::Creep, speed_driven).params().clone();
        // hub 1 (speed-driven in the second case) and hub 2 (torque-driven)
        for (j, cw) in [(0, true), (1, false)] {
            p.pulleys[j].decoupler = Some(DecouplerParams {
                clockwise: cw,
                ..Default::default()
            });
            p.pulleys[j].load_damping = 0.3;
        }
        let d = Drive::mounted(&p, 0.0).unwrap();
        let sys = d.system();
        assert_eq!(sys.n_decouplers(), 2);
        let base = running_state(&d, &[0.0, 3e-5, -7e-5]);
        // hub speeds are -18 and -19 rad/s (running_state), or the
        // prescription -20 rad/s; u = k twist + d w with k = 30, d = 0.02
        for (twist, w_r) in [(0.1, -17.0), (1e-4, -18.0), (0.02, -40.0), (-0.01, 5.0)] {
            let mut y = base.clone();
            for j in 0..2 {
                let o = sys.state_layout.decoupler(j);
                y[o.twist] = twist * (1.0 + 0.1 * j as f64);
                y[o.rotor_speed] = w_r;
            }
            let cols = check(sys, 0.02, &y);
            assert_eq!(cols, sys.dim() - 1);
        }
    }
}

/// The tensioner arm's rows and columns (its own spring, damper, pivot
/// friction holding and sliding, the hub force's lever,
/// every contact on the moving pulley and the pulley's friction torque),
/// on a torque-driven and on a speed-driven tensioner pulley, with a
/// decoupler on the other pulley; the rest of the Jacobian stays right
/// around it.
#[test]
fn jacobian_covers_the_tensioner_arm() {
    // end stops at -5e-5 and 1e-4 rad: the states below press the lower
    // (-1e-4, in the stop's damping ramp) and the upper stop
    let stops = ArmStops {
        min_angle: -5e-5,
        max_angle: 1e-4,
        ..ArmStops::default()
    };
    // hub-load friction (coefficient 0.3 at 20 mm) with and beside the
    // constant pivot friction: its torque scale mu_h r_f |F_hub| moves with
    // every state the hub force depends on (the bodies on the pulley, the
    // arm, the pulley's speed)
    for (law, speed_driven, stops, hub_friction) in [
        (FrictionLaw::Creep, false, None, 0.0),
        (FrictionLaw::Kubas2014, false, None, 0.0),
        (FrictionLaw::Creep, true, None, 0.0),
        (FrictionLaw::Creep, false, Some(stops), 0.0),
        (FrictionLaw::Kubas2014, true, Some(stops), 0.0),
        (FrictionLaw::Creep, false, None, 0.3),
        (FrictionLaw::Kubas2014, true, Some(stops), 0.3),
    ] {
        let mut p = drive(law, false).params().clone();
        // the arm carries pulley 2 (0.25, 0) from a pivot 80 mm above
        // and behind it
        p.pulleys[1].arm = Some(TensionerArm {
            pivot: [0.3, 0.06],
            inertia: 2e-3,
            stiffness: 40.0,
            damping: 0.05,
            friction: 1.5,
            hub_friction,
            friction_radius: 0.02,
            stops,
            ..Default::default()
        });
        p.pulleys[1].speed_driven = speed_driven;
        p.pulleys[0].decoupler = Some(DecouplerParams::default());
        let d = Drive::mounted(&p, 0.0).unwrap();
        let sys = d.system();
        assert_eq!(sys.state_layout.n_arms(), 1);
        let base = running_state(&d, &[0.0, 3e-5, -7e-5]);
        // (angle, rate, deflection over the presliding angle): the pivot
        // friction holding and sliding, the centre moving both ways
        let phi_p = sys.pulleys()[1].arm.as_ref().unwrap().presliding_angle;
        for (angle, rate, z) in [(2e-4, 0.004, 0.3), (-1e-4, -0.3, -0.9), (3e-4, 2.0, 0.99)] {
            let mut y = base.clone();
            let o = sys.state_layout.arm(1);
            y[o.angle] = angle;
            y[o.rate] = rate;
            y[o.deflection] = z * phi_p;
            // the deflection's rate depends on the hub force through the
            // hub-load friction, and the hub force on the arm's angle and
            // rate and the bodies; the Jacobian leaves that out
            // (`elements::tensioner::PivotFriction`), so with hub-load
            // friction its row is checked in the deflection's column only
            let own = [o.deflection];
            let partial = (hub_friction > 0.0).then_some((o.deflection, &own[..]));
            let cols = check_rows(sys, 0.02, &y, partial);
            assert_eq!(cols, sys.dim() - 1);
            // the arm's row is really coupled to the bodies
            let mut jac = Jacobian::new(sys);
            sys.jacobian(0.02, &y, &mut jac);
            assert!(jac
                .arm_bodies
                .iter()
                .any(|b| b.arm_accel_by_position[1].norm() > 0.0));
        }
    }
}

/// Evaluated again at a state where bodies have left pulleys and others
/// have landed, the Jacobian equals one evaluated afresh (an evaluation
/// clears only the pulley entries of the pulleys each body touched at the
/// last one), with the contact at the centre and along the body, on a
/// pulley on an arm.
#[test]
fn a_reevaluated_jacobian_equals_a_fresh_one() {
    for points in [1, 4] {
        let mut p = drive(FrictionLaw::Creep, false).params().clone();
        p.contact.points = points;
        p.pulleys[1].arm = Some(TensionerArm {
            pivot: [0.3, 0.06],
            inertia: 2e-3,
            stiffness: 40.0,
            ..Default::default()
        });
        let d = Drive::mounted(&p, 0.0).unwrap();
        let sys = d.system();
        let before = running_state(&d, &[0.0, 3e-5, -7e-5]);
        // the belt moved 8 mm to the right: bodies leave the left pulley's
        // wrap and sink deeper into the right one's
        let mut after = before.clone();
        for i in 0..sys.n {
            after[BodyIndex::of(i).x] += 8e-3;
        }
        let mut again = Jacobian::new(sys);
        sys.jacobian(0.02, &before, &mut again);
        let touched_before: Vec<u8> = again.bodies.iter().map(|b| b.touching).collect();
        sys.jacobian(0.02, &after, &mut again);
        let mut fresh = Jacobian::new(sys);
        sys.jacobian(0.02, &after, &mut fresh);
        let changed = touched_before
            .iter()
            .zip(&fresh.bodies)
            .filter(|(&t, b)| t != 0 && b.touching != t)
            .count();
        assert!(changed > 0, "{points} points: no body left a pulley");
        let (mut va, mut vb) = (Vec::new(), Vec::new());
        again.save(&mut va);
        fresh.save(&mut vb);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&va), bits(&vb), "{points} points");
        assert_eq!(again, fresh, "{points} points");
    }
}

/// The AVX2 build computes the same numbers to the last bit (it has no
/// FMA), so results do not depend on the CPU the FMU runs on.
#[test]
fn avx2_build_matches_baseline_to_the_bit() {
    if !Isa::Avx2.available() {
        return;
    }
    for law in [FrictionLaw::Creep, FrictionLaw::Kubas2014] {
        let d = drive(law, false);
        let sys = d.system();
        let y = running_state(&d, &[0.0, 3e-5, -7e-5, 1.2e-4]);
        let (mut a, mut b) = (Jacobian::new(sys), Jacobian::new(sys));
        sys.jacobian_with(Isa::Baseline, 0.02, &y, &mut a);
        sys.jacobian_with(Isa::Avx2, 0.02, &y, &mut b);
        let (mut va, mut vb) = (Vec::new(), Vec::new());
        a.save(&mut va);
        b.save(&mut vb);
        assert!(va.iter().any(|&v| v != 0.0));
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&va), bits(&vb), "{law:?}");
    }
}
