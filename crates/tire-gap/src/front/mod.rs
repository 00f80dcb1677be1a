//! What every front end (the command line, the Python package) does around the method: the
//! reading (each file read, then made ready by the method's preparation), the resource check,
//! the diagnosis, where the result came from, and the outputs it can write.

mod read;

pub use read::{load, load_bytes, load_many, load_paths, prepared, read_frame, read_str};

use std::path::Path;

use crate::data::Dataset;
use crate::io::input::{Loaded, combined_sha256};
use crate::io::output::{Failure, FailureKind, bad_input, write_whole};
use crate::io::report::{self, Context, OutputStatus, Provenance};
use crate::io::resources;
use crate::method::diagnose::{Diagnosis, Options, Stopped, diagnose};
use crate::method::observer::Observer;

/// A diagnosis made, with the data it was made on and what its report says around it.
pub struct Finished {
    pub diagnosis: Diagnosis,
    pub dataset: Dataset,
    pub provenance: Provenance,
    /// The readers' notes and the resource check's.
    pub notes: Vec<String>,
}

/// Diagnoses data already read. `notes` are what was noticed before reading (directory
/// contents); `shown` names the input in the report, as the user gave it.
pub fn diagnose_loaded(
    loaded: Loaded,
    mut notes: Vec<String>,
    shown: String,
    options: &Options,
    observer: &dyn Observer,
) -> Result<Finished, Failure> {
    notes.extend(loaded.notes.iter().cloned());
    // What a diagnosis of this size needs, before the work starts.
    let rows = loaded.dataset.len();
    if let Some(note) = resources::check(rows, resources::available_memory()).map_err(bad_input)? {
        notes.push(note);
    }
    for note in &notes {
        observer.note(note);
    }
    let diagnosis = diagnose(&loaded.dataset, options, observer).map_err(|e| match e {
        Stopped::Failed(e) => bad_input(e.to_string()),
        Stopped::Cancelled => Failure {
            kind: FailureKind::Cancelled,
            message: e.to_string(),
        },
    })?;
    let provenance = Provenance {
        input: shown,
        input_sha256: combined_sha256(&loaded.sources),
        inputs: loaded.sources,
        split_seed: options.seed,
        folds: options.folds,
        tool: "tire-gap",
        version: env!("CARGO_PKG_VERSION"),
    };
    Ok(Finished {
        diagnosis,
        dataset: loaded.dataset,
        provenance,
        notes,
    })
}

impl Finished {
    fn context(&self, outputs: Vec<OutputStatus>) -> Context {
        Context {
            provenance: self.provenance.clone(),
            notes: self.notes.clone(),
            outputs,
        }
    }

    /// The report as one JSON object (`tire-gap diagnose --json`).
    pub fn json(&self, outputs: Vec<OutputStatus>) -> String {
        report::json(&self.diagnosis, &self.context(outputs))
    }

    /// The report as text (`tire-gap diagnose`).
    pub fn text(&self, outputs: Vec<OutputStatus>) -> String {
        report::text(&self.diagnosis, &self.context(outputs))
    }

    /// The title of the figures' index page.
    pub fn heading(&self) -> String {
        format!("tire-gap diagnose {}", self.provenance.input)
    }

    /// The fitted model in the FMU's parameter-file format, or why the FMU would refuse it.
    pub fn parameter_file(&self) -> Result<String, String> {
        crate::method::export::parameter_file(&self.diagnosis, &self.dataset)
            .map_err(|e| format!("the fitted model is not a parameter file the FMU accepts: {e}"))
    }

    /// Writes the parameter file; what became of it.
    pub fn write_params(&self, path: &Path) -> OutputStatus {
        let written = self
            .parameter_file()
            .and_then(|text| write_whole(path, text.as_bytes()).map_err(|f| f.message));
        status("params", path, written, Vec::new())
    }

    /// Writes the SVG figures and their index page into `dir`; what became of them.
    pub fn write_plots(&self, dir: &Path) -> OutputStatus {
        let figures = crate::io::plots::render(&self.diagnosis);
        let written =
            crate::io::plots::write(dir, &figures, &self.heading()).map_err(|f| f.message);
        status("plots", dir, written, figures.skipped)
    }
}

fn status(
    output: &'static str,
    path: &Path,
    written: Result<(), String>,
    notes: Vec<String>,
) -> OutputStatus {
    OutputStatus {
        output,
        path: path.display().to_string(),
        written: written.is_ok(),
        error: written.err(),
        notes,
    }
}

/// Checks the paths of the outputs asked for before any work: a parameter file that would
/// overwrite an input or a directory, a figures directory that cannot be made.
pub fn check_targets(
    params: Option<&Path>,
    plots: Option<&Path>,
    inputs: &[std::path::PathBuf],
) -> Result<(), Failure> {
    if let Some(path) = params {
        crate::io::output::check_file_target(path, "--params", inputs)?;
    }
    if let Some(dir) = plots {
        crate::io::plots::check_dir(dir, inputs)?;
    }
    Ok(())
}
