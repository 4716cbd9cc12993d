//! The drive as installed: the installation tension of a belt of given
//! natural length, and the angle a tensioner arm on a spring given by its
//! nominal torque takes (eq. of the static moment balance about the pivot).

use super::*;

/// The drive as installed: with `belt.natural_length` given (> 0), the
/// parameters with the preload replaced by the installation tension of a
/// belt of that natural length, and the length cleared; with a tensioner
/// spring given by its nominal torque (`TensionerArm::nominal`), the arm
/// turned to where that spring balances the belt; otherwise `params`
/// unchanged. `params` must have passed [`DriveParams::validate`].
///
/// The tension is the continuum's: T = EA (L_p(T) / L0 - 1), L_p the belt's
/// path at its pitch line ([`pitch_length`]: the pulleys' radii, each span
/// with its static sag, which shortens as T grows). It does not depend on
/// the mesh or the contact stiffness; the mounted chain then carries T
/// (docs/model.md "Layout and preload"). T - EA (L_p(T) / L0 - 1) grows
/// with T (an arm that yields shortens the path): bisection.
///
/// An arm on a nominal spring sits where its spring and stops balance the
/// moment of the belt's hub force T (u_out - u_in) about the pivot (u the
/// spans' directions of travel; the static sag's tilt of the spans, below
/// 1e-3 rad, left out), found by bisection at each tension (several such
/// arms: in turn until none moves). The installed parameters have the arm
/// drawn there: its pulley centre turned by the arm's angle, its stops and
/// nominal angle counted from it ([`installed_arm_angle`] recovers the
/// angle).
pub fn installed(params: &DriveParams) -> Result<std::borrow::Cow<'_, DriveParams>, ParamError> {
    let target = params.belt.natural_length;
    let mut arms = NominalArms::new(params)?;
    if target <= 0.0 && arms.0.is_empty() {
        return Ok(std::borrow::Cow::Borrowed(params));
    }
    // With an arm whose spring follows from the preload, the arm's angle
    // would be a second unknown without the spring to find it.
    if target > 0.0 {
        if let Some(j) = params
            .pulleys
            .iter()
            .position(|p| p.arm.is_some_and(|a| a.nominal.is_none()))
        {
            return Err(param_error(
                Param::BeltNaturalLength,
                msg![
                    "needs the tensioner's spring as built (",
                    Param::PulleyArmNominalTorque(j),
                    " at ",
                    Param::PulleyArmNominalAngle(j),
                    "): without it the spring's free angle follows from the installation \
                     tension, so ",
                    Param::BeltPreload,
                    " must set the tension",
                ],
            ));
        }
    }
    let mut p = params.clone();
    p.belt.natural_length = 0.0;
    if target <= 0.0 {
        arms.balance(&mut p, params.belt.preload)?;
        arms.draw_installed(&mut p);
        return Ok(std::borrow::Cow::Owned(p));
    }
    let ea = params.belt.ea;
    let fixed = if arms.0.is_empty() {
        Some(PitchPath::new(params)?)
    } else {
        None
    };
    // the belt path at tension t, the arms balanced at t; 0 when an arm
    // finds no balance at a tension above 0: the belt would push it beyond
    // any, so the belt's tension is lower
    let mut path_at = |q: &mut DriveParams, t: f64| -> Result<f64, ParamError> {
        match &fixed {
            Some(path) => Ok(path.length(params, t)),
            None => match arms.balance(q, t) {
                Ok(()) => Ok(PitchPath::new(q)?.length(q, t)),
                Err(_) if t > 0.0 => Ok(0.0),
                Err(e) => Err(e),
            },
        }
    };
    let straight = path_at(&mut p, 0.0)?;
    if straight <= target {
        return Err(param_error(
            Param::BeltNaturalLength,
            format!(
                "a belt of {target} m must be shorter than its path round the pulleys at their \
                 radii ({straight:.6} m), else it hangs slack: give a shorter belt or move the \
                 pulleys apart"
            ),
        ));
    }
    let (mut lo, mut hi) = (0.0, 0.5 * ea);
    if hi - ea * (path_at(&mut p, hi)? / target - 1.0) <= 0.0 {
        return Err(param_error(
            Param::BeltNaturalLength,
            msg![
                format!(
                    "a belt of {target} m stretched onto its {straight:.6} m path would carry \
                     more than half of "
                ),
                Param::BeltEa,
                ": it must be longer (lengths are in metres), or the pulleys closer",
            ],
        ));
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid - ea * (path_at(&mut p, mid)? / target - 1.0) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
        if hi - lo <= 1e-14 * ea {
            break;
        }
    }
    p.belt.preload = 0.5 * (lo + hi);
    if !arms.0.is_empty() {
        let t = p.belt.preload;
        arms.balance(&mut p, t)?;
        arms.draw_installed(&mut p);
    }
    Ok(std::borrow::Cow::Owned(p))
}

/// Angle of the installed arm of pulley `j` from where `params` draws it
/// (`pulley[j].arm.installedAngle`): the turn about the pivot from the
/// centre in `params` to the one in `installed` (their [`installed`]
/// parameters), counterclockwise positive; 0 without an arm.
pub fn installed_arm_angle(params: &DriveParams, installed: &DriveParams, j: usize) -> f64 {
    let (Some(a), Some(b)) = (params.pulleys.get(j), installed.pulleys.get(j)) else {
        return 0.0;
    };
    let Some(arm) = a.arm else {
        return 0.0;
    };
    let (u, v) = (
        [a.x - arm.pivot[0], a.y - arm.pivot[1]],
        [b.x - arm.pivot[0], b.y - arm.pivot[1]],
    );
    (u[0] * v[1] - u[1] * v[0]).atan2(u[0] * v[0] + u[1] * v[1])
}

/// Tensioner arms whose spring is given by its nominal torque: each one's
/// law in the frame of the arm as drawn (the spring's free angle set) and
/// its angle from there.
struct NominalArms(Vec<(usize, Arm, f64)>);

/// Step of the search for an arm's balance [rad].
const ARM_SEARCH_STEP: f64 = 0.01;

impl NominalArms {
    fn new(params: &DriveParams) -> Result<Self, ParamError> {
        let mut arms = Vec::new();
        for (j, q) in params.pulleys.iter().enumerate() {
            let Some(a) = q.arm.as_ref().filter(|a| a.nominal.is_some()) else {
                continue;
            };
            let mut law = Arm::new(a, [q.x, q.y]);
            // which way the belt turns the arm, from the drawn path: the
            // spring turns it back
            let m = Self::hub_moment(&mut params.clone(), j, &law, 0.0, 1.0)?;
            if m.abs() < 1e-9 * law.length {
                return Err(param_error(
                    Param::PulleyArmNominalTorque(j),
                    msg![
                        "cannot be applied: the belt's hub force on ",
                        Part::Pulley(j),
                        " passes through the arm's pivot (",
                        Param::PulleyArmPivotX(j),
                        ", ",
                        Param::PulleyArmPivotY(j),
                        "), so the spring has no side to press the pulley to",
                    ],
                ));
            }
            law.free_angle = law.free_angle_for(m);
            arms.push((j, law, 0.0));
        }
        Ok(Self(arms))
    }

    /// Moment about the pivot of the belt's hub force on pulley `j` at
    /// tension `t` with the arm at `angle` (`q`'s pulley `j` moved there).
    fn hub_moment(
        q: &mut DriveParams,
        j: usize,
        law: &Arm,
        angle: f64,
        t: f64,
    ) -> Result<f64, ParamError> {
        let (c, _) = law.centre(angle);
        q.pulleys[j].x = c[0];
        q.pulleys[j].y = c[1];
        let radii: Vec<f64> = q.pulleys.iter().map(|p| p.radius).collect();
        let (spans, _) = path_in_belt_order(q, &radii)?;
        let dir = |a: f64| [a.cos(), a.sin()];
        let (mut f_in, mut f_out) = ([0.0; 2], [0.0; 2]);
        for s in &spans {
            if s.to == j {
                f_in = dir(s.angle);
            }
            if s.from == j {
                f_out = dir(s.angle);
            }
        }
        let f = [t * (f_out[0] - f_in[0]), t * (f_out[1] - f_in[1])];
        Ok(law.moment(angle, f).0)
    }

    /// Turns each arm (in `q`) to where its spring and stops balance the
    /// belt at tension `t`, in turn until none moves.
    fn balance(&mut self, q: &mut DriveParams, t: f64) -> Result<(), ParamError> {
        for (j, law, angle) in &self.0 {
            let (c, _) = law.centre(*angle);
            q.pulleys[*j].x = c[0];
            q.pulleys[*j].y = c[1];
        }
        for _ in 0..100 {
            let mut moved: f64 = 0.0;
            for (j, law, angle) in &mut self.0 {
                let a = Self::balance_one(q, *j, law, *angle, t)?;
                moved = moved.max((a - *angle).abs());
                *angle = a;
            }
            if moved <= 1e-13 {
                break;
            }
        }
        Ok(())
    }

    /// The angle, searched from `from` in steps of [`ARM_SEARCH_STEP`] up
    /// to a quarter turn the way the net moment turns the arm, then
    /// bisected, where the arm's moment (spring and stops) balances the
    /// belt's at tension `t`; `q`'s pulley `j` left there.
    fn balance_one(
        q: &mut DriveParams,
        j: usize,
        law: &Arm,
        from: f64,
        t: f64,
    ) -> Result<f64, ParamError> {
        let net = |q: &mut DriveParams, a: f64| -> Result<f64, ParamError> {
            Ok(law.torque(a, 0.0).torque + Self::hub_moment(q, j, law, a, t)?)
        };
        let r0 = net(q, from)?;
        let dir = if r0 > 0.0 { 1.0 } else { -1.0 };
        let (mut a, mut b) = (from, from);
        let mut found = r0 == 0.0;
        let steps = (0.5 * std::f64::consts::PI / ARM_SEARCH_STEP).ceil() as usize;
        for k in 1..=steps {
            if found {
                break;
            }
            a = b;
            b = from + dir * ARM_SEARCH_STEP * k as f64;
            let r = net(q, b).map_err(|_| no_balance(j, t, None))?;
            found = r * dir <= 0.0;
        }
        if !found {
            return Err(no_balance(j, t, Some(b)));
        }
        // bisection on [a, b]: the net moment turns the arm towards b at a
        for _ in 0..200 {
            let mid = 0.5 * (a + b);
            if net(q, mid)? * dir > 0.0 {
                a = mid;
            } else {
                b = mid;
            }
            if (b - a).abs() <= 1e-15 {
                break;
            }
        }
        let angle = 0.5 * (a + b);
        Self::hub_moment(q, j, law, angle, t)?;
        Ok(angle)
    }

    /// `q` with each arm drawn where it is installed: its stops and nominal
    /// angle counted from there (its pulley centre is there already).
    fn draw_installed(&self, q: &mut DriveParams) {
        for (j, _, angle) in &self.0 {
            if let Some(a) = q.pulleys[*j].arm.as_mut() {
                if let Some(s) = a.stops.as_mut() {
                    s.min_angle -= angle;
                    s.max_angle -= angle;
                }
                if let Some(n) = a.nominal.as_mut() {
                    n.angle -= angle;
                }
            }
        }
    }
}

/// No balance of the arm of pulley `j` at tension `t` (searched up to
/// `reached`, or until the belt path broke).
fn no_balance(j: usize, t: f64, reached: Option<f64>) -> ParamError {
    let how = match reached {
        Some(a) => format!(
            "turned up to {:.0} deg from where it is drawn",
            a.to_degrees()
        ),
        None => "turned until the belt path breaks".to_string(),
    };
    param_error(
        Param::PulleyArmNominalTorque(j),
        msg![
            "the arm of ",
            Part::Pulley(j),
            format!(" finds no static balance at a belt tension of {t:.1} N ({how}): its spring ("),
            Param::PulleyArmStiffness(j),
            " and this torque at ",
            Param::PulleyArmNominalAngle(j),
            ") and stops never balance the belt's hub force; check the torque, the nominal angle \
             (counterclockwise positive) and the pivot",
        ],
    )
}

/// The belt's length at its pitch line under the tension `tension` [m]:
/// spans and wraps at the pulleys' radii, each span's static sag added
/// (the parabola of [`sag_shape`], longer than its chord by s^2 L^3 / 6).
pub fn pitch_length(params: &DriveParams, tension: f64) -> Result<f64, ParamError> {
    Ok(PitchPath::new(params)?.length(params, tension))
}

/// The natural length of the belt whose installation tension is
/// `params.belt.preload` (`belt.length`): L_p / (1 + T/EA), the inverse of
/// [`installed`].
pub fn natural_length(params: &DriveParams) -> Result<f64, ParamError> {
    let b = &params.belt;
    Ok(pitch_length(params, b.preload)? / (1.0 + b.preload / b.ea))
}

/// The belt path at the pulleys' radii.
struct PitchPath {
    spans: Vec<Span>,
    wrapped: f64,
}

impl PitchPath {
    fn new(params: &DriveParams) -> Result<Self, ParamError> {
        let radii: Vec<f64> = params.pulleys.iter().map(|p| p.radius).collect();
        let (spans, wraps) = path_in_belt_order(params, &radii)?;
        let wrapped = wraps.iter().map(|w| w.angle * radii[w.pulley]).sum();
        Ok(Self { spans, wrapped })
    }

    fn length(&self, params: &DriveParams, tension: f64) -> f64 {
        let b = &params.belt;
        let rho = b.mass_per_length / (1.0 + tension / b.ea);
        let spans: f64 = self
            .spans
            .iter()
            .map(|sp| {
                let (s, _) = sag_shape(params, sp, rho, tension);
                sp.length * (1.0 + s * s * sp.length * sp.length / 6.0)
            })
            .sum();
        spans + self.wrapped
    }
}
