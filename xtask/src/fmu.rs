//! `cargo xtask fmu`: build the binaries and package them as two FMUs of the same library,
//! FMI 2.0 (`<id>.fmu`) and FMI 3.0 (`<id>-fmi3.fmu`), each co-simulation and Model Exchange.

use std::env;
use std::fs::{self, File};
use std::io;
use std::path::{Path, PathBuf};

use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, ZipWriter};

use crate::docs;
use crate::platforms::{self, Binary, Platform, Workspace};

/// The FMI standard of an archive (one per archive: FMI 3.0 allows no other).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Standard {
    Fmi2,
    Fmi3,
}

impl Standard {
    /// The model description in the repository.
    pub fn model_description(self, root: &Path) -> PathBuf {
        match self {
            Standard::Fmi2 => root.join("modelDescription/modelDescription.xml"),
            Standard::Fmi3 => root.join("modelDescription/fmi3/modelDescription.xml"),
        }
    }

    /// The archive's name (without `.fmu`) for the model identifier `id`.
    pub fn archive_name(self, id: &str) -> String {
        match self {
            Standard::Fmi2 => id.to_string(),
            Standard::Fmi3 => format!("{id}-fmi3"),
        }
    }

    /// The binary folder of `platform` under `binaries/`.
    fn folder(self, platform: &Platform) -> &'static str {
        match self {
            Standard::Fmi2 => platform.folder,
            Standard::Fmi3 => platform.tuple,
        }
    }
}

/// The files an FMU is made from.
pub struct Sources {
    pub standard: Standard,
    pub model_description: PathBuf,
    pub binaries: Vec<Binary>,
    pub parameters: PathBuf,
}

/// Which binaries `run` builds.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Build {
    /// linux64 against glibc 2.17 (cargo-zigbuild), and win64 when its cross tools exist.
    Release,
    /// linux64 only, with plain cargo against this machine's glibc.
    Host,
}

pub fn run(build: Build) -> Result<(), String> {
    let (os, arch) = (env::consts::OS, env::consts::ARCH);
    if (os, arch) != ("linux", "x86_64") {
        return Err(format!(
            "packaging is supported on linux x86_64 only (host: {os} {arch})"
        ));
    }
    let ws = workspace();
    let mut binaries = Vec::new();
    let mut skipped = None;
    match build {
        Build::Release => {
            binaries.push(platforms::build_linux64(&ws)?);
            match platforms::build_win64(&ws)? {
                Ok(binary) => binaries.push(binary),
                Err(missing) => {
                    eprintln!("warning: win64 skipped: {missing}");
                    skipped = Some(missing);
                }
            }
        }
        Build::Host => binaries.push(platforms::build_linux64_host(&ws)?),
    }
    let out = ws.target.join("fmu");
    for standard in [Standard::Fmi2, Standard::Fmi3] {
        let sources = Sources {
            standard,
            model_description: standard.model_description(&ws.root),
            binaries: binaries.clone(),
            parameters: ws.root.join("crates/mf87/data/pacejka87.json"),
        };
        let name = stage(&sources, &out)?;
        let fmu = out.join(format!("{name}.fmu"));
        zip_dir(&out.join(&name), &fmu)?;
        let size = fs::metadata(&fmu).map_err(|e| format!("{}: {e}", fmu.display()))?;
        let folders: Vec<_> = binaries
            .iter()
            .map(|b| standard.folder(&b.platform))
            .collect();
        println!(
            "wrote {} ({} bytes) with binaries for {}",
            fmu.display(),
            size.len(),
            folders.join(", ")
        );
    }
    if let Some(missing) = skipped {
        println!("win64 is not inside: {missing}");
    }
    Ok(())
}

/// The workspace root and cargo's target directory.
pub fn workspace() -> Workspace {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace root");
    // Cargo resolves a relative CARGO_TARGET_DIR against its working directory, `root`.
    let target = root.join(env::var_os("CARGO_TARGET_DIR").unwrap_or_else(|| "target".into()));
    Workspace {
        root: root.to_path_buf(),
        target,
    }
}

/// Lays out the FMU tree in `out/<archive name>/` (replacing any old one) and returns the
/// archive's name (see [`Standard::archive_name`]).
pub fn stage(src: &Sources, out: &Path) -> Result<String, String> {
    let xml = fs::read_to_string(&src.model_description)
        .map_err(|e| format!("{}: {e}", src.model_description.display()))?;
    let doc = roxmltree::Document::parse(&xml)
        .map_err(|e| format!("{}: {e}", src.model_description.display()))?;
    let id = model_identifier(&doc)?;
    let name = src.standard.archive_name(&id);

    let dir = out.join(&name);
    if dir.exists() {
        fs::remove_dir_all(&dir).map_err(|e| format!("removing {}: {e}", dir.display()))?;
    }
    copy(&src.model_description, &dir.join("modelDescription.xml"))?;
    for binary in &src.binaries {
        let p = binary.platform;
        let file = format!("binaries/{}/{id}.{}", src.standard.folder(&p), p.extension);
        copy(&binary.path, &dir.join(file))?;
    }
    copy(&src.parameters, &dir.join("resources/pacejka87.json"))?;
    let platforms: Vec<_> = src.binaries.iter().map(|b| b.platform).collect();
    let html = docs::render(&doc, &platforms)?;
    write(&dir.join("documentation/index.html"), html.as_bytes())?;
    Ok(name)
}

/// The `modelIdentifier` of `<CoSimulation>`, which names the binary (a C identifier).
fn model_identifier(doc: &roxmltree::Document) -> Result<String, String> {
    let id = doc
        .root_element()
        .children()
        .find(|n| n.has_tag_name("CoSimulation"))
        .and_then(|n| n.attribute("modelIdentifier"))
        .ok_or("modelDescription.xml has no <CoSimulation modelIdentifier=...>")?;
    let valid = id.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
        && id.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !valid {
        return Err(format!("modelIdentifier {id:?} is not a C identifier"));
    }
    Ok(id.to_owned())
}

fn copy(from: &Path, to: &Path) -> Result<(), String> {
    create_parent(to)?;
    fs::copy(from, to)
        .map(drop)
        .map_err(|e| format!("copying {} to {}: {e}", from.display(), to.display()))
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), String> {
    create_parent(path)?;
    fs::write(path, bytes).map_err(|e| format!("writing {}: {e}", path.display()))
}

fn create_parent(path: &Path) -> Result<(), String> {
    let parent = path.parent().expect("a file path has a parent");
    fs::create_dir_all(parent).map_err(|e| format!("creating {}: {e}", parent.display()))
}

/// Zips the files under `dir` into `dest`, deflated, named relative to `dir` with `/`.
/// Entries get a fixed date and mode, so the archive depends only on the file contents.
pub fn zip_dir(dir: &Path, dest: &Path) -> Result<(), String> {
    let mut files = Vec::new();
    list_files(dir, &mut files).map_err(|e| format!("listing {}: {e}", dir.display()))?;
    files.sort();

    let zip_err = |e: zip::result::ZipError| format!("writing {}: {e}", dest.display());
    let io_err = |e: io::Error| format!("writing {}: {e}", dest.display());
    let mut zip = ZipWriter::new(File::create(dest).map_err(io_err)?);
    let options = SimpleFileOptions::DEFAULT.compression_method(CompressionMethod::Deflated);
    for path in files {
        let rel = path.strip_prefix(dir).expect("listed under dir");
        let name = rel
            .components()
            .map(|c| c.as_os_str().to_str())
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| format!("{}: file name is not UTF-8", path.display()))?
            .join("/");
        zip.start_file(name, options).map_err(zip_err)?;
        let mut file = File::open(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        io::copy(&mut file, &mut zip).map_err(io_err)?;
    }
    zip.finish().map_err(zip_err)?;
    Ok(())
}

fn list_files(dir: &Path, files: &mut Vec<PathBuf>) -> io::Result<()> {
    for entry in fs::read_dir(dir)? {
        let entry = entry?;
        if entry.file_type()?.is_dir() {
            list_files(&entry.path(), files)?;
        } else {
            files.push(entry.path());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::io::Read;

    use super::*;

    #[test]
    fn stages_and_zips_an_fmu() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
        let tmp = env::temp_dir().join(format!("xtask-fmu-test-{}", std::process::id()));
        let _ = fs::remove_dir_all(&tmp);
        fs::create_dir_all(&tmp).unwrap();
        let library = tmp.join("libdummy.so");
        fs::write(&library, b"\x7fELF not really a library").unwrap();
        let dll = tmp.join("dummy.dll");
        fs::write(&dll, b"MZ not really a DLL").unwrap();
        let sources = Sources {
            standard: Standard::Fmi2,
            model_description: root.join("modelDescription/modelDescription.xml"),
            binaries: vec![
                Binary {
                    platform: platforms::LINUX64,
                    path: library.clone(),
                },
                Binary {
                    platform: platforms::WIN64,
                    path: dll.clone(),
                },
            ],
            parameters: root.join("crates/mf87/data/pacejka87.json"),
        };
        let out = tmp.join("fmu");
        // A stale file from an earlier run must not survive restaging.
        fs::create_dir_all(out.join("Pacejka87Tire")).unwrap();
        fs::write(out.join("Pacejka87Tire/stale.txt"), b"old").unwrap();

        let id = stage(&sources, &out).unwrap();
        assert_eq!(id, "Pacejka87Tire");
        let fmu = out.join("Pacejka87Tire.fmu");
        zip_dir(&out.join(&id), &fmu).unwrap();

        let mut archive = zip::ZipArchive::new(File::open(&fmu).unwrap()).unwrap();
        let mut names: Vec<_> = archive.file_names().map(str::to_owned).collect();
        names.sort();
        assert_eq!(
            names,
            [
                "binaries/linux64/Pacejka87Tire.so",
                "binaries/win64/Pacejka87Tire.dll",
                "documentation/index.html",
                "modelDescription.xml",
                "resources/pacejka87.json",
            ]
        );
        let expected = [
            ("modelDescription.xml", &sources.model_description),
            ("binaries/linux64/Pacejka87Tire.so", &library),
            ("binaries/win64/Pacejka87Tire.dll", &dll),
            ("resources/pacejka87.json", &sources.parameters),
        ];
        for (name, source) in expected {
            let mut entry = archive.by_name(name).unwrap();
            assert_eq!(entry.compression(), CompressionMethod::Deflated);
            let mut bytes = Vec::new();
            entry.read_to_end(&mut bytes).unwrap();
            assert_eq!(bytes, fs::read(source).unwrap(), "{name}");
        }
        fs::remove_dir_all(&tmp).unwrap();
    }
}
