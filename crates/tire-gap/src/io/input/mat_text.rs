//! The text lists of a TTC MAT-file's `channel` struct, read from the element's bytes when
//! the `matrw` crate cannot decode it (it fails on the layout of the Round 9 files: a 1x1
//! struct whose fields are cells of short char arrays stored as small `miUINT16` elements).
//! Only what the struct needs is read: a struct of char arrays or cells of char arrays.

use std::collections::BTreeMap;

use super::mat_layout::{Matrix, count, element, matrix};

const MI_INT8: u32 = 1;
const MI_UINT8: u32 = 2;
const MI_UINT16: u32 = 4;
const MI_INT32: u32 = 5;
const MI_UTF8: u32 = 16;
const MI_UTF16: u32 = 17;
const CLASS_CELL: u8 = 1;
const CLASS_STRUCT: u8 = 2;
const CLASS_CHAR: u8 = 4;
/// Deepest nesting followed (struct, cell, char).
const MAX_DEPTH: usize = 4;

/// Every row of a char array, trimmed.
fn char_rows(mx: &Matrix) -> Result<Vec<String>, String> {
    let (kind, bytes, _) = element(mx.data, mx.rest)?;
    let units: Vec<u16> = match kind {
        MI_UINT16 | MI_UTF16 => bytes
            .chunks_exact(2)
            .map(|c| u16::from_le_bytes([c[0], c[1]]))
            .collect(),
        MI_UTF8 | MI_UINT8 | MI_INT8 => {
            return Ok(vec![String::from_utf8_lossy(bytes).trim().to_string()]);
        }
        other => return Err(format!("char data of type {other}")),
    };
    let rows = mx.dims.first().copied().unwrap_or(0).max(1);
    let cols = units.len() / rows;
    // Column-major: row i holds units i, i + rows, ...
    Ok((0..rows)
        .map(|i| {
            let row: Vec<u16> = (0..cols).map(|j| units[i + j * rows]).collect();
            String::from_utf16_lossy(&row).trim().to_string()
        })
        .collect())
}

/// The texts of a char array element (its rows) or of a cell of char arrays (one each).
pub(super) fn texts(m: &[u8], depth: usize) -> Result<Vec<String>, String> {
    if depth > MAX_DEPTH {
        return Err("arrays nested too deep".into());
    }
    let mx = matrix(m)?;
    match mx.class {
        CLASS_CHAR => char_rows(&mx),
        CLASS_CELL => {
            let n = count(&mx.dims);
            let mut at = mx.rest;
            let mut out = Vec::new();
            for _ in 0..n {
                let start = at;
                let (_, _, next) = element(mx.data, at)?;
                out.push(texts(&mx.data[start..next.min(mx.data.len())], depth + 1)?.join(" "));
                at = next;
            }
            Ok(out)
        }
        other => Err(format!("an array of class {other}, not text")),
    }
}

/// The fields of a 1x1 struct element `m` that hold text, by name.
pub(super) fn struct_texts(m: &[u8]) -> Result<BTreeMap<String, Vec<String>>, String> {
    let mx = matrix(m)?;
    if mx.class != CLASS_STRUCT || count(&mx.dims) != 1 {
        return Err("not a 1x1 struct".into());
    }
    let (kind, len, at) = element(mx.data, mx.rest)?;
    let width = match (kind, len) {
        (MI_INT32, [a, b, c, d]) => i32::from_le_bytes([*a, *b, *c, *d]).max(1) as usize,
        _ => return Err("no field name length".into()),
    };
    let (_, names, mut at) = element(mx.data, at)?;
    let mut fields = BTreeMap::new();
    for name in names.chunks(width) {
        let name = String::from_utf8_lossy(name)
            .trim_end_matches('\0')
            .to_string();
        let start = at;
        let (_, _, next) = element(mx.data, at)?;
        let value = &mx.data[start..next.min(mx.data.len())];
        fields.insert(name, texts(value, 1)?);
        at = next;
    }
    Ok(fields)
}

#[cfg(test)]
mod tests {
    use super::super::mat_layout::MI_MATRIX;
    use super::*;

    /// A data element, in the small format when its data fits in 4 bytes.
    fn tag(kind: u32, data: &[u8]) -> Vec<u8> {
        if data.len() > 4 {
            return normal(kind, data);
        }
        let mut t = (((data.len() as u32) << 16) | kind).to_le_bytes().to_vec();
        t.extend_from_slice(data);
        t.resize(8, 0);
        t
    }

    /// An array element; its name in the normal format even when empty, as MATLAB writes it.
    fn array(class: u8, dims: &[i32], name: &str, body: &[u8]) -> Vec<u8> {
        let mut d = normal(6, &[class, 0, 0, 0, 0, 0, 0, 0]);
        let dims: Vec<u8> = dims.iter().flat_map(|x| x.to_le_bytes()).collect();
        d.extend(normal(MI_INT32, &dims));
        d.extend(normal(MI_INT8, name.as_bytes()));
        d.extend_from_slice(body);
        normal(MI_MATRIX, &d)
    }

    /// A data element in the normal (8-byte tag) format.
    fn normal(kind: u32, data: &[u8]) -> Vec<u8> {
        let mut t = kind.to_le_bytes().to_vec();
        t.extend_from_slice(&(data.len() as u32).to_le_bytes());
        t.extend_from_slice(data);
        t.resize(8 + data.len().div_ceil(8) * 8, 0);
        t
    }

    /// A 1 x n char array with its UTF-16 data as a small element when it fits.
    fn chars(s: &str) -> Vec<u8> {
        let data: Vec<u8> = s.encode_utf16().flat_map(|u| u.to_le_bytes()).collect();
        array(CLASS_CHAR, &[1, s.len() as i32], "", &tag(MI_UINT16, &data))
    }

    fn cell(items: &[&str]) -> Vec<u8> {
        let body: Vec<u8> = items.iter().flat_map(|s| chars(s)).collect();
        array(CLASS_CELL, &[1, items.len() as i32], "", &body)
    }

    #[test]
    fn a_round_9_channel_struct_is_read() {
        // As in the Round 9 files: fields name and units, cells of 1 x n char arrays whose
        // UTF-16 data of up to two characters sits in small elements, longer ones in normal.
        let mut body = tag(MI_INT32, &6i32.to_le_bytes());
        body.extend(normal(MI_INT8, b"name\0\0units\0"));
        body.extend(cell(&["ET", "V", "SA", "AMBTMP"]));
        body.extend(cell(&["s", "kph", "deg", "deg C"]));
        let m = array(CLASS_STRUCT, &[1, 1], "channel", &body);
        let f = struct_texts(&m).unwrap();
        assert_eq!(f["name"], ["ET", "V", "SA", "AMBTMP"]);
        assert_eq!(f["units"], ["s", "kph", "deg", "deg C"]);
        // A char matrix (one row per channel, padded with blanks) reads row by row.
        let rows = ["ET ", "SA ", "FZ "];
        let mut colmajor = Vec::new();
        for j in 0..3 {
            for r in rows {
                colmajor.extend((r.as_bytes()[j] as u16).to_le_bytes());
            }
        }
        let matrix = array(CLASS_CHAR, &[3, 3], "", &normal(MI_UINT16, &colmajor));
        assert_eq!(texts(&matrix, 0).unwrap(), ["ET", "SA", "FZ"]);
        // Cut or hostile bytes are errors, never panics.
        for cut in 0..m.len() {
            let _ = struct_texts(&m[..cut]);
        }
        let mut other = m.clone();
        other[16] = CLASS_CELL;
        assert!(struct_texts(&other).is_err());
    }

    /// A column of doubles named `name`.
    fn column(name: &str, values: &[f64]) -> Vec<u8> {
        let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        array(6, &[values.len() as i32, 1], name, &normal(9, &data))
    }

    #[test]
    fn a_run_file_laid_out_as_round_9_reads_with_its_units_and_tire() {
        // matrw fails on this channel struct and tireid, as on the real files.
        let n = 400;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.01).collect();
        let cols: Vec<(&str, &str, Vec<f64>)> = vec![
            ("ET", "s", t.clone()),
            ("V", "kph", vec![40.0; n]),
            (
                "SA",
                "deg",
                t.iter().map(|t| 12.0 * (t * 1.5).sin()).collect(),
            ),
            ("IA", "deg", vec![2.0; n]),
            ("P", "psi", vec![12.0; n]),
            (
                "FY",
                "lb",
                t.iter().map(|t| -300.0 * (t * 1.5).sin()).collect(),
            ),
            ("FZ", "lb", vec![-250.0; n]),
        ];
        let mut file = format!("{:<116}", "MATLAB 5.0 MAT-file, Round 9 layout").into_bytes();
        file.extend_from_slice(&[0; 8]);
        file.extend_from_slice(&[0x00, 0x01]);
        file.extend_from_slice(b"IM");
        for (name, _, v) in &cols {
            file.extend(column(name, v));
        }
        let names: Vec<&str> = cols.iter().map(|c| c.0).collect();
        let units: Vec<&str> = cols.iter().map(|c| c.1).collect();
        let mut body = tag(MI_INT32, &6i32.to_le_bytes());
        body.extend(normal(MI_INT8, b"name\0\0units\0"));
        body.extend(cell(&names));
        body.extend(cell(&units));
        file.extend(array(CLASS_STRUCT, &[1, 1], "channel", &body));
        let id = "Hoosier 43075 16x7.5-10 R25B, 7 inch rim";
        let id16: Vec<u8> = id.encode_utf16().flat_map(|u| u.to_le_bytes()).collect();
        file.extend(array(
            CLASS_CHAR,
            &[1, id.len() as i32],
            "tireid",
            &normal(MI_UINT16, &id16),
        ));
        let (loaded, tire) = super::super::mat::read_run(&file, "B2356run12.mat").unwrap();
        assert_eq!(
            tire.as_deref(),
            Some("Hoosier 43075 16x7.5-10 R25B, 7 inch rim")
        );
        let ds = &loaded.dataset;
        assert_eq!(ds.len(), n);
        // Units from the file: 12 psi, 250 lb, 40 kph.
        let p = ds.pressure.as_ref().unwrap()[0];
        assert!((p - 12.0 * 6.894_757).abs() < 1e-3, "{p}");
        assert!((ds.fz[0] - 250.0 * 4.448_222).abs() < 1e-2, "{}", ds.fz[0]);
        assert!((ds.speed.as_ref().unwrap()[0] - 40.0 / 3.6).abs() < 1e-9);
        assert!(
            !loaded
                .notes
                .iter()
                .any(|n| n.contains("could not be decoded")),
            "{:?}",
            loaded.notes
        );
    }
}
