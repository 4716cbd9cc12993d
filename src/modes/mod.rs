//! Modal analysis of a belt drive: natural frequencies, damping ratios and
//! mode descriptions from the eigen-decomposition of the analytic Jacobian
//! (docs/modes.md).
//!
//! * About the mounted static state: the Jacobian itself.
//! * About steady running: the Floquet analysis about the periodic running
//!   state ([`floquet()`], module [`floquet`]), or its frozen-time
//!   approximation: the Jacobian at one instant, written for
//!   perturbations seen at fixed places along the belt path (each body's
//!   position and velocity in its own tangent/normal frame, plus the
//!   transport of the belt past those places, `-(1/P) D`, P the time the
//!   belt takes to advance one body, D the centred difference along the
//!   body index). This is the average (first-order Floquet) generator of the
//!   time-periodic linearisation of a discrete belt in steady motion; it
//!   freezes which bodies touch which pulley at that instant.
//!
//! States with no dynamics are removed exactly before the eigen-solve: a
//! state whose row or column of the Jacobian is zero off the diagonal (pulley
//! angles, speeds of speed-driven pulleys, the creep of bodies off the
//! pulleys, the energy accumulators) splits off with its diagonal as
//! eigenvalue.
//!
//! Everything the analysis needs from the core goes through [`adapter`].

pub mod adapter;
pub mod degenerate;
pub mod floquet;
pub mod mechanism;
pub mod params;
pub mod tap;

pub use floquet::{floquet, Orbit, FLOQUET_SUBSTEPS, SDIRK_GAMMA};
pub use tap::Tap;

use crate::model::params::MAX_PULLEYS;
use adapter::Linearisation;
use faer::linalg::solvers::Eigen;
use faer::Mat;
use std::f64::consts::TAU;

/// Options of one analysis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Highest natural frequency reported [Hz].
    pub max_frequency_hz: f64,
    /// Add the transport of the moving belt (steady running); off for a
    /// drive at rest.
    pub transport: bool,
    /// Natural frequencies below this count as zero modes (rigid motion) [Hz].
    pub zero_frequency_hz: f64,
    /// Angle amplitude of the tensioner arms' swing [rad] at which
    /// [`analyse_drive`] and [`floquet()`] replace their pivot friction by
    /// its describing function ([`describe_arms`]); 0 linearises the
    /// friction law as it is (the arm held on its presliding stiffness).
    pub arm_amplitude: f64,
}

/// The arm swing a designer reads a tensioner's mode at by default:
/// 0.5 deg (automotive arms swing by tenths of a degree to a degree at
/// idle).
pub const ARM_AMPLITUDE: f64 = 0.5 * std::f64::consts::PI / 180.0;

impl Default for Options {
    fn default() -> Self {
        Self {
            max_frequency_hz: 2000.0,
            transport: false,
            zero_frequency_hz: 0.5,
            arm_amplitude: ARM_AMPLITUDE,
        }
    }
}

/// A frictional tensioner arm in a describing-function analysis
/// ([`describe_arms`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmSwing {
    /// The pulley the arm carries (1-based).
    pub pulley: usize,
    /// Its pivot friction's torque M_c + mu_h r_f |F_hub| [N m].
    pub friction_torque: f64,
    /// Frequency of the swing the damping is taken at: the swing of the
    /// arm's tap with that damping ([`tap`]), iterated to consistency [Hz].
    pub frequency_hz: f64,
    /// The friction's equivalent viscous damping at that swing [N m s/rad].
    pub equivalent_damping: f64,
    /// The arm does not swing at this amplitude (its tap creeps back): the
    /// friction overdamps it (below break-away the arm sticks).
    pub stuck: bool,
    /// The iteration on the frequency ended within its tolerance (false:
    /// stopped at its iteration limit, the damper at the last frequency).
    pub converged: bool,
}

/// Share of a mode's kinetic energy in the swing of the arm carrying
/// pulley `j` (0-based).
fn arm_share(m: &Mode, j: usize) -> f64 {
    m.share_of(Part::Arm(j + 1))
}

/// Modes of `drive` at its state now ([`adapter::linearise`] and
/// [`analyse`]), with the pivot friction of its tensioner arms replaced by
/// the describing function of the friction at `opts.arm_amplitude`
/// ([`describe_arms`]; the swings in [`Modes::arms`]). Without frictional
/// arms or with `arm_amplitude` 0: [`analyse`] of [`adapter::linearise`].
pub fn analyse_drive(drive: &crate::Drive, opts: &Options) -> Result<Modes, String> {
    describe_arms(drive, opts, ARM_FREQUENCY_TOL, 50, |equivalent| {
        let lin = adapter::linearise_with(drive, equivalent);
        let mut modes = analyse(&lin, opts)?;
        if !opts.transport {
            modes.arm_taps = tap::at_rest(&lin)?;
        }
        Ok(modes)
    })
}

/// The describing-function iteration stops when the arm modes' frequencies
/// change by less than this (relative): a few iterations about one
/// instant, where each costs one eigen-solve.
pub const ARM_FREQUENCY_TOL: f64 = 1e-6;

/// The modes `solve` gives with the pivot friction of `drive`'s tensioner
/// arms replaced by the describing function of the friction at
/// `opts.arm_amplitude` (docs/modes.md, "Frictional tensioner arms"): a
/// Coulomb friction of torque M_f swinging at angle amplitude A and
/// angular frequency omega dissipates per cycle what a viscous damper
/// c = 4 M_f / (pi omega A) does
/// ([`crate::model::elements::Arm::friction_describing`], the presliding
/// law's own, which tends to it for swings far beyond the presliding
/// deflection), M_f at the drive's hub forces now. `solve` analyses the
/// drive with arm j's friction replaced by a damper `equivalent[j]`
/// ([`adapter::linearise_with`]). omega is the frequency of the arm's
/// swing after a tap with that damper ([`Modes::arm_taps`], [`tap`]; in
/// the frozen-time approximation, which has no tap, the damped frequency
/// of the oscillating mode with the largest share of the arm's energy):
/// the frequency f the damper is set at must be the swing g(f) it gives.
/// Started from the frictionless arm's swing, each iteration sets the
/// damper at the next f: the swing itself until f and g(f) have been seen
/// on both sides (g > f and g < f), then the secant within that bracket
/// (Illinois' rule), until f changes by less than `tolerance` (at most
/// `iterations` times, then reported not `converged`; a plain iteration f
/// = g(f) went round a cycle of two). An arm whose tap does not swing
/// before a bracket is found is reported `stuck`: the friction overdamps
/// it at this amplitude (the modes then those with its friction at the
/// last frequency); no swing after one counts as a swing at 0 Hz. Without
/// frictional arms or with `arm_amplitude` 0: `solve` with the friction as
/// it is (no replacement).
pub fn describe_arms(
    drive: &crate::Drive,
    opts: &Options,
    tolerance: f64,
    iterations: usize,
    mut solve: impl FnMut(&[Option<f64>; MAX_PULLEYS]) -> Result<Modes, String>,
) -> Result<Modes, String> {
    let friction = adapter::arm_friction(drive);
    let arms: Vec<usize> = (0..MAX_PULLEYS).filter(|&j| friction[j] > 0.0).collect();
    if arms.is_empty() || opts.arm_amplitude == 0.0 {
        return solve(&[None; MAX_PULLEYS]);
    }
    let mut equivalent = [None; MAX_PULLEYS];
    for &j in &arms {
        equivalent[j] = Some(0.0);
    }
    let mut swings: Vec<ArmSwing> = arms
        .iter()
        .map(|&j| ArmSwing {
            pulley: j + 1,
            friction_torque: friction[j],
            frequency_hz: 0.0,
            equivalent_damping: 0.0,
            stuck: false,
            converged: false,
        })
        .collect();
    let mut modes = solve(&equivalent)?;
    // the frozen-time rule's reference: the frictionless arm's share of its
    // mode's energy
    let mut frictionless = [0.0; MAX_PULLEYS];
    let mut fixed = [FixedPoint::default(); MAX_PULLEYS];
    for _ in 0..iterations {
        let mut moved: f64 = 0.0;
        for s in swings.iter_mut().filter(|s| !s.stuck) {
            let j = s.pulley - 1;
            let swing = match modes.arm_taps[j] {
                Some(Tap::Swings(f)) => Some(f),
                Some(Tap::Overdamped) => None,
                // the frozen-time approximation: the oscillating mode that
                // swings the arm most; once the friction is in, none
                // carrying half the frictionless arm's share: overdamped
                None => {
                    let best = modes
                        .modes
                        .iter()
                        .max_by(|a, b| arm_share(a, j).total_cmp(&arm_share(b, j)))
                        .filter(|m| arm_share(m, j) > 0.5 * frictionless[j]);
                    if let (Some(m), 0.0) = (best, s.frequency_hz) {
                        frictionless[j] = arm_share(m, j);
                    }
                    best.map(|m| m.damped_hz)
                }
            };
            let f = s.frequency_hz;
            // the frictionless arm's swing starts the iteration
            let next = if f == 0.0 {
                swing
            } else {
                fixed[j].next(f, swing)
            };
            let Some(next) = next else {
                s.stuck = true;
                continue;
            };
            moved = moved.max((next / f - 1.0).abs());
            s.frequency_hz = next;
            s.equivalent_damping =
                adapter::arm_describing(drive, j, opts.arm_amplitude, TAU * next);
            equivalent[j] = Some(s.equivalent_damping);
        }
        modes = solve(&equivalent)?;
        if moved < tolerance {
            swings.iter_mut().for_each(|s| s.converged = true);
            break;
        }
    }
    modes.arms = swings;
    Ok(modes)
}

/// One arm's describing-function iteration ([`describe_arms`]): the
/// frequency f the damper is set at and the swing g(f) it gives, with the
/// points seen so far either side of the fixed point g(f) = f, as (f, g -
/// f): `lo` where the swing is faster, `hi` where it is slower.
#[derive(Clone, Copy, Debug, Default)]
struct FixedPoint {
    lo: Option<(f64, f64)>,
    hi: Option<(f64, f64)>,
    /// Which side the last point fell on.
    last_lo: Option<bool>,
}

impl FixedPoint {
    /// The frequency to set the damper at next, after the damper set at
    /// `f` gave the swing `g` (None: no swing, counted as a swing at 0 Hz):
    /// the swing itself until both sides are known, then the secant within
    /// the bracket (Illinois' rule: a side kept twice in a row has its
    /// residual halved; the bisection if the secant leaves the bracket).
    /// None: no swing and no point on the faster side, the arm sticks.
    fn next(&mut self, f: f64, g: Option<f64>) -> Option<f64> {
        let r = g.map_or(-f, |g| g - f);
        let is_lo = r > 0.0;
        if self.last_lo == Some(is_lo) {
            let kept = if is_lo { &mut self.hi } else { &mut self.lo };
            if let Some((_, rk)) = kept.as_mut() {
                *rk *= 0.5;
            }
        }
        self.last_lo = Some(is_lo);
        if is_lo {
            self.lo = Some((f, r));
        } else {
            self.hi = Some((f, r));
        }
        match (self.lo, self.hi) {
            (Some((fl, rl)), Some((fh, rh))) => {
                let x = fl - rl * (fh - fl) / (rh - rl);
                Some(if x > fl.min(fh) && x < fl.max(fh) {
                    x
                } else {
                    0.5 * (fl + fh)
                })
            }
            _ => g,
        }
    }
}

/// What moves most in a mode (by kinetic energy).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Span k (1-based: from pulley k to pulley k+1 in the parameter order).
    SpanTransverse(usize),
    /// Span k's stretching along the belt (1-based).
    SpanLongitudinal(usize),
    /// Pulley j's rotation (1-based).
    PulleyRotation(usize),
    /// The tensioner arm carrying pulley j (1-based): its swing about the
    /// pivot (arm and pulley inertia about the pivot).
    Arm(usize),
    /// Bodies rotating against their neighbours: an artefact of the discrete belt.
    BeltPitching,
    /// The belt running round with all free pulleys in phase, held only by
    /// the polygon (cogging) potential of the discrete chain (artefact,
    /// vanishes as the body length squared).
    RigidRotation,
    /// Bodies on pulley j's wrap bouncing on the penalty contact (artefact).
    WrapRadial(usize),
    /// Bodies on pulley j's wrap on the creep spring of the friction law (artefact).
    WrapTangential(usize),
}

impl Part {
    /// Modes of the discrete bodies (not of the belt drive being modelled).
    pub fn artificial(self) -> bool {
        matches!(
            self,
            Self::BeltPitching
                | Self::RigidRotation
                | Self::WrapRadial(_)
                | Self::WrapTangential(_)
        )
    }

    /// The kind of motion the part takes part in: the labels name a mode
    /// after the kind with the largest share of its energy (docs/modes.md,
    /// "Descriptions").
    pub fn family(self) -> Family {
        match self {
            Self::PulleyRotation(_) | Self::SpanLongitudinal(_) => Family::Rotation,
            Self::SpanTransverse(_) => Family::Transverse,
            Self::Arm(_) => Family::Arm,
            Self::BeltPitching
            | Self::RigidRotation
            | Self::WrapRadial(_)
            | Self::WrapTangential(_) => Family::Artefact,
        }
    }

    /// The part in words, for tables and plots.
    pub fn describe(self) -> String {
        match self {
            Self::SpanTransverse(k) => format!("span {k} transverse"),
            Self::SpanLongitudinal(k) => format!("span {k} longitudinal"),
            Self::PulleyRotation(j) => format!("pulley {j} rotation"),
            Self::Arm(j) => format!("arm {j}"),
            Self::BeltPitching => "belt pitching".into(),
            Self::RigidRotation => "belt pitching (rigid rotation on the polygon)".into(),
            Self::WrapRadial(j) => format!("belt pitching (wrap {j} radial contact)"),
            Self::WrapTangential(j) => format!("belt pitching (wrap {j} tangential creep)"),
        }
    }
}

/// Kinds of motion of a drive, by which coordinates move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// The pulleys' rotation and the belt's motion along its path that goes
    /// with it (the wrapped belt moving with its pulley, the spans
    /// stretching): the rotational modes of a drive.
    Rotation,
    /// The spans' motion across the belt path.
    Transverse,
    /// A tensioner arm's swing.
    Arm,
    /// The discrete bodies' own motions (pitching, bouncing on the contact,
    /// on the creep spring).
    Artefact,
}

/// One mode: a complex pair lambda = -zeta w_n +- i w_n sqrt(1 - zeta^2).
#[derive(Clone, Debug, PartialEq)]
pub struct Mode {
    /// Undamped natural frequency |lambda| / 2 pi [Hz].
    pub frequency_hz: f64,
    /// -Re(lambda) / |lambda|.
    pub damping_ratio: f64,
    /// Damped frequency Im(lambda) / 2 pi [Hz].
    pub damped_hz: f64,
    /// The part of the drive with the largest share of the mode's kinetic energy.
    pub part: Part,
    /// Share of the mode's kinetic energy in `part`.
    pub share: f64,
    /// Share of the mode's kinetic energy in each part of the drive
    /// ([`energies`]), largest first.
    pub shares: Vec<(Part, f64)>,
    /// The Floquet analysis' eigenvector: the perturbation of the drive's
    /// state at the analysed instant (in the state's order) that returns
    /// multiplied by the mode's Floquet multiplier after one period (the
    /// state shifted by one body), scaled so that its largest component is
    /// 1; `Re(shape)` kicks the drive along the mode. Empty from the
    /// analysis about one instant ([`analyse`]).
    pub shape: Vec<faer::c64>,
}

/// Share of a mode's kinetic energy from which a pulley's rotation or an
/// arm's swing is named beside the part that labels the mode: one
/// coordinate carrying a tenth of the energy of a mode spread over the
/// belt is what a drive engineer calls that pulley's (or arm's) mode (in
/// the accessory drive's span modes the pulleys carry under 3 %).
pub const COMPANION_SHARE: f64 = 0.1;

impl Mode {
    /// Share of the mode's kinetic energy in `part` (0 if it has none).
    pub fn share_of(&self, part: Part) -> f64 {
        self.shares
            .iter()
            .find(|(p, _)| *p == part)
            .map_or(0.0, |(_, e)| *e)
    }

    /// The pulley rotation or arm swing with the largest share of the
    /// energy, if it carries at least [`COMPANION_SHARE`] and is not the
    /// label itself.
    pub fn companion(&self) -> Option<(Part, f64)> {
        self.shares
            .iter()
            .copied()
            .find(|(p, _)| matches!(p, Part::PulleyRotation(_) | Part::Arm(_)))
            .filter(|&(p, e)| p != self.part && e >= COMPANION_SHARE)
    }

    /// The description written to the CSV: the label, and a pulley
    /// rotation or arm swing carrying at least [`COMPANION_SHARE`] of the
    /// energy beside it, e.g. `span 4 transverse with pulley 3 rotation
    /// (16 %)`.
    pub fn describe(&self) -> String {
        match self.companion() {
            Some((p, e)) => format!(
                "{} with {} ({:.0} %)",
                self.part.describe(),
                p.describe(),
                100.0 * e
            ),
            None => self.part.describe(),
        }
    }
}

/// Result of one analysis.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Modes {
    /// Oscillating modes up to the frequency limit, by frequency.
    pub modes: Vec<Mode>,
    /// Eigenvalues of magnitude below the zero-frequency limit (rigid
    /// rotation of the belt with free pulleys, states without dynamics).
    pub zero_modes: usize,
    /// Real eigenvalues beyond the zero limit (overdamped motions).
    pub overdamped: usize,
    /// Oscillating modes above the frequency limit.
    pub above_limit: usize,
    /// States split off before the eigen-solve (no dynamics of their own).
    pub removed_states: usize,
    /// Size of the eigenproblem solved.
    pub reduced_dim: usize,
    /// Bodies passing a point per second (transport), 0 at rest.
    pub body_rate: f64,
    /// The periodic running state of a Floquet analysis ([`floquet`]).
    pub orbit: Option<Orbit>,
    /// Degenerate pairs split into span-localised modes ([`degenerate`]).
    pub split_pairs: usize,
    /// The frictional tensioner arms, each with the describing function
    /// its pivot friction was replaced by ([`describe_arms`]); empty when
    /// the friction was linearised as it is.
    pub arms: Vec<ArmSwing>,
    /// How each tensioner arm (by pulley, 0-based) swings after a tap of
    /// its rate in the linearised drive ([`tap`]): at rest and in the
    /// Floquet analysis; `None` for pulleys without arm and in the
    /// frozen-time approximation.
    pub arm_taps: [Option<Tap>; MAX_PULLEYS],
}

/// Where a body is: on pulley j's wrap or on span k (0-based).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Region {
    /// On pulley j's wrap.
    Wrap(usize),
    /// On span k.
    Span(usize),
}

/// Region of every body at the linearisation state: contact by the model's
/// own test; a free body belongs to the span between the pulleys it runs
/// between (span k goes from pulley k to pulley k+1 or back).
pub fn regions(lin: &Linearisation) -> Vec<Region> {
    let n = lin.n;
    let np = lin.pulleys.len();
    let contact: Vec<Option<usize>> = (0..n).map(|i| lin.contact_of(i)).collect();
    if contact.iter().all(Option::is_none) {
        return vec![Region::Span(0); n];
    }
    let span_of = |a: usize, b: usize| {
        if (a + 1) % np == b {
            a
        } else if (b + 1) % np == a {
            b
        } else {
            a.min(b)
        }
    };
    (0..n)
        .map(|i| match contact[i] {
            Some(j) => Region::Wrap(j),
            None => {
                let back = (1..n).find_map(|k| contact[(i + n - k) % n]).unwrap_or(0);
                let fwd = (1..n).find_map(|k| contact[(i + k) % n]).unwrap_or(0);
                Region::Span(span_of(back, fwd))
            }
        })
        .collect()
}

/// Centred difference along the periodic body index (spacing 1): entry
/// (i, j). Non-dissipative, so the transport adds no damping of its own. (A
/// spectral derivative, the exact logarithm of the one-body shift, couples
/// the whole loop and gave spurious low modes across the span/wrap junctions.)
fn derivative(n: usize, i: usize, j: usize) -> f64 {
    if j == (i + 1) % n {
        0.5
    } else if j == (i + n - 1) % n {
        -0.5
    } else {
        0.0
    }
}

/// The system matrix of the analysis (row-major), and the transport rate.
/// At rest: the Jacobian. Running: in body frames, with transport.
fn system_matrix(lin: &Linearisation, transport: bool) -> (Vec<f64>, f64) {
    let dim = lin.dim;
    let mut a = lin.jacobian.clone();
    if !transport {
        return (a, 0.0);
    }
    let n = lin.n;
    // Rotate every body's (x, y) and (vx, vy) into its tangent/normal frame:
    // A <- R^T A R, then the frame's own rotation: - phi' G on both blocks.
    let rot: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            let phi = lin.y[lin.body(i, 2)];
            (phi.cos(), phi.sin())
        })
        .collect();
    for (i, &(c, s)) in rot.iter().enumerate() {
        for off in [0, 3] {
            let (p, q) = (lin.body(i, off), lin.body(i, off + 1));
            // rows: R^T
            for col in 0..dim {
                let (u, v) = (a[p * dim + col], a[q * dim + col]);
                a[p * dim + col] = c * u + s * v;
                a[q * dim + col] = -s * u + c * v;
            }
            // columns: R
            for row in 0..dim {
                let (u, v) = (a[row * dim + p], a[row * dim + q]);
                a[row * dim + p] = c * u + s * v;
                a[row * dim + q] = -s * u + c * v;
            }
        }
        let w = lin.y[lin.body(i, 5)];
        for off in [0, 3] {
            let (p, q) = (lin.body(i, off), lin.body(i, off + 1));
            a[p * dim + q] += w;
            a[q * dim + p] -= w;
        }
    }
    // Bodies passing a place per second, with the direction along the index:
    // one over the body-passing period of the Floquet analysis.
    let (period, dir) = floquet::passing_period(lin);
    let rate = dir / period;
    // Transport: perturbations at fixed places, d/dt = material - rate D.
    // The creep states are left out: a body's creep is reset when it leaves
    // the pulley, so it does not travel with the belt as a field.
    for i in 0..n {
        for j in [(i + n - 1) % n, (i + 1) % n] {
            let d = rate * derivative(n, i, j);
            if d == 0.0 {
                continue;
            }
            for k in 0..6 {
                a[lin.body(i, k) * dim + lin.body(j, k)] -= d;
            }
        }
    }
    (a, rate)
}

/// Splits off states whose row or column is zero off the diagonal; returns
/// the kept indices and the split-off diagonal values.
fn reduce(a: &[f64], dim: usize) -> (Vec<usize>, Vec<f64>) {
    let mut keep: Vec<bool> = vec![true; dim];
    let mut split = Vec::new();
    loop {
        let mut changed = false;
        for k in 0..dim {
            if !keep[k] {
                continue;
            }
            let row_zero = (0..dim).all(|c| c == k || !keep[c] || a[k * dim + c] == 0.0);
            let col_zero = (0..dim).all(|r| r == k || !keep[r] || a[r * dim + k] == 0.0);
            if row_zero || col_zero {
                keep[k] = false;
                split.push(a[k * dim + k]);
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    ((0..dim).filter(|&k| keep[k]).collect(), split)
}

/// Diagonal similarity scaling (powers of 2, row and column norms brought
/// together, as LAPACK's balancing), so that the eigen-solve sees entries of
/// comparable size (the raw Jacobian spans 1 to ~1e10). Returns the scales d:
/// the balanced matrix is D^-1 A D.
fn balance(a: &mut Mat<f64>) -> Vec<f64> {
    let n = a.nrows();
    let mut d = vec![1.0; n];
    for _ in 0..100 {
        let mut done = true;
        for i in 0..n {
            let mut c = 0.0;
            let mut r = 0.0;
            for j in 0..n {
                if j != i {
                    c += a[(j, i)].abs();
                    r += a[(i, j)].abs();
                }
            }
            if c == 0.0 || r == 0.0 {
                continue;
            }
            let mut f = 1.0;
            let s = c + r;
            let (mut c2, mut r2) = (c, r);
            while c2 < r2 / 2.0 {
                c2 *= 2.0;
                r2 /= 2.0;
                f *= 2.0;
            }
            while c2 >= r2 * 2.0 {
                c2 /= 2.0;
                r2 *= 2.0;
                f /= 2.0;
            }
            if (c2 + r2) < 0.95 * s {
                done = false;
                d[i] *= f;
                for j in 0..n {
                    a[(i, j)] /= f;
                    a[(j, i)] *= f;
                }
            }
        }
        if done {
            break;
        }
    }
    d
}

/// Modes of the linearised drive.
pub fn analyse(lin: &Linearisation, opts: &Options) -> Result<Modes, String> {
    let dim = lin.dim;
    let (a, rate) = system_matrix(lin, opts.transport);
    let (keep, split) = reduce(&a, dim);
    let m = keep.len();
    let mut red = Mat::<f64>::from_fn(m, m, |r, c| a[keep[r] * dim + keep[c]]);
    if !red.as_ref().is_all_finite() {
        return Err("the Jacobian has non-finite entries at this state".into());
    }
    let scale = balance(&mut red);
    let evd = Eigen::new_from_real(red.as_ref())
        .map_err(|e| format!("eigen-decomposition failed: {e:?}"))?;
    let w_zero = TAU * opts.zero_frequency_hz;
    let mut out = Modes {
        removed_states: dim - m,
        reduced_dim: m,
        body_rate: rate,
        ..Modes::default()
    };
    for d in split {
        if d.abs() < w_zero {
            out.zero_modes += 1;
        } else {
            out.overdamped += 1;
        }
    }
    let regions = regions(lin);
    let s = evd.S();
    let u = evd.U();
    let mut cands = Vec::new();
    for k in 0..m {
        let lam = s[k];
        let mag = lam.re.hypot(lam.im);
        if mag < w_zero {
            out.zero_modes += 1;
            continue;
        }
        if lam.im == 0.0 {
            out.overdamped += 1;
            continue;
        }
        if lam.im < 0.0 {
            continue; // the conjugate of a pair already counted
        }
        if mag / TAU > opts.max_frequency_hz {
            out.above_limit += 1;
            continue;
        }
        let mut vec = vec![faer::c64::new(0.0, 0.0); dim];
        for (r, &idx) in keep.iter().enumerate() {
            vec[idx] = u[(r, k)] * scale[r];
        }
        cands.push(degenerate::Candidate {
            lambda: lam,
            vec,
            shape: Vec::new(),
        });
    }
    cands.sort_by(|a, b| a.lambda.norm().total_cmp(&b.lambda.norm()));
    out.split_pairs = degenerate::localise(lin, &regions, &mut cands, opts.transport);
    for c in &cands {
        let (lam, vec) = (c.lambda, &c.vec);
        let mag = lam.norm();
        let (part, share) = classify(lin, &regions, vec, opts.transport);
        out.modes.push(Mode {
            frequency_hz: mag / TAU,
            damping_ratio: -lam.re / mag,
            damped_hz: lam.im / TAU,
            part,
            share,
            shares: shares(lin, &regions, vec, opts.transport),
            shape: Vec::new(),
        });
    }
    out.modes
        .sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
    Ok(out)
}

/// Kinetic energy of the mode with (complex) eigenvector `v` by part of
/// the drive: every body's motion along and across the belt and its spin,
/// summed by region, and every free pulley's rotation (with the wrapped
/// belt moving with its surface), decoupler rotor and tensioner arm.
/// `local`: the body velocities are already in body frames. Parts with no
/// energy are left out; the order is fixed (spans, wraps, pulleys, arms,
/// pitching).
pub fn energies(
    lin: &Linearisation,
    regions: &[Region],
    v: &[faer::c64],
    local: bool,
) -> Vec<(Part, f64)> {
    let np = lin.pulleys.len();
    // [span transverse, span longitudinal] per span, [radial, tangential]
    // per wrap, rotation per pulley, pitching.
    let mut span = vec![[0.0; 2]; np.max(1)];
    let mut wrap = vec![[0.0; 2]; np];
    let mut pulley = vec![0.0; np];
    let mut pitching = 0.0;
    for (i, region) in regions.iter().enumerate() {
        let (vx, vy, w) = (v[lin.body(i, 3)], v[lin.body(i, 4)], v[lin.body(i, 5)]);
        let (t, nrm) = if local {
            (vx, vy)
        } else {
            let phi = lin.y[lin.body(i, 2)];
            let (c, s) = (phi.cos(), phi.sin());
            (vx * c + vy * s, vy * c - vx * s)
        };
        let ke_t = lin.mass * t.norm_sqr();
        let ke_n = lin.mass * nrm.norm_sqr();
        pitching += lin.inertia * w.norm_sqr();
        match *region {
            Region::Span(k) => {
                span[k][0] += ke_n;
                span[k][1] += ke_t;
            }
            Region::Wrap(j) => {
                wrap[j][0] += ke_n;
                // A body that moves with the pulley surface belongs to the
                // pulley's rotation; only the motion against it is the
                // creep spring's.
                let p = &lin.pulleys[j];
                let surface = v[lin.pulley(j).1] * (p.side * p.lever);
                if !p.speed_driven && (t - surface).norm() < 0.5 * t.norm() {
                    pulley[j] += ke_t;
                } else {
                    wrap[j][1] += ke_t;
                }
            }
        }
    }
    let mut arm = vec![0.0; np];
    for (j, p) in lin.pulleys.iter().enumerate() {
        if !p.speed_driven {
            pulley[j] += p.inertia * v[lin.pulley(j).1].norm_sqr();
        }
        // a decoupler's rotor turns with its pulley (the alternator's rotor)
        if let Some((o, inertia)) = p.decoupler {
            pulley[j] += inertia * v[o + 1].norm_sqr();
        }
        if let Some((o, inertia)) = p.arm {
            arm[j] += inertia * v[o + 1].norm_sqr();
        }
    }
    let mut out = Vec::new();
    for (k, s) in span.iter().enumerate() {
        out.push((Part::SpanTransverse(k + 1), s[0]));
        out.push((Part::SpanLongitudinal(k + 1), s[1]));
    }
    for (j, w) in wrap.iter().enumerate() {
        out.push((Part::WrapRadial(j + 1), w[0]));
        out.push((Part::WrapTangential(j + 1), w[1]));
    }
    for (j, &e) in pulley.iter().enumerate() {
        out.push((Part::PulleyRotation(j + 1), e));
    }
    for (j, &e) in arm.iter().enumerate() {
        out.push((Part::Arm(j + 1), e));
    }
    out.push((Part::BeltPitching, pitching));
    out.retain(|x| x.1 > 0.0);
    out
}

/// [`energies`] as shares of the total, largest first.
pub fn shares(
    lin: &Linearisation,
    regions: &[Region],
    v: &[faer::c64],
    local: bool,
) -> Vec<(Part, f64)> {
    let mut parts = energies(lin, regions, v, local);
    let total: f64 = parts.iter().map(|x| x.1).sum();
    parts.iter_mut().for_each(|x| x.1 /= total);
    parts.sort_by(|a, b| b.1.total_cmp(&a.1));
    parts
}

/// What moves most in the mode with (complex) eigenvector `v`: the part
/// with the largest share of its kinetic energy ([`energies`]), and that
/// share. `local`: the body velocities are already in body frames.
pub fn classify(
    lin: &Linearisation,
    regions: &[Region],
    v: &[faer::c64],
    local: bool,
) -> (Part, f64) {
    let parts = energies(lin, regions, v, local);
    let total: f64 = parts.iter().map(|x| x.1).sum();
    let families = [
        Family::Rotation,
        Family::Transverse,
        Family::Arm,
        Family::Artefact,
    ];
    let family_energy = |f: Family| -> f64 {
        parts
            .iter()
            .filter(|x| x.0.family() == f)
            .map(|x| x.1)
            .sum()
    };
    let mut family = Family::Artefact;
    let mut most = 0.0;
    for f in families {
        let e = family_energy(f);
        if e > most {
            (family, most) = (f, e);
        }
    }
    let mut best = (Part::BeltPitching, 0.0);
    for &(part, e) in parts.iter().filter(|x| x.0.family() == family) {
        if e > best.1 {
            best = (part, e);
        }
    }
    let share = if total > 0.0 { best.1 / total } else { 0.0 };
    // All free pulleys' surfaces moving together, within a factor 2 and in
    // phase: the belt turns round as a whole.
    if let Part::PulleyRotation(_) = best.0 {
        let surf: Vec<faer::c64> = lin
            .pulleys
            .iter()
            .enumerate()
            .filter(|(_, p)| !p.speed_driven)
            .map(|(j, p)| v[lin.pulley(j).1] * (p.side * p.lever))
            .collect();
        // (a speed-driven pulley holds the belt: no rigid rotation then)
        let all_free = lin.pulleys.iter().all(|p| !p.speed_driven);
        let together = all_free
            && surf.len() >= 2
            && surf.iter().all(|a| {
                surf.iter()
                    .all(|b| (a * b.conj()).re > 0.0 && a.norm() < 2.0 * b.norm())
            });
        if together {
            return (Part::RigidRotation, share);
        }
    }
    (best.0, share)
}
