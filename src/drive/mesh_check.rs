//! Is the mesh fine enough for the spans? The warnings that name
//! `belt.nBodies` (docs/model.md, "Body passing: when the mesh is too
//! coarse").
//!
//! The bodies land on and leave every pulley at the body-passing frequency
//! f_bp = v / l (belt speed over the stretched pitch): the chain's polygon
//! action, which a continuous belt does not have, moves each span's ends at
//! f_bp (transversely by l^2 / (8 rho), along the span by ~ l^3 / rho^2) and
//! modulates its tension. A span of free length L at the tension T is a
//! moving string with the modes f_n = n (c^2 - v^2) / (2 L c),
//! c = sqrt(T / rho'), rho' the stretched belt's mass per length. Two
//! resonances of its first modes then come from the mesh alone:
//!
//! * direct: f_bp = f_1, the polygon forcing the fundamental;
//! * parametric: f_bp = 2 f_n, the tension modulated at twice a mode's
//!   frequency (the principal zone of Mathieu's equation), which makes the
//!   running state unstable.
//!
//! With n* = f_bp / (2 f_1) = (L / l) v c / (c^2 - v^2) (the mode number at
//! half the body-passing frequency; L / l is the number of bodies on the
//! span) the first is n* = 1/2, the second n* = n. A span whose n* lies
//! within [`RESONANCE_BAND`] of 1/2, 1, 2 or 3 is warned about, with the
//! body count that puts half the body-passing frequency above the third
//! mode's band (n* >= 3 (1 + band)).
//!
//! Second rule, the span's own resolution: N = L / l straight bodies with
//! their mass spread along them (a consistent mass) give the string's mode n
//! high by about (n pi / N)^2 / 24; a span with fewer than
//! [`MIN_SPAN_BODIES`] bodies has its third mode more than
//! [`MODE_ERROR`] off.
//!
//! Both are checked at the preload (the running tensions depend on loads
//! the mounting does not know) and at the highest belt speed the parameters
//! set: the built-in speed ramp `pulley[j].omegaRamp` of the speed-driven
//! pulleys (a speed given only through the speed input is not known at
//! initialisation, and a drive without a speed-driven pulley is not
//! checked for the first rule).

use crate::model::layout::Layout;
use crate::model::param_id::{msg, Message, Param, Part};
use crate::model::params::{DriveParams, MAX_BODIES};
use std::f64::consts::PI;

/// Half-width of the frequency band around a resonance that is warned
/// about, relative: the running tension of a span lies off its preload by
/// the loads' share (-22 % to +37 % on the shipped accessory sets at idle),
/// and f ~ sqrt(T) moves its modes by sqrt(1 +- 0.3) = 1 +- 0.15.
pub const RESONANCE_BAND: f64 = 0.15;

/// Highest span mode whose resonances with the body passing are checked.
pub const CHECKED_MODES: u32 = 3;

/// Largest relative error of the span's third mode the mesh may make: the
/// tolerance of the modal analysis against the string frequency
/// (tests/modes.rs).
pub const MODE_ERROR: f64 = 0.02;

/// Fewest bodies per span for mode [`CHECKED_MODES`] within
/// [`MODE_ERROR`]: (n pi / N)^2 / 24 <= e, N >= n pi / sqrt(24 e) (13.6).
pub fn min_span_bodies() -> f64 {
    CHECKED_MODES as f64 * PI / (24.0 * MODE_ERROR).sqrt()
}

/// One span's figures at the preload and the checked belt speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpanMesh {
    /// Pulleys the span leaves and reaches.
    pub from: usize,
    /// ...
    pub to: usize,
    /// Bodies on the span, L / l (stretched pitch).
    pub bodies: f64,
    /// First mode of the moving string at the preload [Hz] (0 when the
    /// belt speed reaches the wave speed).
    pub f1: f64,
    /// Body-passing frequency [Hz] (0 at rest).
    pub f_bp: f64,
}

impl SpanMesh {
    /// n* = f_bp / (2 f_1): the mode number at half the body-passing
    /// frequency.
    pub fn n_star(&self) -> f64 {
        self.f_bp / (2.0 * self.f1)
    }

    /// The resonance n* lies nearest within [`RESONANCE_BAND`], if any:
    /// (n, relative distance), n = 0 for the direct resonance of the
    /// fundamental (f_bp = f_1), n >= 1 for the parametric one of mode n
    /// (f_bp = 2 f_n).
    pub fn resonance(&self) -> Option<(u32, f64)> {
        if self.f_bp <= 0.0 || self.f1 <= 0.0 {
            return None;
        }
        let x = self.n_star();
        (0..=CHECKED_MODES)
            .map(|n| {
                let at = if n == 0 { 0.5 } else { n as f64 };
                (n, x / at - 1.0)
            })
            .filter(|(_, d)| d.abs() <= RESONANCE_BAND)
            .min_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
    }
}

/// The highest belt speed the parameters set [m/s]: |omegaRamp| r over the
/// speed-driven pulleys (0 if none).
pub fn belt_speed(params: &DriveParams) -> f64 {
    params
        .pulleys
        .iter()
        .filter(|q| q.speed_driven)
        .map(|q| (q.omega_ramp * q.radius).abs())
        .fold(0.0, f64::max)
}

/// Every free span's figures.
pub fn spans(params: &DriveParams, layout: &Layout) -> Vec<SpanMesh> {
    let b = &params.belt;
    let strain = b.preload / b.ea;
    let pitch = layout.body_length * (1.0 + strain);
    let mass = b.mass_per_length / (1.0 + strain);
    let c = (b.preload / mass).sqrt();
    let v = belt_speed(params);
    layout
        .spans
        .iter()
        .map(|s| SpanMesh {
            from: s.from,
            to: s.to,
            bodies: s.length / pitch,
            f1: if v < c {
                (c * c - v * v) / (2.0 * s.length * c)
            } else {
                0.0
            },
            f_bp: v / pitch,
        })
        .collect()
}

/// The warnings naming `belt.nBodies`: at most one per rule, naming the
/// worst span and the body count that clears every span.
pub fn warnings(params: &DriveParams, layout: &Layout) -> Vec<Message> {
    let n = params.belt.n_bodies;
    let spans = spans(params, layout);
    let mut out = Vec::new();
    let min_bodies = min_span_bodies();
    let coarse: Vec<&SpanMesh> = spans.iter().filter(|s| s.bodies < min_bodies).collect();
    if let Some(worst) = coarse.iter().min_by(|a, b| a.bodies.total_cmp(&b.bodies)) {
        let need = (n as f64 * min_bodies / worst.bodies).ceil() as usize;
        let err = (CHECKED_MODES as f64 * PI / worst.bodies).powi(2) / 24.0;
        out.push(msg![
            Param::BeltBodies,
            format!(
                " = {n}: {} of the {} free spans hold fewer than {min_bodies:.1} bodies, too few \
                 for their first {CHECKED_MODES} transverse modes; the span from ",
                coarse.len(),
                spans.len()
            ),
            Part::Pulley(worst.from),
            " to ",
            Part::Pulley(worst.to),
            format!(
                " holds {:.1}, and its mode {CHECKED_MODES} comes out about {:.1} % high; ",
                worst.bodies,
                100.0 * err
            ),
            Param::BeltBodies,
            format!(
                " >= {} gives every span {min_bodies:.1}",
                need.min(MAX_BODIES)
            ),
        ]);
    }
    let resonant: Vec<(&SpanMesh, (u32, f64))> = spans
        .iter()
        .filter_map(|s| s.resonance().map(|r| (s, r)))
        .collect();
    let Some(&(s, (mode, off))) = resonant
        .iter()
        .min_by(|a, b| a.1 .1.abs().total_cmp(&b.1 .1.abs()))
    else {
        return out;
    };
    let what = if mode == 0 {
        format!(
            " pass a point of the path at {:.0} Hz, within {:.0} % of the first transverse mode \
             of the span from ",
            s.f_bp,
            100.0 * off.abs().max(0.01)
        )
    } else {
        format!(
            " pass a point of the path at {:.0} Hz, and half of that, {:.0} Hz, lies within \
             {:.0} % of transverse mode {mode} of the span from ",
            s.f_bp,
            0.5 * s.f_bp,
            100.0 * off.abs().max(0.01)
        )
    };
    let f_mode = if mode == 0 { s.f1 } else { mode as f64 * s.f1 };
    let n_star_min = spans
        .iter()
        .filter(|s| s.f1 > 0.0)
        .map(SpanMesh::n_star)
        .fold(f64::INFINITY, f64::min);
    let clear = (n as f64 * CHECKED_MODES as f64 * (1.0 + RESONANCE_BAND) / n_star_min).ceil();
    let advice = if clear as usize <= MAX_BODIES {
        format!(
            " >= {clear:.0} puts half the body-passing frequency above mode {CHECKED_MODES} of \
             every span"
        )
    } else {
        format!(
            " would need {clear:.0} (more than {MAX_BODIES}) to put half the body-passing \
             frequency above mode {CHECKED_MODES} of every span"
        )
    };
    let others = match resonant.len() {
        1 => String::new(),
        2 => " (and of one more span)".into(),
        k => format!(" (and of {} more spans)", k - 1),
    };
    out.push(msg![
        Param::BeltBodies,
        format!(
            " = {n}: at the belt speed {:.2} m/s the bodies",
            belt_speed(params)
        ),
        what,
        Part::Pulley(s.from),
        " to ",
        Part::Pulley(s.to),
        format!(
            " ({f_mode:.0} Hz at the preload){others}: the mesh can drive that mode (a {} \
             a continuous belt does not have); ",
            if mode == 0 {
                "resonance"
            } else {
                "parametric resonance"
            }
        ),
        Param::BeltBodies,
        advice,
    ]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span(bodies: f64, f1: f64, f_bp: f64) -> SpanMesh {
        SpanMesh {
            from: 0,
            to: 1,
            bodies,
            f1,
            f_bp,
        }
    }

    #[test]
    fn resonances_at_half_one_two_three() {
        // n* = f_bp / (2 f1)
        assert_eq!(span(30.0, 100.0, 0.0).resonance(), None);
        assert_eq!(span(30.0, 100.0, 100.0).resonance(), Some((0, 0.0)));
        assert_eq!(span(30.0, 100.0, 400.0).resonance(), Some((2, 0.0)));
        let (n, d) = span(30.0, 100.0, 2.0 * 1.79 * 100.0).resonance().unwrap();
        assert_eq!(n, 2);
        assert!((d + 0.105).abs() < 1e-12);
        // between the bands: 1.15 .. 1.7 clear
        assert_eq!(span(30.0, 100.0, 2.0 * 1.5 * 100.0).resonance(), None);
        // above mode 3's band
        assert_eq!(span(30.0, 100.0, 2.0 * 3.5 * 100.0).resonance(), None);
        // below the fundamental's direct band
        assert_eq!(span(30.0, 100.0, 2.0 * 0.4 * 100.0).resonance(), None);
    }

    #[test]
    fn fewest_bodies_per_span_for_three_modes_within_two_percent() {
        let n = min_span_bodies();
        assert!((n - 13.6).abs() < 0.05, "{n}");
        // the consistent-mass chain's dispersion, exact: omega^2 / omega_string^2
        // = 6 (1 - cos k) / (k^2 (2 + cos k)), k = n pi / N
        let k = 3.0 * PI / n;
        let exact = (6.0 * (1.0 - k.cos()) / (k * k * (2.0 + k.cos()))).sqrt() - 1.0;
        assert!((exact - MODE_ERROR).abs() < 0.1 * MODE_ERROR, "{exact}");
    }
}
