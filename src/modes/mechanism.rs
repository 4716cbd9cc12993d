//! Why a running state is unstable, where the discretisation explains it
//! (docs/modes.md, "When the running state is not periodic").
//!
//! The bodies land on and leave every pulley once per body-passing period P
//! (docs/model.md, "Body passing"): the chain's polygon modulates each span's
//! tension at f_bp = 1/P and its harmonics, which a continuous belt does not
//! do. A span mode that grows at half that frequency (Floquet multiplier
//! negative real: the principal parametric resonance of Mathieu's equation),
//! or at 3/2 of it, is the mesh's parametric resonance; one at f_bp itself
//! is the polygon forcing the mode directly. Either is a property of the
//! mesh (`belt.nBodies`), not of the drive. A growing mode at none of these
//! frequencies may still be the mesh's: the body passing can also couple
//! two modes whose frequencies sum to f_bp (a combination resonance), which
//! the reported frequency alone does not show (on
//! `parameters/accessory-drive-4.ssv` the span modes growing at 2,530 and
//! 6,000 rpm with 160 bodies are damped with 240). The test for any growing
//! mode is the same analysis with more bodies ([`on_finer_mesh`]): a
//! continuous belt's instability stays, the mesh's moves away.

use super::{Mode, Modes};
use crate::drive::mesh_check;
use crate::drive::Drive;

/// How close a mode's frequency must lie to a multiple of f_bp / 2 to be
/// read as driven by it, relative. The parametric resonance locks the
/// mode's frequency to f_bp / 2 (the accessory drive's span 3 mode at idle:
/// within 0.01 %); the analysis' frequencies move by up to 0.4 % between
/// 128 and 256 steps (docs/modes.md, "Convergence in the substeps").
pub const LOCK_TOLERANCE: f64 = 0.01;

/// Damping ratios smaller in magnitude than this are not resolved by the
/// analysis (docs/modes.md, "Convergence in the substeps": read them as
/// lightly damped, sign unknown); only modes growing faster are explained.
pub const ZETA_RESOLUTION: f64 = 3e-3;

/// Highest multiple m of f_bp / 2 checked (m = 1, 3: parametric; m = 2:
/// direct).
const MULTIPLES: u32 = 3;

/// What makes a mode of the running state grow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cause {
    /// At m f_bp / 2 with m odd: the mesh's parametric resonance.
    MeshParametric(u32),
    /// At f_bp: the polygon forcing the mode directly.
    MeshDirect,
    /// At no multiple of f_bp / 2: not the principal parametric resonance
    /// nor the direct forcing; a combination resonance of two modes with
    /// the body passing (f_i + f_j = f_bp) is not excluded ([`on_finer_mesh`]
    /// tells).
    OffTheBodyPassing,
}

/// The cause of `mode`'s growth about a running state of body-passing
/// period `period` [s] (`Orbit::period`).
pub fn cause(mode: &Mode, period: f64) -> Cause {
    let half = 0.5 / period;
    for m in 1..=MULTIPLES {
        let at = m as f64 * half;
        if (mode.frequency_hz / at - 1.0).abs() <= LOCK_TOLERANCE {
            return if m % 2 == 1 {
                Cause::MeshParametric(m)
            } else {
                Cause::MeshDirect
            };
        }
    }
    Cause::OffTheBodyPassing
}

/// The growing modes (damping ratio below -[`ZETA_RESOLUTION`]) of a
/// running state's analysis with their causes, most unstable first; empty
/// about a state at rest.
pub fn growing(modes: &Modes) -> Vec<(&Mode, Cause)> {
    let Some(orbit) = &modes.orbit else {
        return Vec::new();
    };
    let mut out: Vec<(&Mode, Cause)> = modes
        .modes
        .iter()
        .filter(|m| m.damping_ratio < -ZETA_RESOLUTION)
        .map(|m| (m, cause(m, orbit.period)))
        .collect();
    out.sort_by(|a, b| a.0.damping_ratio.total_cmp(&b.0.damping_ratio));
    out
}

/// One line for the console: the mode, its growth and its cause.
pub fn explain(mode: &Mode, cause: Cause, period: f64) -> String {
    let f_bp = 1.0 / period;
    let what = format!(
        "{} at {:.2} Hz grows (damping ratio {:+.4})",
        mode.describe(),
        mode.frequency_hz,
        mode.damping_ratio
    );
    match cause {
        Cause::MeshParametric(m) => format!(
            "{what}: {m}/2 of the body-passing frequency ({f_bp:.1} Hz), a parametric resonance \
             driven by the discrete belt's bodies landing and leaving, not by the drive: more \
             bodies (belt.nBodies) move it"
        ),
        Cause::MeshDirect => format!(
            "{what}: at the body-passing frequency ({f_bp:.1} Hz), forced by the discrete belt's \
             polygon, not by the drive: more bodies (belt.nBodies) move it"
        ),
        Cause::OffTheBodyPassing => format!(
            "{what}: not at half, once or 3/2 the body-passing frequency ({f_bp:.1} Hz): not the \
             mesh's parametric resonance nor the polygon's forcing (the same analysis with more \
             bodies tells whether the bodies' passage drives it otherwise: the modes tool's \
             --mesh-check)"
        ),
    }
}

/// How far a span mode's frequency moves between two meshes of the same
/// drive and it is still taken for the same mode, relative. Measured on
/// `parameters/accessory-drive-4.ssv` at 265 rad/s between 160, 200, 240
/// and 320 bodies: span 1's modes 138-835 Hz within 0.9 %, span 4's first
/// mode 67.5 / 68.7 / 70.6 Hz (4.6 %); adjacent modes of one span lie
/// about 140 Hz apart there, 7 % at the analysis' default 2 kHz limit.
pub const SAME_MODE_TOLERANCE: f64 = 0.05;

/// What the same analysis on a finer mesh says of a mode that grows on the
/// analysed one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OnFinerMesh {
    /// A mode of the same kind within [`SAME_MODE_TOLERANCE`] grows there
    /// too (its frequency [Hz] and damping ratio): the drive's, as far as
    /// the mesh can tell.
    StillGrows(f64, f64),
    /// No mode of the same kind within the tolerance grows there; the
    /// nearest mode of the same part (frequency [Hz], damping ratio), if
    /// any: the growth is the discrete belt's.
    Settles(Option<(f64, f64)>),
}

/// Whether `mode`, growing in one analysis, still grows in `finer`, the
/// analysis of the same drive and speed with more bodies. A continuous
/// belt's instability does not depend on the mesh; one that a finer mesh
/// removes comes from the bodies' passage (at 1/P or a combination of two
/// modes with it) however its frequency relates to 1/P. A mode two spans
/// share may be labelled after the other span on the other mesh: any
/// growing mode of the same kind ([`crate::modes::Family`]) within
/// [`SAME_MODE_TOLERANCE`] counts, so that the verdict errs towards the
/// drive's; the nearest mode reported where none grows is the one with
/// the same label.
pub fn on_finer_mesh(mode: &Mode, finer: &Modes) -> OnFinerMesh {
    let near = |m: &&Mode| (m.frequency_hz / mode.frequency_hz - 1.0).abs() <= SAME_MODE_TOLERANCE;
    let same = || {
        finer
            .modes
            .iter()
            .filter(near)
            .filter(|m| m.part == mode.part)
    };
    // growing: any mode of the same kind (a span's transverse motion, a
    // rotation, ...) near it, whichever span its label names
    if let Some(m) = finer
        .modes
        .iter()
        .filter(near)
        .filter(|m| m.part.family() == mode.part.family())
        .filter(|m| m.damping_ratio < -ZETA_RESOLUTION)
        .min_by(|a, b| a.damping_ratio.total_cmp(&b.damping_ratio))
    {
        return OnFinerMesh::StillGrows(m.frequency_hz, m.damping_ratio);
    }
    OnFinerMesh::Settles(
        same()
            .min_by(|a, b| {
                (a.frequency_hz - mode.frequency_hz)
                    .abs()
                    .total_cmp(&(b.frequency_hz - mode.frequency_hz).abs())
            })
            .map(|m| (m.frequency_hz, m.damping_ratio)),
    )
}

/// One line for the console: what the finer mesh of `bodies` bodies says
/// of `mode`.
pub fn explain_finer(mode: &Mode, verdict: OnFinerMesh, bodies: usize) -> String {
    let what = format!("{} at {:.2} Hz", mode.describe(), mode.frequency_hz);
    match verdict {
        OnFinerMesh::StillGrows(f, z) => format!(
            "{what}: still grows with {bodies} bodies (at {f:.2} Hz, damping ratio {z:+.4}): \
             not the discretisation"
        ),
        OnFinerMesh::Settles(Some((f, z))) => format!(
            "{what}: does not grow with {bodies} bodies (the same mode at {f:.2} Hz, damping \
             ratio {z:+.4}): the discrete belt's bodies passing drive it, not the drive"
        ),
        OnFinerMesh::Settles(None) => format!(
            "{what}: no mode of its part within {:.0} % with {bodies} bodies grows: the \
             discrete belt's bodies passing drive it, not the drive",
            100.0 * SAME_MODE_TOLERANCE
        ),
    }
}

/// What the mesh check (the warnings naming `belt.nBodies`,
/// docs/model.md) reads for `drive` at its built-in crank speed: one line
/// per span whose half body-passing frequency lies near one of its first
/// modes at the preload (or whose body-passing frequency near its first),
/// where the mesh may drive the span.
pub fn mesh_resonances(drive: &Drive) -> Vec<String> {
    mesh_check::spans(drive.params(), drive.layout())
        .iter()
        .enumerate()
        .filter_map(|(k, s)| {
            let (n, d) = s.resonance()?;
            let what = if n == 0 {
                format!("the body-passing frequency {:.1} Hz", s.f_bp)
            } else {
                format!("half the body-passing frequency, {:.1} Hz,", s.f_bp / 2.0)
            };
            let mode = if n == 0 { 1 } else { n };
            Some(format!(
                "span {}: {what} lies {:+.1} % from its mode {mode} at the preload ({:.1} Hz; \
                 {:.1} bodies on the span)",
                k + 1,
                100.0 * d,
                mode as f64 * s.f1,
                s.bodies
            ))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modes::Part;

    fn mode(f: f64, zeta: f64) -> Mode {
        Mode {
            frequency_hz: f,
            damping_ratio: zeta,
            damped_hz: f,
            part: Part::SpanTransverse(3),
            share: 1.0,
            shares: vec![(Part::SpanTransverse(3), 1.0)],
            shape: Vec::new(),
        }
    }

    /// A mode as listed: frequency [Hz], damping ratio, part.
    type Listed = (f64, f64, Part);

    fn modes(list: &[Listed]) -> Modes {
        Modes {
            modes: list
                .iter()
                .map(|&(f, z, part)| Mode { part, ..mode(f, z) })
                .collect(),
            ..Modes::default()
        }
    }

    #[test]
    fn a_finer_mesh_tells_the_drive_from_the_discretisation() {
        // the accessory drive at 265 rad/s: span 1 grows at 554.26 Hz with
        // 160 bodies; with 240 its mode lies at 555.5 Hz, damped
        let grows = Mode {
            part: Part::SpanTransverse(1),
            ..mode(554.26, -0.0064)
        };
        use Part::{PulleyRotation, SpanTransverse};
        let damped = (555.5, 0.0034, SpanTransverse(1));
        let cases: [(&[Listed], OnFinerMesh); 5] = [
            // a rotation growing at the same frequency and the same span's
            // modes 6.2 % and 8.3 % away are other modes
            (
                &[
                    damped,
                    (554.0, -0.009, PulleyRotation(2)),
                    (520.0, -0.009, SpanTransverse(1)),
                    (600.0, -0.009, SpanTransverse(1)),
                ],
                OnFinerMesh::Settles(Some((555.5, 0.0034))),
            ),
            // a transverse mode growing there under another span's label
            // counts: the pair may have swapped labels
            (
                &[damped, (556.0, -0.005, SpanTransverse(2))],
                OnFinerMesh::StillGrows(556.0, -0.005),
            ),
            (
                &[damped, (557.0, -0.0051, SpanTransverse(1))],
                OnFinerMesh::StillGrows(557.0, -0.0051),
            ),
            // within the resolution is not growing
            (
                &[(557.0, -0.0029, SpanTransverse(1))],
                OnFinerMesh::Settles(Some((557.0, -0.0029))),
            ),
            (&[], OnFinerMesh::Settles(None)),
        ];
        for (finer, verdict) in cases {
            assert_eq!(on_finer_mesh(&grows, &modes(finer)), verdict, "{finer:?}");
        }
        assert!(explain_finer(&grows, OnFinerMesh::Settles(None), 240).contains("240 bodies"));
    }

    #[test]
    fn causes_by_multiple_of_half_the_body_passing_frequency() {
        // the accessory drive at idle: P = 1 / 737.15 Hz
        let p = 1.0 / 737.15;
        assert_eq!(cause(&mode(368.59, -0.004), p), Cause::MeshParametric(1));
        assert_eq!(
            cause(&mode(737.15 * 1.5, -0.004), p),
            Cause::MeshParametric(3)
        );
        assert_eq!(cause(&mode(737.15 * 1.009, -0.004), p), Cause::MeshDirect);
        // 1.1 % off half the body-passing frequency: outside the lock
        assert_eq!(
            cause(&mode(368.59 * 1.011, -0.004), p),
            Cause::OffTheBodyPassing
        );
        assert_eq!(cause(&mode(146.78, -0.007), p), Cause::OffTheBodyPassing);
        assert!(
            explain(&mode(368.59, -0.004), Cause::MeshParametric(1), p).contains("belt.nBodies")
        );
    }
}
