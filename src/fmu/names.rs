//! The core's parameter ids, pulleys and integrator choices spelt as the
//! FMU's variables, from the table generated from the model description
//! (so the XML stays the one source of the names), and the FMI codes of
//! the enumerated Integer parameters.

use super::variables::{Var, VARIABLES};
use crate::belt::param_id::{Message, Param, Spelling};
use crate::belt::params::{FrictionLaw, Method};
use crate::belt::stepping::StepFailure;
use crate::belt::ParamError;

/// The variable behind a parameter id, and its array index.
fn var_of(p: Param) -> (Var, usize) {
    use Param::*;
    match p {
        PulleyCount => (Var::NPulleys, 0),
        BeltBodies => (Var::BeltNBodies, 0),
        BeltPreload => (Var::BeltPreload, 0),
        BeltEa => (Var::BeltEA, 0),
        BeltAxialDamping => (Var::BeltAxialDamping, 0),
        BeltBendingStiffness => (Var::BeltBendingStiffness, 0),
        BeltBendingDamping => (Var::BeltBendingDamping, 0),
        BeltMassPerLength => (Var::BeltMassPerLength, 0),
        ContactC1 => (Var::ContactC1, 0),
        ContactC2 => (Var::ContactC2, 0),
        ContactDamping => (Var::ContactDamping, 0),
        ContactPMax => (Var::ContactPMax, 0),
        FrictionLaw => (Var::FrictionLaw, 0),
        FrictionDv => (Var::FrictionDv, 0),
        FrictionCreepMax => (Var::FrictionCreepMax, 0),
        FrictionCreepDampingTime => (Var::FrictionCreepDampingTime, 0),
        FrictionZoneFactor => (Var::FrictionZoneFactor, 0),
        FrictionZoneStart => (Var::FrictionZoneStart, 0),
        FrictionZoneBodies => (Var::FrictionZoneBodies, 0),
        Gravity => (Var::Gravity, 0),
        ProbeBody => (Var::ProbeBody, 0),
        SolverMethod => (Var::SolverMethod, 0),
        SolverRelTol => (Var::SolverRelTol, 0),
        SolverAbsTol => (Var::SolverAbsTol, 0),
        SolverInitialStep => (Var::SolverInitialStep, 0),
        SolverMaxSteps => (Var::SolverMaxSteps, 0),
        PulleyX(j) => (Var::PulleyX, j),
        PulleyY(j) => (Var::PulleyY, j),
        PulleyRadius(j) => (Var::PulleyRadius, j),
        PulleyInertia(j) => (Var::PulleyInertia, j),
        PulleyMuStatic(j) => (Var::PulleyMuStatic, j),
        PulleyMuKinetic(j) => (Var::PulleyMuKinetic, j),
        PulleyLoadDamping(j) => (Var::PulleyLoadDamping, j),
        PulleyTorqueRamp(j) => (Var::PulleyTorqueRamp, j),
        PulleyOmegaRamp(j) => (Var::PulleyOmegaRamp, j),
        PulleyRampTime(j) => (Var::PulleyRampTime, j),
        PulleyGrooveAngle(j) => (Var::PulleyGrooveAngle, j),
        PulleyBackSide(j) => (Var::PulleyBackSide, j),
        PulleyDecoupler(j) => (Var::PulleyDecoupler, j),
        PulleyDecouplerStiffness(j) => (Var::PulleyDecouplerStiffness, j),
        PulleyDecouplerDamping(j) => (Var::PulleyDecouplerDamping, j),
        PulleyRotorInertia(j) => (Var::PulleyRotorInertia, j),
        PulleyTensioner(j) => (Var::PulleyTensioner, j),
        PulleyArmPivotX(j) => (Var::PulleyArmPivotX, j),
        PulleyArmPivotY(j) => (Var::PulleyArmPivotY, j),
        PulleyArmInertia(j) => (Var::PulleyArmInertia, j),
        PulleyArmStiffness(j) => (Var::PulleyArmStiffness, j),
        PulleyArmDamping(j) => (Var::PulleyArmDamping, j),
        PulleyArmFriction(j) => (Var::PulleyArmFriction, j),
    }
}

/// The variable name of a parameter id, e.g. `pulley[2].radius` for
/// `Param::PulleyRadius(1)` (the core's own name if the table lacks it).
pub fn param_name(p: Param) -> String {
    let (var, index) = var_of(p);
    VARIABLES
        .iter()
        .find(|v| v.var == var && v.index == index)
        .map_or_else(|| p.to_string(), |v| v.name.to_owned())
}

/// The FMI spelling of a core message.
pub struct FmiNames;

impl Spelling for FmiNames {
    fn param(&self, p: Param) -> String {
        param_name(p)
    }
    /// `pulley[j]`: the array part of the pulley's variables' names.
    fn pulley(&self, j: usize) -> String {
        let x = param_name(Param::PulleyX(j));
        x.strip_suffix(".x").map_or(x.clone(), str::to_owned)
    }
}

/// A core message as the FMU shows it.
pub fn render(m: &Message) -> String {
    m.render(&FmiNames)
}

/// A core parameter error as the FMU shows it: `name: message`.
pub fn render_error(e: &ParamError) -> String {
    format!("{}: {}", param_name(e.parameter), render(&e.message))
}

/// A failed step as the FMU reports it: the core's text and the parameter
/// that bounds the work, if any, e.g. `... after 300 steps (solver.maxSteps)`.
pub fn render_step_failure(e: &StepFailure) -> String {
    match e.parameter() {
        Some(p) => format!("{e} ({})", param_name(p)),
        None => e.to_string(),
    }
}

/// The friction law of `friction.law`'s code.
pub fn friction_law(code: i32) -> Option<FrictionLaw> {
    match code {
        1 => Some(FrictionLaw::Kubas2014),
        2 => Some(FrictionLaw::Creep),
        _ => None,
    }
}

/// The integrator of `solver.method`'s code.
pub fn method(code: i32) -> Option<Method> {
    match code {
        1 => Some(Method::Rkf45),
        2 => Some(Method::Rosenbrock),
        _ => None,
    }
}

/// `solver.method`'s code of an integrator.
pub fn method_code(m: Method) -> i32 {
    match m {
        Method::Rkf45 => 1,
        Method::Rosenbrock => 2,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::belt::{Drive, DriveParams};

    /// Every parameter id names a variable of the table (none falls back to
    /// the core's spelling), and the codes round-trip.
    #[test]
    fn every_id_is_a_variable() {
        use Param::*;
        let mut ids = vec![
            PulleyCount,
            BeltBodies,
            BeltPreload,
            BeltEa,
            BeltAxialDamping,
            BeltBendingStiffness,
            BeltBendingDamping,
            BeltMassPerLength,
            ContactC1,
            ContactC2,
            ContactDamping,
            ContactPMax,
            FrictionLaw,
            FrictionDv,
            FrictionCreepMax,
            FrictionCreepDampingTime,
            FrictionZoneFactor,
            FrictionZoneStart,
            FrictionZoneBodies,
            Gravity,
            ProbeBody,
            SolverMethod,
            SolverRelTol,
            SolverAbsTol,
            SolverInitialStep,
            SolverMaxSteps,
        ];
        for j in 0..crate::belt::params::MAX_PULLEYS {
            ids.extend([
                PulleyX(j),
                PulleyY(j),
                PulleyRadius(j),
                PulleyInertia(j),
                PulleyMuStatic(j),
                PulleyMuKinetic(j),
                PulleyLoadDamping(j),
                PulleyTorqueRamp(j),
                PulleyOmegaRamp(j),
                PulleyRampTime(j),
                PulleyGrooveAngle(j),
                PulleyBackSide(j),
                PulleyDecoupler(j),
                PulleyDecouplerStiffness(j),
                PulleyDecouplerDamping(j),
                PulleyRotorInertia(j),
                PulleyTensioner(j),
                PulleyArmPivotX(j),
                PulleyArmPivotY(j),
                PulleyArmInertia(j),
                PulleyArmStiffness(j),
                PulleyArmDamping(j),
                PulleyArmFriction(j),
            ]);
        }
        for p in ids {
            let (var, index) = var_of(p);
            assert!(
                VARIABLES.iter().any(|v| v.var == var && v.index == index),
                "{p:?}"
            );
        }
        assert_eq!(param_name(PulleyRadius(1)), "pulley[2].radius");
        assert_eq!(FmiNames.pulley(2), "pulley[3]");
        for m in [Method::Rkf45, Method::Rosenbrock] {
            assert_eq!(method(method_code(m)), Some(m));
        }
        assert_eq!(method(3), None);
        assert_eq!(friction_law(0), None);
    }

    /// The paper's drives as built in and the default drive warn about
    /// nothing; a radially undamped contact is flagged with the parameter
    /// that causes it.
    #[test]
    fn warnings_name_the_cause() {
        let warnings = |p: &DriveParams| {
            Drive::mounted(p, 0.0)
                .expect("valid drive")
                .warnings()
                .iter()
                .map(render)
                .collect::<Vec<_>>()
        };
        for p in [DriveParams::kubas_section4(), DriveParams::kubas_section3()] {
            let w = warnings(&p);
            assert!(w.is_empty(), "{w:?}");
        }
        // the 5PK drive's ramp at 30 x the penetration: pMax is named, and
        // the advice is the automatic ramp
        let mut p = DriveParams::kubas_section4();
        p.contact.p_max = 5e-3;
        let w = warnings(&p);
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(w[0].starts_with("contact.pMax = 5e-3 m") && w[0].contains("pulley[1]"));
        assert!(w[0].contains("set contact.pMax to 0 (automatic"), "{w:?}");
        // the automatic ramp (the FMU's default) damps every wrap of the
        // paper's drives and of a heavy belt with the paper's 5PK contact
        let mut p = DriveParams::default();
        assert_eq!(p.contact.p_max, 0.0);
        assert!(warnings(&p).is_empty());
        p.belt.mass_per_length = 0.8;
        p.belt.ea = 7600.0;
        assert!(warnings(&p).is_empty());
        // full ramp but a tiny damping coefficient: contact.damping is named
        let mut p = DriveParams::kubas_section4();
        p.contact.p_max = 1e-5;
        p.contact.damping *= 1e-3;
        let w = warnings(&p);
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(w[1].starts_with("contact.damping = ") && w[1].contains("pulley[2]"));
        // no damping at all is the user's explicit choice
        p.contact.damping = 0.0;
        assert!(warnings(&p).is_empty());
        // no tolerance warning: the stiff method degrades gracefully
        // (tests/defaults.rs)
        let mut p = DriveParams::default();
        p.solver.method = Method::Rosenbrock;
        p.solver.rel_tol = 1e-3;
        assert!(warnings(&p).is_empty());
    }
}
