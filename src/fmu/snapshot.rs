//! Byte image of a [`BeltDrive`]: every parameter, the inputs and, once
//! built, time, state, step size and counters. The drive is rebuilt from the
//! parameters (deterministic) and its state replaced, so a restored model
//! continues bit-identically.

use super::variables::Start;
use super::*;
use crate::drive::Window;
use crate::solver::rkf45::Stats;

/// 2: integrator data (the stiff method's kept Jacobian) after the state;
/// 3: the tensioner springs' free angles found by the mounting after that;
/// 4: the impulse states (mean force outputs) in the state, the window they
/// average over after it;
/// 5: the stiff method's first stage kept from the last step's end (its
/// right-hand side and energy balance) in the integrator data;
/// 6: the interval outputs after the integrator data;
/// 7: eight pulley slots and the tensioner arms' end stops among the
/// parameters;
/// 8: the integrator's step past the communication point (look-ahead) at
/// the start of the integrator data;
/// 9: a third state per tensioner arm (its pivot friction's presliding
/// deflection) and the arms' presliding angle among the parameters.
pub(super) const VERSION: u32 = 9;

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
            let window = d.window();
            w.f64(window.start);
            w.f64s(&window.omega_change);
            w.f64s(&d.integrator_data());
            w.f64s(&d.arm_free_angles());
        }
    }
}

pub fn read(bytes: &[u8]) -> Result<BeltDrive, String> {
    let mut r = Reader(bytes);
    let version = u32::from_le_bytes(r.take()?);
    if version != VERSION {
        return Err(format!(
            "model state version {version} is not supported (expected {VERSION}): it was \
             saved by another version of BeltDrive; rerun the simulation to that time instead"
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
            let mut drive = Drive::mounted(&params, m.start_time)
                .map_err(|e| super::names::render_error(&e))?;
            let y = r.f64s(drive.state().len())?;
            let window = Window {
                start: r.f64()?,
                omega_change: r.f64s(MAX_PULLEYS)?.try_into().expect("length checked"),
            };
            let mut inputs = m.inputs;
            inputs.t0 = t0;
            let finite = y.iter().chain(&window.omega_change).all(|x| x.is_finite());
            if !(t.is_finite() && h.is_finite() && h > 0.0 && window.start.is_finite() && finite) {
                return Err("model state holds non-finite values".into());
            }
            if window.start > t {
                return Err("model state is corrupt (averaging window after its time)".into());
            }
            let data = r.f64s_any()?;
            let free = r.f64s(drive.arm_free_angles().len())?;
            // the free angles first: setting them forgets what the
            // integrator kept, which the integrator data then restore
            if !drive.set_arm_free_angles(&free) {
                return Err("model state holds non-finite tensioner free angles".into());
            }
            if !drive.restore(t, &y, window, inputs, h, stats, &data) {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// This version's layout, pinned: the bytes of a snapshot less those of
    /// the parameters (their number follows the model description, whose
    /// GUID the plumbing checks), for the 60-body fast drive before it is
    /// built and after 5 ms with each integrator. A change of the layout
    /// (a state per body or pulley, the integrator data, a field) changes
    /// them and must come with a new `VERSION`, which
    /// `tests/tensioner_abi.rs` (`a_state_of_the_previous_version_is_refused`)
    /// follows.
    #[test]
    fn layout_of_this_version_is_pinned() {
        let parameter_bytes: usize = parameters()
            .map(|v| match v.start {
                Start::Real(_) => 8,
                _ => 4,
            })
            .sum();
        let layout = |method: Option<i32>| {
            let mut m = BeltDrive::new();
            let int = |m: &mut BeltDrive, name: &str, x: i32| {
                let v = variables::by_name(name).expect("a variable");
                m.set_integer(v, x).expect("accepted");
            };
            int(&mut m, "belt.nBodies", 60);
            for (name, x) in [
                ("pulley[1].radius", 0.05),
                ("pulley[2].radius", 0.05),
                ("pulley[2].x", 0.25),
                ("belt.preload", 300.0),
            ] {
                let v = variables::by_name(name).expect("a variable");
                m.set_real(v, x).expect("accepted");
            }
            if let Some(code) = method {
                int(&mut m, "solver.method", code);
                for k in 0..5 {
                    m.do_step(f64::from(k) * 1e-3, 1e-3).expect("a step");
                }
            }
            let mut bytes = Vec::new();
            write(&m, &mut bytes);
            read(&bytes).expect("reads back");
            bytes.len() - parameter_bytes
        };
        let [unbuilt, rkf45, stiff] = [None, Some(1), Some(2)].map(layout);
        // version 6: the interval outputs at the end of the integrator
        // data; version 7: eight pulley slots and the arms' stops
        // version 8: the look-ahead first in the integrator data: two
        // flags, and after these 5 ms the step taken past the last point
        // (its start, step size and end, the checkpoint's length and
        // RKF45's 3 numbers, y_a, f_a, y_b, f_b: 4 * 434): 16 + 8 * 1743
        // bytes more than version 7's 4276; version 9 changes only drives
        // with tensioner arms (a third state per arm)
        assert_eq!((VERSION, unbuilt, rkf45), (9, 308, 18236));
        // the stiff method's data hold the first stage kept from the last
        // step's end (marker, time, the point's fingerprint in 2, the 434
        // right-hand-side values, the energy balance's 3: 441 numbers) and
        // its Jacobian while it is kept (here after 5 ms) and not after a
        // rejected step: 16 + 8 * 441 bytes more than RKF45's without it
        // (its per-pulley columns for the drive's own pulleys only); the
        // look-ahead as RKF45's with the stiff method's 4-number checkpoint
        // (16 + 8 * 1744 bytes; a Jacobian parked there would add its own)
        assert!(
            [21_788, 146_212].contains(&stiff),
            "the stiff method's layout changed: {stiff} bytes"
        );
    }
}
