//! What a diagnosis of a given size needs, said before the work starts.
//!
//! The figures are measured (`tire-gap diagnose` of `tire-gap synth --effects temperature`
//! programmes, as `benches/python/gap_vs_scipy.py --rows 1000000 10000000` makes them, on the
//! project's 2-core machine; 10M rows as five 2M-row files). Both grow as a fixed part plus a
//! part per row (fits read at most a sample of rows; predictions, tests and the data read all
//! of them).

const MIB: f64 = 1024.0 * 1024.0;
/// Measured at 1M rows: wall time [s] and peak resident memory [MiB].
const ONE_MILLION: (f64, f64) = (26.8, 319.1);
/// Measured at 10M rows: wall time [s] and peak resident memory [MiB].
const TEN_MILLION: (f64, f64) = (112.5, 1784.8);
/// Peak resident memory of a diagnosis: a fixed part [bytes] ...
const FIXED_BYTES: f64 = ONE_MILLION.1 * MIB - 1.0e6 * PEAK_BYTES_PER_ROW;
/// ... plus this per row \[bytes\] (the line through the two measurements).
pub const PEAK_BYTES_PER_ROW: f64 = (TEN_MILLION.1 - ONE_MILLION.1) * MIB / 9.0e6;
/// Wall time of a diagnosis: a fixed part [s] ...
const FIXED_SECONDS: f64 = ONE_MILLION.0 - 1.0e6 * SECONDS_PER_ROW;
/// ... plus this per row [s] (the line through the two measurements).
const SECONDS_PER_ROW: f64 = (TEN_MILLION.0 - ONE_MILLION.0) / 9.0e6;
/// Above this many rows the report's figures were not benchmarked: the estimate is shown.
pub const BENCHMARKED_ROWS: usize = 1_000_000;

/// What a diagnosis of `rows` rows is expected to need.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    pub peak_bytes: f64,
    pub seconds: f64,
}

pub fn estimate(rows: usize) -> Estimate {
    Estimate {
        peak_bytes: FIXED_BYTES + PEAK_BYTES_PER_ROW * rows as f64,
        seconds: FIXED_SECONDS + SECONDS_PER_ROW * rows as f64,
    }
}

/// Memory the system can still give \[bytes\] (`MemAvailable`), where the system says.
pub fn available_memory() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// Up front, for `rows` rows with `available` bytes of memory: `Err` with what the diagnosis
/// would need when that is more than there is; `Ok(Some(note))` with what it will need above
/// the benchmarked size; `Ok(None)` otherwise.
pub fn check(rows: usize, available: Option<f64>) -> Result<Option<String>, String> {
    let e = estimate(rows);
    let time = match e.seconds < 90.0 {
        true => format!("{:.0} s", e.seconds),
        false => format!("{:.0} min", e.seconds / 60.0),
    };
    let needs = format!(
        "{rows} rows: a diagnosis needs about {:.1} GiB of memory at peak and about {time} on \
         a 2-core machine (measured: {:.2} GiB and {:.0} s for 1M rows, {:.1} GiB and {:.0} s \
         for 10M)",
        e.peak_bytes / GIB,
        ONE_MILLION.1 * MIB / GIB,
        ONE_MILLION.0,
        TEN_MILLION.1 * MIB / GIB,
        TEN_MILLION.0,
    );
    match available {
        Some(free) if e.peak_bytes > free => Err(format!(
            "{needs}; this machine has {:.1} GiB available. Diagnose part of the programme (a \
             subset of its run files or runs), or run it where that much memory is free",
            free / GIB
        )),
        _ if rows > BENCHMARKED_ROWS => Ok(Some(needs)),
        _ => Ok(None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn estimates_follow_the_measurements() {
        let one = estimate(1_000_000);
        assert!((one.seconds - ONE_MILLION.0).abs() < 1e-9, "{one:?}");
        assert!(
            (one.peak_bytes - ONE_MILLION.1 * MIB).abs() < 1.0,
            "{one:?}"
        );
        let ten = estimate(10_000_000);
        assert!((ten.seconds - TEN_MILLION.0).abs() < 1e-9, "{ten:?}");
        assert!(
            (ten.peak_bytes - TEN_MILLION.1 * MIB).abs() < 1.0,
            "{ten:?}"
        );
        // Between and beyond, on the line: 3M rows 319.1 + 2 x 162.86 MiB.
        let three = estimate(3_000_000);
        assert!((three.peak_bytes / MIB - 644.8).abs() < 0.1, "{three:?}");
    }

    #[test]
    fn too_little_memory_is_refused_up_front_and_large_sizes_are_announced() {
        let err = check(30_000_000, Some(4.0 * GIB)).unwrap_err();
        assert!(
            err.starts_with("30000000 rows: a diagnosis needs about 4.9 GiB"),
            "{err}"
        );
        assert!(err.contains("this machine has 4.0 GiB available"), "{err}");
        assert!(check(10_000_000, Some(1.5 * GIB)).is_err());
        assert!(check(10_000_000, Some(2.5 * GIB)).is_ok());
        let note = check(3_000_000, Some(16.0 * GIB)).unwrap().unwrap();
        assert!(note.contains("about 0.6 GiB"), "{note}");
        // 3M rows: 26.8 + 2 x 9.52 s.
        assert!(note.contains("about 46 s on a 2-core machine"), "{note}");
        let large = check(30_000_000, Some(16.0 * GIB)).unwrap().unwrap();
        assert!(large.contains("about 5 min"), "{large}");
        assert!(
            note.contains("0.31 GiB and 27 s for 1M rows, 1.7 GiB and 112 s for 10M"),
            "{note}"
        );
        assert_eq!(check(35_000, Some(16.0 * GIB)), Ok(None));
        assert_eq!(check(35_000, None), Ok(None));
    }
}
