//! The layout of MAT-file level 5 elements: a data element (normal or small format) and an
//! array (`miMATRIX`: class, dimensions, name, then its data), read from the bytes; and the
//! check of one array element before it is decoded: every subelement lies within its
//! parent, every count of values or of nested arrays fits in the bytes that hold them, and
//! arrays nest at most [`MAX_NESTING`] deep. The decoder takes counts from the file and
//! allocates for them; a corrupt count (a flipped bit in a dimension) would otherwise ask
//! for gigabytes from a file of kilobytes.

/// Data type of an array element.
pub(super) const MI_MATRIX: u32 = 14;

/// Array classes (the low byte of the array flags).
const CLASS_CELL: u8 = 1;
const CLASS_STRUCT: u8 = 2;
const CLASS_OBJECT: u8 = 3;
const CLASS_SPARSE: u8 = 5;

/// Arrays within arrays (cells of structs of cells ...) at most this deep: TTC files nest two.
pub(super) const MAX_NESTING: usize = 16;

/// One data element of `d` at `at`: its type, its data and where the next one starts.
pub(super) fn element(d: &[u8], at: usize) -> Result<(u32, &[u8], usize), String> {
    let tag = d
        .get(at..at.saturating_add(8))
        .ok_or_else(|| format!("the element tag at byte {at} is cut off"))?;
    let first = u32::from_le_bytes([tag[0], tag[1], tag[2], tag[3]]);
    if first >> 16 != 0 {
        // Small format: up to 4 bytes of data inside the tag.
        let len = (first >> 16) as usize;
        if len > 4 {
            return Err(format!("a small element of {len} bytes at byte {at}"));
        }
        return Ok((first & 0xffff, &tag[4..4 + len], at + 8));
    }
    let len = u32::from_le_bytes([tag[4], tag[5], tag[6], tag[7]]) as usize;
    let data = d
        .get(at + 8..at.saturating_add(8).saturating_add(len))
        .ok_or_else(|| format!("the element at byte {at} claims {len} bytes past the end"))?;
    Ok((first, data, at + 8 + len.div_ceil(8) * 8))
}

/// An array: its class, its dimensions, its data (after the tag), and where the elements
/// after its name start in the data.
pub(super) struct Matrix<'a> {
    pub(super) class: u8,
    pub(super) dims: Vec<usize>,
    pub(super) data: &'a [u8],
    pub(super) rest: usize,
}

/// The array element `m`.
pub(super) fn matrix(m: &[u8]) -> Result<Matrix<'_>, String> {
    let (kind, data, _) = element(m, 0)?;
    if kind != MI_MATRIX {
        return Err(format!("data type {kind}, not an array"));
    }
    let (_, flags, at) = element(data, 0)?;
    let class = *flags.first().ok_or("no array flags")?;
    let (_, dims, at) = element(data, at)?;
    let dims = dims
        .chunks_exact(4)
        .map(|c| i32::from_le_bytes([c[0], c[1], c[2], c[3]]).max(0) as usize)
        .collect();
    let (_, _name, rest) = element(data, at)?;
    Ok(Matrix {
        class,
        dims,
        data,
        rest,
    })
}

/// The number of values of an array of dimensions `dims` (saturating).
pub(super) fn count(dims: &[usize]) -> usize {
    dims.iter().fold(1usize, |a, &d| a.saturating_mul(d))
}

/// Checks the array element `element` (its tag included).
pub(super) fn check(element: &[u8]) -> Result<(), String> {
    check_at(element, 0)
}

fn check_at(m: &[u8], depth: usize) -> Result<(), String> {
    if depth > MAX_NESTING {
        return Err(format!("arrays nest more than {MAX_NESTING} deep"));
    }
    let (kind, body, _) = element(m, 0)?;
    if kind != MI_MATRIX {
        return Err(format!("data type {kind} where an array belongs"));
    }
    if body.is_empty() {
        // An empty array (MATLAB writes empty cells this way).
        return Ok(());
    }
    let mx = matrix(m)?;
    let values = count(&mx.dims);
    let (nested, mut at) = match mx.class {
        CLASS_CELL => (values, mx.rest),
        CLASS_STRUCT | CLASS_OBJECT => {
            let mut at = mx.rest;
            if mx.class == CLASS_OBJECT {
                at = element(mx.data, at)?.2; // the class name
            }
            let (_, width, at) = element(mx.data, at)?;
            let width = width
                .get(..4)
                .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
                .ok_or("a field-name length of fewer than 4 bytes")?;
            let (_, names, at) = element(mx.data, at)?;
            let fields = names.len().checked_div(width).unwrap_or(0);
            (values.saturating_mul(fields), at)
        }
        CLASS_SPARSE => return Ok(()),
        _ => {
            // Numbers or text: at least one byte per value in the real part.
            let (_, real, _) = element(mx.data, mx.rest)?;
            if values > real.len() {
                return Err(format!(
                    "dimensions of {values} values with {} bytes of data",
                    real.len()
                ));
            }
            return Ok(());
        }
    };
    // Each nested array takes at least its 8-byte tag.
    let left = mx.data.len().saturating_sub(at);
    if nested > left / 8 {
        return Err(format!(
            "{nested} nested arrays in {left} bytes (each takes at least 8)"
        ));
    }
    for _ in 0..nested {
        let (_, _, next) = element(mx.data, at)?;
        check_at(&mx.data[at..next.min(mx.data.len())], depth + 1)?;
        at = next;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const MI_INT8: u32 = 1;
    const MI_INT32: u32 = 5;
    const MI_UINT32: u32 = 6;

    /// A tag and its data, padded to 8 bytes.
    fn sub(kind: u32, data: &[u8]) -> Vec<u8> {
        let mut v = kind.to_le_bytes().to_vec();
        v.extend((data.len() as u32).to_le_bytes());
        v.extend(data);
        v.resize(v.len().div_ceil(8) * 8, 0);
        v
    }

    fn array(class: u8, dims: &[i32], rest: &[u8]) -> Vec<u8> {
        let mut body = sub(MI_UINT32, &[class, 0, 0, 0, 0, 0, 0, 0]);
        let d: Vec<u8> = dims.iter().flat_map(|x| x.to_le_bytes()).collect();
        body.extend(sub(MI_INT32, &d));
        body.extend(sub(MI_INT8, b"x"));
        body.extend(rest);
        sub(MI_MATRIX, &body)
    }

    #[test]
    fn counts_beyond_the_bytes_are_refused_and_true_ones_pass() {
        // A 1 x 3 double array (class 6, miDOUBLE 9).
        let values: Vec<u8> = [1.0f64, 2.0, 3.0]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let good = array(6, &[1, 3], &sub(9, &values));
        assert_eq!(check(&good), Ok(()));
        // The same data claiming 1 x 300000000 values.
        let bad = array(6, &[1, 300_000_000], &sub(9, &values));
        assert!(check(&bad).unwrap_err().contains("300000000 values"));
        // A cell of 2 holding the array twice, and one claiming 139 million cells.
        let cells = [good.clone(), good.clone()].concat();
        assert_eq!(check(&array(1, &[1, 2], &cells)), Ok(()));
        let e = check(&array(1, &[139_000, 1000], &cells)).unwrap_err();
        assert!(e.contains("139000000 nested arrays"), "{e}");
        // A subelement longer than its array.
        let mut cut = good.clone();
        cut.truncate(good.len() - 16);
        assert!(check(&cut).is_err());
    }

    #[test]
    fn nesting_is_bounded() {
        let mut a = array(6, &[0, 0], &sub(9, &[]));
        for _ in 0..MAX_NESTING {
            a = array(1, &[1, 1], &a);
        }
        assert_eq!(check(&a), Ok(()));
        let deeper = array(1, &[1, 1], &a);
        assert!(check(&deeper).unwrap_err().contains("nest more than"));
    }
}
