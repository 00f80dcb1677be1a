//! The FMI 3.0 side of build.rs: reads `modelDescription/fmi3/modelDescription.xml`, maps each
//! of its variables onto the FMI 2.0 description's (the same model behind both: a scalar by
//! its name, a coefficient array by its elements `<channel>_<coefficient>`) and generates the
//! table the `fmi3*` functions translate value references with. Fails the build when the two
//! descriptions disagree: a variable of one missing from the other, another unit, start
//! value, causality or variability, a coefficient array not in the coefficient table's order,
//! another model identifier or log categories, a ModelStructure that does not list the
//! outputs and derivatives.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use mf87::{Channel, Params};

use super::{attr, child, declared_units, parse_f64};

/// An FMI 2.0 variable as the FMI 3.0 description is checked against it.
struct Fmi2Variable {
    kind: &'static str,
    vr: u32,
    causality: String,
    variability: String,
    unit: String,
    start: Option<String>,
}

/// The FMI 2.0 description's variables by name.
fn fmi2_variables(root: roxmltree::Node) -> Result<BTreeMap<String, Fmi2Variable>, String> {
    let units = declared_units(root, "Real")?;
    let mut out = BTreeMap::new();
    for var in child(root, "ModelVariables")?
        .children()
        .filter(|n| n.has_tag_name("ScalarVariable"))
    {
        let element = var.children().find(|n| n.is_element()).unwrap();
        let kind = match element.tag_name().name() {
            "Real" => "Float64",
            "Boolean" => "Boolean",
            _ => "String",
        };
        let unit = match element.attribute("declaredType") {
            Some(t) => units.iter().find(|(n, _)| n == t).unwrap().1.clone(),
            None => element.attribute("unit").unwrap_or("").to_string(),
        };
        out.insert(
            attr(var, "name")?.to_string(),
            Fmi2Variable {
                kind,
                vr: attr(var, "valueReference")?.parse().unwrap(),
                causality: var.attribute("causality").unwrap_or("local").to_string(),
                variability: var
                    .attribute("variability")
                    .unwrap_or("continuous")
                    .to_string(),
                unit,
                start: element.attribute("start").map(str::to_string),
            },
        );
    }
    Ok(out)
}

/// The start values of a variable of either description as numbers (a Boolean as 0/1).
fn start_values(text: &str, name: &str) -> Result<Vec<f64>, String> {
    text.split_whitespace()
        .map(|s| match s {
            "true" => Ok(1.0),
            "false" => Ok(0.0),
            s => parse_f64(s, name),
        })
        .collect()
}

/// The Rust source of the FMI 3.0 tables, from the FMI 3.0 description `doc3` checked against
/// the FMI 2.0 one, `doc2`.
pub(super) fn generate(
    doc3: &roxmltree::Document,
    doc2: &roxmltree::Document,
) -> Result<String, String> {
    let root = doc3.root_element();
    let root2 = doc2.root_element();
    if attr(root, "fmiVersion")? != "3.0" {
        return Err("fmiVersion must be 3.0".into());
    }
    let token = attr(root, "instantiationToken")?;
    let identifier2 = attr(child(root2, "CoSimulation")?, "modelIdentifier")?;
    for interface in ["CoSimulation", "ModelExchange"] {
        let id = attr(child(root, interface)?, "modelIdentifier")?;
        if id != identifier2 {
            return Err(format!(
                "{interface} modelIdentifier {id:?} differs from the FMI 2.0 FMU's {identifier2:?}: both archives hold the same library"
            ));
        }
    }
    check_log_categories(root, root2)?;
    let fmi2 = fmi2_variables(root2)?;
    let units = declared_units(root, "Float64")?;
    let mut rows = String::new();
    let mut covered: BTreeSet<String> = BTreeSet::new();
    let mut vrs: BTreeMap<u32, String> = BTreeMap::new();
    let mut outputs = BTreeSet::new();
    let mut derivatives = BTreeSet::new();
    let mut states: BTreeMap<u32, String> = BTreeMap::new();
    for var in child(root, "ModelVariables")?
        .children()
        .filter(|n| n.is_element())
    {
        let kind = var.tag_name().name();
        let name = attr(var, "name")?;
        let vr: u32 = attr(var, "valueReference")?
            .parse()
            .map_err(|_| format!("{name}: valueReference is not an unsigned integer"))?;
        if let Some(other) = vrs.insert(vr, name.to_string()) {
            return Err(format!("{name}: value reference {vr} is also {other}'s"));
        }
        let causality = var.attribute("causality").unwrap_or("local");
        let variability = var.attribute("variability").unwrap_or(match kind {
            "Float64" | "Float32" => "continuous",
            _ => "discrete",
        });
        let unit = match var.attribute("declaredType") {
            Some(t) => units
                .iter()
                .find(|(n, _)| n == t)
                .map(|(_, u)| u.clone())
                .ok_or_else(|| format!("{name}: unknown declaredType {t:?}"))?,
            None => var.attribute("unit").unwrap_or("").to_string(),
        };
        let start = match kind {
            "String" => var
                .children()
                .find(|n| n.has_tag_name("Start"))
                .and_then(|s| s.attribute("value"))
                .map(str::to_string),
            _ => var.attribute("start").map(str::to_string),
        };
        let dimensions: Vec<roxmltree::Node> = var
            .children()
            .filter(|n| n.has_tag_name("Dimension"))
            .collect();
        if causality == "independent" {
            if kind != "Float64" || name != "time" {
                return Err(format!(
                    "the independent variable must be Float64 time, not {name}"
                ));
            }
            writeln!(
                rows,
                "    Variable3 {{ vr: {vr}, name: {name:?}, kind: Kind3::Time }},"
            )
            .unwrap();
            continue;
        }
        let elements: Vec<String> = if dimensions.is_empty() {
            vec![name.to_string()]
        } else {
            array_elements(name, &dimensions)?
        };
        let mut fmi2_vrs = Vec::new();
        for element in &elements {
            let Some(v2) = fmi2.get(element) else {
                return Err(format!(
                    "{name}: {element} is not a variable of the FMI 2.0 FMU"
                ));
            };
            if !covered.insert(element.clone()) {
                return Err(format!("{element} appears twice"));
            }
            if v2.kind != kind {
                return Err(format!(
                    "{name} is {kind}, the FMI 2.0 FMU's {element} is {}",
                    v2.kind
                ));
            }
            if (v2.causality.as_str(), v2.variability.as_str()) != (causality, variability) {
                return Err(format!(
                    "{name}: causality/variability {causality}/{variability}, the FMI 2.0 FMU's {element} has {}/{}",
                    v2.causality, v2.variability
                ));
            }
            if v2.unit != unit {
                return Err(format!(
                    "{name}: unit {unit:?}, the FMI 2.0 FMU's {element} has {:?}",
                    v2.unit
                ));
            }
            fmi2_vrs.push(v2.vr);
        }
        check_start(name, kind, start.as_deref(), &elements, &fmi2)?;
        if causality == "output" {
            outputs.insert(vr);
        }
        if name.starts_with("lag_") {
            states.insert(vr, name.to_string());
        }
        if let Some(of) = var.attribute("derivative") {
            let of: u32 = of.parse().map_err(|_| format!("{name}: bad derivative"))?;
            let state = &name[4..name.len() - 1];
            if states.get(&of).map(String::as_str) != Some(state) {
                return Err(format!(
                    "{name}: derivative=\"{of}\" is not the value reference of {state}"
                ));
            }
            derivatives.insert(vr);
        }
        let kind_row = match kind {
            "Float64" => format!("Kind3::Float64(&{fmi2_vrs:?})"),
            "Boolean" => format!("Kind3::Boolean({})", fmi2_vrs[0]),
            _ => format!("Kind3::String({})", fmi2_vrs[0]),
        };
        writeln!(
            rows,
            "    Variable3 {{ vr: {vr}, name: {name:?}, kind: {kind_row} }},"
        )
        .unwrap();
    }
    if let Some(missing) = fmi2.keys().find(|n| !covered.contains(*n)) {
        return Err(format!(
            "the FMI 2.0 FMU's {missing} has no FMI 3.0 variable"
        ));
    }
    check_structure(root, &outputs, &derivatives)?;
    let mut code = String::from(
        "// Generated by build.rs from modelDescription/fmi3/modelDescription.xml. Do not edit.\n\n",
    );
    writeln!(code, "pub const INSTANTIATION_TOKEN: &str = {token:?};").unwrap();
    writeln!(code, "\npub const VARIABLES_3: &[Variable3] = &[\n{rows}];").unwrap();
    Ok(code)
}

/// The FMI 2.0 names of a coefficient array's elements: `<channel>_coefficients` of one
/// dimension as long as the channel's coefficient table.
fn array_elements(name: &str, dimensions: &[roxmltree::Node]) -> Result<Vec<String>, String> {
    let channel = name
        .strip_suffix("_coefficients")
        .and_then(Channel::from_name)
        .ok_or_else(|| format!("{name}: only <channel>_coefficients may be an array"))?;
    let names = Params::coefficient_names(channel);
    let [dimension] = dimensions else {
        return Err(format!("{name}: one dimension expected"));
    };
    let size: usize = attr(*dimension, "start")?
        .parse()
        .map_err(|_| format!("{name}: Dimension start is not a size"))?;
    if size != names.len() {
        return Err(format!(
            "{name}: dimension {size}, {channel} has {} coefficients",
            names.len()
        ));
    }
    Ok(names.iter().map(|c| format!("{channel}_{c}")).collect())
}

/// A variable's start values equal the FMI 2.0 FMU's of its elements.
fn check_start(
    name: &str,
    kind: &str,
    start: Option<&str>,
    elements: &[String],
    fmi2: &BTreeMap<String, Fmi2Variable>,
) -> Result<(), String> {
    let expected: Vec<Option<&str>> = elements.iter().map(|e| fmi2[e].start.as_deref()).collect();
    if kind == "String" {
        return if start == expected[0] {
            Ok(())
        } else {
            Err(format!(
                "{name}: start {start:?}, the FMI 2.0 FMU's is {:?}",
                expected[0]
            ))
        };
    }
    match (start, expected.iter().all(Option::is_none)) {
        (None, true) => Ok(()),
        (Some(s), false) => {
            let got = start_values(s, name)?;
            let want: Vec<f64> = expected
                .iter()
                .map(|e| start_values(e.unwrap_or("nan"), name).map(|v| v[0]))
                .collect::<Result<_, _>>()?;
            let same = got.len() == want.len()
                && got
                    .iter()
                    .zip(&want)
                    .all(|(a, b)| (a - b).abs() <= 1e-12 * b.abs().max(1.0));
            if same {
                Ok(())
            } else {
                Err(format!(
                    "{name}: start {got:?}, the FMI 2.0 FMU's is {want:?}"
                ))
            }
        }
        _ => Err(format!("{name}: a start value in one description only")),
    }
}

fn check_log_categories(root: roxmltree::Node, root2: roxmltree::Node) -> Result<(), String> {
    let names = |r: roxmltree::Node| -> Result<Vec<String>, String> {
        Ok(child(r, "LogCategories")?
            .children()
            .filter(|n| n.has_tag_name("Category"))
            .filter_map(|n| n.attribute("name").map(str::to_string))
            .collect())
    };
    if names(root)? != names(root2)? {
        return Err("LogCategories differ from the FMI 2.0 FMU's".into());
    }
    Ok(())
}

/// ModelStructure lists exactly the outputs and the state derivatives.
fn check_structure(
    root: roxmltree::Node,
    outputs: &BTreeSet<u32>,
    derivatives: &BTreeSet<u32>,
) -> Result<(), String> {
    let structure = child(root, "ModelStructure")?;
    for (tag, expected) in [
        ("Output", outputs),
        ("ContinuousStateDerivative", derivatives),
    ] {
        let listed: BTreeSet<u32> = structure
            .children()
            .filter(|n| n.has_tag_name(tag))
            .map(|n| {
                attr(n, "valueReference")
                    .and_then(|v| v.parse().map_err(|_| "bad valueReference".to_string()))
            })
            .collect::<Result<_, _>>()?;
        if listed != *expected {
            return Err(format!(
                "ModelStructure lists {tag} {listed:?}, the variables are {expected:?}"
            ));
        }
    }
    Ok(())
}
