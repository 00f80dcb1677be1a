//! The extensions' schema: the macro that turns the one list of effects (in [`super`]) into
//! the kinds ([`Extension`], with their names) and a channel's set ([`ChannelExtensions`]),
//! what is generic about them, and the `extensions` section of a parameter file
//! ([`Extensions`]). Each effect's parameters, math and checks are in its own file.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::channel::Channel;
use crate::conditions::{ConditionLimits, ConditionVar, Nominal};
use crate::extensions::effect::{Effect, Visit};
use crate::extensions::{ChannelExtensions, Extension};

/// Generates, from the one list of effects in [`super`] (`Variant = snake_name`, the
/// effect's struct and variant, its name and module): each effect's `mod` and re-export, the
/// kinds ([`Extension`] with their names) and [`ChannelExtensions`] with one optional field
/// per kind (field name = the kind's name), and the visits of a channel's effects.
macro_rules! effects {
    ($( $kind:ident = $name:ident ),+ $(,)?) => {
        $(
            pub mod $name;
            pub use $name::$kind;
        )+

        /// A kind of extension: the identifier of an effect. Its [`name`](Extension::name)
        /// (e.g. `combined_slip`) names it in parameter files, reports and as serde value.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Extension {
            $(
                #[doc = concat!("[`", stringify!($kind), "`]")]
                $kind
            ),+
        }

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
                match self {
                    $(Extension::$kind => <$kind as $crate::extensions::effect::Parameters<f64>>::NAMES),+
                }
            }

            /// How many of the parameters (the first) a parameter file must give; the
            /// others are 0 when left out.
            pub fn required_parameters(self) -> usize {
                match self {
                    $(Extension::$kind => <$kind as $crate::extensions::effect::Parameters<f64>>::REQUIRED),+
                }
            }

            /// Whether the kind may be used on a channel.
            pub fn applies_to(self, channel: $crate::channel::Channel) -> bool {
                match self {
                    $(Extension::$kind => <$kind as $crate::extensions::effect::Effect>::applies_to(channel)),+
                }
            }

            /// The operating condition the kind depends on, if any.
            pub fn condition(self) -> Option<$crate::conditions::ConditionVar> {
                match self {
                    $(Extension::$kind => <$kind as $crate::extensions::effect::Effect>::CONDITION),+
                }
            }

            /// The kind's rows of [`crate::bounds_table`].
            pub(crate) fn bound_rows(self) -> Vec<$crate::bounds::Row> {
                match self {
                    $(Extension::$kind => <$kind as $crate::extensions::effect::Effect>::bound_rows()),+
                }
            }
        }

        /// The extensions of one channel, each kind at most once; an absent kind is not applied.
        #[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
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
                use $crate::extensions::effect::Parameters;
                match kind { $(Extension::$kind => self.$name.map(|p| p.values())),+ }
            }

            /// Adds (or replaces) `kind` with `values` in [`Extension::parameter_names`] order.
            pub fn set(&mut self, kind: Extension, values: &[P]) -> Result<(), $crate::error::ParamError> {
                use $crate::extensions::effect::Parameters;
                let names = kind.parameter_names();
                if values.len() != names.len() {
                    return Err($crate::error::ParamError::Format(format!(
                        "{} takes {} parameters ({}), not {}",
                        kind.name(),
                        names.len(),
                        names.join(", "),
                        values.len()
                    )));
                }
                let mut next = values.iter().copied();
                // The length is checked above.
                let take = || next.next().expect("one value per parameter");
                match kind {
                    $(Extension::$kind => self.$name = Some($kind::from_values(take))),+
                }
                Ok(())
            }

            /// Visits each effect present, in [`Extension::ALL`] order.
            #[inline]
            pub(crate) fn visit(&self, v: &mut impl $crate::extensions::effect::Visit<P>) {
                $(
                    if let Some(q) = &self.$name {
                        v.visit::<$kind>(Extension::$kind, q);
                    }
                )+
            }
        }

        impl ChannelExtensions {
            /// Checks each effect present, in [`Extension::ALL`] order, up to the first
            /// rejection.
            pub(crate) fn visit_checked(
                &self,
                v: &mut impl $crate::extensions::effect::VisitChecked,
            ) -> Result<(), $crate::error::ParamError> {
                $(
                    if let Some(q) = &self.$name {
                        v.visit::<$kind>(Extension::$kind, q)?;
                    }
                )+
                Ok(())
            }
        }
    };
}
pub(crate) use effects;

impl Extension {
    /// The kind named `name` (see [`Extension::name`]).
    pub fn from_name(name: &str) -> Option<Extension> {
        Extension::ALL.into_iter().find(|k| k.name() == name)
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

    /// The relaxation length \[m\], if the channel has one (an effect that lags its slip).
    pub fn relaxation_length_m(&self) -> Option<P> {
        struct Lag<P>(Option<P>);
        impl<P: Copy> Visit<P> for Lag<P> {
            fn visit<E: Effect>(&mut self, _: Extension, q: &E::Of<P>) {
                self.0 = self.0.or(E::relaxation_length_m(q));
            }
        }
        let mut lag = Lag(None);
        self.visit(&mut lag);
        lag.0
    }

    /// Whether the channel's slip lags (see [`Self::relaxation_length_m`]).
    pub fn has_lag(&self) -> bool {
        self.relaxation_length_m().is_some()
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
        Channel::ALL.iter().any(|c| self.channel(*c).has_lag())
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
                    // The optional parameters only where they are not 0.
                    let params: Vec<String> = k
                        .parameter_names()
                        .iter()
                        .zip(values)
                        .enumerate()
                        .filter(|(i, (_, v))| *i < k.required_parameters() || *v != 0.0)
                        .map(|(_, (n, v))| format!("{n} = {v}"))
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
