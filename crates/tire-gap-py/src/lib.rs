//! `tire_gap._native`: the diagnosis and the generator of tire-gap for the Python package
//! `tire_gap` (python/tire_gap), which wraps these functions for users. Long work runs on a
//! thread of its own with the GIL released; Ctrl-C (or any pending Python signal) cancels it.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use tire_gap::front::{Finished, diagnose_loaded, load_many, read_frame};
use tire_gap::io::input::frame::FrameColumn;
use tire_gap::io::input::{InputError, expand};
use tire_gap::io::output::{Failure, FailureKind, bad_input};
use tire_gap::method::diagnose::Options;
use tire_gap::method::fit::effects::parse_names;
use tire_gap::method::observer::Observer;
use tire_gap::method::parallel::with_threads;

/// Why the work failed, before it reaches Python.
enum Error {
    /// Bad input, where it is.
    Input(InputError),
    /// Anything else the command line would exit for, with its kind.
    Failure(Failure),
    /// Ctrl-C.
    Interrupted(PyErr),
    /// A bug: the work panicked.
    Internal(String),
}

impl From<InputError> for Error {
    fn from(e: InputError) -> Self {
        Error::Input(e)
    }
}

impl From<Failure> for Error {
    fn from(f: Failure) -> Self {
        Error::Failure(f)
    }
}

/// `tire_gap.TireGapError(message, kind=..., file=..., line=..., column=..., rows=...)`.
fn to_py(py: Python<'_>, e: Error) -> PyErr {
    let kwargs = PyDict::new(py);
    let message = match e {
        Error::Interrupted(err) => return err,
        Error::Input(e) => {
            let set = || -> PyResult<()> {
                kwargs.set_item("kind", "input")?;
                kwargs.set_item("file", &e.file)?;
                kwargs.set_item("line", e.line)?;
                kwargs.set_item("column", e.column.as_deref())?;
                kwargs.set_item("rows", e.rows.clone())
            };
            if let Err(err) = set() {
                return err;
            }
            e.to_string()
        }
        Error::Failure(f) => {
            let kind = match f.kind {
                FailureKind::BadInput => "input",
                FailureKind::Output | FailureKind::Incomplete => "failure",
                FailureKind::Cancelled => return PyKeyboardInterrupt::new_err(f.message),
            };
            if let Err(err) = kwargs.set_item("kind", kind) {
                return err;
            }
            f.message
        }
        Error::Internal(m) => {
            if let Err(err) = kwargs.set_item("kind", "internal") {
                return err;
            }
            format!("internal error (a bug in tire-gap): {m}")
        }
    };
    let raised = py
        .import("tire_gap._errors")
        .and_then(|m| m.getattr("TireGapError"))
        .and_then(|cls| cls.call((message,), Some(&kwargs)));
    match raised {
        Ok(instance) => PyErr::from_value(instance),
        Err(err) => err,
    }
}

/// The Python package's observer: no progress shown (the report has the notes), stopped by
/// a flag set on Ctrl-C.
struct Cancellable {
    cancel: Arc<AtomicBool>,
}

impl Observer for Cancellable {
    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
}

/// Runs `work` on a thread of its own with the GIL released, on at most `threads` threads
/// (`None`: every core), checking for Python signals every 50 ms; a signal (Ctrl-C) cancels
/// the work (the jobs not yet started are skipped) and raises.
fn run_released<T: Send>(
    py: Python<'_>,
    threads: Option<usize>,
    work: impl FnOnce(&dyn Observer) -> Result<T, Error> + Send,
) -> PyResult<T> {
    let cancel = Arc::new(AtomicBool::new(false));
    let progress = Cancellable {
        cancel: cancel.clone(),
    };
    let limited = |progress: &dyn Observer| match threads {
        Some(n) => with_threads(n, || work(progress)),
        None => work(progress),
    };
    let outcome = std::thread::scope(|scope| {
        let handle = scope.spawn(|| catch_unwind(AssertUnwindSafe(|| limited(&progress))));
        let mut interrupted = None;
        while !handle.is_finished() {
            py.detach(|| std::thread::sleep(Duration::from_millis(50)));
            if interrupted.is_none()
                && let Err(e) = py.check_signals()
            {
                cancel.store(true, Ordering::Relaxed);
                interrupted = Some(e);
            }
        }
        let joined = py.detach(|| handle.join());
        match (interrupted, joined) {
            (Some(e), _) => Err(Error::Interrupted(e)),
            (None, Ok(Ok(result))) => result,
            (None, Ok(Err(payload)) | Err(payload)) => Err(panic_error(payload)),
        }
    });
    outcome.map_err(|e| to_py(py, e))
}

/// What a panic payload says.
fn panic_error(payload: Box<dyn std::any::Any + Send>) -> Error {
    let message = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".to_string());
    Error::Internal(message)
}

/// The diagnosis's settings, checked as the command line checks them.
fn options(
    folds: u16,
    seed: u64,
    stability_draws: u16,
    effects: Option<Vec<String>>,
) -> Result<Options, Error> {
    let bad = |m: String| Error::Failure(bad_input(m));
    let effects = effects
        .map(|names| parse_names(&names))
        .transpose()
        .map_err(bad)?;
    let options = Options {
        folds: folds as usize,
        seed,
        stability_draws: stability_draws as usize,
        effects,
        ..Options::default()
    };
    options.validate().map_err(bad)?;
    Ok(options)
}

/// A finished diagnosis: its report in both forms, its parameter file and its figures.
#[pyclass(frozen, module = "tire_gap._native")]
struct Diagnosis {
    finished: Finished,
}

#[pymethods]
impl Diagnosis {
    /// The report as one JSON object, as `tire-gap diagnose --json` prints it.
    fn json(&self) -> String {
        self.finished.json(Vec::new())
    }

    /// The report as text, as `tire-gap diagnose` prints it.
    fn text(&self) -> String {
        self.finished.text(Vec::new())
    }

    /// The fitted model in the FMU's parameter-file format (JSON text).
    fn parameter_file(&self, py: Python<'_>) -> PyResult<String> {
        self.finished
            .parameter_file()
            .map_err(|m| to_py(py, Error::Failure(tire_gap::io::output::output_failure(m))))
    }

    /// Writes the SVG figures and index.html into `dir` (created if missing); returns the
    /// notes on figures left out.
    fn write_plots(&self, py: Python<'_>, dir: PathBuf) -> PyResult<Vec<String>> {
        let status = py.detach(|| self.finished.write_plots(&dir));
        match status.error {
            None => Ok(status.notes),
            Some(m) => Err(to_py(
                py,
                Error::Failure(tire_gap::io::output::output_failure(m)),
            )),
        }
    }
}

/// Diagnoses the data in files and directories, read as one data set as the command line
/// reads them; `shown` names the input in the report.
#[pyfunction]
#[pyo3(signature = (paths, shown, folds, seed, stability_draws, effects=None, threads=None))]
#[allow(clippy::too_many_arguments)] // the Python signature: diagnose's options
fn diagnose_paths(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    shown: String,
    folds: u16,
    seed: u64,
    stability_draws: u16,
    effects: Option<Vec<String>>,
    threads: Option<usize>,
) -> PyResult<Diagnosis> {
    let options = options(folds, seed, stability_draws, effects).map_err(|e| to_py(py, e))?;
    let finished = run_released(py, threads, |progress| {
        let (files, notes) = expand(&paths)?;
        let loaded = load_many(&files)?;
        Ok(diagnose_loaded(loaded, notes, shown, &options, progress)?)
    })?;
    Ok(Diagnosis { finished })
}

/// Diagnoses a table given as columns: (name, float64 little-endian bytes, rows that were
/// not numbers); `source` names it in messages and in the report.
#[pyfunction]
#[pyo3(signature = (columns, source, folds, seed, stability_draws, effects=None, threads=None))]
#[allow(clippy::too_many_arguments)] // the Python signature: diagnose's options
fn diagnose_columns(
    py: Python<'_>,
    columns: Vec<(String, Bound<'_, PyBytes>, Vec<usize>)>,
    source: String,
    folds: u16,
    seed: u64,
    stability_draws: u16,
    effects: Option<Vec<String>>,
    threads: Option<usize>,
) -> PyResult<Diagnosis> {
    let options = options(folds, seed, stability_draws, effects).map_err(|e| to_py(py, e))?;
    let columns: Vec<FrameColumn> = columns
        .into_iter()
        .map(|(name, bytes, not_numbers)| FrameColumn {
            name,
            values: bytes
                .as_bytes()
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
                .collect(),
            not_numbers,
        })
        .collect();
    let finished = run_released(py, threads, |progress| {
        let loaded = read_frame(columns, &source)?;
        Ok(diagnose_loaded(
            loaded,
            Vec::new(),
            source.clone(),
            &options,
            progress,
        )?)
    })?;
    Ok(Diagnosis { finished })
}

/// The options of `tire-gap synth` that shape the data, from a dict of the same names.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
struct SynthOptions {
    seed: u64,
    effects: Vec<String>,
    tire: String,
    rows: usize,
    noise: f64,
    couple: Option<String>,
    drift: f64,
    forms: String,
    /// Also write the data here, as the command line's `--out` (`format`: csv or tydex).
    out: Option<PathBuf>,
    format: String,
    tydex_units: Option<String>,
}

/// Named float64 columns, each as little-endian bytes.
type Columns = Vec<(String, Py<PyBytes>)>;

/// A value of a command-line enum, by its command-line name.
fn value_of<T: clap::ValueEnum>(option: &str, text: &str) -> Result<T, Error> {
    T::from_str(text, true).map_err(|_| {
        let known: Vec<String> = T::value_variants()
            .iter()
            .filter_map(|v| Some(v.to_possible_value()?.get_name().to_string()))
            .collect();
        Error::Failure(bad_input(format!(
            "{option} = {text:?}: unknown; known: {}",
            known.join(", ")
        )))
    })
}

/// Synthetic rig data as `tire-gap synth` makes it: the columns as its CSV holds them
/// (`run` first) and the truth record (JSON); with `out`, also written as the command line
/// writes them.
#[pyfunction]
fn synth(py: Python<'_>, options: SynthOptions) -> PyResult<(Columns, String)> {
    use tire_gap::synth::cli::{Output, SynthArgs, write_outputs};
    use tire_gap::synth::{csv_columns, generate_with_truth, tydex::check_programme_dir};
    let SynthOptions {
        seed,
        effects,
        tire,
        rows,
        noise,
        couple,
        drift,
        forms,
        out,
        format,
        tydex_units,
    } = options;
    let (columns, truth) = run_released(py, None, |_| {
        let args = SynthArgs {
            seed,
            effects,
            tire,
            rows,
            noise,
            couple,
            drift,
            forms,
            format: value_of("format", &format)?,
            tydex_units: tydex_units
                .map(|u| value_of("tydex_units", &u))
                .transpose()?,
            out,
            truth: None,
        };
        let cfg = args.config().map_err(|m| Error::Failure(bad_input(m)))?;
        let output = match &args.out {
            Some(_) => Some(args.output().map_err(|m| Error::Failure(bad_input(m)))?),
            None => None,
        };
        if let Some(Output::Tydex { dir, .. }) = &output {
            check_programme_dir(dir)?;
        }
        let (ds, truth) = generate_with_truth(&cfg);
        if let Some(output) = &output {
            write_outputs(&ds, output, None, &mut std::io::sink())?;
        }
        let truth = serde_json::to_string_pretty(&truth)
            .map_err(|e| Error::Internal(format!("cannot encode the truth record: {e}")))?;
        let run: Vec<f64> = ds.run.iter().map(|r| *r as f64).collect();
        let mut columns = vec![("run".to_string(), le_bytes(&run))];
        columns.extend(
            csv_columns(&ds)
                .into_iter()
                .map(|(name, values)| (name.to_string(), le_bytes(&values))),
        );
        Ok((columns, truth))
    })?;
    let columns = columns
        .into_iter()
        .map(|(name, bytes)| (name, PyBytes::new(py, &bytes).unbind()))
        .collect();
    Ok((columns, truth))
}

fn le_bytes(values: &[f64]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// The names of the candidate effects, in the order the diagnosis tests them.
#[pyfunction]
fn effect_names() -> Vec<&'static str> {
    tire_gap::method::fit::effects::Extension::NAMES.to_vec()
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Diagnosis>()?;
    m.add_function(wrap_pyfunction!(diagnose_paths, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose_columns, m)?)?;
    m.add_function(wrap_pyfunction!(synth, m)?)?;
    m.add_function(wrap_pyfunction!(effect_names, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    let defaults = Options::default();
    m.add("DEFAULT_FOLDS", defaults.folds)?;
    m.add("DEFAULT_SEED", defaults.seed)?;
    m.add("DEFAULT_STABILITY_DRAWS", defaults.stability_draws)?;
    Ok(())
}
