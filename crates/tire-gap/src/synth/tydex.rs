//! The synthetic data as a TYDEX measurement programme: one `.tdx` file per run.
//!
//! Each file has `**HEADER` (with `MEASID` = the run id), `**COMMENTS`, an empty
//! `**CONSTANTS`, `**MEASURCHANNELS` in the format's fixed columns (name 1-10, description
//! 11-40, unit 41-50, then factor 1 and offset 0), `**MEASURDATA` and `**END`. Channels:
//! `RUNTIME LONGVEL FZW SLIPANGL LONGSLIP INCLANGL INFLPRES TREADTMP FXW FYW MZW`, in one of
//! two unit styles ([`TydexUnits`]); columns the dataset lacks are left out.
//!
//! **Axes.** TYDEX W axes are ISO (x forward, y left, z up), so `FYW = -Fy` and `MZW = -Mz`
//! of the paper's axes; slip angle, camber, slip and Fx keep their sign. Real files carry the
//! load with either sign, so the SI style writes it negative (`FZW = -Fz`) and the
//! engineering style positive in compression; the reader takes either.
//!
//! Values are converted with [`crate::io::units`] (the inverse of what the reader applies) and
//! written in shortest round-trip form, so reading a file back gives the data to rounding.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use crate::data::{Dataset, Quantity};
use crate::io::input::tydex::channel_name;
use crate::io::output::{Failure, bad_input, output_failure};
use crate::io::units;

/// The unit style of the files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum TydexUnits {
    /// N, N.m, rad, m/s, Pa, K, slip ratio (unit `1`); FZW negative (minus the load).
    Si,
    /// N, Nm, deg, km/h, bar, deg C, slip in %; FZW positive in compression.
    #[default]
    Engineering,
}

impl TydexUnits {
    pub fn id(self) -> &'static str {
        match self {
            TydexUnits::Si => "si",
            TydexUnits::Engineering => "engineering",
        }
    }

    /// The unit written for `q` (always one the reader accepts).
    pub fn unit(self, q: Quantity) -> &'static str {
        use Quantity as Q;
        match (self, q) {
            (_, Q::Run) => "",
            (_, Q::Time) => "s",
            (_, Q::Fz | Q::Fx | Q::Fy) => "N",
            (TydexUnits::Si, Q::Speed) => "m/s",
            (TydexUnits::Si, Q::Alpha | Q::Gamma) => "rad",
            (TydexUnits::Si, Q::Kappa) => "1",
            (TydexUnits::Si, Q::Pressure) => "Pa",
            (TydexUnits::Si, Q::Temperature) => "K",
            (TydexUnits::Si, Q::Mz) => "N.m",
            (TydexUnits::Engineering, Q::Speed) => "km/h",
            (TydexUnits::Engineering, Q::Alpha | Q::Gamma) => "deg",
            (TydexUnits::Engineering, Q::Kappa) => "%",
            (TydexUnits::Engineering, Q::Pressure) => "bar",
            (TydexUnits::Engineering, Q::Temperature) => "deg C",
            (TydexUnits::Engineering, Q::Mz) => "Nm",
        }
    }

    /// The sign a value of `q` takes in the file (paper axes -> ISO W axes).
    fn sign(self, q: Quantity) -> f64 {
        match (self, q) {
            (_, Quantity::Fy | Quantity::Mz) => -1.0,
            (TydexUnits::Si, Quantity::Fz) => -1.0,
            _ => 1.0,
        }
    }
}

/// The channels in file order, with their descriptions (at most 30 characters).
const CHANNELS: [(Quantity, &str); 11] = [
    (Quantity::Time, "Running time"),
    (Quantity::Speed, "Longitudinal velocity"),
    (Quantity::Fz, "Vertical force"),
    (Quantity::Alpha, "Slip angle"),
    (Quantity::Kappa, "Longitudinal slip"),
    (Quantity::Gamma, "Inclination angle"),
    (Quantity::Pressure, "Inflation pressure"),
    (Quantity::Temperature, "Tread temperature"),
    (Quantity::Fx, "Longitudinal force"),
    (Quantity::Fy, "Lateral force"),
    (Quantity::Mz, "Self aligning moment"),
];

/// A fixed-column line: name 1-10, description 11-40, unit 41-50, then the value(s).
fn fixed_line(name: &str, description: &str, unit: &str, values: &str) -> String {
    format!("{name:<10}{description:<30}{unit:<10}{values}")
}

/// The runs of `ds` in order of first appearance, each with its rows in data order.
pub fn run_rows(ds: &Dataset) -> Vec<(i64, Vec<usize>)> {
    let mut out: Vec<(i64, Vec<usize>)> = Vec::new();
    let mut index = std::collections::HashMap::new();
    for (i, &run) in ds.run.iter().enumerate() {
        let k = *index.entry(run).or_insert_with(|| {
            out.push((run, Vec::new()));
            out.len() - 1
        });
        out[k].1.push(i);
    }
    out
}

/// The file name of `run`, zero-padded to `width` digits (`run_0007.tdx`).
pub fn run_file_name(run: i64, width: usize) -> String {
    format!("run_{run:0width$}.tdx")
}

/// The file's header, comments and (empty) constants sections.
fn write_header(
    w: &mut impl Write,
    ds: &Dataset,
    run: i64,
    samples: usize,
    units: TydexUnits,
) -> io::Result<()> {
    writeln!(w, "**HEADER")?;
    writeln!(
        w,
        "{}",
        fixed_line("RELEASE", "Release of TYDEX-Format", "", "1.3")
    )?;
    writeln!(
        w,
        "{}",
        fixed_line("MEASID", "Measurement id", "", &run.to_string())
    )?;
    writeln!(
        w,
        "{}",
        fixed_line("SUPPLIER", "Data supplier", "", "tire-gap synth")
    )?;
    writeln!(w, "**COMMENTS")?;
    writeln!(w, "Synthetic test-rig data: {}", ds.source)?;
    writeln!(w, "Run {run}: {} samples.", samples)?;
    writeln!(
        w,
        "Units: {}. W axes are ISO (x forward, y left, z up): FYW and MZW are the",
        units.id()
    )?;
    writeln!(
        w,
        "negated Fy and Mz of the 1987 paper's axes; FZW is {}.",
        match units {
            TydexUnits::Si => "minus the load (negative)",
            TydexUnits::Engineering => "the load, positive in compression",
        }
    )?;
    writeln!(w, "**CONSTANTS")?;
    writeln!(w, "! none: every quantity is a channel")?;
    Ok(())
}

/// Writes the rows `rows` of `ds` as one TYDEX file with `MEASID` = `run`.
pub fn write_tydex_run(
    ds: &Dataset,
    run: i64,
    rows: &[usize],
    units: TydexUnits,
    w: impl Write,
) -> io::Result<()> {
    let mut w = io::BufWriter::new(w);
    // Present columns with the map from internal units to the file's.
    let mut columns = Vec::new();
    for (q, description) in CHANNELS {
        let Some(values) = ds.column(q) else {
            continue;
        };
        let unit = units.unit(q);
        let conv = units::conversion(q, unit).ok_or_else(|| {
            io::Error::other(format!("unit {unit} is not accepted for {}", q.name()))
        })?;
        columns.push((q, description, unit, conv, units.sign(q), values));
    }

    write_header(&mut w, ds, run, rows.len(), units)?;
    writeln!(w, "**MEASURCHANNELS")?;
    writeln!(
        w,
        "{}",
        fixed_line("!Key", "Description", "Unit", "Factor    Offset")
    )?;
    for (q, description, unit, _, _, _) in &columns {
        writeln!(
            w,
            "{}",
            fixed_line(channel_name(*q), description, unit, "1         0")
        )?;
    }
    writeln!(w, "**MEASURDATA")?;
    for &i in rows {
        for (k, (_, _, _, conv, sign, values)) in columns.iter().enumerate() {
            // The reader computes file * scale + offset, then changes the sign.
            let v = (sign * values[i] - conv.offset) / conv.scale;
            if k > 0 {
                write!(w, " ")?;
            }
            write!(w, "{v:e}")?;
        }
        writeln!(w)?;
    }
    writeln!(w, "**END")?;
    w.flush()
}

/// Writes `ds` as a TYDEX programme into `dir`, one file per run named after the run id
/// (`run_0001.tdx`, ...), and returns the paths in run order. See [`write_files_whole`] for
/// what happens to `dir`.
pub fn write_tydex_programme(
    ds: &Dataset,
    units: TydexUnits,
    dir: &Path,
) -> Result<Vec<PathBuf>, Failure> {
    let runs = run_rows(ds);
    let digits = |r: i64| r.unsigned_abs().to_string().len();
    let width = runs
        .iter()
        .map(|(r, _)| digits(*r))
        .max()
        .unwrap_or(0)
        .max(4);
    let files = runs.iter().map(|(run, rows)| {
        let mut text = Vec::new();
        write_tydex_run(ds, *run, rows, units, &mut text)?;
        Ok((run_file_name(*run, width), text))
    });
    write_files_whole(dir, files)
}

/// Checks that `dir` can take a new programme: missing, or a directory holding no `.tdx`
/// file. Otherwise bad input.
pub fn check_programme_dir(dir: &Path) -> Result<(), Failure> {
    match fs::metadata(dir) {
        Ok(m) if m.is_dir() => {
            let entries = fs::read_dir(dir).map_err(|e| {
                output_failure(format!("cannot read the directory {}: {e}", dir.display()))
            })?;
            let mut tdx: Vec<String> = entries
                .filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|name| {
                    Path::new(name)
                        .extension()
                        .is_some_and(|x| x.eq_ignore_ascii_case("tdx"))
                })
                .collect();
            if tdx.is_empty() {
                return Ok(());
            }
            tdx.sort();
            let shown = if tdx.len() > 3 {
                format!("{}, ... ({} files)", tdx[..3].join(", "), tdx.len())
            } else {
                tdx.join(", ")
            };
            Err(bad_input(format!(
                "{} already holds TYDEX files ({shown}): a programme is written only into a new \
                 directory or one without .tdx files, so runs of two programmes never mix",
                dir.display()
            )))
        }
        Ok(_) => Err(bad_input(format!(
            "{} is not a directory: a TYDEX programme is a directory of .tdx files",
            dir.display()
        ))),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(output_failure(format!(
            "cannot write to {}: {e}",
            dir.display()
        ))),
    }
}

/// Writes `files` (name, contents) into `dir` so that either all of them appear or none.
///
/// `dir` must pass [`check_programme_dir`]. A missing `dir` is made as a hidden sibling
/// directory, filled, then renamed to `dir` (its parents are created). An existing `dir`
/// is filled through a hidden subdirectory whose files are moved in at the end; if a move
/// fails, the files already moved are removed again. On any failure nothing of the new
/// files is left behind. An `Err` item stops the writing as a failure.
pub fn write_files_whole(
    dir: &Path,
    files: impl IntoIterator<Item = io::Result<(String, Vec<u8>)>>,
) -> Result<Vec<PathBuf>, Failure> {
    check_programme_dir(dir)?;
    let cannot = |e: io::Error| output_failure(format!("cannot write to {}: {e}", dir.display()));
    let tag = format!("tire-gap-partial-{}", std::process::id());
    let exists = dir.exists();
    let new_name = dir.file_name().filter(|_| !exists);
    let (staging, created) = match new_name {
        Some(name) => {
            let parent = dir
                .parent()
                .filter(|p| !p.as_os_str().is_empty())
                .unwrap_or(Path::new("."));
            fs::create_dir_all(parent).map_err(cannot)?;
            (
                parent.join(format!(".{}.{tag}", name.to_string_lossy())),
                false,
            )
        }
        None => {
            // Existing, or a path without a last name (`a/..`): fill in place.
            fs::create_dir_all(dir).map_err(cannot)?;
            (dir.join(format!(".{tag}")), !exists)
        }
    };
    fs::create_dir(&staging).map_err(cannot)?;
    let mut names = Vec::new();
    let filled = files.into_iter().try_for_each(|item| {
        let (name, bytes) = item?;
        fs::write(staging.join(&name), bytes)?;
        names.push(name);
        Ok(())
    });
    let give_up = |e: io::Error| {
        let _ = fs::remove_dir_all(&staging);
        if created {
            let _ = fs::remove_dir(dir);
        }
        cannot(e)
    };
    filled.map_err(give_up)?;
    let paths: Vec<PathBuf> = names.iter().map(|n| dir.join(n)).collect();
    if new_name.is_some() {
        fs::rename(&staging, dir).map_err(give_up)?;
        return Ok(paths);
    }
    for (k, name) in names.iter().enumerate() {
        if let Err(e) = fs::rename(staging.join(name), &paths[k]) {
            for p in &paths[..k] {
                let _ = fs::remove_file(p);
            }
            return Err(give_up(e));
        }
    }
    let _ = fs::remove_dir(&staging);
    Ok(paths)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::input::Format;

    fn tiny() -> Dataset {
        Dataset {
            source: "test".into(),
            run: vec![3, 3, 8].into(),
            time: Some(vec![0.0, 0.01, 0.0].into()),
            speed: Some(vec![10.0, 10.5, 27.0].into()),
            fz: vec![4000.0, 4100.5, 1500.25].into(),
            alpha: Some(vec![0.05, -0.1, 0.0].into()),
            kappa: Some(vec![0.0, 0.12, -0.2].into()),
            gamma: Some(vec![0.0, 0.02, -0.05].into()),
            pressure: Some(vec![210.0, 210.3, 185.0].into()),
            temperature: Some(vec![25.0, 25.4, 80.0].into()),
            fx: Some(vec![-50.0, 2500.0, -3100.0].into()),
            fy: Some(vec![-1500.0, 2400.0, 10.0].into()),
            mz: Some(vec![40.0, -30.5, 0.25].into()),
        }
    }

    fn text(ds: &Dataset, run: i64, rows: &[usize], units: TydexUnits) -> String {
        let mut out = Vec::new();
        write_tydex_run(ds, run, rows, units, &mut out).unwrap();
        String::from_utf8(out).unwrap()
    }

    /// The `**MEASURCHANNELS` lines, and the data rows as numbers.
    fn parts(text: &str) -> (Vec<&str>, Vec<Vec<f64>>) {
        let section = |name: &str| -> Vec<&str> {
            text.lines()
                .skip_while(|l| *l != name)
                .skip(1)
                .take_while(|l| !l.starts_with("**"))
                .filter(|l| !l.starts_with('!'))
                .collect()
        };
        let rows = section("**MEASURDATA")
            .iter()
            .map(|l| l.split(' ').map(|x| x.parse().unwrap()).collect())
            .collect();
        (section("**MEASURCHANNELS"), rows)
    }

    #[test]
    fn every_unit_written_is_accepted_by_the_reader() {
        for units in [TydexUnits::Si, TydexUnits::Engineering] {
            for (q, description) in CHANNELS {
                assert!(description.len() <= 30);
                assert!(
                    units::conversion(q, units.unit(q)).is_some(),
                    "{} {:?}",
                    units.id(),
                    q
                );
            }
        }
    }

    #[test]
    fn channels_in_fixed_columns_and_values_in_file_units_and_iso_signs() {
        let ds = tiny();
        let t = text(&ds, 3, &[0, 1], TydexUnits::Engineering);
        let (channels, rows) = parts(&t);
        let names: Vec<&str> = channels.iter().map(|l| l[..10].trim()).collect();
        assert_eq!(
            names,
            [
                "RUNTIME", "LONGVEL", "FZW", "SLIPANGL", "LONGSLIP", "INCLANGL", "INFLPRES",
                "TREADTMP", "FXW", "FYW", "MZW"
            ]
        );
        let units: Vec<&str> = channels.iter().map(|l| l[40..50].trim()).collect();
        assert_eq!(
            units,
            [
                "s", "km/h", "N", "deg", "%", "deg", "bar", "deg C", "N", "N", "Nm"
            ]
        );
        assert!(
            channels
                .iter()
                .all(|l| l[50..].split_whitespace().eq(["1", "0"]))
        );
        assert!(channels[6][10..40].starts_with("Inflation pressure"));
        assert_eq!(rows.len(), 2);
        let r = &rows[1];
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * b.abs();
        assert_eq!(r[0], 0.01);
        assert!(close(r[1], 10.5 * 3.6), "{}", r[1]);
        assert_eq!(r[2], 4100.5);
        assert!(close(r[3], (-0.1f64).to_degrees()));
        assert!(close(r[4], 12.0));
        assert!(close(r[6], 2.103));
        assert_eq!(r[7], 25.4);
        assert_eq!(r[8], 2500.0);
        // ISO: y left, so FYW and MZW change sign.
        assert_eq!(r[9], -2400.0);
        assert_eq!(r[10], 30.5);
        assert!(t.contains(&fixed_line("MEASID", "Measurement id", "", "3")));

        let t = text(&ds, 3, &[0, 1], TydexUnits::Si);
        let (channels, rows) = parts(&t);
        let units: Vec<&str> = channels.iter().map(|l| l[40..50].trim()).collect();
        assert_eq!(
            units,
            [
                "s", "m/s", "N", "rad", "1", "rad", "Pa", "K", "N", "N", "N.m"
            ]
        );
        let r = &rows[0];
        assert_eq!(r[1], 10.0);
        // The SI style writes minus the load.
        assert_eq!(r[2], -4000.0);
        assert_eq!(r[3], 0.05);
        assert!(close(r[6], 210_000.0));
        assert!(close(r[7], 298.15));
        assert_eq!(r[9], 1500.0);
        assert_eq!(r[10], -40.0);
    }

    #[test]
    fn a_file_reads_back_as_its_run() {
        let ds = tiny();
        for units in [TydexUnits::Si, TydexUnits::Engineering] {
            let l =
                crate::front::read_str(&text(&ds, 8, &[2], units), "r.tdx", Format::Tydex).unwrap();
            let d = &l.dataset;
            assert_eq!(d.run, vec![8].into());
            for q in Quantity::ALL.into_iter().filter(|q| *q != Quantity::Run) {
                let (a, b) = (d.column(q).unwrap()[0], ds.column(q).unwrap()[2]);
                assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{q:?} {a} {b}");
            }
            assert!(
                l.notes.iter().all(|n| !n.contains("ignored")),
                "{:?}",
                l.notes
            );
        }
    }

    #[test]
    fn missing_columns_are_left_out() {
        let mut ds = tiny();
        ds.temperature = None;
        ds.mz = None;
        let t = text(&ds, 3, &[0], TydexUnits::Si);
        let (channels, rows) = parts(&t);
        assert_eq!(channels.len(), 9);
        assert!(channels.iter().all(|l| !l.starts_with("TREADTMP")));
        assert_eq!(rows[0].len(), 9);
    }

    #[test]
    fn runs_group_rows_and_name_files() {
        let mut ds = tiny();
        ds.run = vec![5, 2, 5].into();
        assert_eq!(run_rows(&ds), vec![(5, vec![0, 2]), (2, vec![1])]);
        assert_eq!(run_file_name(7, 4), "run_0007.tdx");
        assert_eq!(run_file_name(123_456, 4), "run_123456.tdx");
    }

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!(
            "tire-gap-synth-tydex-{}-{name}",
            std::process::id()
        ));
        let _ = fs::remove_dir_all(&d);
        d
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    /// Three files; the third is an error when `fail`.
    fn three(fail: bool) -> Vec<io::Result<(String, Vec<u8>)>> {
        vec![
            Ok(("a.tdx".into(), b"a".to_vec())),
            Ok(("b.tdx".into(), b"b".to_vec())),
            if fail {
                Err(io::Error::other("disk full"))
            } else {
                Ok(("c.tdx".into(), b"c".to_vec()))
            },
        ]
    }

    #[test]
    fn a_programme_is_written_whole_or_not_at_all() {
        let root = scratch("whole");
        // A new directory (and its parent).
        let dir = root.join("new/prog");
        let paths = write_files_whole(&dir, three(false)).unwrap();
        assert_eq!(paths, ["a.tdx", "b.tdx", "c.tdx"].map(|n| dir.join(n)));
        assert_eq!(listing(&dir), ["a.tdx", "b.tdx", "c.tdx"]);
        assert_eq!(fs::read(dir.join("b.tdx")).unwrap(), b"b");
        assert_eq!(listing(&root.join("new")), ["prog"]);

        // A failure leaves neither the directory nor the staging one.
        let dir = root.join("new/failed");
        let e = write_files_whole(&dir, three(true)).unwrap_err();
        assert_eq!(e.kind, crate::io::output::FailureKind::Output);
        assert!(e.message.contains("disk full"), "{}", e.message);
        assert_eq!(listing(&root.join("new")), ["prog"]);

        // An existing directory without .tdx files keeps its files and gets the new ones,
        // or, on failure, nothing.
        let dir = root.join("existing");
        fs::create_dir_all(&dir).unwrap();
        fs::write(dir.join("truth.json"), "{}").unwrap();
        write_files_whole(&dir, three(true)).unwrap_err();
        assert_eq!(listing(&dir), ["truth.json"]);
        write_files_whole(&dir, three(false)).unwrap();
        assert_eq!(listing(&dir), ["a.tdx", "b.tdx", "c.tdx", "truth.json"]);

        // A directory that already holds a programme is refused, and left alone.
        let e = write_files_whole(&dir, three(false)).unwrap_err();
        assert_eq!(e.kind, crate::io::output::FailureKind::BadInput);
        assert!(
            e.message
                .contains("already holds TYDEX files (a.tdx, b.tdx, c.tdx)")
        );
        fs::write(dir.join("D.TDX"), "").unwrap();
        let e = check_programme_dir(&dir).unwrap_err();
        assert!(
            e.message.contains("(D.TDX, a.tdx, b.tdx, ... (4 files))"),
            "{}",
            e.message
        );
        // A file is not a directory.
        let e = check_programme_dir(&dir.join("truth.json")).unwrap_err();
        assert_eq!(e.kind, crate::io::output::FailureKind::BadInput);
        assert!(e.message.contains("is not a directory"));
        fs::remove_dir_all(&root).unwrap();
    }
}
