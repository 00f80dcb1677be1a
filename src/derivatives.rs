//! Exact directional derivatives (fmi2/fmi3GetDirectionalDerivative): the model evaluated once
//! over a dual number whose derivative part is the seed `dvKnown`, so one call gives
//! `dvUnknown = J dvKnown` for every unknown at the cost of about two evaluations.
//!
//! Knowns are inputs (Fz, alpha, kappa, gamma, vx, p, T_tread) and the relaxation states;
//! unknowns are outputs and the states' time derivatives. A clamped input has derivative 0
//! beyond its range (see `mf87::real`).

use mf87::{Dual64, Inputs, LaggedSlip, OperatingConditions, evaluate_extended};

use crate::call_sequence::Abi;
use crate::instance_values::InstanceValues;
use crate::variables::{REAL_VARIABLES, RealRole, RealVariable, real_index};

/// The names of the arguments a derivative call's messages refer to: FMI 2.0's or FMI 3.0's.
pub(crate) struct Arguments {
    pub(crate) unknown: &'static str,
    pub(crate) known: &'static str,
    pub(crate) seed: &'static str,
}

impl Arguments {
    pub(crate) fn of(abi: Abi) -> Arguments {
        match abi {
            Abi::Fmi2 => Arguments {
                unknown: "vUnknown_ref",
                known: "vKnown_ref",
                seed: "dvKnown",
            },
            Abi::Fmi3 => Arguments {
                unknown: "unknowns",
                known: "knowns",
                seed: "seed",
            },
        }
    }
}

/// `J dv_known` for the variables `unknown`, with `known[i]` seeded by `dv_known[i]`; or the
/// message naming the reference that cannot take part (in the words of `arguments`).
pub(crate) fn directional(
    arguments: &Arguments,
    model: &InstanceValues,
    unknown: &[u32],
    known: &[u32],
    dv_known: &[f64],
    dv_unknown: &mut [f64],
) -> Result<(), String> {
    let dual = |v: f64| Dual64::from_re(v);
    let mut inputs = Inputs {
        fz: dual(model.inputs.fz),
        alpha: dual(model.inputs.alpha),
        kappa: dual(model.inputs.kappa),
        gamma: dual(model.inputs.gamma),
    };
    let c = &model.conditions;
    let mut conditions = OperatingConditions {
        vx: dual(c.vx),
        p: dual(c.p),
        t_tread: dual(c.t_tread),
    };
    let l = &model.lagged;
    let mut lagged = LaggedSlip {
        fx: dual(l.fx),
        fy: dual(l.fy),
        mz: dual(l.mz),
    };
    for (vr, seed) in known.iter().zip(dv_known) {
        let var = variable(*vr, arguments.known)?;
        if !seed.is_finite() {
            return Err(format!(
                "{} for {} is {seed}: it must be finite",
                arguments.seed, var.name
            ));
        }
        match var.role {
            RealRole::Input(v) => {
                let mut x = inputs.get(v);
                x.eps += seed;
                inputs.set(v, x);
            }
            RealRole::Condition(v) => {
                let mut x = conditions.get(v);
                x.eps += seed;
                conditions.set(v, x);
            }
            RealRole::State(channel) => lagged.get_mut(channel).eps += seed,
            _ => {
                return Err(format!(
                    "{} {vr} ({}) is neither an input nor a state: derivatives are \
                     taken with respect to the inputs and the relaxation states",
                    arguments.known, var.name
                ));
            }
        }
    }
    let out = evaluate_extended(
        &model.params,
        &inputs,
        &conditions,
        &lagged,
        model.convention,
    );
    let rates = lagged.rates(&model.params, &inputs, conditions.vx);
    for (vr, value) in unknown.iter().zip(dv_unknown.iter_mut()) {
        let var = variable(*vr, arguments.unknown)?;
        match var.role {
            RealRole::Output(v) => *value = out.get(v).eps,
            RealRole::Derivative(channel) => *value = rates.get(channel).eps,
            _ => {
                return Err(format!(
                    "{} {vr} ({}) is neither an output nor a state derivative: \
                     derivatives are given of those",
                    arguments.unknown, var.name
                ));
            }
        }
    }
    Ok(())
}

/// The Real variable `vr`, or the message naming the argument it came in.
fn variable(vr: u32, argument: &str) -> Result<&'static RealVariable, String> {
    real_index(vr)
        .map(|i| &REAL_VARIABLES[i])
        .ok_or_else(|| format!("{argument}: {vr} is not the value reference of a Real variable"))
}
