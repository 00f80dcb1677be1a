//! Writing a data set in tire-gap's CSV input format: the columns `run, t_s, vx_mps, fz_N,
//! alpha_deg, kappa, gamma_deg, p_kPa, temp_C, fx_N, fy_N, mz_Nm` (those present), values in
//! shortest round-trip form, so that reading the file back gives the same data set.

use std::borrow::Cow;
use std::io::{self, Write};

use crate::data::{Dataset, Quantity};
use crate::io::input::csv::canonical;

/// The columns of `ds` as [`write_csv`] writes them, after `run`: in [`Quantity::ALL`]'s
/// order, named as [`canonical`] names them (`t_s,vx_mps,fz_N,alpha_deg,kappa,gamma_deg,
/// p_kPa,temp_C,fx_N,fy_N,mz_Nm`), angles in degrees and everything else in internal units.
/// Columns the dataset lacks are left out.
pub fn csv_columns(ds: &Dataset) -> Vec<(&'static str, Cow<'_, [f64]>)> {
    Quantity::ALL
        .into_iter()
        .filter_map(|q| {
            let values = ds.column(q)?;
            let values = match q {
                Quantity::Alpha | Quantity::Gamma => Cow::Owned(
                    values
                        .iter()
                        .map(|x| mf87::units::radians_to_degrees(*x))
                        .collect(),
                ),
                _ => Cow::Borrowed(values),
            };
            Some((canonical(q), values))
        })
        .collect()
}

/// Writes `ds` as CSV: `run`, then [`csv_columns`], every value in shortest round-trip form.
pub fn write_csv(ds: &Dataset, w: impl Write) -> io::Result<()> {
    write_csv_with(ds, None, w)
}

/// [`write_csv`] with, after `run`, an integer column `extra` (name, one value per row).
pub fn write_csv_with(
    ds: &Dataset,
    extra: Option<(&str, &[usize])>,
    w: impl Write,
) -> io::Result<()> {
    let present = csv_columns(ds);
    let mut w = io::BufWriter::new(w);
    write!(w, "{}", canonical(Quantity::Run))?;
    if let Some((name, _)) = extra {
        write!(w, ",{name}")?;
    }
    for (name, _) in &present {
        write!(w, ",{name}")?;
    }
    writeln!(w)?;
    for (i, run) in ds.run.iter().enumerate() {
        write!(w, "{run}")?;
        if let Some((_, values)) = extra {
            write!(w, ",{}", values[i])?;
        }
        for (_, c) in &present {
            write!(w, ",{}", c[i])?;
        }
        writeln!(w)?;
    }
    w.flush()
}
