//! Generates the Rust side of the FMU's interface from `modelDescription/modelDescription.xml`:
//! the GUID, the model identifier, the variable tables (value reference, name, role, start)
//! and the log categories. Fails the build when the XML and the model disagree: an unknown
//! variable name, a model input, coefficient or limit without a variable, a start value that
//! differs from the coefficient table, a ModelStructure that does not list the outputs.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::PathBuf;

use mf87::{Channel, ConditionVar, InputVar, LimitVar, OutputVar, Params};

#[path = "build/fmi3.rs"]
mod fmi3;

const MODEL_DESCRIPTION: &str = "modelDescription/modelDescription.xml";
const MODEL_DESCRIPTION_3: &str = "modelDescription/fmi3/modelDescription.xml";
/// Linker version script: only the fmi2* and fmi3* functions are global.
const EXPORTS_MAP: &str = "exports.map";

/// Boolean, String and log-category names and the Rust items they map to.
const BOOLEAN_ROLES: &[(&str, &str)] = &[("isoSignConvention", "BooleanRole::IsoSignConvention")];
const STRING_ROLES: &[(&str, &str)] = &[("parameterFile", "StringRole::ParameterFile")];
const LOG_CATEGORIES: &[(&str, &str)] = &[
    ("logStatusError", "LogCategory::StatusError"),
    ("logStatusWarning", "LogCategory::StatusWarning"),
    ("logEvents", "LogCategory::Events"),
    ("logCalls", "LogCategory::Calls"),
];

fn main() {
    println!("cargo::rerun-if-changed={MODEL_DESCRIPTION}");
    println!("cargo::rerun-if-changed={MODEL_DESCRIPTION_3}");
    println!("cargo::rerun-if-changed=build/fmi3.rs");
    // Export only the FMI functions: keep symbols of dependencies (fmi-sys defines a
    // `callback_log`) out of the FMU's dynamic symbol table. On Windows the linker wrapper
    // `xtask/linkers/win64-fmi-gcc` does the same to rustc's export list.
    println!("cargo::rerun-if-changed={EXPORTS_MAP}");
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        let map = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap()).join(EXPORTS_MAP);
        println!(
            "cargo::rustc-cdylib-link-arg=-Wl,--version-script={}",
            map.display()
        );
    }
    let text = std::fs::read_to_string(MODEL_DESCRIPTION)
        .unwrap_or_else(|e| panic!("cannot read {MODEL_DESCRIPTION}: {e}"));
    let doc = roxmltree::Document::parse(&text)
        .unwrap_or_else(|e| panic!("{MODEL_DESCRIPTION} is not well-formed XML: {e}"));
    let code = generate(&doc).unwrap_or_else(|e| panic!("{MODEL_DESCRIPTION}: {e}"));
    let out = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    std::fs::write(out.join("model_description.rs"), code).unwrap();
    let text3 = std::fs::read_to_string(MODEL_DESCRIPTION_3)
        .unwrap_or_else(|e| panic!("cannot read {MODEL_DESCRIPTION_3}: {e}"));
    let doc3 = roxmltree::Document::parse(&text3)
        .unwrap_or_else(|e| panic!("{MODEL_DESCRIPTION_3} is not well-formed XML: {e}"));
    let code3 =
        fmi3::generate(&doc3, &doc).unwrap_or_else(|e| panic!("{MODEL_DESCRIPTION_3}: {e}"));
    std::fs::write(out.join("model_description_fmi3.rs"), code3).unwrap();
}

fn child<'a, 'i>(
    node: roxmltree::Node<'a, 'i>,
    name: &str,
) -> Result<roxmltree::Node<'a, 'i>, String> {
    node.children()
        .find(|n| n.has_tag_name(name))
        .ok_or_else(|| format!("<{}> has no <{name}>", node.tag_name().name()))
}

fn attr<'a>(node: roxmltree::Node<'a, '_>, name: &str) -> Result<&'a str, String> {
    node.attribute(name)
        .ok_or_else(|| format!("<{}> lacks attribute {name}", node.tag_name().name()))
}

fn lookup<'a>(table: &[(&str, &'a str)], name: &str, what: &str) -> Result<&'a str, String> {
    table
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, item)| *item)
        .ok_or_else(|| format!("{what} {name:?} is not known to the FMU code"))
}

fn parse_f64(text: &str, name: &str) -> Result<f64, String> {
    text.parse()
        .map_err(|_| format!("start value {text:?} of {name} is not a number"))
}

/// The Rust expression for a Real variable's role, and the model's own default for parameters.
fn real_role(
    name: &str,
    causality: &str,
    params: &Params,
) -> Result<(String, Option<f64>), String> {
    match causality {
        "input" => InputVar::from_name(name)
            .map(|v| format!("RealRole::Input(InputVar::{v:?})"))
            .or_else(|| {
                ConditionVar::from_name(name)
                    .map(|v| format!("RealRole::Condition(ConditionVar::{v:?})"))
            })
            .map(|role| (role, None))
            .ok_or_else(|| {
                format!(
                    "input {name:?} is neither an input of the model nor an operating condition"
                )
            }),
        "output" => OutputVar::from_name(name)
            .map(|v| (format!("RealRole::Output(OutputVar::{v:?})"), None))
            .ok_or_else(|| format!("output {name:?} is not an output of the model")),
        "parameter" => {
            if let Some(limit) = LimitVar::from_name(name) {
                let default = limit.get(&params.limits);
                return Ok((
                    format!("RealRole::Limit(LimitVar::{limit:?})"),
                    Some(default),
                ));
            }
            let (channel, coef) = name
                .split_once('_')
                .and_then(|(ch, coef)| Some((Channel::from_name(ch)?, coef)))
                .ok_or_else(|| {
                    format!("parameter {name:?} is neither a limit nor <channel>_<coefficient>")
                })?;
            let index = Params::coefficient_index(channel, coef)
                .ok_or_else(|| format!("{channel} has no coefficient {coef:?} ({name})"))?;
            let default = params.coefficient(channel, index).unwrap();
            Ok((
                format!("RealRole::Coefficient(Channel::{channel:?}, {index})"),
                Some(default),
            ))
        }
        "local" => {
            let state = |n: &str| n.strip_prefix("lag_").and_then(Channel::from_name);
            if let Some(channel) = state(name) {
                return Ok((format!("RealRole::State(Channel::{channel:?})"), None));
            }
            name.strip_prefix("der(")
                .and_then(|n| n.strip_suffix(')'))
                .and_then(state)
                .map(|channel| (format!("RealRole::Derivative(Channel::{channel:?})"), None))
                .ok_or_else(|| {
                    format!("local {name:?} is neither lag_<channel> nor der(lag_<channel>)")
                })
        }
        other => Err(format!(
            "Real variable {name} has unsupported causality {other:?}"
        )),
    }
}

/// (declared type name, unit) of every type definition of `kind`: FMI 2.0's `Real`
/// (`<SimpleType><Real unit>`), FMI 3.0's `Float64` (`<Float64Type unit>`).
fn declared_units(root: roxmltree::Node, kind: &str) -> Result<Vec<(String, String)>, String> {
    let Ok(types) = child(root, "TypeDefinitions") else {
        return Ok(Vec::new());
    };
    let fmi3_tag = format!("{kind}Type");
    types
        .children()
        .filter(|n| n.is_element())
        .filter_map(|t| {
            let unit_holder = if t.has_tag_name("SimpleType") {
                child(t, kind).ok()?
            } else if t.has_tag_name(fmi3_tag.as_str()) {
                t
            } else {
                return None;
            };
            Some(attr(t, "name").map(|name| {
                (
                    name.to_string(),
                    unit_holder.attribute("unit").unwrap_or("").to_string(),
                )
            }))
        })
        .collect()
}

/// The unit of variable `name` whose type attributes `element` holds: its declared type's
/// (from `units`, see [`declared_units`]), else its own, else none.
fn unit_of(
    name: &str,
    element: roxmltree::Node,
    units: &[(String, String)],
) -> Result<String, String> {
    match element.attribute("declaredType") {
        Some(t) => units
            .iter()
            .find(|(n, _)| n == t)
            .map(|(_, u)| u.clone())
            .ok_or_else(|| format!("{name}: unknown declaredType {t:?}")),
        None => Ok(element.attribute("unit").unwrap_or("").to_string()),
    }
}

/// The variable tables read from `<ModelVariables>`, and what the checks after the loop need.
#[derive(Default)]
struct Tables {
    /// Rust source of the rows of REAL_VARIABLES, BOOLEAN_VARIABLES, STRING_VARIABLES.
    reals: String,
    booleans: String,
    strings: String,
    /// 1-based indices of the outputs and of the state derivatives.
    outputs: BTreeSet<usize>,
    derivatives: BTreeSet<usize>,
    /// State name -> its 1-based index.
    states: BTreeMap<String, usize>,
    /// Value references seen per type (Real, Boolean, String).
    seen_vr: [BTreeSet<u32>; 3],
    /// (value reference, position in REAL_VARIABLES).
    real_index: Vec<(u32, usize)>,
    /// Names of the coefficient and limit parameters, and of the inputs.
    model_names: BTreeSet<String>,
    input_names: BTreeSet<String>,
}

/// One ScalarVariable's attributes as the tables need them.
struct Variable<'a, 'i> {
    /// 1-based position in `<ModelVariables>`.
    index: usize,
    name: &'a str,
    vr: u32,
    causality: &'a str,
    variability: &'a str,
    description: &'a str,
    /// The type element (`<Real>`, `<Boolean>`, `<String>`).
    element: roxmltree::Node<'a, 'i>,
    start: Option<&'a str>,
    unit: String,
}

fn generate(doc: &roxmltree::Document) -> Result<String, String> {
    let root = doc.root_element();
    let guid = attr(root, "guid")?;
    let model_identifier = attr(child(root, "CoSimulation")?, "modelIdentifier")?;

    let mut code = String::from(
        "// Generated by build.rs from modelDescription/modelDescription.xml. Do not edit.\n\n",
    );
    writeln!(code, "pub const GUID: &str = {guid:?};").unwrap();
    writeln!(
        code,
        "pub const MODEL_IDENTIFIER: &str = {model_identifier:?};"
    )
    .unwrap();

    let tables = read_variables(root)?;
    check_model_has_variables(&tables)?;
    check_model_structure(root, &tables)?;
    let categories = log_categories(root)?;
    write_tables(&mut code, tables, &categories);
    Ok(code)
}

/// Reads every ScalarVariable into the tables, checking each against the model.
fn read_variables(root: roxmltree::Node) -> Result<Tables, String> {
    let params = Params::paper_table();
    let units = declared_units(root, "Real")?;
    let mut tables = Tables::default();
    let variables = child(root, "ModelVariables")?;
    for (position, var) in variables
        .children()
        .filter(|n| n.has_tag_name("ScalarVariable"))
        .enumerate()
    {
        let variable = read_variable(position + 1, var, &units, &mut tables.seen_vr)?;
        match variable.element.tag_name().name() {
            "Real" => tables.add_real(&variable, &params)?,
            "Boolean" => {
                let Variable { vr, name, .. } = variable;
                let role = lookup(BOOLEAN_ROLES, name, "Boolean")?;
                let start = variable.start.unwrap_or("false") == "true";
                writeln!(tables.booleans, "    BooleanVariable {{ vr: {vr}, name: {name:?}, role: {role}, start: {start} }},").unwrap();
            }
            _ => {
                let Variable { vr, name, .. } = variable;
                let role = lookup(STRING_ROLES, name, "String")?;
                let start = variable.start.unwrap_or("");
                writeln!(tables.strings, "    StringVariable {{ vr: {vr}, name: {name:?}, role: {role}, start: {start:?} }},").unwrap();
            }
        }
    }
    Ok(tables)
}

/// A ScalarVariable's attributes; fails on an unsupported type, a value reference used twice
/// for one type (recorded in `seen_vr`) or a non-fixed parameter.
fn read_variable<'a, 'i>(
    index: usize,
    var: roxmltree::Node<'a, 'i>,
    units: &[(String, String)],
    seen_vr: &mut [BTreeSet<u32>; 3],
) -> Result<Variable<'a, 'i>, String> {
    let name = attr(var, "name")?;
    let vr: u32 = attr(var, "valueReference")?
        .parse()
        .map_err(|_| format!("{name}: valueReference is not an unsigned integer"))?;
    let causality = var.attribute("causality").unwrap_or("local");
    let variability = var.attribute("variability").unwrap_or("continuous");
    let description = var.attribute("description").unwrap_or("");
    let element = var
        .children()
        .find(|n| n.is_element())
        .ok_or_else(|| format!("{name} has no type element"))?;
    let kind = element.tag_name().name();
    let slot = match kind {
        "Real" => 0,
        "Boolean" => 1,
        "String" => 2,
        other => return Err(format!("{name}: type {other} is not supported")),
    };
    if !seen_vr[slot].insert(vr) {
        return Err(format!(
            "{name}: value reference {vr} is used twice for {kind}"
        ));
    }
    if causality == "parameter" && variability != "fixed" {
        return Err(format!("{name}: parameters are fixed in this FMU"));
    }
    let start = element.attribute("start");
    let unit = unit_of(name, element, units)?;
    Ok(Variable {
        index,
        name,
        vr,
        causality,
        variability,
        description,
        element,
        start,
        unit,
    })
}

impl Tables {
    /// Adds a Real variable: its role, its start value (a parameter's must equal the
    /// coefficient table's) and its place among the states, derivatives, outputs and inputs.
    fn add_real(&mut self, variable: &Variable, params: &Params) -> Result<(), String> {
        let Variable {
            index,
            name,
            vr,
            causality,
            description,
            ref unit,
            ..
        } = *variable;
        let (role, default) = real_role(name, causality, params)?;
        let start_value = real_start(name, variable.start, default)?;
        if role.starts_with("RealRole::State") {
            self.states.insert(name.to_string(), index);
        }
        if role.starts_with("RealRole::Derivative") {
            self.add_derivative(variable)?;
        }
        match causality {
            "output" => {
                self.outputs.insert(index);
            }
            "input" => {
                self.input_names.insert(name.to_string());
            }
            _ => {}
        }
        if role.starts_with("RealRole::Coefficient") || role.starts_with("RealRole::Limit") {
            self.model_names.insert(name.to_string());
        }
        self.real_index.push((vr, self.real_index.len()));
        let start = if start_value.is_nan() {
            "f64::NAN".to_string()
        } else {
            format!("{start_value:?}")
        };
        writeln!(
            self.reals,
            "    RealVariable {{ vr: {vr}, name: {name:?}, role: {role}, start: {start}, unit: {unit:?}, description: {description:?} }},"
        )
        .unwrap();
        Ok(())
    }

    /// der(x) must name x's index as its `derivative`.
    fn add_derivative(&mut self, variable: &Variable) -> Result<(), String> {
        let name = variable.name;
        let of = variable
            .element
            .attribute("derivative")
            .and_then(|d| d.parse::<usize>().ok())
            .ok_or_else(|| format!("{name} needs derivative=\"<index of its state>\""))?;
        let state = &name[4..name.len() - 1];
        if self.states.get(state) != Some(&of) {
            return Err(format!(
                "{name}: derivative=\"{of}\" is not the index of {state}"
            ));
        }
        self.derivatives.insert(variable.index);
        Ok(())
    }
}

/// A Real variable's start value: a parameter's must be given and equal the model's
/// `default`; NaN when there is neither.
fn real_start(name: &str, start: Option<&str>, default: Option<f64>) -> Result<f64, String> {
    match (start, default) {
        (Some(s), Some(default)) => {
            let s = parse_f64(s, name)?;
            if (s - default).abs() > 1e-12 * default.abs().max(1.0) {
                return Err(format!(
                    "start value {s} of {name} differs from the coefficient table's {default}"
                ));
            }
            Ok(s)
        }
        (Some(s), None) => parse_f64(s, name),
        (None, Some(_)) => Err(format!("parameter {name} needs a start value")),
        (None, None) => Ok(f64::NAN),
    }
}

/// Every coefficient, limit and input of the model must be a variable of the FMU.
fn check_model_has_variables(tables: &Tables) -> Result<(), String> {
    if tables.real_index.len() > 64 {
        return Err("more than 64 Real variables: widen the explicitly-set mask".into());
    }
    for channel in Channel::ALL {
        for coef in Params::coefficient_names(channel) {
            let name = format!("{channel}_{coef}");
            if !tables.model_names.contains(&name) {
                return Err(format!("coefficient {name} has no parameter variable"));
            }
        }
    }
    for limit in LimitVar::ALL {
        if !tables.model_names.contains(limit.name()) {
            return Err(format!("limit {} has no parameter variable", limit.name()));
        }
    }
    let declared_inputs: Vec<&str> = InputVar::ALL
        .iter()
        .map(|v| v.name())
        .chain(ConditionVar::ALL.iter().map(|v| v.name()))
        .collect();
    if let Some(missing) = declared_inputs
        .iter()
        .find(|n| !tables.input_names.contains(**n))
    {
        return Err(format!(
            "input {missing} of the model has no input variable"
        ));
    }
    Ok(())
}

/// ModelStructure lists exactly the outputs and the derivatives.
fn check_model_structure(root: roxmltree::Node, tables: &Tables) -> Result<(), String> {
    let structure = child(root, "ModelStructure")?;
    for (section, expected) in [
        ("Outputs", &tables.outputs),
        ("Derivatives", &tables.derivatives),
    ] {
        let listed: BTreeSet<usize> = child(structure, section)?
            .children()
            .filter(|n| n.has_tag_name("Unknown"))
            .map(|n| {
                attr(n, "index")
                    .and_then(|i| i.parse().map_err(|_| "bad Unknown index".to_string()))
            })
            .collect::<Result<_, _>>()?;
        if listed != *expected {
            return Err(format!(
                "ModelStructure/{section} lists {listed:?}, the variables are {expected:?}"
            ));
        }
    }
    Ok(())
}

/// The rows of LOG_CATEGORIES; the code logs to every category it knows, so each must be
/// declared.
fn log_categories(root: roxmltree::Node) -> Result<String, String> {
    let mut categories = String::new();
    let mut declared = BTreeSet::new();
    for cat in child(root, "LogCategories")?
        .children()
        .filter(|n| n.has_tag_name("Category"))
    {
        let name = attr(cat, "name")?;
        let item = lookup(LOG_CATEGORIES, name, "log category")?;
        writeln!(categories, "    ({name:?}, {item}),").unwrap();
        declared.insert(name);
    }
    if let Some((missing, _)) = LOG_CATEGORIES.iter().find(|(n, _)| !declared.contains(n)) {
        return Err(format!(
            "log category {missing} is not declared in <LogCategories>"
        ));
    }
    Ok(categories)
}

/// Writes the variable tables, the value-reference index and the log categories.
fn write_tables(code: &mut String, tables: Tables, categories: &str) {
    let Tables {
        reals,
        booleans,
        strings,
        real_index,
        ..
    } = tables;
    writeln!(
        code,
        "\npub const REAL_VARIABLES: &[RealVariable] = &[\n{reals}];"
    )
    .unwrap();
    // Value reference -> position in REAL_VARIABLES, as a dense table (u8::MAX: none).
    let max_vr = real_index.iter().map(|(vr, _)| *vr).max().unwrap_or(0) as usize;
    let mut table = vec![u8::MAX; max_vr + 1];
    for (vr, index) in real_index {
        table[vr as usize] = index as u8;
    }
    writeln!(
        code,
        "\nconst REAL_INDEX: [u8; {}] = {table:?};\n\n\
         /// The position in REAL_VARIABLES of the Real variable with value reference `vr`.\n\
         #[inline]\n\
         pub fn real_index(vr: u32) -> Option<usize> {{\n    \
         match REAL_INDEX.get(vr as usize) {{\n        Some(&i) if i != u8::MAX => Some(i as usize),\n        _ => None,\n    }}\n}}",
        table.len()
    )
    .unwrap();
    writeln!(
        code,
        "\npub const BOOLEAN_VARIABLES: &[BooleanVariable] = &[\n{booleans}];"
    )
    .unwrap();
    writeln!(
        code,
        "\npub const STRING_VARIABLES: &[StringVariable] = &[\n{strings}];"
    )
    .unwrap();
    writeln!(
        code,
        "\npub const LOG_CATEGORIES: &[(&str, LogCategory)] = &[\n{categories}];"
    )
    .unwrap();
}
