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
use crate::model::params::{self, PulleyParams, MAX_PULLEYS, PROBE_AUTO};
use crate::{Drive, DriveParams, Inputs};
use variables::{Start, Var, VarInfo, MODEL_DESCRIPTION, VARIABLES};

/// Integer parameters as the user set them; checked against the ranges of
/// the model description when the drive is built, so the message can name
/// the variable and its range.
#[derive(Clone, Debug, Default, PartialEq)]
struct IntegerParams {
    n_pulleys: i32,
    n_bodies: i32,
    friction_law: i32,
    zone_start: i32,
    zone_bodies: i32,
    probe_body: i32,
    method: i32,
    max_steps: i32,
    contact_points: i32,
}

#[derive(Clone, Debug)]
/// The FMU's model: parameters and inputs as set through FMI, and the drive built from them.
pub struct BeltDrive {
    /// Every parameter; `params.pulleys` always holds all six slots.
    params: DriveParams,
    ints: IntegerParams,
    inputs: Inputs,
    start_time: f64,
    drive: Option<Drive>,
    outputs: Option<Outputs>,
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

/// The scalar variable `var` of the model description.
fn info(var: Var) -> &'static VarInfo {
    VARIABLES
        .iter()
        .find(|v| v.var == var)
        .expect("every Var is a variable of the table")
}

/// The field behind a Real parameter (every pulley slot, used or not).
fn real_slot<'a>(p: &'a mut DriveParams, v: &VarInfo) -> Option<&'a mut f64> {
    let j = v.index;
    Some(match v.var {
        Var::BeltPreload => &mut p.belt.preload,
        Var::BeltNaturalLength => &mut p.belt.natural_length,
        Var::BeltEA => &mut p.belt.ea,
        Var::BeltAxialDamping => &mut p.belt.axial_damping,
        Var::BeltShearDampingFactor => &mut p.belt.shear_damping_factor,
        Var::BeltBendingStiffness => &mut p.belt.bending_stiffness,
        Var::BeltBendingDamping => &mut p.belt.bending_damping,
        Var::BeltTransverseDamping => &mut p.belt.transverse_damping,
        Var::BeltMassPerLength => &mut p.belt.mass_per_length,
        Var::Gravity => &mut p.gravity,
        Var::ContactC1 => &mut p.contact.c1,
        Var::ContactC2 => &mut p.contact.c2,
        Var::ContactDamping => &mut p.contact.damping,
        Var::ContactPMax => &mut p.contact.p_max,
        Var::FrictionDv => &mut p.friction.dv,
        Var::FrictionCreepMax => &mut p.friction.creep_max,
        Var::FrictionCreepDampingTime => &mut p.friction.creep_damping_time,
        Var::FrictionZoneFactor => &mut p.friction.zone_factor,
        Var::SolverRelTol => &mut p.solver.rel_tol,
        Var::SolverAbsTol => &mut p.solver.abs_tol,
        Var::SolverInitialStep => &mut p.solver.initial_step,
        Var::PulleyX => &mut p.pulleys[j].x,
        Var::PulleyY => &mut p.pulleys[j].y,
        Var::PulleyRadius => &mut p.pulleys[j].radius,
        Var::PulleyInertia => &mut p.pulleys[j].inertia,
        Var::PulleyMuStatic => &mut p.pulleys[j].mu_static,
        Var::PulleyMuKinetic => &mut p.pulleys[j].mu_kinetic,
        Var::PulleyLoadDamping => &mut p.pulleys[j].load_damping,
        Var::PulleyTorqueRamp => &mut p.pulleys[j].torque_ramp,
        Var::PulleyOmegaRamp => &mut p.pulleys[j].omega_ramp,
        Var::PulleyRampTime => &mut p.pulleys[j].ramp_time,
        Var::PulleyGrooveAngle => &mut p.pulleys[j].groove_angle,
        Var::PulleyDecouplerStiffness => &mut p.pulleys[j].decoupler_stiffness,
        Var::PulleyDecouplerDamping => &mut p.pulleys[j].decoupler_damping,
        Var::PulleyRotorInertia => &mut p.pulleys[j].rotor_inertia,
        Var::PulleyArmPivotX => &mut p.pulleys[j].arm_pivot[0],
        Var::PulleyArmPivotY => &mut p.pulleys[j].arm_pivot[1],
        Var::PulleyArmInertia => &mut p.pulleys[j].arm_inertia,
        Var::PulleyArmStiffness => &mut p.pulleys[j].arm_stiffness,
        Var::PulleyArmDamping => &mut p.pulleys[j].arm_damping,
        Var::PulleyArmFriction => &mut p.pulleys[j].arm_friction,
        _ => return None,
    })
}

/// The field behind an Integer parameter.
fn int_slot<'a>(i: &'a mut IntegerParams, v: &VarInfo) -> Option<&'a mut i32> {
    Some(match v.var {
        Var::NPulleys => &mut i.n_pulleys,
        Var::BeltNBodies => &mut i.n_bodies,
        Var::FrictionLaw => &mut i.friction_law,
        Var::FrictionZoneStart => &mut i.zone_start,
        Var::FrictionZoneBodies => &mut i.zone_bodies,
        Var::ProbeBody => &mut i.probe_body,
        Var::SolverMethod => &mut i.method,
        Var::SolverMaxSteps => &mut i.max_steps,
        Var::ContactPoints => &mut i.contact_points,
        _ => return None,
    })
}

impl BeltDrive {
    /// The physics parameters: the integer ones decoded, all of them
    /// checked by the core (`DriveParams::validate`); public for tests that
    /// compare parameter sets with `DriveParams`.
    pub fn drive_params(&self) -> Result<DriveParams, String> {
        let i = &self.ints;
        let mut p = self.params.clone();
        // The Integer parameters are converted by the core, which checks
        // their declared ranges: the counts (`nPulleys`, `belt.nBodies`,
        // `friction.zoneBodies`, `solver.maxSteps`, `contact.points`) by
        // `params::count` (a count outside its range cannot become a list of
        // pulley slots or a negative size), the body numbers
        // (`friction.zoneStart`, `probe.body`, 0 = chosen automatically) by
        // `params::body_number`. The adapter decodes only the FMI codes
        // (`friction.law`, `solver.method`), with the codes listed once
        // (the registry, `modelDescription/src/registry/table.rs`) and explained by the variable's description.
        // The Real parameters go to the core as they are:
        // `DriveParams::validate` checks their declared ranges (the same
        // table, `Param::declared`), for FMU and library users alike.
        let core = |e| names::render_error(&e);
        let count = |p, n: i32| params::count(p, n.into()).map_err(core);
        let body = |p, n: i32| params::body_number(p, n.into()).map_err(core);
        let used = count(Param::PulleyCount, i.n_pulleys)?;
        let n_bodies = count(Param::BeltBodies, i.n_bodies)?;
        let zone_bodies = count(Param::FrictionZoneBodies, i.zone_bodies)?;
        let max_steps = count(Param::SolverMaxSteps, i.max_steps)?;
        let contact_points = count(Param::ContactPoints, i.contact_points)?;
        // The unused pulley slots keep their declared ranges too (importers
        // are shown them for every slot).
        for (j, q) in p.pulleys.iter().enumerate().skip(used) {
            q.validate_ranges(j).map_err(core)?;
        }
        p.pulleys.truncate(used);
        p.belt.n_bodies = n_bodies;
        p.friction.law = names::friction_law(i.friction_law)
            .ok_or_else(|| no_code(Var::FrictionLaw, i.friction_law))?;
        p.friction.zone_start = body(Param::FrictionZoneStart, i.zone_start)?;
        p.friction.zone_bodies = zone_bodies;
        p.probe_body = body(Param::ProbeBody, i.probe_body)?;
        p.solver.method =
            names::method(i.method).ok_or_else(|| no_code(Var::SolverMethod, i.method))?;
        p.solver.max_steps = max_steps as u64;
        p.contact.points = contact_points;
        p.validate().map_err(|e| names::render_error(&e))?;
        Ok(p)
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

    fn outputs(&mut self) -> Result<&Outputs, String> {
        if self.outputs.is_none() {
            let out = self.ensure_drive()?.outputs();
            self.outputs = Some(out);
        }
        Ok(self.outputs.as_ref().expect("computed above"))
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

    fn real_param(&mut self, v: &VarInfo) -> Option<&mut f64> {
        real_slot(&mut self.params, v)
    }

    fn int_param(&mut self, v: &VarInfo) -> Option<&mut i32> {
        int_slot(&mut self.ints, v)
    }

    fn bool_param(&mut self, v: &VarInfo) -> Option<&mut bool> {
        let p = &mut self.params.pulleys[v.index.min(MAX_PULLEYS - 1)];
        Some(match v.var {
            Var::PulleySpeedDriven => &mut p.speed_driven,
            Var::PulleyBackSide => &mut p.back_side,
            Var::PulleyDecoupler => &mut p.decoupler,
            Var::PulleyDecouplerClockwise => &mut p.decoupler_clockwise,
            Var::PulleyTensioner => &mut p.tensioner,
            _ => return None,
        })
    }

    fn output(&mut self, v: &VarInfo) -> Result<f64, String> {
        let j = v.index;
        if matches!(v.var, Var::BeltLength) {
            let d = self.ensure_drive()?;
            // The continuum's natural length for the installation tension.
            return crate::model::layout::natural_length(d.params())
                .map_err(|e| names::render_error(&e));
        }
        if matches!(v.var, Var::BeltInstalledTension) {
            // The drive's preload: with belt.naturalLength, the one solved for.
            return Ok(self.ensure_drive()?.params().belt.preload);
        }
        if let Some(stats) = self.stats_output(v) {
            return Ok(stats);
        }
        let o = self.outputs()?;
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
        // the core's defaults are the model description's start values
        // (generated from it), in every pulley slot
        let params = DriveParams {
            pulleys: (0..MAX_PULLEYS).map(PulleyParams::start).collect(),
            ..DriveParams::default()
        };
        let mut model = Self {
            params,
            ints: IntegerParams::default(),
            inputs: Inputs::default(),
            start_time: 0.0,
            drive: None,
            outputs: None,
        };
        // The Integer parameters' start values as the adapter holds them
        // (codes, 1-based indices), and the rest once more from the same
        // table (the Real and Boolean ones are already the core's defaults,
        // `start_values_are_the_core_defaults`).
        for v in VARIABLES {
            let _ = match v.start {
                Start::Real(x) => model.set_real(v, x),
                Start::Integer(x) => model.set_integer(v, x),
                Start::Boolean(x) => model.set_boolean(v, x),
                _ => Ok(()),
            };
        }
        model.invalidate();
        model
    }

    fn get_real(&mut self, v: &VarInfo) -> Result<f64, String> {
        if let Some(x) = self.real_param(v) {
            return Ok(*x);
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
            _ => {
                let slot = self
                    .real_param(v)
                    .ok_or_else(|| format!("{} cannot be set", v.name))?;
                *slot = value;
                self.invalidate();
                Ok(())
            }
        }
    }

    fn get_integer(&mut self, v: &VarInfo) -> Result<i32, String> {
        self.int_param(v)
            .map(|x| *x)
            .ok_or_else(|| format!("{} is not an Integer variable", v.name))
    }

    fn set_integer(&mut self, v: &VarInfo, value: i32) -> Result<(), String> {
        let slot = self
            .int_param(v)
            .ok_or_else(|| format!("{} is not an Integer parameter", v.name))?;
        *slot = value;
        self.invalidate();
        Ok(())
    }

    fn get_boolean(&mut self, v: &VarInfo) -> Result<bool, String> {
        self.bool_param(v)
            .map(|x| *x)
            .ok_or_else(|| format!("{} is not a Boolean variable", v.name))
    }

    fn set_boolean(&mut self, v: &VarInfo, value: bool) -> Result<(), String> {
        let slot = self
            .bool_param(v)
            .ok_or_else(|| format!("{} is not a Boolean parameter", v.name))?;
        *slot = value;
        self.invalidate();
        Ok(())
    }

    fn setup_experiment(&mut self, tolerance: Option<f64>, start_time: f64) {
        if let Some(tol) = tolerance {
            self.params.solver.rel_tol = tol;
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
        let p = self.outputs()?.pulleys[v.index.min(MAX_PULLEYS - 1)];
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
    use super::variables::{by_name, Causality, VarType};
    use super::*;
    use crate::model::params::MAX_BODIES;

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
            assert_eq!(m.params.pulleys[j], PulleyParams::start(j), "slot {j}");
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
            (Var::NPulleys, 7, "nPulleys must be in 2..=6 (got 7)"),
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
