//! Equations of motion of belt bodies and pulleys (eq. 20-24) with contact
//! (eq. 4-11) and friction (eq. 12-19): the right-hand side of the ODE.
//!
//! State layout (one contiguous `f64` vector, bodies first so the Jacobian
//! of the chain is banded):
//! * body i: `[x, y, phi, vx, vy, omega, z]` at `7 i`, z = creep displacement;
//! * pulley j: `[theta, omega]` at `7 n + 2 j`;
//! * `[work_in, energy_dissipated]` last.

use super::contact::ContactLaw;
use super::friction::Friction;
use super::layout::Layout;
use super::params::{DriveParams, MAX_PULLEYS};
use std::f64::consts::TAU;

/// Values per body in the state vector.
pub const BODY_DOF: usize = 7;

/// Inputs held over a communication step: value at `t0` plus a rate (FMI
/// input derivatives), so inputs ramp linearly within the step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Inputs {
    pub t0: f64,
    pub torque: [f64; MAX_PULLEYS],
    pub torque_rate: [f64; MAX_PULLEYS],
    pub omega_ref: [f64; MAX_PULLEYS],
    pub omega_ref_rate: [f64; MAX_PULLEYS],
}

/// Constant data of one pulley in the hot loop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PulleyConst {
    pub cx: f64,
    pub cy: f64,
    pub radius: f64,
    pub radius2: f64,
    pub inv_inertia: f64,
    pub inertia: f64,
    pub mu_s: f64,
    pub mu_k: f64,
    pub speed_driven: bool,
    pub load_damping: f64,
    pub torque_ramp: f64,
    pub omega_ramp: f64,
    pub ramp_time: f64,
}

/// Observer of the force evaluation, used for outputs. The hot path uses
/// [`NoRecord`], whose calls compile away.
pub trait Recorder {
    const ACTIVE: bool;
    /// Translational SDE `k` (between body k-1 and body k): its tension and
    /// the midpoint of the gap it spans.
    fn sde(&mut self, _k: usize, _tension: f64, _mid: [f64; 2]) {}
    /// Contact of `body` with `pulley`: normal force, signed friction force
    /// along the pulley tangent, relative velocity v_T, penetration.
    fn contact(&mut self, _body: usize, _pulley: usize, _n: f64, _f: f64, _v_t: f64, _p: f64) {}
    /// Force the belt exerts on a pulley's hub.
    fn hub_force(&mut self, _pulley: usize, _fx: f64, _fy: f64) {}
    /// Per pulley: torque of the belt, torque a speed drive must supply, acceleration.
    fn pulley(&mut self, _pulley: usize, _belt_torque: f64, _drive_torque: f64, _alpha: f64) {}
    fn power(&mut self, _input: f64, _dissipated: f64) {}
}

pub struct NoRecord;
impl Recorder for NoRecord {
    const ACTIVE: bool = false;
}

/// The belt drive as an ODE system.
#[derive(Clone, Debug, PartialEq)]
pub struct BeltSystem {
    pub n: usize,
    pub np: usize,
    pub pulleys: [PulleyConst; MAX_PULLEYS],
    pub half_length: f64,
    pub mass: f64,
    pub inv_mass: f64,
    pub inertia: f64,
    pub inv_inertia: f64,
    /// Translational SDE: stiffness EA/l, damping B/l.
    pub k_axial: f64,
    pub b_axial: f64,
    /// Torsional SDE: stiffness EI/l, damping.
    pub k_bend: f64,
    pub b_bend: f64,
    pub gravity: f64,
    pub contact: ContactLaw,
    pub friction: Friction,
    /// Friction factor of every body (1 outside the modified zone).
    pub zone_factor: Vec<f64>,
    /// Squared regularisation length of the SDE direction (zero-length gap).
    pub eps2: f64,
    /// Mass-proportional damping [1/s] used only while the mounted belt is
    /// relaxed into static equilibrium (see `Drive::new`); 0 when running.
    pub relax_damping: f64,
    pub inputs: Inputs,
}

/// Angle wrapped to [-pi, pi].
#[inline(always)]
pub(crate) fn wrap_angle(a: f64) -> f64 {
    a - TAU * (a * (1.0 / TAU)).round()
}

impl BeltSystem {
    pub fn new(params: &DriveParams, layout: &Layout) -> Self {
        let l = layout.body_length;
        let b = &params.belt;
        let mass = b.mass_per_length * l;
        let inertia = mass * l * l / 12.0; // eq. 2
        let zero = PulleyConst {
            cx: 0.0,
            cy: 0.0,
            radius: 0.0,
            radius2: 0.0,
            inv_inertia: 0.0,
            inertia: 0.0,
            mu_s: 0.0,
            mu_k: 0.0,
            speed_driven: false,
            load_damping: 0.0,
            torque_ramp: 0.0,
            omega_ramp: 0.0,
            ramp_time: 1.0,
        };
        let mut pulleys = [zero; MAX_PULLEYS];
        for (pc, p) in pulleys.iter_mut().zip(&params.pulleys) {
            *pc = PulleyConst {
                cx: p.x,
                cy: p.y,
                radius: p.radius,
                radius2: p.radius * p.radius,
                inv_inertia: 1.0 / p.inertia,
                inertia: p.inertia,
                mu_s: p.mu_static,
                mu_k: p.mu_kinetic,
                speed_driven: p.speed_driven,
                load_damping: p.load_damping,
                torque_ramp: p.torque_ramp,
                omega_ramp: p.omega_ramp,
                ramp_time: p.ramp_time,
            };
        }
        let f = &params.friction;
        let n = b.n_bodies;
        let mut zone_factor = vec![1.0; n];
        for k in 0..f.zone_bodies {
            zone_factor[(f.zone_start + k) % n] = f.zone_factor;
        }
        let c = &params.contact;
        Self {
            n,
            np: params.pulleys.len(),
            pulleys,
            half_length: 0.5 * l,
            mass,
            inv_mass: 1.0 / mass,
            inertia,
            inv_inertia: 1.0 / inertia,
            k_axial: b.ea / l,
            b_axial: b.axial_damping / l,
            k_bend: b.bending_stiffness / l,
            b_bend: b.bending_damping / l,
            gravity: params.gravity,
            contact: ContactLaw {
                c1: c.c1 * l,
                c2: c.c2 * l,
                b: c.damping * l,
                inv_p_max: 1.0 / c.p_max,
            },
            friction: Friction::new(f.law, f.dv, f.creep_max),
            zone_factor,
            eps2: (1e-6 * l) * (1e-6 * l),
            relax_damping: 0.0,
            inputs: Inputs::default(),
        }
    }

    pub fn dim(&self) -> usize {
        BODY_DOF * self.n + 2 * self.np + 2
    }

    pub fn pulley_offset(&self, j: usize) -> usize {
        BODY_DOF * self.n + 2 * j
    }

    pub fn energy_offset(&self) -> usize {
        BODY_DOF * self.n + 2 * self.np
    }

    /// Torque input plus built-in ramp on pulley j at time t.
    #[inline]
    pub fn applied_torque(&self, j: usize, t: f64) -> f64 {
        let p = &self.pulleys[j];
        let inp = &self.inputs;
        inp.torque[j] + inp.torque_rate[j] * (t - inp.t0) + ramp(p, p.torque_ramp, t)
    }

    /// Prescribed speed of a speed-driven pulley j at time t, and its rate.
    #[inline]
    pub fn prescribed_speed(&self, j: usize, t: f64) -> (f64, f64) {
        let p = &self.pulleys[j];
        let inp = &self.inputs;
        let w = inp.omega_ref[j] + inp.omega_ref_rate[j] * (t - inp.t0) + ramp(p, p.omega_ramp, t);
        let dw = inp.omega_ref_rate[j] + ramp_rate(p, p.omega_ramp, t);
        (w, dw)
    }

    /// Angular speed of pulley j used by the contact: the state for
    /// torque-driven pulleys, the prescription for speed-driven ones.
    #[inline]
    pub fn pulley_speed(&self, j: usize, t: f64, y: &[f64]) -> f64 {
        if self.pulleys[j].speed_driven {
            self.prescribed_speed(j, t).0
        } else {
            y[self.pulley_offset(j) + 1]
        }
    }

    /// dy/dt = f(t, y). Allocates nothing.
    pub fn rhs<R: Recorder>(&self, t: f64, y: &[f64], dy: &mut [f64], rec: &mut R) {
        let n = self.n;
        let np = self.np;
        let hl = self.half_length;
        let (ks, bs, kt, bt) = (self.k_axial, self.b_axial, self.k_bend, self.b_bend);
        let weight = self.mass * self.gravity;

        let mut omega_p = [0.0; MAX_PULLEYS];
        for (j, w) in omega_p.iter_mut().enumerate().take(np) {
            *w = self.pulley_speed(j, t, y);
        }
        let mut belt_torque = [0.0; MAX_PULLEYS];
        let mut p_diss = 0.0;

        // End points of a body: (left end, its velocity, right end, its velocity, h).
        let ends = |i: usize| {
            let b = &y[BODY_DOF * i..BODY_DOF * i + BODY_DOF];
            let (s, c) = b[2].sin_cos();
            let (hx, hy) = (hl * c, hl * s);
            let (vx, vy, w) = (b[3], b[4], b[5]);
            (
                [b[0] - hx, b[1] - hy],
                [vx + w * hy, vy - w * hx],
                [b[0] + hx, b[1] + hy],
                [vx - w * hy, vy + w * hx],
                [hx, hy],
            )
        };

        // Own forces of each body: gravity, contact, friction; creep rate.
        for i in 0..n {
            let o = BODY_DOF * i;
            let (x, yy, vx, vy, z) = (y[o], y[o + 1], y[o + 3], y[o + 4], y[o + 6]);
            dy[o] = vx;
            dy[o + 1] = vy;
            dy[o + 2] = y[o + 5];
            let (mut fx, mut fy) = (0.0, -weight);
            let mut dz = 0.0;
            for j in 0..np {
                let pc = &self.pulleys[j];
                let (rx, ry) = (x - pc.cx, yy - pc.cy);
                let d2 = rx * rx + ry * ry;
                if d2 >= pc.radius2 {
                    continue;
                }
                // eq. 4-8: direction, penetration and its rate
                let dist = d2.sqrt();
                let inv = 1.0 / dist.max(1e-12);
                let (nx, ny) = (rx * inv, ry * inv);
                let p = pc.radius - dist;
                let p_dot = -(vx * nx + vy * ny);
                let (normal, elastic) = self.contact.normal_force(p, p_dot);
                // eq. 14-18 with the pulley radius as lever: v_T = omega r_p - v.tau
                let (tx, ty) = (-ny, nx);
                let v_t = omega_p[j] * pc.radius - (vx * tx + vy * ty);
                let zf = self.zone_factor[i];
                let mu = self
                    .friction
                    .coefficient(v_t, z, pc.mu_s * zf, pc.mu_k * zf);
                let f = mu * normal; // eq. 19, along +tau
                let (cfx, cfy) = (normal * nx + f * tx, normal * ny + f * ty);
                fx += cfx;
                fy += cfy;
                belt_torque[j] -= pc.radius * f; // eq. 24
                dz += self.friction.creep_rate(v_t, z);
                p_diss += (normal - elastic) * p_dot + f * v_t;
                if R::ACTIVE {
                    rec.contact(i, j, normal, f, v_t, p);
                    rec.hub_force(j, -cfx, -cfy);
                }
            }
            dy[o + 3] = fx;
            dy[o + 4] = fy;
            dy[o + 5] = 0.0;
            dy[o + 6] = dz;
        }

        // Translational and torsional SDEs (eq. 20-23): SDE k joins the right
        // end of body k-1 to the left end of body k (k = 0 closes the loop).
        let mut prev = ends(n - 1);
        for k in 0..n {
            let cur = ends(k);
            let (ip, ic) = (BODY_DOF * ((k + n - 1) % n), BODY_DOF * k);
            let d = [cur.0[0] - prev.2[0], cur.0[1] - prev.2[1]];
            let dd = [cur.1[0] - prev.3[0], cur.1[1] - prev.3[1]];
            let d2 = d[0] * d[0] + d[1] * d[1];
            let rate = (d[0] * dd[0] + d[1] * dd[1]) / (d2 + self.eps2);
            // Zero-rest-length Kelvin-Voigt element: elastic force EA/l * gap
            // vector, damping along the gap (regularised at zero gap).
            let fx = ks * d[0] + bs * rate * d[0];
            let fy = ks * d[1] + bs * rate * d[1];
            // torques of the end forces about each body's centre
            let t_cur = cur.4[0] * fy - cur.4[1] * fx; // (-h) x (-F)
            let t_prev = prev.4[0] * fy - prev.4[1] * fx; // h x F
            let dphi = wrap_angle(y[ic + 2] - y[ip + 2]);
            let dw = y[ic + 5] - y[ip + 5];
            let m = kt * dphi + bt * dw;
            dy[ic + 3] -= fx;
            dy[ic + 4] -= fy;
            dy[ic + 5] += t_cur - m;
            dy[ip + 3] += fx;
            dy[ip + 4] += fy;
            dy[ip + 5] += t_prev + m;
            p_diss += bs * rate * rate * d2 + bt * dw * dw;
            if R::ACTIVE {
                let len = d2.sqrt();
                let tension = ks * len + bs * rate * len;
                let mid = [0.5 * (cur.0[0] + prev.2[0]), 0.5 * (cur.0[1] + prev.2[1])];
                rec.sde(k, tension, mid);
            }
            prev = cur;
        }
        let c = self.relax_damping;
        for i in 0..n {
            let o = BODY_DOF * i;
            dy[o + 3] = dy[o + 3] * self.inv_mass - c * y[o + 3];
            dy[o + 4] = dy[o + 4] * self.inv_mass - c * y[o + 4];
            dy[o + 5] = dy[o + 5] * self.inv_inertia - c * y[o + 5];
        }

        // Pulleys (eq. 24).
        let mut p_in = 0.0;
        for j in 0..np {
            let pc = &self.pulleys[j];
            let o = self.pulley_offset(j);
            let w = omega_p[j];
            let applied = self.applied_torque(j, t);
            let load = pc.load_damping * w;
            dy[o] = w;
            let (alpha, drive) = if pc.speed_driven {
                let alpha = self.prescribed_speed(j, t).1;
                let drive = pc.inertia * alpha - belt_torque[j] - applied + load;
                (alpha, drive)
            } else {
                ((applied - load + belt_torque[j]) * pc.inv_inertia, 0.0)
            };
            dy[o + 1] = alpha;
            p_in += (applied + drive) * w;
            p_diss += load * w;
            if R::ACTIVE {
                rec.pulley(j, belt_torque[j], drive, alpha);
            }
        }
        let e = self.energy_offset();
        dy[e] = p_in;
        dy[e + 1] = p_diss;
        if R::ACTIVE {
            rec.power(p_in, p_diss);
        }
    }

    /// Discrete update after every accepted step: the creep displacement of a
    /// body that touches no pulley is reset, and kept within its cap.
    pub fn after_step(&self, y: &mut [f64]) {
        let cap = self.friction.creep_cap();
        for i in 0..self.n {
            let o = BODY_DOF * i;
            let (x, yy) = (y[o], y[o + 1]);
            let touching = self.pulleys[..self.np].iter().any(|pc| {
                let (rx, ry) = (x - pc.cx, yy - pc.cy);
                rx * rx + ry * ry < pc.radius2
            });
            y[o + 6] = if touching {
                y[o + 6].clamp(-cap, cap)
            } else {
                0.0
            };
        }
    }

    /// Kinetic and potential (elastic + gravity) energy of state `y`.
    pub fn energies(&self, y: &[f64]) -> (f64, f64) {
        let n = self.n;
        let hl = self.half_length;
        let mut kin = 0.0;
        let mut pot = 0.0;
        for i in 0..n {
            let o = BODY_DOF * i;
            let b = &y[o..o + BODY_DOF];
            kin += 0.5 * self.mass * (b[3] * b[3] + b[4] * b[4]) + 0.5 * self.inertia * b[5] * b[5];
            pot += self.mass * self.gravity * b[1];
            for pc in &self.pulleys[..self.np] {
                let dist = (b[0] - pc.cx).hypot(b[1] - pc.cy);
                pot += self.contact.energy(pc.radius - dist);
            }
            let q = &y[BODY_DOF * ((i + n - 1) % n)..];
            let (s, c) = b[2].sin_cos();
            let (sq, cq) = q[2].sin_cos();
            let gx = (b[0] - hl * c) - (q[0] + hl * cq);
            let gy = (b[1] - hl * s) - (q[1] + hl * sq);
            pot += 0.5 * self.k_axial * (gx * gx + gy * gy);
            let dphi = wrap_angle(b[2] - q[2]);
            pot += 0.5 * self.k_bend * dphi * dphi;
        }
        for j in 0..self.np {
            let w = y[self.pulley_offset(j) + 1];
            kin += 0.5 * self.pulleys[j].inertia * w * w;
        }
        (kin, pot)
    }
}

fn ramp(p: &PulleyConst, amp: f64, t: f64) -> f64 {
    if amp == 0.0 || t <= 0.0 {
        0.0
    } else if t >= p.ramp_time {
        amp
    } else {
        amp * t / p.ramp_time
    }
}

fn ramp_rate(p: &PulleyConst, amp: f64, t: f64) -> f64 {
    if amp != 0.0 && t > 0.0 && t < p.ramp_time {
        amp / p.ramp_time
    } else {
        0.0
    }
}
