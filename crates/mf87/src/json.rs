//! Parameter files: [`Params::from_json`] reads and validates one, [`Params::to_json`] writes
//! one, and [`Params::paper_table`] is the bundled table of the paper.

use std::sync::LazyLock;

use crate::error::ParamError;
use crate::params::{PAPER_TABLE_JSON, Params};

impl Default for Params {
    /// The paper's table.
    fn default() -> Self {
        Self::paper_table()
    }
}

impl Params {
    /// The paper's coefficient table (Tables 1 and 2 with the errata of docs/errata.md applied).
    /// Read once per process.
    pub fn paper_table() -> Params {
        static TABLE: LazyLock<Params> = LazyLock::new(|| {
            Params::from_json(PAPER_TABLE_JSON).expect("the bundled coefficient table is valid")
        });
        TABLE.clone()
    }

    /// Parses and validates a JSON parameter set: an object with named fields (a UTF-8 byte
    /// order mark before it is skipped).
    pub fn from_json(text: &str) -> Result<Params, ParamError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let format = |e: serde_json::Error| ParamError::Format(e.to_string());
        // serde reads a struct from an array of its fields in order too; the format names
        // every value, so no array may appear anywhere.
        let tree: serde_json::Value = serde_json::from_str(text).map_err(format)?;
        if !tree.is_object() {
            return Err(ParamError::Format(format!(
                "the parameter set must be a JSON object with named fields, not {}",
                json_kind(&tree)
            )));
        }
        if let Some(path) = first_array(&tree, String::new()) {
            return Err(ParamError::Format(format!(
                "`{path}` is a JSON array; the format names every value: write an object \
                 with named fields"
            )));
        }
        // Parsed again from the text, so that errors carry line and column.
        let params: Params = serde_json::from_str(text).map_err(format)?;
        params.validate()?;
        Ok(params)
    }

    /// The parameter set as pretty JSON, in the format [`Params::from_json`] reads.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("parameters serialize")
    }
}

/// The dotted path of the first array in `value`, if any.
fn first_array(value: &serde_json::Value, path: String) -> Option<String> {
    match value {
        serde_json::Value::Array(_) => Some(path),
        serde_json::Value::Object(fields) => fields.iter().find_map(|(name, v)| {
            let inner = if path.is_empty() {
                name.clone()
            } else {
                format!("{path}.{name}")
            };
            first_array(v, inner)
        }),
        _ => None,
    }
}

fn json_kind(value: &serde_json::Value) -> &'static str {
    match value {
        serde_json::Value::Null => "null",
        serde_json::Value::Bool(_) => "a boolean",
        serde_json::Value::Number(_) => "a number",
        serde_json::Value::String(_) => "a string",
        serde_json::Value::Array(_) => "an array",
        serde_json::Value::Object(_) => "an object",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::channel::Channel;
    use crate::params::Limits;

    #[test]
    fn paper_table_has_errata_values() {
        let p = Params::paper_table();
        // Erratum 1: Fy a8 is 0.707, not the Mz row's -4.04.
        assert_eq!(p.Fy.a8, 0.707);
        assert_eq!(p.Mz.a8, -4.04);
        assert_eq!((p.Fy.C, p.Mz.C, p.Fx.C), (1.30, 2.40, 1.65));
    }

    #[test]
    fn json_round_trip_is_lossless() {
        let p = Params::paper_table();
        assert_eq!(Params::from_json(&p.to_json()).unwrap(), p);
    }

    #[test]
    fn incomplete_or_unknown_fields_are_rejected() {
        let mut v: serde_json::Value = serde_json::from_str(PAPER_TABLE_JSON).unwrap();
        v["Fy"].as_object_mut().unwrap().remove("a7");
        let err = Params::from_json(&v.to_string()).unwrap_err();
        assert!(err.to_string().contains("a7"), "{err}");

        let mut v: serde_json::Value = serde_json::from_str(PAPER_TABLE_JSON).unwrap();
        v["Fx"]["a9"] = serde_json::json!(0.0);
        let err = Params::from_json(&v.to_string()).unwrap_err();
        assert!(err.to_string().contains("a9"), "{err}");
    }

    #[test]
    fn a_byte_order_mark_is_skipped() {
        let text = format!("\u{feff}{PAPER_TABLE_JSON}");
        assert_eq!(Params::from_json(&text).unwrap(), Params::paper_table());
        // Only at the start.
        let err = Params::from_json(&format!("{PAPER_TABLE_JSON}\u{feff}")).unwrap_err();
        assert!(matches!(err, ParamError::Format(_)), "{err}");
    }

    #[test]
    fn arrays_in_place_of_objects_are_rejected() {
        let table: serde_json::Value = serde_json::from_str(PAPER_TABLE_JSON).unwrap();
        let values = |channel: &str| -> serde_json::Value {
            let ch = Channel::from_name(channel).unwrap();
            Params::coefficient_names(ch)
                .iter()
                .map(|n| table[channel][*n].clone())
                .collect()
        };
        // serde_json itself reads a struct from its fields in order.
        let limits: Limits = serde_json::from_str("[10000.0, 10.0]").unwrap();
        assert_eq!(limits.fz_max_N, 10000.0);

        let mut v = table.clone();
        v["Mz"] = values("Mz");
        let err = Params::from_json(&v.to_string()).unwrap_err().to_string();
        assert!(
            err.contains("`Mz` is a JSON array") && err.contains("object with named fields"),
            "{err}"
        );
        let mut v = table.clone();
        v["limits"] = serde_json::json!([10000.0, 10.0]);
        let err = Params::from_json(&v.to_string()).unwrap_err().to_string();
        assert!(err.contains("`limits` is a JSON array"), "{err}");
        let whole = serde_json::json!([values("Fy"), values("Mz"), values("Fx"), [10000.0, 10.0]]);
        let err = Params::from_json(&whole.to_string())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("must be a JSON object with named fields, not an array"),
            "{err}"
        );
        let mut v = table.clone();
        v["extensions"] = serde_json::json!({
            "nominal": { "pressure_kPa": 220.0, "speed_mps": 15.0, "temperature_degC": 40.0 },
            "Fx": { "rolling_resistance": [0.01, 0.002] }
        });
        let err = Params::from_json(&v.to_string()).unwrap_err().to_string();
        assert!(
            err.contains("`extensions.Fx.rolling_resistance` is a JSON array"),
            "{err}"
        );
        let err = Params::from_json("42").unwrap_err().to_string();
        assert!(err.contains("not a number"), "{err}");
    }
}
