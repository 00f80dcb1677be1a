//! Every conversion from file units to tire-gap's internal units, in one place.
//!
//! Internal units are those of [`crate::data`]: time s, speed m/s, load and forces N,
//! angles rad, slip ratio 1, pressure kPa, temperature degC, moment N.m. A file value `x`
//! in some unit becomes `x * scale + offset` internally. Where the model crate already
//! defines a conversion (degrees, kilonewtons, percent slip) its function supplies the
//! scale, so the constants live in one place for the whole workspace.
//!
//! Unit names are matched ignoring ASCII case and surrounding blanks: no two accepted
//! units differ only in case, and TYDEX files often write `DEG` or `NM`.

use crate::data::Quantity;
use mf87::units::{degrees_to_radians, kilonewtons_to_newtons, percent_to_slip_ratio};

/// Seconds per millisecond.
const SECONDS_PER_MILLISECOND: f64 = 1e-3;
/// Metres per second per km/h.
const MPS_PER_KPH: f64 = 1.0 / 3.6;
/// Metres per second per mile per hour (international mile, exact).
const MPS_PER_MPH: f64 = 0.447_04;
/// Newtons per pound-force (exact by definition).
const NEWTONS_PER_LBF: f64 = 4.448_221_615_260_5;
/// Newton metres per foot pound-force (exact by definition).
const NM_PER_FT_LBF: f64 = 1.355_817_948_331_400_4;
/// Newton metres per inch pound-force (exact by definition).
const NM_PER_IN_LBF: f64 = NM_PER_FT_LBF / 12.0;
/// Kilopascals per bar.
const KPA_PER_BAR: f64 = 100.0;
/// Kilopascals per pascal.
const KPA_PER_PA: f64 = 1e-3;
/// Kilopascals per psi.
const KPA_PER_PSI: f64 = 6.894_757_293_168_361;
/// 0 degC in kelvin.
const ZERO_CELSIUS_IN_KELVIN: f64 = 273.15;

/// A linear map from a file unit to the internal unit: `internal = file * scale + offset`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conversion {
    pub scale: f64,
    pub offset: f64,
}

impl Conversion {
    /// The file is already in internal units.
    pub const IDENTITY: Conversion = Conversion {
        scale: 1.0,
        offset: 0.0,
    };

    const fn scale(scale: f64) -> Conversion {
        Conversion { scale, offset: 0.0 }
    }

    /// A file value in internal units.
    pub fn apply(self, x: f64) -> f64 {
        x * self.scale + self.offset
    }

    /// Applies `self` after `first`: one conversion doing both.
    pub fn after(self, first: Conversion) -> Conversion {
        Conversion {
            scale: first.scale * self.scale,
            offset: first.offset * self.scale + self.offset,
        }
    }
}

/// Unit spellings accepted for each quantity, canonical first (used in error messages).
pub fn accepted_units(q: Quantity) -> &'static [&'static str] {
    match q {
        Quantity::Run => &["", "-", "1"],
        Quantity::Time => &["s", "sec", "ms"],
        Quantity::Speed => &["m/s", "mps", "km/h", "kph", "kmh", "mph"],
        Quantity::Fz | Quantity::Fx | Quantity::Fy => &["N", "kN", "lbf", "lb"],
        Quantity::Alpha | Quantity::Gamma => &["deg", "degree", "degrees", "°", "rad"],
        // TTC writes "SAE" for its slip ratios (SAE J670 definition, a plain ratio).
        Quantity::Kappa => &["", "-", "1", "none", "SAE", "%", "pct", "percent"],
        Quantity::Pressure => &["kPa", "bar", "Pa", "MPa", "psi"],
        Quantity::Temperature => &[
            "degC", "C", "deg C", "°C", "celsius", "K", "degF", "F", "deg F", "°F",
        ],
        Quantity::Mz => &[
            "Nm", "N.m", "N*m", "N-m", "N m", "N·m", "kNm", "kN.m", "ft-lb", "lb-ft", "ft.lbf",
            "in-lb", "lb-in",
        ],
    }
}

/// How a value of `q` written in `unit` becomes internal units; `None` if the unit is not
/// accepted for that quantity (see [`accepted_units`]).
pub fn conversion(q: Quantity, unit: &str) -> Option<Conversion> {
    let u = unit.trim().to_ascii_lowercase();
    let u = u.as_str();
    let c = match q {
        Quantity::Run => match u {
            "" | "-" | "1" => Conversion::IDENTITY,
            _ => return None,
        },
        Quantity::Time => match u {
            "s" | "sec" => Conversion::IDENTITY,
            "ms" => Conversion::scale(SECONDS_PER_MILLISECOND),
            _ => return None,
        },
        Quantity::Speed => match u {
            "m/s" | "mps" => Conversion::IDENTITY,
            "km/h" | "kph" | "kmh" => Conversion::scale(MPS_PER_KPH),
            "mph" => Conversion::scale(MPS_PER_MPH),
            _ => return None,
        },
        Quantity::Fz | Quantity::Fx | Quantity::Fy => match u {
            "n" => Conversion::IDENTITY,
            "kn" => Conversion::scale(kilonewtons_to_newtons(1.0)),
            // TTC's US files write pound-force as "lb".
            "lbf" | "lb" => Conversion::scale(NEWTONS_PER_LBF),
            _ => return None,
        },
        Quantity::Alpha | Quantity::Gamma => match u {
            "rad" => Conversion::IDENTITY,
            "deg" | "degree" | "degrees" | "°" => Conversion::scale(degrees_to_radians(1.0)),
            _ => return None,
        },
        Quantity::Kappa => match u {
            "" | "-" | "1" | "none" | "sae" => Conversion::IDENTITY,
            "%" | "pct" | "percent" => Conversion::scale(percent_to_slip_ratio(1.0)),
            _ => return None,
        },
        Quantity::Pressure => match u {
            "kpa" => Conversion::IDENTITY,
            "bar" => Conversion::scale(KPA_PER_BAR),
            "pa" => Conversion::scale(KPA_PER_PA),
            "mpa" => Conversion::scale(1.0 / KPA_PER_PA),
            "psi" => Conversion::scale(KPA_PER_PSI),
            _ => return None,
        },
        Quantity::Temperature => match u {
            "degc" | "c" | "deg c" | "°c" | "celsius" => Conversion::IDENTITY,
            "k" => Conversion {
                scale: 1.0,
                offset: -ZERO_CELSIUS_IN_KELVIN,
            },
            // degC = (degF - 32) * 5/9
            "degf" | "f" | "deg f" | "°f" => Conversion {
                scale: 5.0 / 9.0,
                offset: -32.0 * 5.0 / 9.0,
            },
            _ => return None,
        },
        Quantity::Mz => match u {
            "nm" | "n.m" | "n*m" | "n-m" | "n m" | "n·m" => Conversion::IDENTITY,
            "knm" | "kn.m" => Conversion::scale(kilonewtons_to_newtons(1.0)),
            "ft-lb" | "lb-ft" | "ft.lbf" => Conversion::scale(NM_PER_FT_LBF),
            "in-lb" | "lb-in" => Conversion::scale(NM_PER_IN_LBF),
            _ => return None,
        },
    };
    Some(c)
}

/// Units of channels that tire-gap reads past but never converts (TTC's loaded and effective
/// radii, wheel speed, normalised forces).
const OTHER_UNITS: &[&str] = &["cm", "mm", "m", "in", "rpm", "rad/s", "none"];

/// Whether `text` (ignoring case and surrounding blanks) is a unit spelling tire-gap knows:
/// one accepted for some quantity, or one of a channel it does not convert (`cm`, `in`,
/// `rpm`, ...). Used to split unit lines whose entries contain blanks (`deg C`).
pub fn is_known(text: &str) -> bool {
    let u = text.trim();
    !u.is_empty()
        && (Quantity::ALL.iter().any(|&q| conversion(q, u).is_some())
            || OTHER_UNITS.iter().any(|o| o.eq_ignore_ascii_case(u)))
}

/// The accepted units of `q` as a readable list, for error messages.
pub fn accepted_list(q: Quantity) -> String {
    accepted_units(q)
        .iter()
        .map(|u| if u.is_empty() { "(none)" } else { u })
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn conv(q: Quantity, unit: &str, x: f64) -> f64 {
        conversion(q, unit)
            .unwrap_or_else(|| panic!("{unit} not accepted for {q:?}"))
            .apply(x)
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1.0)
    }

    #[test]
    fn forces_and_moment() {
        assert_eq!(conv(Quantity::Fz, "N", 4000.0), 4000.0);
        assert_eq!(conv(Quantity::Fz, "kN", 4.0), 4000.0);
        assert_eq!(conv(Quantity::Fy, "KN", -2.5), -2500.0);
        assert!(close(conv(Quantity::Fx, "lbf", 100.0), 444.822_161_526_05));
        for u in ["Nm", "N.m", "N*m", "NM", "n-m"] {
            assert_eq!(conv(Quantity::Mz, u, 12.5), 12.5, "{u}");
        }
        assert_eq!(conv(Quantity::Mz, "kNm", 0.1), 100.0);
        // 1 in-lbf = 0.0254 m * 4.4482216152605 N.
        assert!(close(
            conv(Quantity::Mz, "in-lb", 10.0),
            1.129_848_290_276_167
        ));
        assert!(conversion(Quantity::Fz, "Nm").is_none());
        assert!(conversion(Quantity::Mz, "N").is_none());
    }

    #[test]
    fn angles_use_the_model_crate_conversion() {
        assert!(close(
            conv(Quantity::Alpha, "deg", 180.0),
            std::f64::consts::PI
        ));
        assert!(close(
            conv(Quantity::Gamma, "DEG", -3.0),
            degrees_to_radians(-3.0)
        ));
        assert_eq!(conv(Quantity::Alpha, "rad", 0.1), 0.1);
        assert!(conversion(Quantity::Alpha, "").is_none());
        assert!(conversion(Quantity::Alpha, "grad").is_none());
    }

    #[test]
    fn slip_ratio_and_percent() {
        // TTC's "SAE" slip ratio is a plain ratio, like "none".
        for u in ["", "-", "1", "none", "SAE"] {
            assert_eq!(conv(Quantity::Kappa, u, 0.08), 0.08);
        }
        for u in ["%", "pct", "percent"] {
            assert!(close(conv(Quantity::Kappa, u, 8.0), 0.08), "{u}");
        }
        assert!(close(conv(Quantity::Kappa, "%", -100.0), -1.0));
    }

    #[test]
    fn speed_time_pressure() {
        assert_eq!(conv(Quantity::Speed, "m/s", 16.7), 16.7);
        assert_eq!(conv(Quantity::Speed, "mps", 16.7), 16.7);
        assert!(close(
            conv(Quantity::Speed, "km/h", 60.0),
            16.666_666_666_666_668
        ));
        assert!(close(conv(Quantity::Speed, "kph", 36.0), 10.0));
        assert!(close(conv(Quantity::Speed, "mph", 10.0), 4.4704));
        assert_eq!(conv(Quantity::Time, "s", 1.5), 1.5);
        assert!(close(conv(Quantity::Time, "ms", 1500.0), 1.5));
        assert_eq!(conv(Quantity::Pressure, "kPa", 210.0), 210.0);
        assert!(close(conv(Quantity::Pressure, "bar", 2.1), 210.0));
        assert!(close(conv(Quantity::Pressure, "Pa", 210_000.0), 210.0));
        assert!(close(
            conv(Quantity::Pressure, "psi", 30.0),
            206.842_718_795_050_83
        ));
        assert!(conversion(Quantity::Pressure, "atm").is_none());
    }

    #[test]
    fn temperature_has_offsets() {
        for u in ["degC", "C", "deg C", "°C"] {
            assert_eq!(conv(Quantity::Temperature, u, 25.0), 25.0, "{u}");
        }
        assert!(close(conv(Quantity::Temperature, "K", 298.15), 25.0));
        assert!(close(conv(Quantity::Temperature, "degF", 212.0), 100.0));
        assert!(close(conv(Quantity::Temperature, "F", 32.0), 0.0));
        assert!(close(conv(Quantity::Temperature, "deg F", 140.0), 60.0));
        assert_eq!(conv(Quantity::Temperature, "deg c", 25.0), 25.0);
        // "deg" alone is an angle, never a temperature.
        assert!(conversion(Quantity::Temperature, "deg").is_none());
    }

    #[test]
    fn run_is_dimensionless() {
        assert_eq!(conversion(Quantity::Run, ""), Some(Conversion::IDENTITY));
        assert!(conversion(Quantity::Run, "s").is_none());
    }

    #[test]
    fn every_listed_unit_is_accepted() {
        for q in Quantity::ALL {
            for u in accepted_units(q) {
                assert!(conversion(q, u).is_some(), "{q:?} {u}");
            }
        }
        assert_eq!(accepted_list(Quantity::Fz), "N, kN, lbf, lb");
        assert_eq!(
            accepted_list(Quantity::Kappa),
            "(none), -, 1, none, SAE, %, pct, percent"
        );
    }

    #[test]
    fn known_units_include_ttc_channels_not_converted() {
        for u in [
            "deg c", "DEG C", "degF", "SAE", "none", "cm", "in", "rpm", "N-m", "kph", "s",
        ] {
            assert!(is_known(u), "{u}");
        }
        for u in ["", "deg c c", "furlong", "c deg"] {
            assert!(!is_known(u), "{u}");
        }
    }

    #[test]
    fn composition() {
        // A TYDEX channel: raw * 0.1 + 2 (in kN), then kN -> N.
        let file = Conversion {
            scale: 0.1,
            offset: 2.0,
        };
        let c = conversion(Quantity::Fz, "kN").unwrap().after(file);
        assert!(close(c.apply(30.0), 5000.0));
    }
}
