//! Every unit conversion of the project, in one place.
//!
//! The model's interface is SI: load in N, angles in rad, slip ratio kappa in 1, speed in
//! m/s, pressure in Pa, temperature in K.
//! The 1987 formula works in its own units: load in kN, angles in degrees, slip in percent;
//! its extensions take pressure in kPa and temperature in degC (as tire-gap reports them).

use crate::real::Real;

/// Newtons per kilonewton.
const NEWTONS_PER_KILONEWTON: f64 = 1000.0;
/// Percent per unit slip ratio (sigma = 100 kappa).
const PERCENT_PER_UNIT: f64 = 100.0;
/// Pascals per kilopascal.
const PASCALS_PER_KILOPASCAL: f64 = 1000.0;
/// 0 degC in K.
const ZERO_CELSIUS_IN_KELVIN: f64 = 273.15;

/// Degrees per radian, as [`f64::to_degrees`] multiplies.
const DEGREES_PER_RADIAN: f64 = 180.0 / std::f64::consts::PI;
/// Radians per degree, as [`f64::to_radians`] multiplies.
const RADIANS_PER_DEGREE: f64 = std::f64::consts::PI / 180.0;

// The conversions are generic over the number type, so the formula's exact derivatives go
// through them too (see `crate::real`); for `f64` they are the plain conversions.

/// Load from N to the formula's kN.
#[inline]
pub fn newtons_to_kilonewtons<T: Real>(f_n: T) -> T {
    f_n / NEWTONS_PER_KILONEWTON
}

/// Load from the formula's kN to N.
#[inline]
pub fn kilonewtons_to_newtons<T: Real>(f_kn: T) -> T {
    f_kn * NEWTONS_PER_KILONEWTON
}

/// Angle from rad to the formula's degrees.
#[inline]
pub fn radians_to_degrees<T: Real>(angle_rad: T) -> T {
    angle_rad * DEGREES_PER_RADIAN
}

/// Angle from degrees to rad.
#[inline]
pub fn degrees_to_radians<T: Real>(angle_deg: T) -> T {
    angle_deg * RADIANS_PER_DEGREE
}

/// Slip ratio kappa (1) to the formula's percent slip sigma.
#[inline]
pub fn slip_ratio_to_percent<T: Real>(kappa: T) -> T {
    kappa * PERCENT_PER_UNIT
}

/// Percent slip sigma to slip ratio kappa (1).
#[inline]
pub fn percent_to_slip_ratio<T: Real>(sigma_pct: T) -> T {
    sigma_pct / PERCENT_PER_UNIT
}

/// Pressure from Pa to the extensions' kPa.
#[inline]
pub fn pascals_to_kilopascals<T: Real>(p_pa: T) -> T {
    p_pa / PASCALS_PER_KILOPASCAL
}

/// Pressure from kPa to Pa.
#[inline]
pub fn kilopascals_to_pascals<T: Real>(p_kpa: T) -> T {
    p_kpa * PASCALS_PER_KILOPASCAL
}

/// Temperature from K to the extensions' degC.
#[inline]
pub fn kelvin_to_celsius<T: Real>(t_k: T) -> T {
    t_k - ZERO_CELSIUS_IN_KELVIN
}

/// Temperature from degC to K.
#[inline]
pub fn celsius_to_kelvin<T: Real>(t_c: T) -> T {
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
        assert!((kelvin_to_celsius(298.15f64) - 25.0).abs() < 1e-12);
        assert!((celsius_to_kelvin(-273.15f64)).abs() < 1e-12);
        // The angle conversions are bit for bit std's.
        for x in [0.1f64, -1.3, 57.0, 1e-9, 3.0e5] {
            assert_eq!(radians_to_degrees(x).to_bits(), x.to_degrees().to_bits());
            assert_eq!(degrees_to_radians(x).to_bits(), x.to_radians().to_bits());
        }
    }
}
