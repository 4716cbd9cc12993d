//! The FMU's model: the adapter between the FMI plumbing and the belt
//! physics, the only module that knows both worlds.
//!
//! * [`variables`]: the variable table generated from
//!   `modelDescription/modelDescription.xml` (names, value references,
//!   start values, ranges);
//! * this module: [`BeltDrive`], the [`FmuModel`] the FMU exports: variables
//!   onto [`DriveParams`], [`Inputs`] and [`Outputs`], defaults and ranges
//!   from the table;
//! * `snapshot`: the model's part of a serialized FMU state.

pub mod names;
mod snapshot;
pub mod variables;

use crate::drive::Outputs;
use crate::fmi::{FmuModel, ModelDescription, StepError};
use crate::model::param_id::Param;
use crate::model::params::{self, MAX_PULLEYS, PROBE_AUTO};
use crate::{Drive, DriveParams, Inputs};
use std::collections::HashMap;
use variables::{Causality, Var, VarInfo, VarType, MODEL_DESCRIPTION, VARIABLES};

/// "n" before a type name that starts with a vowel.
fn article(ty: VarType) -> &'static str {
    match ty {
        VarType::Integer => "n Integer",
        VarType::Real => " Real",
        VarType::Boolean => " Boolean",
        _ => " String",
    }
}

#[derive(Clone, Debug)]
/// The FMU's model: parameters and inputs as set through FMI, and the drive built from them.
pub struct BeltDrive {
    /// Every parameter's value as set, by the core's id (an Integer as a
    /// number, a Boolean 0 or 1), in every pulley slot: the core reads them
    /// when the drive is built (`DriveParams::from_values`), each element
    /// its own.
    values: HashMap<Param, f64>,
    inputs: Inputs,
    start_time: f64,
    drive: Option<Drive>,
    /// The outputs at the drive's time, evaluated when first read; true
    /// once those that take a pass over the belt are in
    /// ([`Drive::add_evaluated_outputs`]), so that a master reading speeds,
    /// angles and means pays for no force evaluation.
    outputs: Option<(Outputs, bool)>,
}

/// The refusal of a coded Integer parameter whose value is no code: its
/// name, the value and its description, which lists the codes (the build
/// checks that every code is listed there).
fn no_code(var: Var, code: i32) -> String {
    let v = info(var);
    format!(
        "{} must be one of its codes (got {code}): {}",
        v.name, v.description
    )
}

/// Whether output `var` takes a pass over the belt
/// ([`Drive::add_evaluated_outputs`]: forces, energies, mid-span
/// deflections, the belt's smallest tension over the interval); the means do only over an empty window, where they are the
/// instantaneous values.
fn needs_evaluation(var: Var, window_empty: bool) -> bool {
    match var {
        Var::PulleyOmega
        | Var::PulleyAngle
        | Var::PulleySlip
        | Var::PulleyWrapAngle
        | Var::PulleyRotorOmega
        | Var::PulleyArmAngle
        | Var::PulleyArmOmega
        | Var::PulleyArmSpringTorque
        | Var::PulleyArmFreeAngle
        | Var::SpanSlip
        | Var::SpanMeanTension
        | Var::SpanMinTension
        | Var::SpanMaxTension
        | Var::PulleyArmMeanSpringTorque
        | Var::ProbeX
        | Var::ProbeY
        | Var::EnergyInput => false,
        Var::PulleyMeanBeltTorque
        | Var::PulleyMeanDriveTorque
        | Var::PulleyMeanHubForceX
        | Var::PulleyMeanHubForceY
        | Var::PulleyMeanAlpha => window_empty,
        _ => true,
    }
}

/// The scalar variable `var` of the model description.
fn info(var: Var) -> &'static VarInfo {
    VARIABLES
        .iter()
        .find(|v| v.var == var)
        .expect("every Var is a variable of the table")
}

/// The parameter id behind a variable, if it is a parameter.
fn param(v: &VarInfo) -> Option<Param> {
    names::param_of(v.var, v.index)
}

impl BeltDrive {
    /// The physics parameters: the integer ones decoded, all of them
    /// checked by the core (`DriveParams::validate`); public for tests that
    /// compare parameter sets with `DriveParams`.
    pub fn drive_params(&self) -> Result<DriveParams, String> {
        // The Integer parameters are converted by the core, which checks
        // their declared ranges: the counts (`nPulleys`, `belt.nBodies`,
        // `friction.zoneBodies`, `solver.maxSteps`, `contact.points`) by
        // `params::count` (a count outside its range cannot become a list of
        // pulley slots or a negative size), the body numbers
        // (`friction.zoneStart`, `probe.body`, 0 = chosen automatically) by
        // `params::body_number`. The adapter decodes only the FMI codes
        // (`friction.law`, `solver.method`), with the codes listed once
        // (the registry, `modelDescription/src/registry/table.rs`) and
        // explained by the variable's description. The Real and Boolean
        // parameters go to the core as they are (`DriveParams::from_values`):
        // `DriveParams::validate` checks their declared ranges (the same
        // table, `Param::declared`), for FMU and library users alike.
        let v = |p: Param| self.value(p);
        let int = |p: Param| v(p) as i32;
        let core = |e| names::render_error(&e);
        let count = |p| params::count(p, int(p).into()).map_err(core);
        let body = |p| params::body_number(p, int(p).into()).map_err(core);
        let used = count(Param::PulleyCount)?;
        let n_bodies = count(Param::BeltBodies)?;
        let zone_bodies = count(Param::FrictionZoneBodies)?;
        let max_steps = count(Param::SolverMaxSteps)?;
        let contact_points = count(Param::ContactPoints)?;
        let mut p = DriveParams::from_values(&v, used);
        p.belt.n_bodies = n_bodies;
        let law = int(Param::FrictionLaw);
        p.friction.law = names::friction_law(law).ok_or_else(|| no_code(Var::FrictionLaw, law))?;
        p.friction.zone_start = body(Param::FrictionZoneStart)?;
        p.friction.zone_bodies = zone_bodies;
        p.probe_body = body(Param::ProbeBody)?;
        let method = int(Param::SolverMethod);
        p.solver.method =
            names::method(method).ok_or_else(|| no_code(Var::SolverMethod, method))?;
        p.solver.max_steps = max_steps as u64;
        p.contact.points = contact_points;
        // Every Real parameter keeps its declared range in every slot, used
        // or not, and whether its hardware (decoupler, arm, stops) is set or
        // not: importers are shown the ranges of them all. Checked before
        // the rules that tie parameters together, so a value outside its
        // range is named with the range (tests/fuzz_params.rs).
        for var in VARIABLES
            .iter()
            .filter(|x| x.causality == Causality::Parameter && x.ty == VarType::Real)
        {
            if let Some(q) = param(var) {
                params::declared(q, v(q)).map_err(core)?;
            }
        }
        p.validate().map_err(core)?;
        Ok(p)
    }

    /// A parameter's value as set (its start value until then).
    fn value(&self, p: Param) -> f64 {
        self.values.get(&p).copied().unwrap_or_else(|| p.start())
    }

    /// Sets the parameter behind `v`, if it is one of type `ty`.
    fn set_param(&mut self, v: &VarInfo, ty: VarType, value: f64) -> Result<(), String> {
        match param(v) {
            Some(p) if v.ty == ty => {
                self.values.insert(p, value);
                self.invalidate();
                Ok(())
            }
            _ => Err(format!("{} is not a{} parameter", v.name, article(ty))),
        }
    }

    /// The parameter behind `v`, if it is one of type `ty`.
    fn get_param(&self, v: &VarInfo, ty: VarType) -> Result<f64, String> {
        match param(v) {
            Some(p) if v.ty == ty => Ok(self.value(p)),
            _ => Err(format!("{} is not a{} variable", v.name, article(ty))),
        }
    }

    fn ensure_drive(&mut self) -> Result<&mut Drive, String> {
        if self.drive.is_none() {
            let params = self.drive_params()?;
            let mut drive =
                Drive::new(&params, self.start_time).map_err(|e| names::render_error(&e))?;
            drive.set_inputs(self.inputs);
            self.drive = Some(drive);
            self.outputs = None;
        }
        Ok(self.drive.as_mut().expect("built above"))
    }

    /// The outputs, with those that take a pass over the belt if `evaluated`.
    fn outputs(&mut self, evaluated: bool) -> Result<&Outputs, String> {
        self.ensure_drive()?;
        let drive = self.drive.as_mut().expect("built above");
        match &mut self.outputs {
            Some((_, true)) => {}
            Some((_, false)) if !evaluated => {}
            Some((out, have)) => {
                drive.add_evaluated_outputs(out);
                *have = true;
            }
            None => {
                let mut out = drive.state_outputs();
                if evaluated {
                    drive.add_evaluated_outputs(&mut out);
                }
                self.outputs = Some((out, evaluated));
            }
        }
        Ok(&self.outputs.as_ref().expect("evaluated above").0)
    }

    /// A parameter changed: the drive must be rebuilt.
    fn invalidate(&mut self) {
        self.drive = None;
        self.outputs = None;
    }

    fn inputs_changed(&mut self) {
        if let Some(d) = self.drive.as_mut() {
            d.set_inputs(self.inputs);
        }
        self.outputs = None;
    }

    fn output(&mut self, v: &VarInfo) -> Result<f64, String> {
        let j = v.index;
        if matches!(v.var, Var::BeltLength) {
            let d = self.ensure_drive()?;
            // The continuum's natural length for the installation tension.
            return crate::model::layout::natural_length(d.params())
                .map_err(|e| names::render_error(&e));
        }
        if matches!(v.var, Var::PulleyArmInstalledAngle) {
            // Where the mounting turned the arm from its drawing (with its
            // spring given by arm.nominalTorque).
            let drawn = self.drive_params()?;
            let d = self.ensure_drive()?;
            return Ok(crate::model::layout::installed_arm_angle(
                &drawn,
                d.params(),
                j,
            ));
        }
        if matches!(v.var, Var::BeltInstalledTension) {
            // The drive's preload: with belt.naturalLength, the one solved for.
            return Ok(self.ensure_drive()?.params().belt.preload);
        }
        if let Some(stats) = self.stats_output(v) {
            return Ok(stats);
        }
        let window_empty = self.ensure_drive()?.window_empty();
        let o = self.outputs(needs_evaluation(v.var, window_empty))?;
        let p = &o.pulleys[j.min(MAX_PULLEYS - 1)];
        Ok(match v.var {
            Var::PulleyOmega => p.omega,
            Var::PulleyAngle => p.angle,
            Var::PulleyAlpha => p.alpha,
            Var::PulleyBeltTorque => p.belt_torque,
            Var::PulleyDriveTorque => p.drive_torque,
            Var::PulleyHubForceX => p.hub_force[0],
            Var::PulleyHubForceY => p.hub_force[1],
            Var::PulleyMeanBeltTorque => p.mean_belt_torque,
            Var::PulleyMeanDriveTorque => p.mean_drive_torque,
            Var::PulleyMeanHubForceX => p.mean_hub_force[0],
            Var::PulleyMeanHubForceY => p.mean_hub_force[1],
            Var::PulleyMeanAlpha => p.mean_alpha,
            Var::PulleySlip => p.slip,
            Var::PulleyWrapAngle => p.wrap_angle,
            Var::PulleyRotorOmega => p.rotor_omega,
            Var::PulleyDecouplerTorque => p.decoupler_torque,
            Var::PulleyArmAngle => p.arm_angle,
            Var::PulleyArmOmega => p.arm_omega,
            Var::PulleyArmSpringTorque => p.arm_spring_torque,
            Var::PulleyArmFreeAngle => p.arm_free_angle,
            Var::ProbeNormalForce => o.probe.normal_force[j],
            Var::ProbeFrictionForce => o.probe.friction_force[j],
            Var::ProbeSlipVelocity => o.probe.slip_velocity[j],
            Var::SpanTension => o.span_tension[j],
            Var::SpanSlip => o.span_slip[j],
            Var::SpanMidDeflection => o.span_mid_deflection[j],
            Var::SpanMidDeflectionRate => o.span_mid_deflection_rate[j],
            Var::BeltMinTension => o.min_tension,
            Var::SpanMeanTension => o.interval.span_mean_tension[j],
            Var::SpanMinTension => o.interval.span_min_tension[j],
            Var::SpanMaxTension => o.interval.span_max_tension[j],
            Var::BeltIntervalMinTension => o.interval.belt_min_tension,
            Var::PulleyArmMeanSpringTorque => o.interval.arm_mean_spring_torque[j],
            Var::BeltMaxTension => o.max_tension,
            Var::ProbeSdeForce => o.probe.sde_force,
            Var::ProbeX => o.probe.position[0],
            Var::ProbeY => o.probe.position[1],
            Var::PowerDissipated => o.power_dissipated,
            Var::BeltPowerLoss => o.belt_power_loss,
            Var::EnergyDissipated => o.energy_dissipated,
            Var::EnergyInput => o.energy_input,
            Var::EnergyKinetic => o.kinetic_energy,
            Var::EnergyPotential => o.potential_energy,
            _ => return Err(format!("{} is not a Real output", v.name)),
        })
    }

    fn stats_output(&self, v: &VarInfo) -> Option<f64> {
        let s = self.drive.as_ref().map(|d| d.stats()).unwrap_or_default();
        Some(match v.var {
            Var::SolverSteps => s.steps as f64,
            Var::SolverRejectedSteps => s.rejected as f64,
            Var::SolverRhsEvaluations => s.rhs_evals as f64,
            Var::SolverLastStepSize => s.last_step,
            _ => return None,
        })
    }
}

impl FmuModel for BeltDrive {
    type Var = Var;

    const STATE_MAGIC: [u8; 8] = *b"BELTFMU\0";

    fn description() -> &'static ModelDescription<Var> {
        &MODEL_DESCRIPTION
    }

    fn new() -> Self {
        // the model description's start values (generated from it), in
        // every pulley slot; the core's defaults are the same
        Self {
            values: Param::all(MAX_PULLEYS).map(|p| (p, p.start())).collect(),
            inputs: Inputs::default(),
            start_time: 0.0,
            drive: None,
            outputs: None,
        }
    }

    fn get_real(&mut self, v: &VarInfo) -> Result<f64, String> {
        if let Some(p) = param(v) {
            return Ok(self.value(p));
        }
        match v.var {
            Var::PulleyTorque => Ok(self.inputs.torque[v.index]),
            Var::PulleyOmegaRef => Ok(self.inputs.omega_ref[v.index]),
            _ => self.output(v),
        }
    }

    fn set_real(&mut self, v: &VarInfo, value: f64) -> Result<(), String> {
        match v.var {
            Var::PulleyTorque | Var::PulleyOmegaRef => {
                if !value.is_finite() {
                    return Err(format!("{} must be finite (got {value})", v.name));
                }
                if v.var == Var::PulleyTorque {
                    self.inputs.torque[v.index] = value;
                } else {
                    self.inputs.omega_ref[v.index] = value;
                }
                self.inputs_changed();
                Ok(())
            }
            _ => self
                .set_param(v, VarType::Real, value)
                .map_err(|_| format!("{} cannot be set", v.name)),
        }
    }

    fn get_integer(&mut self, v: &VarInfo) -> Result<i32, String> {
        self.get_param(v, VarType::Integer).map(|x| x as i32)
    }

    fn set_integer(&mut self, v: &VarInfo, value: i32) -> Result<(), String> {
        self.set_param(v, VarType::Integer, value.into())
    }

    fn get_boolean(&mut self, v: &VarInfo) -> Result<bool, String> {
        self.get_param(v, VarType::Boolean).map(|x| x != 0.0)
    }

    fn set_boolean(&mut self, v: &VarInfo, value: bool) -> Result<(), String> {
        self.set_param(v, VarType::Boolean, f64::from(u8::from(value)))
    }

    fn setup_experiment(&mut self, tolerance: Option<f64>, start_time: f64) {
        if let Some(tol) = tolerance {
            self.values.insert(Param::SolverRelTol, tol);
        }
        self.start_time = start_time;
        self.invalidate();
    }

    fn initialize(&mut self) -> Result<Vec<String>, String> {
        self.ensure_drive()
            .map(|d| d.warnings().iter().map(names::render).collect())
    }

    fn notes(&self) -> Vec<String> {
        match &self.drive {
            Some(d) if d.params().probe_body == PROBE_AUTO => vec![format!(
                "probe.body = 0: the probe outputs report body {}, the one nearest the middle \
                 of the free span from pulley[1] to pulley[2] in the mounted belt",
                d.probe_body() + 1
            )],
            _ => Vec::new(),
        }
    }

    fn do_step(&mut self, t: f64, h: f64) -> Result<(), StepError> {
        self.outputs = None;
        let drive = self.ensure_drive().map_err(StepError::Error)?;
        if (drive.time() - t).abs() > 1e-9 * t.abs().max(1.0) {
            return Err(StepError::Error(format!(
                "communication point {t} s does not match the model time {} s",
                drive.time()
            )));
        }
        drive.advance(t + h).map_err(|e| {
            StepError::Discard(format!(
                "step from t = {t} s to {} s not completed: {}; the state stays at t = {t} s",
                t + h,
                names::render_step_failure(&e)
            ))
        })?;
        // Input derivatives hold for one communication step: the inputs end
        // the step at their ramped values and are held from there.
        for j in 0..MAX_PULLEYS {
            self.inputs.torque[j] += self.inputs.torque_rate[j] * h;
            self.inputs.omega_ref[j] += self.inputs.omega_ref_rate[j] * h;
        }
        self.inputs.torque_rate = [0.0; MAX_PULLEYS];
        self.inputs.omega_ref_rate = [0.0; MAX_PULLEYS];
        self.inputs_changed();
        Ok(())
    }

    fn set_input_derivative(&mut self, v: &VarInfo, order: i32, value: f64) -> Result<(), String> {
        if order != 1 {
            return Err(format!(
                "{}: input derivative order must be 1 (got {order})",
                v.name
            ));
        }
        if !value.is_finite() {
            return Err(format!(
                "{}: derivative must be finite (got {value})",
                v.name
            ));
        }
        match v.var {
            Var::PulleyTorque => self.inputs.torque_rate[v.index] = value,
            Var::PulleyOmegaRef => self.inputs.omega_ref_rate[v.index] = value,
            _ => return Err(format!("{} is not an input", v.name)),
        }
        self.inputs_changed();
        Ok(())
    }

    fn get_output_derivative(&mut self, v: &VarInfo, order: i32) -> Result<f64, String> {
        if order != 1 {
            return Err(format!(
                "{}: output derivative order must be 1 (got {order})",
                v.name
            ));
        }
        let p = self.outputs(true)?.pulleys[v.index.min(MAX_PULLEYS - 1)];
        match v.var {
            Var::PulleyOmega => Ok(p.alpha),
            Var::PulleyAngle => Ok(p.omega),
            _ => Err(format!(
                "{}: output derivatives are provided for pulley[j].omega and pulley[j].angle",
                v.name
            )),
        }
    }

    fn serialize(&self, out: &mut Vec<u8>) {
        snapshot::write(self, out);
    }

    fn deserialize(bytes: &[u8]) -> Result<Self, String> {
        snapshot::read(bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::variables::{by_name, Start};
    use super::*;
    use crate::model::params::{PulleyParams, MAX_BODIES};

    /// The ranges the model description shows importers are the core's.
    #[test]
    fn declared_ranges_match_the_core() {
        let n = info(Var::NPulleys);
        assert_eq!((n.min, n.max), (Some(2.0), Some(MAX_PULLEYS as f64)));
        let b = info(Var::BeltNBodies);
        assert_eq!((b.min, b.max), (Some(3.0), Some(MAX_BODIES as f64)));
        assert_eq!(
            (info(Var::SolverMethod).min, info(Var::SolverMethod).max),
            (Some(1.0), Some(2.0))
        );
    }

    /// A fresh model holds every start value of the model description.
    #[test]
    fn start_values_are_the_defaults() {
        let mut m = BeltDrive::new();
        for v in VARIABLES {
            match v.start {
                Start::Real(x) => assert_eq!(m.get_real(v).unwrap(), x, "{}", v.name),
                Start::Integer(x) => assert_eq!(m.get_integer(v).unwrap(), x, "{}", v.name),
                Start::Boolean(x) => assert_eq!(m.get_boolean(v).unwrap(), x, "{}", v.name),
                _ => {}
            }
        }
    }

    /// The core's defaults are the model description's start values, in
    /// every pulley slot, but for the step guard of a library run (the one
    /// deliberate difference, `params::LIBRARY_MAX_STEPS`); and every start
    /// value is inside its declared range.
    #[test]
    fn start_values_are_the_core_defaults() {
        let m = BeltDrive::new();
        for j in 0..MAX_PULLEYS {
            let slot = PulleyParams::from_values(j, &|p: Param| m.value(p));
            assert_eq!(slot, PulleyParams::start(j), "slot {j}");
        }
        let mut expected = DriveParams::default();
        expected.solver.max_steps = 100_000;
        assert_ne!(params::LIBRARY_MAX_STEPS, 100_000);
        assert_eq!(m.drive_params().unwrap(), expected);
        assert_eq!(info(Var::SolverMaxSteps).start, Start::Integer(100_000));
        // the coded parameters decoded as the adapter decodes them
        let Start::Integer(law) = info(Var::FrictionLaw).start else {
            panic!("friction.law has an Integer start")
        };
        assert_eq!(names::friction_law(law), Some(params::START_FRICTION_LAW));
        let mut n = 0;
        for p in Param::all(MAX_PULLEYS) {
            let r = p.declared();
            assert!(
                r.contains(p.start()),
                "{p}: {} not {}",
                p.start(),
                r.describe()
            );
            n += 1;
        }
        assert!(n > 20 * MAX_PULLEYS, "{n} parameters");
        DriveParams::default()
            .validate()
            .expect("the default drive is valid");
    }

    #[test]
    fn integer_ranges_come_from_the_table() {
        // the refusal of one integer set alone on the default drive
        let refused = |var: Var, value: i32| {
            let mut m = BeltDrive::new();
            m.set_integer(info(var), value).unwrap();
            m.drive_params().unwrap_err()
        };
        for (var, value, message) in [
            (Var::NPulleys, 9, "nPulleys must be in 2..=8 (got 9)"),
            (
                Var::FrictionZoneBodies,
                -1,
                "friction.zoneBodies must be >= 0 (got -1)",
            ),
            (
                Var::ContactPoints,
                6,
                "contact.points must be in 1..=5 (got 6)",
            ),
            (
                Var::SolverMaxSteps,
                0,
                "solver.maxSteps must be >= 1 (got 0)",
            ),
            (
                Var::ProbeBody,
                151,
                "probe.body must be in 1..=150 or 0 (chosen automatically; got 151)",
            ),
            // the body numbers: 1-based, probe.body 0 the automatic choice
            (Var::ProbeBody, -1, "probe.body must be >= 0 (got -1)"),
            (
                Var::FrictionZoneStart,
                0,
                "friction.zoneStart must be >= 1 (got 0)",
            ),
        ] {
            assert_eq!(refused(var, value), message);
        }
        let mut m = BeltDrive::new();
        m.set_integer(info(Var::FrictionZoneStart), 150).unwrap();
        m.set_integer(info(Var::ProbeBody), 150).unwrap();
        let p = m.drive_params().unwrap();
        assert_eq!((p.friction.zone_start, p.probe_body), (149, 149));
        m.set_integer(info(Var::ProbeBody), 0).unwrap();
        assert_eq!(m.drive_params().unwrap().probe_body, PROBE_AUTO);
        // a code outside the list is refused with the codes' meanings, as
        // the model description states them
        let mut m = BeltDrive::new();
        m.set_integer(info(Var::FrictionLaw), 3).unwrap();
        assert_eq!(
            m.drive_params().unwrap_err(),
            format!(
                "friction.law must be one of its codes (got 3): {}",
                info(Var::FrictionLaw).description
            )
        );
        assert!(info(Var::FrictionLaw).description.contains("2 = creep"));
        let mut m = BeltDrive::new();
        m.set_integer(info(Var::SolverMethod), 0).unwrap();
        let e = m.drive_params().unwrap_err();
        assert!(
            e.starts_with("solver.method must be one of its codes (got 0): ")
                && e.contains("1 = RKF45")
                && e.contains("2 = Rosenbrock-W"),
            "{e}"
        );
    }

    /// Every declared bound of every parameter is enforced: a value just
    /// outside it is refused with the variable's name.
    #[test]
    fn every_declared_range_is_checked() {
        let bounded = VARIABLES
            .iter()
            .filter(|v| v.causality == Causality::Parameter)
            .filter(|v| v.min.is_some() || v.max.is_some());
        let mut n = 0;
        for v in bounded {
            for (bound, step) in [(v.min, -1.0), (v.max, 1.0)] {
                let Some(b) = bound else { continue };
                let outside = match v.ty {
                    VarType::Integer => b + step,
                    _ => b + step * b.abs().max(1.0) * 1e-6,
                };
                let mut m = BeltDrive::new();
                match v.ty {
                    VarType::Integer => m.set_integer(v, outside as i32).unwrap(),
                    _ => m.set_real(v, outside).unwrap(),
                }
                let e = m.drive_params().unwrap_err();
                assert!(e.starts_with(&format!("{} must be", v.name)), "{e}");
                n += 1;
            }
        }
        assert!(n >= 11, "{n} bounds checked");
        assert!(by_name("nPulleys").unwrap().max.is_some());
    }
}
