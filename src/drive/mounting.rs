//! Mounting a drive: the equilibrium relaxation, the tensioner arms' free
//! angles, the automatic probe body and the warnings about parameter
//! choices that run badly.

use crate::model::elements::contact::{smoothstep, AUTO_P_MAX_PER_PENETRATION};
use crate::model::layout::Layout;
use crate::model::param_id::{msg, Message, Param, Part};
use crate::model::params::{DriveParams, MAX_PULLEYS};
use crate::model::state;
use crate::model::system::{BeltSystem, Recorder, Relaxation, Workspace};
use crate::solver::rkf45::Rkf45;

/// Settles the mounted belt into its frictionless static equilibrium with
/// the pulleys held: the layout gives every SDE the preload, but where a
/// span meets an arc the chord geometry cannot also balance the contact
/// forces exactly, and friction would lock that error in. A short damped
/// relaxation (mass-proportional damping near critical for the contact mode,
/// friction off) removes it; the belt then starts at rest with zero creep.
/// `max_steps` bounds the work in total (the solver's step-count guard, at
/// most `RELAX_MAX_STEPS`); a relaxation cut short leaves the belt as far as
/// it got.
pub(super) fn relax_into_equilibrium(
    sys: &BeltSystem,
    ws: &mut Workspace,
    y: &mut [f64],
    max_steps: u64,
) {
    // Contact mode of one body: stiffness dN/dp at the typical penetration.
    let k_contact = sys.contact.stiffness(MOUNTING.penetration);
    // Friction off, the pulleys (and a decoupler's rotor, a tensioner's
    // arm) held at rest.
    let relax = sys.with_relaxation(Relaxation {
        damping: 2.0 * (k_contact / sys.mass).sqrt(),
        frictionless: true,
        pulleys_held: true,
    });
    // Relax over a few axial diffusion times of the damped belt, at least
    // ten contact periods; stop early once everything is at rest.
    const CHUNKS: u64 = MOUNTING.chunks;
    let per_chunk = (max_steps.min(RELAX_MAX_STEPS) / CHUNKS).max(1);
    let mut rk = Rkf45::new(
        y.len(),
        MOUNTING.rel_tol,
        MOUNTING.abs_tol,
        MOUNTING.initial_step,
        per_chunk,
    );
    let mut t = 0.0;
    let period = std::f64::consts::TAU / (k_contact / relax.mass).sqrt();
    let chunk = 2.0 * period;
    for _ in 0..CHUNKS {
        let target = t + chunk;
        if rk.advance(&relax, ws, &mut t, y, target).is_err() {
            break;
        }
        let v_max = state::bodies(y, relax.n)
            .map(|b| b.velocity()[0].abs().max(b.velocity()[1].abs()))
            .fold(0.0, f64::max);
        if t >= MOUNTING.min_periods * period && v_max < MOUNTING.rest_speed {
            break;
        }
    }
    for i in 0..relax.n {
        let mut b = state::body_mut(y, i);
        b.set_velocity([0.0, 0.0]);
        b.set_spin(0.0);
        b.set_creep(0.0);
    }
    let states = relax.state_layout;
    let e = states.energy();
    y[e.work_in] = 0.0;
    y[e.dissipated] = 0.0;
    y[relax.controlled_dim()..].fill(0.0);
    for (j, p) in relax.pulleys[..relax.np].iter().enumerate() {
        if p.decoupler.is_some() {
            let d = states.decoupler(j);
            y[d.twist] = 0.0;
            y[d.rotor_speed] = 0.0;
        }
        if p.arm.is_some() {
            let a = states.arm(j);
            y[a.angle] = 0.0;
            y[a.rate] = 0.0;
        }
    }
}

/// Collects the belt's force on every pulley's hub.
struct HubRecorder([[f64; 2]; MAX_PULLEYS]);

impl Recorder for HubRecorder {
    const ACTIVE: bool = true;
    fn hub_force(&mut self, pulley: usize, fx: f64, fy: f64) {
        self.0[pulley][0] += fx;
        self.0[pulley][1] += fy;
    }
}

/// Mounting of the tensioner arms: with the belt at rest in its static
/// equilibrium (`y`, arms at their mounted positions), each arm's spring
/// gets the free angle at which its torque balances the moment of the
/// belt's hub force about the pivot, `-k (0 - alpha_free) + M_hub = 0`
/// (`elements::tensioner::Arm::free_angle_for`); the pivot friction's
/// deflection starts at zero (it carries nothing at mounting).
pub(super) fn mount_arms(sys: &mut BeltSystem, ws: &mut Workspace, t: f64, y: &[f64]) {
    if sys.state_layout.n_arms() == 0 {
        return;
    }
    let mut rec = HubRecorder([[0.0; 2]; MAX_PULLEYS]);
    let mut dy = vec![0.0; y.len()];
    sys.rhs(ws, t, y, &mut dy, &mut rec);
    let states = sys.state_layout;
    for (j, pc) in sys.pulleys[..sys.np].iter_mut().enumerate() {
        if let Some(arm) = pc.arm.as_mut() {
            let moment = arm.moment(y[states.arm(j).angle], rec.0[j]).0;
            arm.free_angle = arm.free_angle_for(moment);
        }
    }
}

/// Step-count guard of the equilibrium relaxation.
const RELAX_MAX_STEPS: u64 = MOUNTING.max_steps;

/// The probe body [`PROBE_AUTO`] stands for: the body whose centre lies
/// nearest the middle of the free span from pulley 1 to pulley 2 in the
/// mounted belt. It starts free, in a span with a defined tension, so its
/// forces (Figs. 15-18) show a whole passage: span, pulley 2, the next span,
/// ...; and it exists for any body count.
pub(super) fn auto_probe(layout: &Layout) -> usize {
    let Some(span) = layout.span_between(0, 1) else {
        return 0;
    };
    let m = span.midpoint();
    let d = |b: &crate::model::layout::BodyPose| (b.x - m[0]).hypot(b.y - m[1]);
    (0..layout.bodies.len())
        .min_by(|&a, &b| d(&layout.bodies[a]).total_cmp(&d(&layout.bodies[b])))
        .unwrap_or(0)
}

/// Damping ratio of the radial contact mode at the equilibrium penetration
/// below which a wrap counts as undamped: the belt then rattles on the
/// pulley after a shock and loses traction (docs/model.md, "Contact"; the
/// paper's 5PK drive has 0.26, its section-3 drive as printed 6e-5).
const WEAK_CONTACT_DAMPING: f64 = MOUNTING.weak_contact_damping;

/// Mass per length above which a belt is taken for a unit slip and warned
/// about [kg/m]: drive belts weigh about 0.01 (small flat and round belts)
/// to 2 kg/m (wide banded V-belts); a belt's g/m typed as kg/m lands at
/// 10 to 2000. Heavier belts (conveyors) still run, with the warning.
const HEAVIEST_BELT: f64 = 5.0;

/// Parameter choices that are valid but make the drive behave badly, one
/// message each, naming the parameter and the value to use instead.
pub(super) fn warnings(params: &DriveParams, layout: &Layout, sys: &BeltSystem) -> Vec<Message> {
    let mut out = Vec::new();
    let mu = params.belt.mass_per_length;
    if mu > HEAVIEST_BELT {
        out.push(msg![
            Param::BeltMassPerLength,
            format!(
                " = {mu} kg/m is more than the {HEAVIEST_BELT} kg/m of the heaviest drive belts \
                 (flat, V, V-ribbed and synchronous belts weigh about 0.01 to 2 kg/m); it is in \
                 kg/m: if {mu} was meant in g/m, set {}",
                mu * 1e-3
            ),
        ]);
    }
    let c = &sys.contact;
    if c.b <= 0.0 {
        out.extend(super::mesh_check::warnings(params, layout));
        return out;
    }
    let mut wraps: Vec<_> = layout.wraps.iter().collect();
    wraps.sort_by_key(|w| w.pulley);
    for w in wraps {
        let p0 = w.penetration;
        let inv_p_max = sys.pulleys[w.pulley].inv_p_max;
        let share = smoothstep(p0 * inv_p_max);
        let zeta = c.damping_ratio(p0, sys.mass, inv_p_max);
        if zeta >= WEAK_CONTACT_DAMPING {
            continue;
        }
        if share >= 0.5 {
            out.push(msg![
                Param::ContactDamping,
                format!(
                    " = {:e} N s/m2 damps the belt's bounce on ",
                    params.contact.damping
                ),
                Part::Pulley(w.pulley),
                format!(
                    " with a damping ratio of only {zeta:.1e}, so the belt can rattle on the \
                     pulley and lose traction; a ratio of 0.1 needs "
                ),
                Param::ContactDamping,
                format!(
                    " of about {:.1e} N s/m2",
                    params.contact.damping * 0.1 / zeta
                ),
            ]);
        } else {
            // only a user's contact.pMax can be this long: the automatic
            // one puts the full damping at the penetration
            let p_max = params.contact.p_max;
            out.push(msg![
                Param::ContactPMax,
                format!(
                    " = {p_max:e} m is {:.0} times the equilibrium penetration {p0:.2e} m on ",
                    p_max / p0
                ),
                Part::Pulley(w.pulley),
                format!(": the contact damping acts there with {share:.1e} of "),
                Param::ContactDamping,
                format!(
                    " (damping ratio {zeta:.1e}), so the belt can rattle on the pulley and lose \
                     traction; set "
                ),
                Param::ContactPMax,
                format!(
                    " to 0 (automatic: {AUTO_P_MAX_PER_PENETRATION} x each pulley's penetration, \
                     here {:.1e} m)",
                    AUTO_P_MAX_PER_PENETRATION * p0
                ),
            ]);
        }
    }
    out.extend(super::mesh_check::warnings(params, layout));
    out
}

/// The mounting's knobs, each with its value and why: the relaxation of the
/// mounted belt into equilibrium (its own RKF45 run, not the drive's
/// solver settings) and the contact-damping warning.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct MountingKnobs {
    /// The relaxation of the mounted belt into equilibrium (before t0, with
    /// friction off and mass-proportional damping near critical for the
    /// contact mode) runs RKF45 at this relative tolerance...
    pub(crate) rel_tol: f64,
    /// ... this absolute tolerance [m, m/s] ...
    pub(crate) abs_tol: f64,
    /// ... from this first step [s] ...
    pub(crate) initial_step: f64,
    /// ... in this many chunks of two contact periods each ...
    pub(crate) chunks: u64,
    /// ... for at least this many contact periods, and stops once every body
    /// moves slower than `rest_speed` [m/s].
    pub(crate) min_periods: f64,
    /// See `min_periods`.
    pub(crate) rest_speed: f64,
    /// Penetration [m] at which the relaxation takes the contact stiffness
    /// dN/dp for its damping (a typical equilibrium penetration).
    pub(crate) penetration: f64,
    /// Step-count guard of the relaxation in total.
    pub(crate) max_steps: u64,
    /// Damping ratio of the radial contact mode below which a wrap counts as
    /// undamped and a warning names the contact damping (the belt rattles on
    /// the pulley after a shock; the paper's 5PK drive has 0.26).
    pub(crate) weak_contact_damping: f64,
}

/// The values in use.
pub(crate) const MOUNTING: MountingKnobs = MountingKnobs {
    rel_tol: 1e-5,
    abs_tol: 1e-9,
    initial_step: 1e-7,
    chunks: 20,
    min_periods: 10.0,
    rest_speed: 1e-5,
    penetration: 2e-4,
    max_steps: 5_000_000,
    weak_contact_damping: 0.02,
};
