//! The extensions' schema: the kinds of extension ([`Extension`], the one list of them with
//! their names), one serde parameter struct per kind, a channel's set ([`ChannelExtensions`])
//! and the `extensions` section of a parameter file ([`Extensions`]).
//!
//! Field names are the parameter names of the parameter files. What the parameters do is in
//! [`super::physics`], what values they may take in [`super::validation`].

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::channel::Channel;
use crate::conditions::{ConditionLimits, ConditionVar, Nominal};
use crate::error::ParamError;

/// Generates, from one list, the kinds of extension ([`Extension`] with their names), one
/// parameter struct per kind (serde, field names = parameter names) and [`ChannelExtensions`]
/// with one optional field per kind (field name = the kind's name).
macro_rules! extensions {
    ($( $(#[$doc:meta])* $kind:ident = $name:ident { $($param:ident),+ } ),+ $(,)?) => {
        /// A kind of extension: the identifier of an effect. Its [`name`](Extension::name)
        /// (e.g. `combined_slip`) names it in parameter files, reports and as serde value.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Extension { $($(#[$doc])* $kind),+ }

        impl Extension {
            /// Every kind, in parameter-file order.
            pub const ALL: [Extension; [$(stringify!($kind)),+].len()] = [$(Extension::$kind),+];

            /// Every kind's name, in [`Extension::ALL`] order.
            pub const NAMES: [&'static str; Extension::ALL.len()] = [$(stringify!($name)),+];

            /// The stable snake_case name in parameter files and reports, e.g. `combined_slip`.
            pub fn name(self) -> &'static str {
                match self { $(Extension::$kind => stringify!($name)),+ }
            }

            /// Parameter names, in order.
            pub fn parameter_names(self) -> &'static [&'static str] {
                match self { $(Extension::$kind => &[$(stringify!($param)),+]),+ }
            }
        }

        $(
            $(#[$doc])*
            /// Parameters are `f64`, or dual numbers for derivatives with respect to them.
            #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
            #[serde(deny_unknown_fields)]
            #[allow(non_snake_case)]
            pub struct $kind<P = f64> { $(pub $param: P),+ }
        )+

        /// The extensions of one channel, each kind at most once; an absent kind is not applied.
        #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct ChannelExtensions<P = f64> {
            $(
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub $name: Option<$kind<P>>,
            )+
        }

        impl<P> Default for ChannelExtensions<P> {
            fn default() -> Self {
                ChannelExtensions { $($name: None),+ }
            }
        }

        impl<P: Copy> ChannelExtensions<P> {
            /// Whether `kind` is present.
            pub fn has(&self, kind: Extension) -> bool {
                match kind { $(Extension::$kind => self.$name.is_some()),+ }
            }

            /// The parameters of `kind` in [`Extension::parameter_names`] order, if present.
            pub fn get(&self, kind: Extension) -> Option<Vec<P>> {
                match kind { $(Extension::$kind => self.$name.map(|p| vec![$(p.$param),+])),+ }
            }

            /// Adds (or replaces) `kind` with `values` in [`Extension::parameter_names`] order.
            pub fn set(&mut self, kind: Extension, values: &[P]) -> Result<(), ParamError> {
                let names = kind.parameter_names();
                if values.len() != names.len() {
                    return Err(ParamError::Format(format!(
                        "{} takes {} parameters ({}), not {}",
                        kind.name(),
                        names.len(),
                        names.join(", "),
                        values.len()
                    )));
                }
                let mut next = values.iter().copied();
                // The length is checked above.
                let mut take = || next.next().expect("one value per parameter");
                match kind {
                    $(Extension::$kind => {
                        self.$name = Some($kind { $($param: take()),+ })
                    })+
                }
                Ok(())
            }
        }
    };
}

extensions! {
    /// Combined slip: the output weighted by `G = cos(C atan(B s))` of the other slip s (slip
    /// ratio for Fy and Mz, slip angle [rad] for Fx).
    CombinedSlip = combined_slip { B, C },
    /// First-order lag of the channel's slip over travelled distance, relaxation length
    /// `sigma_m` [m] (0: no lag).
    RelaxationLength = relaxation_length { sigma_m },
    /// Stiffness BCD times `1 + k dp`, peak D times `1 + d dp`, `dp = (p - p0) / p0`.
    InflationPressure = inflation_pressure { k, d },
    /// Peak D times `1 + v dV`, `dV = (V - V0) / V0`.
    SpeedDependence = speed_dependence { v },
    /// Shifts at zero slip and camber: `Sh += Sh_deg` [deg], `Sv += Sv` [N or N.m] (Fy, Mz).
    PlySteerConicity = ply_steer_conicity { Sh_deg, Sv },
    /// `Fx - (q1 + q2 V / V0) Fz` [N] (Fx only).
    RollingResistance = rolling_resistance { q1, q2 },
    /// Peak D times `1 - w ((T - T0 - Topt_degC) / 50)^2`, stiffness BCD times
    /// `1 + k (T - T0) / 50` (T in degC).
    Temperature = temperature { w, Topt_degC, k },
    /// Horizontal shift of the longitudinal curve, growing with load:
    /// `Fx = MF(kappa + Sh + Sh_per_kN Fz)`, Sh [slip ratio], Sh_per_kN [slip ratio per kN]
    /// (Fz in kN; Fx only).
    SlipRatioShift = slip_ratio_shift { Sh, Sh_per_kN },
}

impl Extension {
    /// The kind named `name` (see [`Extension::name`]).
    pub fn from_name(name: &str) -> Option<Extension> {
        Extension::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Whether the kind may be used on a channel.
    pub fn applies_to(self, channel: Channel) -> bool {
        match self {
            Extension::PlySteerConicity => channel != Channel::Fx,
            Extension::RollingResistance | Extension::SlipRatioShift => channel == Channel::Fx,
            _ => true,
        }
    }

    /// The operating condition the kind depends on, if any.
    pub fn condition(self) -> Option<ConditionVar> {
        match self {
            Extension::InflationPressure => Some(ConditionVar::Pressure),
            Extension::SpeedDependence | Extension::RollingResistance => Some(ConditionVar::Speed),
            Extension::Temperature => Some(ConditionVar::Temperature),
            Extension::CombinedSlip
            | Extension::RelaxationLength
            | Extension::PlySteerConicity
            | Extension::SlipRatioShift => None,
        }
    }
}

impl fmt::Display for Extension {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl Serialize for Extension {
    /// As its name.
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Extension {
    /// From its name.
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let name = String::deserialize(deserializer)?;
        Extension::from_name(&name)
            .ok_or_else(|| serde::de::Error::unknown_variant(&name, &Extension::NAMES))
    }
}

impl<P: Copy> ChannelExtensions<P> {
    pub fn is_empty(&self) -> bool {
        self.kinds().next().is_none()
    }

    /// The kinds present, in [`Extension::ALL`] order.
    pub fn kinds(&self) -> impl Iterator<Item = Extension> + '_ {
        Extension::ALL.into_iter().filter(|k| self.has(*k))
    }

    /// The relaxation length [m], if the channel has one.
    pub fn relaxation_length_m(&self) -> Option<P> {
        self.relaxation_length.map(|r| r.sigma_m)
    }
}

/// The extensions of all three channels with their nominal conditions and range.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct Extensions {
    pub nominal: Nominal,
    /// Absent from a file: [`ConditionLimits::default`].
    #[serde(default)]
    pub limits: ConditionLimits,
    #[serde(default, skip_serializing_if = "ChannelExtensions::is_empty")]
    pub Fy: ChannelExtensions,
    #[serde(default, skip_serializing_if = "ChannelExtensions::is_empty")]
    pub Mz: ChannelExtensions,
    #[serde(default, skip_serializing_if = "ChannelExtensions::is_empty")]
    pub Fx: ChannelExtensions,
}

impl Extensions {
    /// No extension on any channel yet.
    pub fn new(nominal: Nominal, limits: ConditionLimits) -> Extensions {
        Extensions {
            nominal,
            limits,
            Fy: ChannelExtensions::default(),
            Mz: ChannelExtensions::default(),
            Fx: ChannelExtensions::default(),
        }
    }

    pub fn channel(&self, channel: Channel) -> &ChannelExtensions {
        match channel {
            Channel::Fy => &self.Fy,
            Channel::Mz => &self.Mz,
            Channel::Fx => &self.Fx,
        }
    }

    pub fn channel_mut(&mut self, channel: Channel) -> &mut ChannelExtensions {
        match channel {
            Channel::Fy => &mut self.Fy,
            Channel::Mz => &mut self.Mz,
            Channel::Fx => &mut self.Fx,
        }
    }

    /// Whether no channel has any extension.
    pub fn is_empty(&self) -> bool {
        Channel::ALL.iter().all(|c| self.channel(*c).is_empty())
    }

    /// Whether some channel has a relaxation length (the lag is then state).
    pub fn has_relaxation(&self) -> bool {
        Channel::ALL
            .iter()
            .any(|c| self.channel(*c).relaxation_length.is_some())
    }

    /// Whether some extension depends on `condition`.
    pub fn uses(&self, condition: ConditionVar) -> bool {
        Channel::ALL.iter().any(|c| {
            self.channel(*c)
                .kinds()
                .any(|k| k.condition() == Some(condition))
        })
    }
}

impl fmt::Display for Extensions {
    /// One line: each channel's extensions with their parameters, the nominal and the range.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut channels = Vec::new();
        for channel in Channel::ALL {
            let ext = self.channel(channel);
            let kinds: Vec<String> = ext
                .kinds()
                .map(|k| {
                    let values = ext.get(k).unwrap_or_default();
                    let params: Vec<String> = k
                        .parameter_names()
                        .iter()
                        .zip(values)
                        .map(|(n, v)| format!("{n} = {v}"))
                        .collect();
                    format!("{k} ({})", params.join(", "))
                })
                .collect();
            if !kinds.is_empty() {
                channels.push(format!("{channel}: {}", kinds.join(", ")));
            }
        }
        if channels.is_empty() {
            channels.push("none".into());
        }
        let (n, l) = (&self.nominal, &self.limits);
        write!(
            f,
            "{}; nominal p0 = {} kPa, V0 = {} m/s, T0 = {} degC; conditions clamped to |vx| in [{}, {}] m/s, \
             p in [{}, {}] kPa, T in [{}, {}] degC",
            channels.join("; "),
            n.pressure_kpa,
            n.speed_mps,
            n.temperature_c,
            l.speed_min_mps,
            l.speed_max_mps,
            l.pressure_min_kPa,
            l.pressure_max_kPa,
            l.temperature_min_degC,
            l.temperature_max_degC
        )
    }
}
