//! V-ribbed grooves: the wedge effect on friction.
//!
//! A rib pressed into a V-groove of included angle 2 beta by the radial
//! force N carries the flank normal forces N / (2 sin beta) on each flank
//! (the flanks' own friction along the groove is neglected, as in the
//! classical V-belt theory), so the tangential friction it can carry is
//! mu N / sin beta: the groove multiplies the friction coefficient by
//! 1 / sin beta. The user gives the coefficient of the belt's rubber on the
//! pulley's metal (`pulley[j].muStatic`, `muKinetic`), which is the
//! coefficient of a flat pulley; the belt's flat back on a back-side idler
//! keeps it.

/// Factor on the friction coefficient of a pulley with groove angle
/// `groove_angle` = 2 beta [rad] (0 = flat), wrapped by the belt's ribs
/// (inside the loop) or by its flat back (`back_side`).
pub fn friction_factor(groove_angle: f64, back_side: bool) -> f64 {
    if back_side || groove_angle == 0.0 {
        1.0
    } else {
        1.0 / (0.5 * groove_angle).sin()
    }
}

/// Smallest groove angle accepted [rad] (10 deg; a 5 deg wedge would
/// multiply mu by 23): real V-ribbed grooves have 40 deg (ISO 9982).
pub const MIN_GROOVE_ANGLE: f64 = 10.0 * std::f64::consts::PI / 180.0;

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn wedge_factor() {
        // ISO 9982 PK groove, 40 deg: 1 / sin 20 deg = 2.9238
        let f = friction_factor(40f64.to_radians(), false);
        assert!((f - 2.923_804_400_163_087).abs() < 1e-12, "{f}");
        assert_eq!(friction_factor(0.0, false), 1.0);
        // the belt's back on a grooved idler stays flat
        assert_eq!(friction_factor(40f64.to_radians(), true), 1.0);
        // an opened-out groove (2 beta -> pi) is flat
        assert!((friction_factor(PI - 1e-9, false) - 1.0).abs() < 1e-12);
    }
}
