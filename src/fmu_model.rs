//! The adapter between the FMI plumbing and the belt physics: maps the
//! variables of `modelDescription/modelDescription.xml` (through the table
//! `build.rs` generates from it) onto [`DriveParams`], [`Inputs`] and
//! [`Outputs`]. The only file that knows both worlds.

use crate::belt::drive::Outputs;
use crate::belt::params::{FrictionLaw, Method, PulleyParams, MAX_PULLEYS};
use crate::belt::rkf45::Stats;
use crate::belt::{Drive, DriveParams, Inputs};
use crate::fmi::{FmuModel, ModelDescription, StepError};
use crate::variables::{Start, Var, VarInfo, VarType, MODEL_DESCRIPTION, VARIABLES};

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
}

#[derive(Clone, Debug)]
pub struct BeltDrive {
    /// Every parameter; `params.pulleys` always holds all six slots.
    params: DriveParams,
    ints: IntegerParams,
    inputs: Inputs,
    start_time: f64,
    drive: Option<Drive>,
    outputs: Option<Outputs>,
}

fn range_error(name: &str, allowed: &str, got: impl std::fmt::Display) -> String {
    format!("{name} must be {allowed} (got {got})")
}

/// The field behind a Real parameter (every pulley slot, used or not).
fn real_slot<'a>(p: &'a mut DriveParams, v: &VarInfo) -> Option<&'a mut f64> {
    let j = v.index;
    Some(match v.var {
        Var::BeltPreload => &mut p.belt.preload,
        Var::BeltEA => &mut p.belt.ea,
        Var::BeltAxialDamping => &mut p.belt.axial_damping,
        Var::BeltBendingStiffness => &mut p.belt.bending_stiffness,
        Var::BeltBendingDamping => &mut p.belt.bending_damping,
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
        _ => return None,
    })
}

impl BeltDrive {
    /// The physics parameters with the integer ones checked and applied
    /// (public for tests that compare parameter sets with `DriveParams`).
    pub fn drive_params(&self) -> Result<DriveParams, String> {
        let i = &self.ints;
        let mut p = self.params.clone();
        // Every min/max of the model description (the ranges importers are
        // shown), in XML order; for all pulley slots, used or not.
        let mut ints = i.clone();
        for v in VARIABLES
            .iter()
            .filter(|v| v.min.is_some() || v.max.is_some())
        {
            let x = match v.ty {
                VarType::Real => real_slot(&mut p, v).map(|x| *x),
                VarType::Integer => int_slot(&mut ints, v).map(|&mut x| f64::from(x)),
                _ => None,
            };
            if let Some(x) = x {
                v.check_range(x)?;
            }
        }
        p.pulleys.truncate(i.n_pulleys as usize);
        p.belt.n_bodies = i.n_bodies as usize;
        p.friction.law = FrictionLaw::from_code(i.friction_law).ok_or_else(|| {
            range_error("friction.law", "1 (kubas2014) or 2 (creep)", i.friction_law)
        })?;
        p.friction.zone_start = (i.zone_start - 1) as usize;
        p.friction.zone_bodies = i.zone_bodies as usize;
        if i.probe_body > i.n_bodies {
            return Err(range_error(
                "probe.body",
                &format!("in 1..={}", i.n_bodies),
                i.probe_body,
            ));
        }
        p.probe_body = (i.probe_body - 1) as usize;
        p.solver.method = Method::from_code(i.method).ok_or_else(|| {
            range_error(
                "solver.method",
                "1 (RKF45) or 2 (Rosenbrock-W, stiff)",
                i.method,
            )
        })?;
        p.solver.max_steps = i.max_steps as u64;
        Ok(p)
    }

    fn ensure_drive(&mut self) -> Result<&mut Drive, String> {
        if self.drive.is_none() {
            let params = self.drive_params()?;
            let mut drive = Drive::new(&params, self.start_time).map_err(|e| e.to_string())?;
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
            _ => return None,
        })
    }

    fn output(&mut self, v: &VarInfo) -> Result<f64, String> {
        let j = v.index;
        if matches!(v.var, Var::BeltLength) {
            let d = self.ensure_drive()?;
            return Ok(d.layout().body_length * d.params().belt.n_bodies as f64);
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
            Var::PulleySlip => p.slip,
            Var::PulleyWrapAngle => p.wrap_angle,
            Var::PulleyRotorOmega => p.rotor_omega,
            Var::PulleyDecouplerTorque => p.decoupler_torque,
            Var::ProbeNormalForce => o.probe.normal_force[j],
            Var::ProbeFrictionForce => o.probe.friction_force[j],
            Var::ProbeSlipVelocity => o.probe.slip_velocity[j],
            Var::SpanTension => o.span_tension[j],
            Var::SpanSlip => o.span_slip[j],
            Var::SpanMidDeflection => o.span_mid_deflection[j],
            Var::SpanMidDeflectionRate => o.span_mid_deflection_rate[j],
            Var::BeltMinTension => o.min_tension,
            Var::BeltMaxTension => o.max_tension,
            Var::ProbeSdeForce => o.probe.sde_force,
            Var::ProbeX => o.probe.position[0],
            Var::ProbeY => o.probe.position[1],
            Var::PowerDissipated => o.power_dissipated,
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
        let mut params = DriveParams::kubas_section4();
        params
            .pulleys
            .resize(MAX_PULLEYS, PulleyParams::paper_5pk(0.0, 0.0));
        let mut model = Self {
            params,
            ints: IntegerParams::default(),
            inputs: Inputs::default(),
            start_time: 0.0,
            drive: None,
            outputs: None,
        };
        // Start values come from the model description (single source of truth).
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
        self.ensure_drive().map(|d| d.warnings().to_vec())
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
                "step from t = {t} s to {} s not completed: {e}; the state stays at t = {t} s",
                t + h
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

/// Byte image of a [`BeltDrive`]: every parameter, the inputs and, once
/// built, time, state, step size and counters. The drive is rebuilt from the
/// parameters (deterministic) and its state replaced, so a restored model
/// continues bit-identically.
mod snapshot {
    use super::*;

    /// 2: integrator data (the stiff method's kept Jacobian) after the state.
    const VERSION: u32 = 2;

    struct Writer<'a>(&'a mut Vec<u8>);
    impl Writer<'_> {
        fn f64(&mut self, x: f64) {
            self.0.extend_from_slice(&x.to_le_bytes());
        }
        fn u64(&mut self, x: u64) {
            self.0.extend_from_slice(&x.to_le_bytes());
        }
        fn i32(&mut self, x: i32) {
            self.0.extend_from_slice(&x.to_le_bytes());
        }
        fn f64s(&mut self, xs: &[f64]) {
            self.u64(xs.len() as u64);
            xs.iter().for_each(|&x| self.f64(x));
        }
    }

    struct Reader<'a>(&'a [u8]);
    impl Reader<'_> {
        fn take<const N: usize>(&mut self) -> Result<[u8; N], String> {
            if self.0.len() < N {
                return Err("model state is truncated".into());
            }
            let (head, rest) = self.0.split_at(N);
            self.0 = rest;
            Ok(head.try_into().expect("length checked"))
        }
        fn f64(&mut self) -> Result<f64, String> {
            Ok(f64::from_le_bytes(self.take()?))
        }
        fn u64(&mut self) -> Result<u64, String> {
            Ok(u64::from_le_bytes(self.take()?))
        }
        fn i32(&mut self) -> Result<i32, String> {
            Ok(i32::from_le_bytes(self.take()?))
        }
        fn f64s(&mut self, expect: usize) -> Result<Vec<f64>, String> {
            let n = self.u64()?;
            if n != expect as u64 {
                return Err(format!(
                    "model state holds {n} values where {expect} belong"
                ));
            }
            (0..expect).map(|_| self.f64()).collect()
        }
        /// A length-prefixed list whose length is known only from the data:
        /// refused unless the bytes for it are there.
        fn f64s_any(&mut self) -> Result<Vec<f64>, String> {
            let n = self.u64()?;
            if n > (self.0.len() / 8) as u64 {
                return Err("model state is truncated".into());
            }
            (0..n).map(|_| self.f64()).collect()
        }
    }

    /// Every variable that is a parameter, in model-description order.
    fn parameters() -> impl Iterator<Item = &'static VarInfo> {
        VARIABLES
            .iter()
            .filter(|v| {
                matches!(
                    v.start,
                    Start::Real(_) | Start::Integer(_) | Start::Boolean(_)
                )
            })
            .filter(|v| !matches!(v.var, Var::PulleyTorque | Var::PulleyOmegaRef))
    }

    pub fn write(m: &BeltDrive, out: &mut Vec<u8>) {
        let mut w = Writer(out);
        w.0.extend_from_slice(&VERSION.to_le_bytes());
        let mut m2 = m.clone();
        for v in parameters() {
            match v.start {
                Start::Real(_) => w.f64(m2.get_real(v).unwrap_or(f64::NAN)),
                Start::Integer(_) => w.i32(m2.get_integer(v).unwrap_or(0)),
                Start::Boolean(_) => w.i32(m2.get_boolean(v).unwrap_or(false) as i32),
                _ => {}
            }
        }
        w.f64(m.start_time);
        let i = &m.inputs;
        for xs in [&i.torque, &i.torque_rate, &i.omega_ref, &i.omega_ref_rate] {
            w.f64s(xs);
        }
        match &m.drive {
            None => w.u64(0),
            Some(d) => {
                w.u64(1);
                w.f64(d.time());
                w.f64(d.inputs().t0);
                w.f64(d.next_step_size());
                let s = d.stats();
                w.u64(s.steps);
                w.u64(s.rejected);
                w.u64(s.rhs_evals);
                w.f64(s.last_step);
                w.f64s(d.state());
                w.f64s(&d.integrator_data());
            }
        }
    }

    pub fn read(bytes: &[u8]) -> Result<BeltDrive, String> {
        let mut r = Reader(bytes);
        let version = u32::from_le_bytes(r.take()?);
        if version != VERSION {
            return Err(format!(
                "model state version {version} is not supported (expected {VERSION})"
            ));
        }
        let mut m = BeltDrive::new();
        for v in parameters() {
            match v.start {
                Start::Real(_) => m.set_real(v, r.f64()?)?,
                Start::Integer(_) => m.set_integer(v, r.i32()?)?,
                Start::Boolean(_) => m.set_boolean(v, r.i32()? != 0)?,
                _ => {}
            }
        }
        m.start_time = r.f64()?;
        let arr = |r: &mut Reader| -> Result<[f64; MAX_PULLEYS], String> {
            let v = r.f64s(MAX_PULLEYS)?;
            Ok(v.try_into().expect("length checked"))
        };
        m.inputs.torque = arr(&mut r)?;
        m.inputs.torque_rate = arr(&mut r)?;
        m.inputs.omega_ref = arr(&mut r)?;
        m.inputs.omega_ref_rate = arr(&mut r)?;
        match r.u64()? {
            0 => {}
            1 => {
                let t = r.f64()?;
                let t0 = r.f64()?;
                let h = r.f64()?;
                let stats = Stats {
                    steps: r.u64()?,
                    rejected: r.u64()?,
                    rhs_evals: r.u64()?,
                    last_step: r.f64()?,
                };
                let params = m.drive_params()?;
                let mut drive = Drive::mounted(&params, m.start_time).map_err(|e| e.to_string())?;
                let y = r.f64s(drive.state().len())?;
                let mut inputs = m.inputs;
                inputs.t0 = t0;
                if !(t.is_finite() && h.is_finite() && h > 0.0 && y.iter().all(|x| x.is_finite())) {
                    return Err("model state holds non-finite values".into());
                }
                let data = r.f64s_any()?;
                if !drive.restore(t, &y, inputs, h, stats, &data) {
                    return Err("model state's integrator data does not fit the parameters".into());
                }
                m.drive = Some(drive);
            }
            k => return Err(format!("model state is corrupt (drive flag {k})")),
        }
        if !r.0.is_empty() {
            return Err(format!("model state has {} trailing bytes", r.0.len()));
        }
        Ok(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::belt::params::MAX_BODIES;
    use crate::variables::{by_name, Causality};

    /// The scalar variable `var` of the model description.
    fn info(var: Var) -> &'static VarInfo {
        VARIABLES.iter().find(|v| v.var == var).unwrap()
    }

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

    #[test]
    fn integer_ranges_come_from_the_table() {
        let mut m = BeltDrive::new();
        m.set_integer(info(Var::NPulleys), 7).unwrap();
        assert_eq!(
            m.drive_params().unwrap_err(),
            "nPulleys must be in 2..=6 (got 7)"
        );
        let mut m = BeltDrive::new();
        m.set_integer(info(Var::FrictionZoneBodies), -1).unwrap();
        assert_eq!(
            m.drive_params().unwrap_err(),
            "friction.zoneBodies must be >= 0 (got -1)"
        );
        let mut m = BeltDrive::new();
        m.set_integer(info(Var::ProbeBody), 151).unwrap();
        assert_eq!(
            m.drive_params().unwrap_err(),
            "probe.body must be in 1..=150 (got 151)"
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
