//! A running mode's growth (or decay) in the time domain, from a kick along
//! its Floquet eigenvector (docs/modes.md, "Checks against closed forms and
//! the time domain"), shared by examples/span_growth.rs and tests/modes.rs:
//! included with `#[path]`, so each keeps one definition.

use belt_drive::modes::{adapter, Mode};
use belt_drive::Drive;

/// The time-domain growth of one mode.
pub struct Growth {
    /// The fitted growth rate sigma [1/s] (the slope of the log amplitude).
    pub rate: f64,
    /// The damping ratio it gives, -sigma / omega.
    pub zeta: f64,
    /// The kicked run's difference from the plain one, demodulated at the
    /// mode's frequency: (window centre [s] from the kick, amplitude [m]).
    pub windows: Vec<(f64, f64)>,
    /// The same of the plain run alone (the orbit's residual and its own
    /// growth).
    pub plain: Vec<(f64, f64)>,
    /// Windows fitted (from the first on).
    pub fitted: usize,
    /// The rate fitted over the first and the second half of those windows.
    pub halves: (f64, f64),
    /// Largest deviation of a fitted window's log amplitude from the line.
    pub off_line: f64,
}

/// Follows the settled running `drive` for `run` seconds twice, as it is and
/// kicked along `mode` (its eigenvector's real part, `Mode::shape`, scaled
/// so that no body moves by more than `kick` m), samples span `span`'s
/// mid-point deflection every 0.1 ms, demodulates the difference of the two
/// runs at the mode's frequency over windows of four cycles (rejecting the
/// span's other modes and the orbit's ripple at the body-passing
/// frequency) and fits the slope of the log amplitude over the windows from
/// the first on until one reaches `limit` m (the end of the linear range).
/// The difference holds the kick's response alone: the orbit's residual,
/// which grows along the unstable modes in both runs, cancels. The two runs
/// go on two threads.
pub fn kicked_growth(
    drive: &Drive,
    mode: &Mode,
    span: usize,
    kick: f64,
    run: f64,
    limit: f64,
) -> Growth {
    let lin = adapter::linearise(drive);
    let largest = (0..lin.n)
        .flat_map(|i| [lin.body(i, 0), lin.body(i, 1)])
        .map(|q| mode.shape[q].re.abs())
        .fold(0.0, f64::max);
    let mut kicked = drive.clone();
    let mut y = adapter::state(&kicked).to_vec();
    for (v, s) in y.iter_mut().zip(&mode.shape) {
        *v += kick / largest * s.re;
    }
    adapter::set_state(&mut kicked, &y).expect("the kicked state fits the drive");
    let (dt, t0) = (1e-4, drive.time());
    let samples = (run / dt).round() as usize;
    let [plain, pushed]: [Vec<f64>; 2] = std::thread::scope(|s| {
        [drive.clone(), kicked]
            .map(|mut d| {
                s.spawn(move || {
                    (1..=samples)
                        .map(|i| {
                            adapter::run_to(&mut d, t0 + i as f64 * dt)
                                .expect("run from the orbit");
                            d.outputs().span_mid_deflection[span - 1]
                        })
                        .collect::<Vec<f64>>()
                })
            })
            .map(|h| h.join().expect("run"))
    });
    let w = std::f64::consts::TAU * mode.frequency_hz;
    let per = (4.0 / (mode.frequency_hz * dt)).round() as usize;
    let demodulate = |x: &[f64]| -> Vec<(f64, f64)> {
        x.chunks_exact(per)
            .enumerate()
            .map(|(j, chunk)| {
                let mean = chunk.iter().sum::<f64>() / chunk.len() as f64;
                let (mut re, mut im) = (0.0, 0.0);
                for (i, v) in chunk.iter().enumerate() {
                    let t = (j * per + i + 1) as f64 * dt;
                    re += (v - mean) * (w * t).cos();
                    im -= (v - mean) * (w * t).sin();
                }
                let amp = 2.0 * re.hypot(im) / chunk.len() as f64;
                ((j as f64 + 0.5) * per as f64 * dt, amp)
            })
            .collect()
    };
    let diff: Vec<f64> = pushed.iter().zip(&plain).map(|(a, b)| a - b).collect();
    let windows = demodulate(&diff);
    let fit: Vec<(f64, f64)> = windows
        .iter()
        .take_while(|p| p.1 < limit)
        .map(|p| (p.0, p.1.ln()))
        .collect();
    let line = |fit: &[(f64, f64)]| {
        let n = fit.len() as f64;
        let (mt, ma) = (
            fit.iter().map(|p| p.0).sum::<f64>() / n,
            fit.iter().map(|p| p.1).sum::<f64>() / n,
        );
        let slope = fit.iter().map(|p| (p.0 - mt) * (p.1 - ma)).sum::<f64>()
            / fit.iter().map(|p| (p.0 - mt).powi(2)).sum::<f64>();
        (slope, ma - slope * mt)
    };
    let (rate, at0) = if fit.len() >= 2 {
        line(&fit)
    } else {
        (f64::NAN, f64::NAN)
    };
    let h = fit.len() / 2;
    let halves = if fit.len() >= 4 {
        (line(&fit[..=h]).0, line(&fit[h..]).0)
    } else {
        (f64::NAN, f64::NAN)
    };
    let off_line = fit
        .iter()
        .map(|p| (p.1 - at0 - rate * p.0).abs())
        .fold(0.0, f64::max);
    Growth {
        rate,
        zeta: -rate / w,
        windows,
        plain: demodulate(&plain),
        fitted: fit.len(),
        halves,
        off_line,
    }
}

impl Growth {
    /// One line: the fit and the amplitudes.
    pub fn describe(&self) -> String {
        let amps = |w: &[(f64, f64)]| {
            w.iter()
                .map(|p| format!("{:.1e}", p.1))
                .collect::<Vec<_>>()
                .join(" ")
        };
        format!(
            "growth {:.2} 1/s (halves {:.2}, {:.2}; largest log deviation {:.3}) over {} windows, \
             zeta {:+.4}; kicked minus plain [m]: {}; plain alone: {}",
            self.rate,
            self.halves.0,
            self.halves.1,
            self.off_line,
            self.fitted,
            self.zeta,
            amps(&self.windows),
            amps(&self.plain)
        )
    }
}
