//! MAT-files that hold a programme as a struct of sweeps: one struct variable whose fields
//! are structs, each holding one sweep's TTC channels (`r.r_55kPa_0deg_1113N.FZ`, ...), as
//! teams' import scripts save a run cut into its sweeps. The sweeps are joined in time order
//! (by their first `ET`, else in field order) into the channels of one programme, which is
//! then read as a run file; the pauses between the sweeps split it into its blocks again.

use matrw::{MatVariable, MatlabType, NumericArray};

use super::ttc;

/// A sweep: the path of its struct and its channels (name, values).
struct Sweep {
    path: String,
    channels: Vec<(String, Vec<f64>)>,
}

impl Sweep {
    fn channel(&self, name: &str) -> Option<&Vec<f64>> {
        self.channels
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, v)| v)
    }
}

/// The numbers of a numeric vector.
fn vector(v: &MatVariable) -> Option<Vec<f64>> {
    let MatVariable::NumericArray(a) = v else {
        return None;
    };
    if a.value_cmp.is_some() || a.dim.iter().filter(|&&d| d > 1).count() > 1 {
        return None;
    }
    match &a.value {
        MatlabType::F64(v) => Some(v.clone()),
        MatlabType::F32(v) => Some(v.iter().map(|&x| x.into()).collect()),
        _ => None,
    }
}

/// The sweep a struct holds: its fields that are TTC channels, if the load and a slip are
/// among them.
fn sweep_of(path: String, fields: &[(&String, &MatVariable)]) -> Option<Sweep> {
    let channels: Vec<(String, Vec<f64>)> = fields
        .iter()
        .filter(|(n, _)| ttc::canonical_of(n).is_some())
        .filter_map(|(n, v)| Some((n.to_string(), vector(v)?)))
        .collect();
    let has = |c: &str| channels.iter().any(|(n, _)| ttc::names_channel(n, c));
    (has("FZ") && ["SA", "SR", "SL"].iter().any(|c| has(c))).then_some(Sweep { path, channels })
}

/// The sweeps of the top-level structs, and the text fields of those structs.
fn sweeps(vars: &[(String, MatVariable)]) -> (Vec<Sweep>, Vec<(String, MatVariable)>) {
    let mut found = Vec::new();
    let mut texts = Vec::new();
    for (name, v) in vars {
        let MatVariable::Structure(outer) = v else {
            continue;
        };
        for (field, inner) in &outer.value {
            match inner {
                MatVariable::Structure(s) => {
                    let fields: Vec<(&String, &MatVariable)> = s.value.iter().collect();
                    found.extend(sweep_of(format!("{name}.{field}"), &fields));
                }
                MatVariable::NumericArray(a)
                    if matches!(a.value, MatlabType::UTF8(_) | MatlabType::UTF16(_)) =>
                {
                    texts.push((field.clone(), inner.clone()));
                }
                _ => {}
            }
        }
    }
    (found, texts)
}

fn column(values: Vec<f64>) -> MatVariable {
    MatVariable::NumericArray(NumericArray {
        dim: vec![values.len(), 1],
        value: MatlabType::F64(values),
        value_cmp: None,
    })
}

/// When `vars` hold no TTC channel at the top level but structs of sweeps do: the sweeps'
/// channels joined in time order as top-level variables, with the structs' text fields
/// (`tireid`, `testid`) where the top level lacks them; noted. Otherwise `vars` unchanged.
pub(super) fn flatten(vars: &mut Vec<(String, MatVariable)>, notes: &mut Vec<String>) {
    let top_level = vars
        .iter()
        .any(|(n, v)| ttc::canonical_of(n).is_some() && vector(v).is_some());
    if top_level {
        return;
    }
    let (mut found, texts) = sweeps(vars);
    if found.is_empty() {
        return;
    }
    let start = |s: &Sweep| s.channel("ET").and_then(|t| t.first().copied());
    if found.iter().all(|s| start(s).is_some()) {
        found.sort_by(|a, b| start(a).unwrap_or(0.0).total_cmp(&start(b).unwrap_or(0.0)));
    }
    let names: Vec<String> = found[0]
        .channels
        .iter()
        .map(|(n, _)| n.clone())
        .filter(|n| found.iter().all(|s| s.channel(n).is_some()))
        .collect();
    let partial: Vec<String> = found
        .iter()
        .flat_map(|s| s.channels.iter().map(|(n, _)| n.clone()))
        .filter(|n| !names.iter().any(|m| m.eq_ignore_ascii_case(n)))
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    let mut joined: Vec<(String, MatVariable)> = names
        .iter()
        .map(|n| {
            let values = found
                .iter()
                .flat_map(|s| s.channel(n).cloned().unwrap_or_default());
            (n.clone(), column(values.collect()))
        })
        .collect();
    for (field, text) in texts {
        if !vars.iter().any(|(n, _)| n.eq_ignore_ascii_case(&field)) {
            joined.push((field, text));
        }
    }
    let paths: Vec<&str> = found.iter().map(|s| s.path.as_str()).collect();
    const SHOWN: usize = 4;
    let more = if paths.len() > SHOWN { ", ..." } else { "" };
    notes.push(format!(
        "the file holds {} sweeps as structs of channels ({}{more}): read as one programme, \
         joined in time order",
        paths.len(),
        paths[..paths.len().min(SHOWN)].join(", ")
    ));
    if !partial.is_empty() {
        notes.push(format!(
            "channels not in every sweep, not read: {}",
            partial.join(" ")
        ));
    }
    vars.retain(|(_, v)| !matches!(v, MatVariable::Structure(_)));
    vars.extend(joined);
}

#[cfg(test)]
mod tests {
    use super::*;
    use matrw::Structure;

    fn sweep(et0: f64, fz: f64) -> MatVariable {
        let mut map = indexmap::IndexMap::new();
        map.insert("ET".to_string(), column(vec![et0, et0 + 0.02]));
        map.insert("FZ".to_string(), column(vec![fz, fz]));
        map.insert("SA".to_string(), column(vec![1.0, 2.0]));
        map.insert("MX".to_string(), column(vec![0.0, 0.0]));
        MatVariable::Structure(Structure::new(map))
    }

    #[test]
    fn sweeps_in_a_struct_are_joined_in_time_order() {
        let mut outer = indexmap::IndexMap::new();
        outer.insert("late".to_string(), sweep(20.0, -900.0));
        outer.insert("early".to_string(), sweep(10.0, -450.0));
        let mut vars = vec![(
            "r".to_string(),
            MatVariable::Structure(Structure::new(outer)),
        )];
        let mut notes = Vec::new();
        flatten(&mut vars, &mut notes);
        let get = |n: &str| vector(&vars.iter().find(|(k, _)| k == n).unwrap().1).unwrap();
        assert_eq!(get("ET"), vec![10.0, 10.02, 20.0, 20.02]);
        assert_eq!(get("FZ"), vec![-450.0, -450.0, -900.0, -900.0]);
        assert!(
            notes[0]
                .starts_with("the file holds 2 sweeps as structs of channels (r.early, r.late)")
        );
        // A file with channels at the top level is left as it is.
        let mut flat = vec![("FZ".to_string(), column(vec![1.0]))];
        flatten(&mut flat, &mut notes);
        assert_eq!(flat.len(), 1);
    }
}
