//! Every unit conversion of the project, in one place.
//!
//! The model's interface is SI: load in N, angles in rad, slip ratio kappa in 1.
//! The 1987 formula works in its own units: load in kN, angles in degrees, slip in percent.

/// Newtons per kilonewton.
const NEWTONS_PER_KILONEWTON: f64 = 1000.0;
/// Percent per unit slip ratio (sigma = 100 kappa).
const PERCENT_PER_UNIT: f64 = 100.0;

/// Load from N to the formula's kN.
pub fn newtons_to_kilonewtons(f_n: f64) -> f64 {
    f_n / NEWTONS_PER_KILONEWTON
}

/// Load from the formula's kN to N.
pub fn kilonewtons_to_newtons(f_kn: f64) -> f64 {
    f_kn * NEWTONS_PER_KILONEWTON
}

/// Angle from rad to the formula's degrees.
pub fn radians_to_degrees(angle_rad: f64) -> f64 {
    angle_rad.to_degrees()
}

/// Angle from degrees to rad.
pub fn degrees_to_radians(angle_deg: f64) -> f64 {
    angle_deg.to_radians()
}

/// Slip ratio kappa (1) to the formula's percent slip sigma.
pub fn slip_ratio_to_percent(kappa: f64) -> f64 {
    kappa * PERCENT_PER_UNIT
}

/// Percent slip sigma to slip ratio kappa (1).
pub fn percent_to_slip_ratio(sigma_pct: f64) -> f64 {
    sigma_pct / PERCENT_PER_UNIT
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversions_round_trip_and_match_definitions() {
        assert_eq!(newtons_to_kilonewtons(4000.0), 4.0);
        assert_eq!(
            kilonewtons_to_newtons(newtons_to_kilonewtons(1234.5)),
            1234.5
        );
        assert!((radians_to_degrees(std::f64::consts::FRAC_PI_2) - 90.0).abs() < 1e-12);
        assert!((degrees_to_radians(180.0) - std::f64::consts::PI).abs() < 1e-15);
        assert_eq!(slip_ratio_to_percent(0.1), 10.0);
        assert_eq!(percent_to_slip_ratio(-50.0), -0.5);
    }
}
