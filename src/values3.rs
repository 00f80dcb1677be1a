//! FMI 3.0 variables on the instance: each FMI 3.0 value reference translated to the FMI 2.0
//! ones of the same model (a coefficient array to its elements, see `variables::Kind3`), and
//! the values counted against `nValues`. Safe code: the exports hand it checked slices.

use std::ffi::{CStr, c_char};

use crate::call_sequence::State;
use crate::instance::Instance;
use crate::logging::Status;
use crate::variables::{
    Kind3, REAL_VARIABLES, RealRole, VARIABLES_3, Variable3, real_index, variable_3,
};

/// The FMI 3.0 type names of the variable kinds, for messages.
fn type_name(kind: Kind3) -> &'static str {
    match kind {
        Kind3::Time | Kind3::Float64(_) => "Float64",
        Kind3::Boolean(_) => "Boolean",
        Kind3::String(_) => "String",
    }
}

/// The number of values a variable holds (an array's elements).
fn size(kind: Kind3) -> usize {
    match kind {
        Kind3::Float64(elements) => elements.len(),
        _ => 1,
    }
}

/// The variables behind `vrs`, each of type `wanted`, and their values matching `n_values`;
/// else the error naming the first reference or count that does not fit.
fn variables(
    inst: &Instance,
    vrs: &[u32],
    n_values: usize,
    wanted: &str,
) -> Result<Vec<&'static Variable3>, Status> {
    let mut out = Vec::with_capacity(vrs.len());
    for (i, &vr) in vrs.iter().enumerate() {
        match variable_3(vr) {
            Some(v) if type_name(v.kind) == wanted => out.push(v),
            Some(v) => {
                return Err(inst.error(format!(
                    "valueReferences[{i}] = {vr} is {}, a {} variable, not {wanted}",
                    v.name,
                    type_name(v.kind)
                )));
            }
            None => return Err(unknown(inst, i, vr, wanted)),
        }
    }
    let total: usize = out.iter().map(|v| size(v.kind)).sum();
    if total != n_values {
        return Err(inst.error(format!(
            "nValues = {n_values}, but the variables asked for hold {total} values"
        )));
    }
    Ok(out)
}

#[cold]
fn unknown(inst: &Instance, i: usize, vr: u32, wanted: &str) -> Status {
    let known: Vec<String> = VARIABLES_3
        .iter()
        .filter(|v| type_name(v.kind) == wanted)
        .map(|v| format!("{} {}", v.vr, v.name))
        .collect();
    inst.error(format!(
        "valueReferences[{i}] = {vr} is not a variable of this FMU; its {wanted} variables are {}",
        if known.is_empty() {
            "none".to_string()
        } else {
            known.join(", ")
        }
    ))
}

/// An error for a type this FMU has no variable of (nothing to get or set unless no
/// reference is passed).
pub(crate) fn no_variables_of_type(inst: &Instance, vrs: &[u32], type_name: &str) -> Status {
    match vrs.first() {
        None => Status::Ok,
        Some(&vr) => unknown(inst, 0, vr, type_name),
    }
}

pub(crate) fn get_float64(inst: &mut Instance, vrs: &[u32], values: &mut [f64]) -> Status {
    let vars = match variables(inst, vrs, values.len(), "Float64") {
        Ok(v) => v,
        Err(s) => return s,
    };
    let mut status = Status::Ok;
    let mut at = 0;
    for v in vars {
        match v.kind {
            Kind3::Time => {
                values[at] = inst.model.time;
                at += 1;
            }
            Kind3::Float64(elements) => {
                if inst.model.state == State::Instantiated
                    && let Some(s) = calculated(inst, v, elements)
                {
                    return s;
                }
                let n = elements.len();
                status = status.max(inst.get_real(elements, &mut values[at..at + n]));
                at += n;
            }
            _ => unreachable!("checked Float64"),
        }
    }
    status
}

/// Before initialization mode the outputs, states and state derivatives have no value yet
/// (they are calculated): an error naming the variable, for one of them.
fn calculated(inst: &Instance, v: &Variable3, elements: &[u32]) -> Option<Status> {
    let role = real_index(*elements.first()?).map(|i| REAL_VARIABLES[i].role)?;
    matches!(
        role,
        RealRole::Output(_) | RealRole::State(_) | RealRole::Derivative(_)
    )
    .then(|| {
        inst.error(format!(
            "{} is calculated: it has a value from fmi3EnterInitializationMode on",
            v.name
        ))
    })
}

pub(crate) fn set_float64(inst: &mut Instance, vrs: &[u32], values: &[f64]) -> Status {
    let vars = match variables(inst, vrs, values.len(), "Float64") {
        Ok(v) => v,
        Err(s) => return s,
    };
    let mut status = Status::Ok;
    let mut at = 0;
    for v in vars {
        match v.kind {
            Kind3::Time => {
                status = status.max(inst.error(format!(
                    "{} is the independent variable: it is set by fmi3EnterInitializationMode's \
                     startTime, fmi3SetTime (Model Exchange) and fmi3DoStep (co-simulation)",
                    v.name
                )));
                at += 1;
            }
            Kind3::Float64(elements) => {
                let n = elements.len();
                status = status.max(inst.set_real(elements, &values[at..at + n]));
                at += n;
            }
            _ => unreachable!("checked Float64"),
        }
    }
    status
}

/// The FMI 2.0 value reference behind each of `vars` (Boolean or String scalars).
fn scalar_references(vars: &[&Variable3]) -> Vec<u32> {
    vars.iter()
        .map(|v| match v.kind {
            Kind3::Boolean(vr) | Kind3::String(vr) => vr,
            _ => unreachable!("checked Boolean or String"),
        })
        .collect()
}

pub(crate) fn get_boolean(inst: &mut Instance, vrs: &[u32], values: &mut [bool]) -> Status {
    let vars = match variables(inst, vrs, values.len(), "Boolean") {
        Ok(v) => v,
        Err(s) => return s,
    };
    let mut ints = vec![0; values.len()];
    let status = inst.get_boolean(&scalar_references(&vars), &mut ints);
    for (b, i) in values.iter_mut().zip(ints) {
        *b = i != 0;
    }
    status
}

pub(crate) fn set_boolean(inst: &mut Instance, vrs: &[u32], values: &[bool]) -> Status {
    let vars = match variables(inst, vrs, values.len(), "Boolean") {
        Ok(v) => v,
        Err(s) => return s,
    };
    let ints: Vec<i32> = values.iter().map(|b| i32::from(*b)).collect();
    inst.set_boolean(&scalar_references(&vars), &ints)
}

pub(crate) fn get_string(inst: &mut Instance, vrs: &[u32], values: &mut [*const c_char]) -> Status {
    let vars = match variables(inst, vrs, values.len(), "String") {
        Ok(v) => v,
        Err(s) => return s,
    };
    inst.get_string(&scalar_references(&vars), values)
}

pub(crate) fn set_string(inst: &mut Instance, vrs: &[u32], values: &[Option<&CStr>]) -> Status {
    let vars = match variables(inst, vrs, values.len(), "String") {
        Ok(v) => v,
        Err(s) => return s,
    };
    inst.set_string(&scalar_references(&vars), values)
}

/// The FMI 2.0 Real value references of scalar Float64 variables `vrs` (inputs, outputs,
/// states, derivatives: what derivatives are taken of and with respect to), or the error
/// naming the argument `what` and the reference that is not one.
pub(crate) fn scalar_reals(inst: &Instance, vrs: &[u32], what: &str) -> Result<Vec<u32>, Status> {
    vrs.iter()
        .enumerate()
        .map(|(i, &vr)| match variable_3(vr).map(|v| v.kind) {
            Some(Kind3::Float64([element])) => Ok(*element),
            Some(_) => Err(inst.error(format!(
                "{what}[{i}] = {vr} ({}) is not a scalar Float64 input, output, state or \
                 derivative: derivatives are taken of the outputs and state derivatives with \
                 respect to the inputs and states",
                variable_3(vr).map_or("?", |v| v.name)
            ))),
            None => Err(unknown(inst, i, vr, "Float64")),
        })
        .collect()
}
