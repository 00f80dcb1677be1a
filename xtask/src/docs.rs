//! documentation/index.html, generated from modelDescription.xml (FMI 2.0 or 3.0) into
//! templates/index.html.

use std::collections::HashMap;
use std::fmt::Write;

use roxmltree::{Document, Node};

use crate::platforms::Platform;

const TEMPLATE: &str = include_str!("../templates/index.html");

/// (unit, display unit) -> (factor, offset) of the display-unit conversion.
type Conversions<'a> = HashMap<(Option<&'a str>, Option<&'a str>), (f64, f64)>;

/// The documentation page of the FMU described by `doc`, whose binaries are for `platforms`.
pub fn render(doc: &Document, platforms: &[Platform]) -> Result<String, String> {
    let root = doc.root_element();
    let co_sim = child(root, "CoSimulation").ok_or("no <CoSimulation> element")?;
    let interfaces = match child(root, "ModelExchange") {
        Some(_) => "co-simulation and Model Exchange",
        None => "co-simulation",
    };
    let id = attr(co_sim, "modelIdentifier");
    let fmi3 = root
        .attribute("fmiVersion")
        .is_some_and(|v| v.starts_with('3'));
    let binaries = binary_rows(&id, platforms, fmi3);
    let (token_label, token) = if fmi3 {
        ("Instantiation token", attr(root, "instantiationToken"))
    } else {
        ("GUID", attr(root, "guid"))
    };
    fill(
        TEMPLATE,
        &[
            ("modelName", attr(root, "modelName")),
            ("description", attr(root, "description")),
            ("fmiVersion", attr(root, "fmiVersion")),
            ("interfaces", interfaces.to_owned()),
            ("version", attr(root, "version")),
            ("tokenLabel", token_label.to_owned()),
            ("guid", token),
            ("generationTool", attr(root, "generationTool")),
            ("modelIdentifier", id),
            ("platforms", binaries),
            ("variables", variable_rows(root)?),
            ("logCategories", category_rows(root)),
        ],
    )
}

/// An attribute, escaped; empty when absent.
fn attr(node: Node, name: &str) -> String {
    escape(node.attribute(name).unwrap_or(""))
}

/// The display-unit conversions of `<UnitDefinitions>`.
fn conversions<'a>(root: Node<'a, '_>) -> Conversions<'a> {
    let mut conversions = HashMap::new();
    for unit in elements(root, "UnitDefinitions", "Unit") {
        for display in unit.children().filter(|n| n.has_tag_name("DisplayUnit")) {
            let num = |a, default| {
                let value = display.attribute(a).and_then(|v| v.parse().ok());
                value.unwrap_or(default)
            };
            let key = (unit.attribute("name"), display.attribute("name"));
            conversions.insert(key, (num("factor", 1.0), num("offset", 0.0)));
        }
    }
    conversions
}

/// The type definitions by name: FMI 2.0's `<SimpleType>` as its type element (`<Real unit=...
/// displayUnit=.../>`), FMI 3.0's `<Float64Type ...>` and the like as themselves.
fn type_definitions<'a, 'i>(root: Node<'a, 'i>) -> HashMap<&'a str, Node<'a, 'i>> {
    child(root, "TypeDefinitions")
        .into_iter()
        .flat_map(|s| s.children())
        .filter(|t| t.is_element())
        .filter_map(|t| {
            let element = if t.has_tag_name("SimpleType") {
                t.first_element_child()?
            } else {
                t
            };
            Some((t.attribute("name")?, element))
        })
        .collect()
}

/// Each variable as (the element with its name and causality, the element with its type
/// attributes): FMI 2.0's `<ScalarVariable>` and its type child, FMI 3.0's typed element
/// twice.
fn variables<'a, 'i>(root: Node<'a, 'i>) -> Result<Vec<(Node<'a, 'i>, Node<'a, 'i>)>, String> {
    child(root, "ModelVariables")
        .into_iter()
        .flat_map(|s| s.children())
        .filter(|n| n.is_element())
        .map(|var| {
            if var.has_tag_name("ScalarVariable") {
                let ty = var
                    .first_element_child()
                    .ok_or("a ScalarVariable has no type element")?;
                Ok((var, ty))
            } else {
                Ok((var, var))
            }
        })
        .collect()
}

/// One table row per variable: name, value reference, causality, variability, type (an
/// array's with its dimensions), unit and display unit (resolved through the declared type),
/// start (also in the display unit), description.
fn variable_rows(root: Node) -> Result<String, String> {
    let conversions = conversions(root);
    let types = type_definitions(root);
    let mut rows = String::new();
    for (var, ty) in variables(root)? {
        let declared = ty.attribute("declaredType");
        let base = declared.and_then(|d| types.get(d));
        // A variable's own attribute overrides its declared type's.
        let resolved = |a| {
            ty.attribute(a)
                .or_else(|| base.and_then(|b| b.attribute(a)))
        };
        let (unit, display) = (resolved("unit"), resolved("displayUnit"));

        let dimensions: Vec<&str> = ty
            .children()
            .filter(|n| n.has_tag_name("Dimension"))
            .filter_map(|d| d.attribute("start"))
            .collect();
        let mut type_name = ty.tag_name().name().to_owned();
        if !dimensions.is_empty() {
            write!(type_name, "[{}]", dimensions.join(", ")).unwrap();
        }
        if let Some(d) = declared {
            write!(type_name, " ({d})").unwrap();
        }
        // FMI 3.0 writes a String's start as a child element.
        let start_child = ty
            .children()
            .find(|n| n.has_tag_name("Start"))
            .and_then(|n| n.attribute("value"));
        let start = start_cell(
            ty.attribute("start").or(start_child),
            conversions.get(&(unit, display)),
            display,
        );
        let name = attr(var, "name");
        let cells = [
            format!("<code>{name}</code>"),
            attr(var, "valueReference"),
            escape(var.attribute("causality").unwrap_or("local")),
            escape(var.attribute("variability").unwrap_or("continuous")),
            escape(&type_name),
            escape(unit.unwrap_or("")),
            escape(display.unwrap_or("")),
            escape(&start),
            attr(var, "description"),
        ];
        write!(rows, "<tr id=\"var-{name}\">").unwrap();
        for cell in cells {
            write!(rows, "<td>{cell}</td>").unwrap();
        }
        rows.push_str("</tr>\n");
    }
    Ok(rows)
}

/// The start value as written, followed by its value in the display unit when it has one
/// and is not zero.
fn start_cell(
    start: Option<&str>,
    conversion: Option<&(f64, f64)>,
    display: Option<&str>,
) -> String {
    match start {
        None => String::new(),
        Some("") => "(empty)".to_owned(),
        Some(s) => match (s.parse::<f64>(), conversion) {
            (Ok(v), Some((factor, offset))) if v != 0.0 => {
                format!(
                    "{s} ({} {})",
                    short(v * factor + offset),
                    display.unwrap_or("")
                )
            }
            _ => s.to_owned(),
        },
    }
}

/// One table row per log category.
fn category_rows(root: Node) -> String {
    let mut categories = String::new();
    for cat in elements(root, "LogCategories", "Category") {
        let (name, description) = (attr(cat, "name"), attr(cat, "description"));
        writeln!(
            categories,
            "<tr><td><code>{name}</code></td><td>{description}</td></tr>"
        )
        .unwrap();
    }
    categories
}

/// One table row per binary: folder (FMI 3.0's platform tuple with `fmi3`), file name, what
/// it needs.
fn binary_rows(id: &str, platforms: &[Platform], fmi3: bool) -> String {
    let mut binaries = String::new();
    for p in platforms {
        writeln!(
            binaries,
            "<tr><td><code>binaries/{}</code></td><td><code>{id}.{}</code></td><td>{}</td></tr>",
            if fmi3 { p.tuple } else { p.folder },
            p.extension,
            escape(p.needs)
        )
        .unwrap();
    }
    binaries
}

fn child<'a, 'i>(node: Node<'a, 'i>, tag: &str) -> Option<Node<'a, 'i>> {
    node.children().find(|n| n.has_tag_name(tag))
}

/// The `<tag>` children of the `<section>` child of `root`.
fn elements<'a, 'i>(
    root: Node<'a, 'i>,
    section: &str,
    tag: &'static str,
) -> impl Iterator<Item = Node<'a, 'i>> {
    child(root, section)
        .into_iter()
        .flat_map(|s| s.children())
        .filter(move |n| n.has_tag_name(tag))
}

/// A number in at most 6 decimals, without trailing zeros.
fn short(x: f64) -> String {
    let s = format!("{x:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// Replaces each `{{key}}` in `template` by its (already escaped) value, in one pass.
fn fill(template: &str, values: &[(&str, String)]) -> Result<String, String> {
    let mut out = String::with_capacity(template.len() * 2);
    let mut rest = template;
    while let Some(start) = rest.find("{{") {
        let len = rest[start..].find("}}").ok_or("template: unclosed {{")?;
        let key = &rest[start + 2..start + len];
        let (_, value) = values
            .iter()
            .find(|(k, _)| *k == key)
            .ok_or_else(|| format!("template: unknown placeholder {key:?}"))?;
        out.push_str(&rest[..start]);
        out.push_str(value);
        rest = &rest[start + len + 2..];
    }
    out.push_str(rest);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn page() -> (String, String) {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../modelDescription/modelDescription.xml"
        );
        let xml = std::fs::read_to_string(path).unwrap();
        let platforms = [crate::platforms::LINUX64, crate::platforms::WIN64];
        let html = render(&Document::parse(&xml).unwrap(), &platforms).unwrap();
        (xml, html)
    }

    /// The table row of variable `name`.
    fn row<'h>(html: &'h str, name: &str) -> &'h str {
        let start = html
            .find(&format!("<tr id=\"var-{name}\">"))
            .unwrap_or_else(|| panic!("no row for {name}"));
        let len = html[start..].find("</tr>").unwrap();
        &html[start..start + len]
    }

    #[test]
    fn documents_every_variable_with_resolved_units() {
        let (xml, html) = page();
        let doc = Document::parse(&xml).unwrap();
        let names: Vec<_> = elements(doc.root_element(), "ModelVariables", "ScalarVariable")
            .map(|v| v.attribute("name").unwrap())
            .collect();
        assert_eq!(html.matches("<tr id=\"var-").count(), names.len());
        assert!(names.contains(&"der(lag_Fy)"), "{names:?}");
        for name in &names {
            assert!(
                row(&html, name).contains(&format!("<code>{name}</code>")),
                "{name}"
            );
        }
        // Units come from the declared types.
        assert!(row(&html, "Mz").contains("<td>N.m</td>"));
        assert!(row(&html, "Fz").contains("<td>N</td>"));
        assert!(row(&html, "kappa").contains("<td>1</td>"));
        let alpha = row(&html, "alpha");
        assert!(alpha.contains("<td>rad</td><td>deg</td>"), "{alpha}");
        assert!(row(&html, "gamma_max").contains("0.17453292519943295 (10 deg)"));
        assert!(row(&html, "Fx").contains("<td>output</td><td>continuous</td>"));
        assert!(row(&html, "isoSignConvention").contains("<td>Boolean</td>"));
        // Display units with a factor and with an offset.
        assert!(row(&html, "p").contains("<td>Pa</td><td>kPa</td><td>200000.0 (200 kPa)</td>"));
        assert!(row(&html, "T_tread").contains("<td>K</td><td>degC</td><td>298.15 (25 degC)</td>"));
        assert!(row(&html, "vx").contains("<td>input</td>"));
    }

    #[test]
    fn documents_the_fmi3_description_with_arrays_and_its_token() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../modelDescription/fmi3/modelDescription.xml"
        );
        let xml = std::fs::read_to_string(path).unwrap();
        let doc = Document::parse(&xml).unwrap();
        let platforms = [crate::platforms::LINUX64, crate::platforms::WIN64];
        let html = render(&doc, &platforms).unwrap();
        let names: Vec<_> = variables(doc.root_element())
            .unwrap()
            .iter()
            .map(|(v, _)| v.attribute("name").unwrap())
            .collect();
        assert_eq!(html.matches("<tr id=\"var-").count(), names.len());
        assert!(names.contains(&"Fy_coefficients") && names.contains(&"time"));
        let fy = row(&html, "Fy_coefficients");
        assert!(fy.contains("<td>Float64[14]</td>"), "{fy}");
        assert!(fy.contains("1.3 -22.1 1011.0"), "{fy}");
        assert!(row(&html, "alpha").contains("<td>Float64 (Angle)</td><td>rad</td><td>deg</td>"));
        assert!(row(&html, "parameterFile").contains("<td>(empty)</td>"));
        assert!(row(&html, "T_tread").contains("<td>K</td><td>degC</td><td>298.15 (25 degC)</td>"));
        let token = doc.root_element().attribute("instantiationToken").unwrap();
        assert!(html.contains(&format!(
            "<th>Instantiation token</th><td><code>{token}</code>"
        )));
        assert!(html.contains("<code>binaries/x86_64-windows</code>"));
        assert!(!html.contains("{{"));
    }

    #[test]
    fn page_is_filled_and_escaped() {
        let (_, html) = page();
        assert!(!html.contains("{{"));
        assert!(html.contains("<title>Pacejka87Tire"));
        assert!(html.contains("<code>Pacejka87Tire</code>"));
        assert!(
            html.contains("<code>binaries/win64</code></td><td><code>Pacejka87Tire.dll</code>")
        );
        assert!(html.contains("glibc 2.17 or later"));
        // The model description declares both interfaces; the page says so.
        assert!(html.contains("<td>co-simulation and Model Exchange, from one binary</td>"));
        assert!(html.contains("<h2 id=\"model-exchange\">Model Exchange</h2>"));
        // "Fz <= 0" in a description must arrive escaped.
        assert!(html.contains("Fz &lt;= 0 is a lifted wheel"));
        assert!(!html.contains("Fz <= 0"));
        // Self-contained: no external resources.
        assert!(!html.contains("src=") && !html.contains("<link"));
    }

    #[test]
    fn fill_and_escape() {
        assert_eq!(
            escape(r#"<a href="x">&'"#),
            "&lt;a href=&quot;x&quot;&gt;&amp;&#39;"
        );
        let values = [("a", "1".to_owned()), ("b", "{{a}}".to_owned())];
        assert_eq!(fill("x{{a}}y{{b}}", &values).unwrap(), "x1y{{a}}");
        assert!(fill("{{c}}", &values).is_err());
        assert_eq!(short(9.999_999_999_999_998), "10");
        assert_eq!(short(-0.5), "-0.5");
    }
}
