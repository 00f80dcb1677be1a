//! Every unit conversion of the project, in one place.
//!
//! The model's interface is SI: load in N, angles in rad, slip ratio kappa in 1, speed in
//! m/s, pressure in Pa, temperature in K.
//! The 1987 formula works in its own units: load in kN, angles in degrees, slip in percent;
//! its extensions take pressure in kPa and temperature in degC (as tire-gap reports them).

/// Newtons per kilonewton.
const NEWTONS_PER_KILONEWTON: f64 = 1000.0;
/// Percent per unit slip ratio (sigma = 100 kappa).
const PERCENT_PER_UNIT: f64 = 100.0;
/// Pascals per kilopascal.
const PASCALS_PER_KILOPASCAL: f64 = 1000.0;
/// 0 degC in K.
const ZERO_CELSIUS_IN_KELVIN: f64 = 273.15;

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

/// Pressure from Pa to the extensions' kPa.
pub fn pascals_to_kilopascals(p_pa: f64) -> f64 {
    p_pa / PASCALS_PER_KILOPASCAL
}

/// Pressure from kPa to Pa.
pub fn kilopascals_to_pascals(p_kpa: f64) -> f64 {
    p_kpa * PASCALS_PER_KILOPASCAL
}

/// Temperature from K to the extensions' degC.
pub fn kelvin_to_celsius(t_k: f64) -> f64 {
    t_k - ZERO_CELSIUS_IN_KELVIN
}

/// Temperature from degC to K.
pub fn celsius_to_kelvin(t_c: f64) -> f64 {
    t_c + ZERO_CELSIUS_IN_KELVIN
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
        assert_eq!(pascals_to_kilopascals(220_000.0), 220.0);
        assert_eq!(kilopascals_to_pascals(pascals_to_kilopascals(2.5e5)), 2.5e5);
        assert!((kelvin_to_celsius(298.15) - 25.0).abs() < 1e-12);
        assert!((celsius_to_kelvin(-273.15)).abs() < 1e-12);
    }
}
