//! The FMU's binaries and how each is built on this (Linux x86-64) machine:
//! - linux64 with cargo-zigbuild against glibc 2.17, so that the library loads on Linux
//!   systems older than the build machine;
//! - win64 cross-built with Debian's Rust (which ships the standard library's source, so that
//!   `-Zbuild-std` can build it for the `x86_64-win7-windows-gnu` target) and mingw-w64.
//!
//! Each tool that is missing makes its platform fall back or be skipped with a message that
//! names the tool; `scripts/setup.sh` installs them all.

use std::env;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;

pub const PACKAGE: &str = "pacejka87-tire-fmu";
const LIBRARY: &str = "pacejka87_tire";

/// A platform's binary folders (FMI 2.0's name, FMI 3.0's platform tuple) and what a host
/// needs to load its binary.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Platform {
    pub folder: &'static str,
    pub tuple: &'static str,
    pub extension: &'static str,
    pub needs: &'static str,
}

pub const LINUX64: Platform = Platform {
    folder: "linux64",
    tuple: "x86_64-linux",
    extension: "so",
    needs: "x86-64 Linux with glibc 2.17 or later (RHEL/CentOS 7, Ubuntu 14.04 and newer); \
            it links only libc, libm, libdl, libpthread and the loader",
};

pub const WIN64: Platform = Platform {
    folder: "win64",
    tuple: "x86_64-windows",
    extension: "dll",
    needs: "64-bit Windows 10 or later (x86-64); it imports only DLLs that are part of \
            Windows (kernel32, advapi32, ntdll, userenv, ws2_32, msvcrt), no runtime to install",
};

/// glibc version the linux64 binary is linked against (cargo-zigbuild's target suffix).
const GLIBC: &str = "2.17";
const ZIG_TARGET: &str = "x86_64-unknown-linux-gnu";
/// The Windows 7 API level keeps `bcryptprimitives.dll` (Windows 10's random source, which
/// Wine 8 lacks) out of the imports; the DLL runs on Windows 10 and later all the same.
pub const WIN_TARGET: &str = "x86_64-win7-windows-gnu";
/// Debian's Rust with the standard library's source (packages rustc-web, cargo-web,
/// rust-web-src); the default toolchain has no source to build std for a tier-3 target.
const DEBIAN_CARGO: &str = "/usr/bin/cargo";
const DEBIAN_RUSTC: &str = "/usr/bin/rustc";
const DEBIAN_RUSTDOC: &str = "/usr/bin/rustdoc";
const DEBIAN_STD_SOURCE: &str = "/usr/lib/rustlib/src/rust/library";
const MINGW_GCC: &str = "x86_64-w64-mingw32-gcc";

/// A built binary for one platform.
#[derive(Clone)]
pub struct Binary {
    pub platform: Platform,
    pub path: PathBuf,
}

/// Where things are: the workspace root and cargo's target directory.
pub struct Workspace {
    pub root: PathBuf,
    pub target: PathBuf,
}

/// Builds the linux64 library; with cargo-zigbuild against glibc 2.17, otherwise (with a
/// warning) against this machine's glibc.
pub fn build_linux64(ws: &Workspace) -> Result<Binary, String> {
    let path = match find_zigbuild(ws) {
        Some(zigbuild) => {
            let target = format!("{ZIG_TARGET}.{GLIBC}");
            let target_dir = ws.target.join("linux64");
            let mut cmd = Command::new(zigbuild);
            cmd.env("CARGO_ENCODED_RUSTFLAGS", remapped_paths(ws))
                .args([
                    "build",
                    "--release",
                    "--lib",
                    "-p",
                    PACKAGE,
                    "--target",
                    &target,
                ])
                .arg("--target-dir")
                .arg(&target_dir)
                .env("PATH", path_with_venv(ws))
                // bindgen (fmi-sys) parses the FMI headers with the host's libclang, which
                // needs its own builtin headers; the glibc headers only supply C types,
                // identical for this target.
                .env(
                    format!("BINDGEN_EXTRA_CLANG_ARGS_{ZIG_TARGET}"),
                    format!(
                        "-isystem {} -isystem /usr/include/x86_64-linux-gnu -isystem /usr/include",
                        clang_include()?.display()
                    ),
                );
            run(&mut cmd, &ws.root)?;
            target_dir.join(format!("{ZIG_TARGET}/release/lib{LIBRARY}.so"))
        }
        None => {
            eprintln!(
                "warning: linux64: cargo-zigbuild not found (scripts/setup.sh installs it); \
                 the library is built against this machine's glibc and will not load on \
                 older Linux systems"
            );
            let cargo = env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
            let mut cmd = Command::new(cargo);
            cmd.args(["build", "--release", "--lib", "-p", PACKAGE]);
            run(&mut cmd, &ws.root)?;
            ws.target.join(format!("release/lib{LIBRARY}.so"))
        }
    };
    Ok(Binary {
        platform: LINUX64,
        path,
    })
}

/// Builds the linux64 library with plain cargo against this machine's glibc (no
/// cargo-zigbuild), for an FMU used where it is built; the FMU's documentation names that
/// glibc version as the oldest the library loads on.
pub fn build_linux64_host(ws: &Workspace) -> Result<Binary, String> {
    let glibc = host_glibc()?;
    let target_dir = ws.target.join("host");
    let cargo = env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.env("CARGO_ENCODED_RUSTFLAGS", remapped_paths(ws))
        .args(["build", "--release", "--lib", "-p", PACKAGE])
        .arg("--target-dir")
        .arg(&target_dir);
    run(&mut cmd, &ws.root)?;
    let needs = format!(
        "x86-64 Linux with glibc {glibc} or later (the build machine's: built by cargo xtask \
         fmu --host); it links only libc, libm, libgcc_s and the loader"
    );
    Ok(Binary {
        platform: Platform {
            // One FMU per process: the description lives as long as the process.
            needs: Box::leak(needs.into_boxed_str()),
            ..LINUX64
        },
        path: target_dir.join(format!("release/lib{LIBRARY}.so")),
    })
}

/// This machine's glibc version ("2.36"), from `getconf GNU_LIBC_VERSION`.
fn host_glibc() -> Result<String, String> {
    let out = Command::new("getconf")
        .arg("GNU_LIBC_VERSION")
        .output()
        .map_err(|e| format!("cannot run getconf GNU_LIBC_VERSION: {e}"))?;
    let text = String::from_utf8_lossy(&out.stdout);
    match text.trim().strip_prefix("glibc ") {
        Some(version) if out.status.success() && !version.is_empty() => Ok(version.to_owned()),
        _ => Err(format!(
            "getconf GNU_LIBC_VERSION printed {:?} ({}), expected \"glibc <version>\"",
            text.trim(),
            out.status
        )),
    }
}

/// Builds the win64 DLL, or says which tools are missing.
pub fn build_win64(ws: &Workspace) -> Result<Result<Binary, String>, String> {
    let mut cmd = match win64_cargo(ws, "build") {
        Ok(cmd) => cmd,
        Err(missing) => return Ok(Err(missing)),
    };
    cmd.args(["--release", "--lib"])
        .env("CARGO_ENCODED_RUSTFLAGS", remapped_paths(ws));
    run(&mut cmd, &ws.root)?;
    Ok(Ok(Binary {
        platform: WIN64,
        path: ws
            .target
            .join(format!("win64/{WIN_TARGET}/release/{LIBRARY}.dll")),
    }))
}

/// Runs the FMU crate's own tests (unit tests and the C-ABI tests) compiled for Windows,
/// under Wine.
pub fn test_win64(ws: &Workspace) -> Result<(), String> {
    let mut cmd = win64_cargo(ws, "test")
        .map_err(|missing| format!("cannot test the Windows build: {missing}"))?;
    let wine = which("wine").ok_or(
        "cannot test the Windows build: wine is not installed (scripts/setup.sh installs it)",
    )?;
    let prefix = ws.target.join("wine/prefix");
    std::fs::create_dir_all(&prefix).map_err(|e| format!("{}: {e}", prefix.display()))?;
    cmd.env(runner_variable(), wine)
        .env("WINEPREFIX", prefix)
        .env("WINEDEBUG", "-all");
    run(&mut cmd, &ws.root)
}

/// A `cargo <subcommand>` for the FMU crate on the Windows target with everything set, or a
/// message naming what is missing.
fn win64_cargo(ws: &Workspace, subcommand: &str) -> Result<Command, String> {
    let missing = missing_win64_tools(
        Path::new(DEBIAN_CARGO),
        [Path::new(DEBIAN_RUSTC), Path::new(DEBIAN_RUSTDOC)],
        Path::new(DEBIAN_STD_SOURCE),
        which(MINGW_GCC).is_some(),
    );
    if !missing.is_empty() {
        return Err(format!(
            "missing {} (scripts/setup.sh installs them as root)",
            missing.join(", ")
        ));
    }
    let clang_include = clang_include()?;
    let target_var = WIN_TARGET.replace('-', "_");
    let mut cmd = Command::new(DEBIAN_CARGO);
    cmd.args([subcommand, "-p", PACKAGE, "--target", WIN_TARGET])
        .arg("-Zbuild-std=std,panic_unwind")
        .arg("--target-dir")
        .arg(ws.target.join("win64"))
        .env("RUSTC", DEBIAN_RUSTC)
        // The doc tests are compiled for the target too, by the rustdoc of the same compiler.
        .env("RUSTDOC", DEBIAN_RUSTDOC)
        // -Zbuild-std is unstable; Debian's stable compiler allows it with this switch.
        .env("RUSTC_BOOTSTRAP", "1")
        .env(
            format!("CARGO_TARGET_{}_LINKER", target_var.to_uppercase()),
            ws.root.join("xtask/linkers/win64-fmi-gcc"),
        )
        .env(
            format!("BINDGEN_EXTRA_CLANG_ARGS_{target_var}"),
            format!("-isystem {}", clang_include.display()),
        );
    Ok(cmd)
}

/// The Debian packages of the win64 build whose files are not where they belong.
fn missing_win64_tools(
    cargo: &Path,
    rustc_and_rustdoc: [&Path; 2],
    std_source: &Path,
    have_mingw_gcc: bool,
) -> Vec<&'static str> {
    [
        (cargo.is_file(), "cargo-web"),
        (rustc_and_rustdoc.iter().all(|p| p.is_file()), "rustc-web"),
        (std_source.is_dir(), "rust-web-src"),
        (have_mingw_gcc, "gcc-mingw-w64-x86-64"),
    ]
    .into_iter()
    .filter(|(present, _)| !present)
    .map(|(_, package)| package)
    .collect()
}

fn runner_variable() -> String {
    format!(
        "CARGO_TARGET_{}_RUNNER",
        WIN_TARGET.replace('-', "_").to_uppercase()
    )
}

/// rustc flags that keep the build machine's paths (of the workspace and of cargo's registry,
/// which panic locations name) out of the binaries.
fn remapped_paths(ws: &Workspace) -> String {
    let cargo_home = env::var_os("CARGO_HOME")
        .map(PathBuf::from)
        .or_else(|| env::var_os("HOME").map(|h| PathBuf::from(h).join(".cargo")));
    let mut flags = vec![format!("--remap-path-prefix={}=/build", ws.root.display())];
    if let Some(home) = cargo_home {
        flags.push(format!("--remap-path-prefix={}=/cargo", home.display()));
    }
    flags.join("\x1f")
}

/// libclang's builtin headers (stddef.h, ...), which bindgen needs for a cross target.
fn clang_include() -> Result<PathBuf, String> {
    let mut found: Vec<PathBuf> = std::fs::read_dir("/usr/lib")
        .map_err(|e| format!("/usr/lib: {e}"))?
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with("llvm-"))
        .flat_map(|e| {
            std::fs::read_dir(e.path().join("lib/clang"))
                .into_iter()
                .flatten()
        })
        .filter_map(|e| e.ok())
        .map(|e| e.path().join("include"))
        .filter(|p| p.join("stddef.h").is_file())
        .collect();
    found.sort();
    found.pop().ok_or_else(|| {
        "libclang's headers not found (scripts/setup.sh installs libclang-dev)".into()
    })
}

/// cargo-zigbuild from the project's Python environment or from PATH.
fn find_zigbuild(ws: &Workspace) -> Option<PathBuf> {
    let in_venv = ws.root.join(".venv/bin/cargo-zigbuild");
    if in_venv.is_file() {
        return Some(in_venv);
    }
    which("cargo-zigbuild")
}

/// PATH with the project's Python environment first: cargo-zigbuild finds zig (the ziglang
/// package) through its Python.
fn path_with_venv(ws: &Workspace) -> OsString {
    let venv = ws.root.join(".venv/bin");
    let mut paths = vec![venv];
    paths.extend(env::split_paths(&env::var_os("PATH").unwrap_or_default()));
    env::join_paths(paths).expect("PATH entries have no separator")
}

fn which(program: &str) -> Option<PathBuf> {
    env::split_paths(&env::var_os("PATH")?)
        .map(|dir| dir.join(program))
        .find(|p| p.is_file())
}

/// Runs `cmd` in `dir`, streaming its output.
fn run(cmd: &mut Command, dir: &Path) -> Result<(), String> {
    let shown = format!(
        "{} {}",
        cmd.get_program().to_string_lossy(),
        cmd.get_args()
            .map(|a| a.to_string_lossy())
            .collect::<Vec<_>>()
            .join(" ")
    );
    let status = cmd
        .current_dir(dir)
        .status()
        .map_err(|e| format!("cannot run {shown}: {e}"))?;
    if !status.success() {
        return Err(format!("`{shown}` failed ({status})"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn host_glibc_is_a_version_of_glibc_2() {
        let version = host_glibc().unwrap();
        let (major, minor) = version.split_once('.').unwrap();
        assert_eq!(major, "2", "{version}");
        // The oldest glibc the project's binaries target is 2.17; no build machine is older.
        assert!(minor.parse::<u32>().unwrap() >= 17, "{version}");
    }

    #[test]
    fn missing_win64_tools_are_named_by_their_debian_package() {
        let nowhere = Path::new("/nonexistent/p87");
        assert_eq!(
            missing_win64_tools(nowhere, [nowhere, nowhere], nowhere, false),
            [
                "cargo-web",
                "rustc-web",
                "rust-web-src",
                "gcc-mingw-w64-x86-64"
            ]
        );
        let file = env::current_exe().unwrap();
        let dir = env::temp_dir();
        assert!(missing_win64_tools(&file, [&file, &file], &dir, true).is_empty());
        // A directory where a program belongs, and a file where the source tree belongs.
        assert_eq!(
            missing_win64_tools(&dir, [&file, &dir], &file, true),
            ["cargo-web", "rustc-web", "rust-web-src"]
        );
    }
}
