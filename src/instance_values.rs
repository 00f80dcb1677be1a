//! The values of one instance, which are also what an FMU state copies: the state-machine
//! state, time, inputs, parameters, outputs; their start values and the model evaluation.

use mf87::{
    InputVar, Inputs, LaggedSlip, OperatingConditions, OutputVar, Outputs, Params, SignConvention,
    evaluate, evaluate_extended,
};
use serde::{Deserialize, Serialize};

use crate::call_sequence::State;
use crate::variables::{
    BOOLEAN_VARIABLES, BooleanRole, REAL_VARIABLES, RealRole, RealVariable, STRING_VARIABLES,
    StringRole,
};

/// Everything that makes up the FMU state (what fmi2GetFMUstate copies).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InstanceValues {
    pub(crate) state: State,
    pub(crate) time: f64,
    pub(crate) stop_time: Option<f64>,
    pub(crate) inputs: Inputs,
    /// Speed, pressure, temperature: inputs only the extensions use.
    pub(crate) conditions: OperatingConditions,
    /// The relaxation lag of each channel's slip (state when the extensions have one).
    pub(crate) lagged: LaggedSlip,
    pub(crate) outputs: Outputs,
    /// Inputs or parameters changed since the outputs were computed.
    pub(crate) outputs_stale: bool,
    pub params: Params,
    /// Bit i: REAL_VARIABLES[i] (a parameter) was set explicitly; it overrides the parameter file.
    pub(crate) explicitly_set: u64,
    pub(crate) convention: SignConvention,
    pub(crate) parameter_file: String,
    /// Bit per input or condition (see [`clamp_bit`]): its clamping was logged already.
    clamp_logged: u8,
}

impl InstanceValues {
    /// Start values, as after fmi2Instantiate.
    pub(crate) fn initial() -> InstanceValues {
        let mut inputs = Inputs::default();
        let mut conditions = OperatingConditions {
            vx: 0.0,
            p: 0.0,
            t_tread: 0.0,
        };
        for v in REAL_VARIABLES {
            match v.role {
                RealRole::Input(input) => inputs.set(input, v.start),
                RealRole::Condition(c) => conditions.set(c, v.start),
                _ => {}
            }
        }
        let mut convention = SignConvention::Paper;
        for v in BOOLEAN_VARIABLES {
            match v.role {
                BooleanRole::IsoSignConvention => convention = convention_of(v.start),
            }
        }
        let mut parameter_file = String::new();
        for v in STRING_VARIABLES {
            match v.role {
                StringRole::ParameterFile => parameter_file = v.start.to_string(),
            }
        }
        InstanceValues {
            state: State::Instantiated,
            time: 0.0,
            stop_time: None,
            inputs,
            conditions,
            lagged: LaggedSlip::default(),
            outputs: Outputs::default(),
            outputs_stale: true,
            params: Params::paper_table(),
            explicitly_set: 0,
            convention,
            parameter_file,
            clamp_logged: 0,
        }
    }

    /// The value of the Real variable `var`.
    #[inline]
    pub(crate) fn real(&self, var: &RealVariable) -> f64 {
        match var.role {
            RealRole::Input(v) => self.inputs.get(v),
            RealRole::Condition(v) => self.conditions.get(v),
            RealRole::Output(v) => self.outputs.get(v),
            RealRole::Coefficient(channel, index) => {
                self.params.coefficient(channel, index).unwrap_or(f64::NAN)
            }
            RealRole::Limit(limit) => limit.get(&self.params.limits),
            RealRole::State(channel) => self.lagged.get(channel),
            RealRole::Derivative(channel) => self.state_rates().get(channel),
        }
    }

    /// The time derivatives of the relaxation states (see `LaggedSlip::rates`).
    pub(crate) fn state_rates(&self) -> LaggedSlip {
        self.lagged
            .rates(&self.params, &self.inputs, self.conditions.vx)
    }

    /// Computes the outputs from the inputs. Validated parameters keep them finite; should
    /// one still not be, the previous outputs are kept (so the state stays finite and
    /// serializable), they stay stale, and the error says which output and inputs.
    pub(crate) fn compute_outputs(&mut self) -> Result<(), String> {
        let outputs = if self.params.extensions.is_some() {
            self.extended_outputs()
        } else {
            evaluate(&self.params, &self.inputs, self.convention)
        };
        if !(outputs.fx.is_finite() && outputs.fy.is_finite() && outputs.mz.is_finite()) {
            return Err(self.non_finite_outputs(&outputs));
        }
        self.outputs = outputs;
        self.outputs_stale = false;
        Ok(())
    }

    /// Out of line, so that the 1987 model alone is evaluated as fast as without extensions.
    #[inline(never)]
    fn extended_outputs(&self) -> Outputs {
        evaluate_extended(
            &self.params,
            &self.inputs,
            &self.conditions,
            &self.lagged,
            self.convention,
        )
    }

    #[cold]
    #[inline(never)]
    fn non_finite_outputs(&self, outputs: &Outputs) -> String {
        let bad: Vec<String> = OutputVar::ALL
            .iter()
            .filter(|v| !outputs.get(**v).is_finite())
            .map(|v| format!("{} = {}", v.name(), outputs.get(*v)))
            .collect();
        let x = &self.inputs;
        let c = &self.conditions;
        let l = &self.lagged;
        let kept: Vec<String> = OutputVar::ALL
            .iter()
            .map(|v| format!("{} = {}", v.name(), self.outputs.get(*v)))
            .collect();
        format!(
            "the model gives {} (not finite) at Fz = {} N, alpha = {} rad, kappa = {}, gamma = {} rad, \
             vx = {} m/s, p = {} Pa, T_tread = {} K (lagged slips Fx {}, Fy {}, Mz {}); \
             the outputs keep their previous values ({})",
            bad.join(", "),
            x.fz,
            x.alpha,
            x.kappa,
            x.gamma,
            c.vx,
            c.p,
            c.t_tread,
            l.fx,
            l.fy,
            l.mz,
            kept.join(", ")
        )
    }

    /// Advances the relaxation lag, if any, over the distance |vx| h travelled with the
    /// inputs held over the step.
    #[inline(never)]
    pub(crate) fn advance_lag(&mut self, h: f64) {
        if let Some(ext) = &self.params.extensions
            && ext.has_relaxation()
        {
            let distance = self.conditions.vx.abs() * h;
            self.lagged = self.lagged.advanced(&self.params, &self.inputs, distance);
            self.outputs_stale = true;
        }
    }

    /// Records that the clamping of the input or condition `role` is logged: true the first
    /// time, false afterwards.
    pub(crate) fn first_clamping(&mut self, role: RealRole) -> bool {
        let bit = clamp_bit(role);
        let first = self.clamp_logged & bit == 0;
        self.clamp_logged |= bit;
        first
    }

    /// The parameters set explicitly, which override the parameter file, with their values.
    pub(crate) fn explicitly_set_parameters(
        &self,
    ) -> impl Iterator<Item = (&'static RealVariable, f64)> + '_ {
        REAL_VARIABLES
            .iter()
            .enumerate()
            .filter(|(i, _)| self.explicitly_set & (1 << i) != 0)
            .map(|(_, var)| (var, self.real(var)))
    }

    /// Outputs in initialization: the relaxation lag in its steady state.
    pub(crate) fn compute_initial_outputs(&mut self) -> Result<(), String> {
        self.lagged = LaggedSlip::steady(&self.params, &self.inputs);
        self.compute_outputs()
    }
}

/// The bit of `clamp_logged` for an input or operating condition.
fn clamp_bit(role: RealRole) -> u8 {
    match role {
        RealRole::Input(v) => 1 << v as u8,
        RealRole::Condition(v) => 1 << (InputVar::ALL.len() as u8 + v as u8),
        RealRole::Output(_)
        | RealRole::Coefficient(..)
        | RealRole::Limit(_)
        | RealRole::State(_)
        | RealRole::Derivative(_) => 0,
    }
}

/// Sets the coefficient or limit a parameter variable stands for.
pub(crate) fn set_parameter(params: &mut Params, role: RealRole, value: f64) {
    match role {
        RealRole::Coefficient(channel, index) => {
            if let Some(c) = params.coefficient_mut(channel, index) {
                *c = value;
            }
        }
        RealRole::Limit(limit) => limit.set(&mut params.limits, value),
        RealRole::Input(_)
        | RealRole::Condition(_)
        | RealRole::Output(_)
        | RealRole::State(_)
        | RealRole::Derivative(_) => {}
    }
}

/// The sign convention `isoSignConvention = iso` selects.
pub(crate) fn convention_of(iso: bool) -> SignConvention {
    if iso {
        SignConvention::Iso
    } else {
        SignConvention::Paper
    }
}
