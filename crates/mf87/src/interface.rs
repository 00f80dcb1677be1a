//! The model's SI interface: [`Inputs`] and [`Outputs`], their variables ([`InputVar`],
//! [`OutputVar`]) with names and valid ranges, and the axis system ([`SignConvention`]).

use serde::{Deserialize, Serialize};

use crate::coefficients::{LimitVar, Limits};
use crate::real::{self, Real};

/// Model inputs in SI units.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Inputs<T = f64> {
    /// Vertical load \[N\], positive in compression.
    pub fz: T,
    /// Slip angle \[rad\].
    pub alpha: T,
    /// Longitudinal slip ratio \[1\] (the paper's sigma = 100 kappa percent).
    pub kappa: T,
    /// Camber (inclination) angle \[rad\].
    pub gamma: T,
}

/// Model outputs in SI units.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Outputs<T = f64> {
    /// Longitudinal force \[N\].
    pub fx: T,
    /// Lateral force \[N\].
    pub fy: T,
    /// Aligning moment [N.m].
    pub mz: T,
}

/// Which axis system inputs and outputs are expressed in.
///
/// `Paper`: the 1987 paper's convention: alpha > 0 gives Fy > 0 and Mz < 0, gamma > 0 gives
/// Fy > 0 at zero slip, sigma > 0 (driving) gives Fx > 0.
///
/// `Iso`: ISO 8855 / TYDEX W-axes (x forward, y left, z up). The paper's y and z axes point the
/// other way (y right, z down): alpha, gamma and Fx keep their values, Fy and Mz change sign.
/// So in ISO, alpha > 0 gives Fy < 0 and Mz > 0, and gamma > 0 (top of the wheel leaning to the
/// right, seen from behind) gives Fy < 0 at zero slip.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum SignConvention {
    #[default]
    Paper,
    Iso,
}

/// An input variable, for range checks and messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputVar {
    Fz,
    Alpha,
    Kappa,
    Gamma,
}

impl InputVar {
    pub const ALL: [InputVar; 4] = [
        InputVar::Fz,
        InputVar::Alpha,
        InputVar::Kappa,
        InputVar::Gamma,
    ];

    /// The variable's interface name.
    pub fn name(self) -> &'static str {
        match self {
            InputVar::Fz => "Fz",
            InputVar::Alpha => "alpha",
            InputVar::Kappa => "kappa",
            InputVar::Gamma => "gamma",
        }
    }

    pub fn from_name(name: &str) -> Option<InputVar> {
        InputVar::ALL.into_iter().find(|v| v.name() == name)
    }

    /// The range [lo, hi] (SI units) in which the model is valid; inputs outside are clamped.
    /// Loads <= 0 are valid (a lifted wheel gives no force).
    #[inline]
    pub fn valid_range(self, limits: &Limits) -> (f64, f64) {
        match self {
            InputVar::Fz => (f64::NEG_INFINITY, limits.fz_max_N),
            InputVar::Alpha => (-std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_2),
            InputVar::Kappa => (-1.0, 1.0),
            InputVar::Gamma => {
                let g = LimitVar::GammaMax.get(limits);
                (-g, g)
            }
        }
    }
}

/// An output variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputVar {
    Fx,
    Fy,
    Mz,
}

impl OutputVar {
    pub const ALL: [OutputVar; 3] = [OutputVar::Fx, OutputVar::Fy, OutputVar::Mz];

    pub fn name(self) -> &'static str {
        match self {
            OutputVar::Fx => "Fx",
            OutputVar::Fy => "Fy",
            OutputVar::Mz => "Mz",
        }
    }

    pub fn from_name(name: &str) -> Option<OutputVar> {
        OutputVar::ALL.into_iter().find(|v| v.name() == name)
    }
}

impl<T: Copy> Inputs<T> {
    #[inline]
    pub fn get(&self, var: InputVar) -> T {
        match var {
            InputVar::Fz => self.fz,
            InputVar::Alpha => self.alpha,
            InputVar::Kappa => self.kappa,
            InputVar::Gamma => self.gamma,
        }
    }

    #[inline]
    pub fn set(&mut self, var: InputVar, value: T) {
        match var {
            InputVar::Fz => self.fz = value,
            InputVar::Alpha => self.alpha = value,
            InputVar::Kappa => self.kappa = value,
            InputVar::Gamma => self.gamma = value,
        }
    }

    /// The inputs clamped to their valid ranges.
    #[inline]
    pub fn clamped(&self, limits: &Limits) -> Inputs<T>
    where
        T: Real,
    {
        let mut out = *self;
        for var in InputVar::ALL {
            let (lo, hi) = var.valid_range(limits);
            out.set(var, real::clamp(self.get(var), lo, hi));
        }
        out
    }
}

impl<T: Copy> Outputs<T> {
    #[inline]
    pub fn get(&self, var: OutputVar) -> T {
        match var {
            OutputVar::Fx => self.fx,
            OutputVar::Fy => self.fy,
            OutputVar::Mz => self.mz,
        }
    }
}

/// Outputs computed in the paper's axes, expressed in `convention`'s.
#[inline]
pub(crate) fn oriented<T: Real>(paper: Outputs<T>, convention: SignConvention) -> Outputs<T> {
    match convention {
        SignConvention::Paper => paper,
        SignConvention::Iso => Outputs {
            fx: paper.fx,
            fy: -paper.fy,
            mz: -paper.mz,
        },
    }
}
