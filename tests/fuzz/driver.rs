//! The commands of the fuzzer (see main.rs): the forked run, the valgrind run, replay, shrink.

use std::collections::BTreeMap;
use std::io::{Read, Seek, SeekFrom};
use std::os::fd::AsRawFd;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

use crate::fmi;
use crate::run::{Files, Host};
use crate::seq::{Generator, Mode, Op};

/// Seconds a sequence may take before it counts as a hang.
const HANG_SECONDS: u32 = 20;

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

pub fn main() -> ExitCode {
    // cargo passes libtest's options (e.g. --quiet, a filter): only the commands count.
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let number = |i: usize| -> u64 {
        args.get(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or_else(|| panic!("usage: {} NUMBER...", args[0]))
    };
    // The valgrind child ("run") loads what its parent built.
    if args.first().map(String::as_str) != Some("run") {
        build_library();
    }
    let work = std::env::temp_dir().join(format!("p87-fuzz-{}", std::process::id()));
    let files = Files::prepare(&work.join("resources"));
    let ok = match args.first().map(String::as_str) {
        Some("replay") => replay(&files, number(1)),
        Some("shrink") => shrink(&files, number(1)),
        Some("run") => in_process(&files, number(1), number(2)),
        Some("fuzz") => forked(&files, &work, number(1), number(2)),
        Some("valgrind") => under_valgrind(&work, number(1), number(2)),
        // The test: the counts the test command runs, the valgrind run alongside the forked
        // one.
        _ => {
            let first = env_u64("FUZZ_SEED", 0);
            let valgrind = start_valgrind(&work, first, env_u64("FUZZ_VALGRIND_SEQUENCES", 600));
            let plain = forked(&files, &work, first, env_u64("FUZZ_SEQUENCES", 30_000));
            let checked = valgrind.map_or_else(|ok| ok, finish_valgrind);
            plain && checked
        }
    };
    let _ = std::fs::remove_dir_all(&work);
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

/// Builds the FMU library the sequences load, in the test's own profile (cargo does nothing
/// when it is up to date; `cargo test` builds the crate's rlib, not its cdylib), unless
/// `FUZZ_FMU_LIB` names a library.
fn build_library() {
    if std::env::var_os("FUZZ_FMU_LIB").is_some() {
        return;
    }
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let path = fmi::library_path();
    let release = path
        .parent()
        .and_then(Path::file_name)
        .is_some_and(|n| n == "release");
    let mut build = Command::new(cargo);
    build.args(["build", "--quiet", "-p", "pacejka87-tire-fmu", "--lib"]);
    if release {
        build.arg("--release");
    }
    let status = build.status().expect("cargo runs");
    assert!(status.success(), "building {} failed", path.display());
}

fn load() -> (fmi::Fmi, fmi::Fmi3) {
    let path = fmi::library_path();
    let hint = "build it: cargo build -p pacejka87-tire-fmu";
    (
        fmi::Fmi::load(&path).unwrap_or_else(|e| panic!("{e} ({hint})")),
        fmi::Fmi3::load(&path).unwrap_or_else(|e| panic!("{e} ({hint})")),
    )
}

fn ops_of(files: &Files, seed: u64) -> Vec<Op> {
    Generator::sequence(seed, files.names.len(), files.good)
}

/// One sequence in-process, verbosely.
fn replay(files: &Files, seed: u64) -> bool {
    let (fmi, fmi3) = load();
    fmi::capture_logs(true);
    let ops = ops_of(files, seed);
    println!(
        "seed {seed} ({}): {} calls",
        Mode::of(seed).name(),
        ops.len()
    );
    let mut host = Host::new(&fmi, &fmi3, files, true);
    host.run(&ops);
    println!("{} findings", host.findings.len());
    host.findings.is_empty()
}

/// Sequences in-process, no fork (under valgrind).
fn in_process(files: &Files, first: u64, count: u64) -> bool {
    let (fmi, fmi3) = load();
    fmi::capture_logs(false);
    let mut ok = true;
    for seed in first..first + count {
        let ops = ops_of(files, seed);
        let mut host = Host::new(&fmi, &fmi3, files, false);
        host.run(&ops);
        for f in &host.findings {
            println!("seed {seed} call {}: {}", f.call, f.what);
            ok = false;
        }
    }
    ok
}

/// What one forked sequence showed.
#[derive(Debug, Default)]
struct Outcome {
    /// Crash, hang, output or findings, one line each.
    problems: Vec<String>,
    /// Calls per FMI function: (returned OK, all).
    calls: BTreeMap<String, (u64, u64)>,
}

/// Runs `ops` in a forked child; `out` and `report` are scratch files.
fn run_forked(
    (fmi, fmi3): &(fmi::Fmi, fmi::Fmi3),
    files: &Files,
    ops: &[Op],
    out: &mut std::fs::File,
    report: &mut std::fs::File,
) -> Outcome {
    for f in [&mut *out, &mut *report] {
        f.set_len(0).unwrap();
        f.seek(SeekFrom::Start(0)).unwrap();
    }
    // SAFETY: the child only runs the sequence and exits; the parent waits for it.
    let pid = unsafe { libc::fork() };
    if pid == 0 {
        // SAFETY: valid descriptors; the child's output goes to `out`.
        unsafe {
            libc::dup2(out.as_raw_fd(), 1);
            libc::dup2(out.as_raw_fd(), 2);
            libc::alarm(HANG_SECONDS);
        }
        let mut host = Host::new(fmi, fmi3, files, false);
        fmi::capture_logs(false);
        host.run(ops);
        let mut text = String::new();
        for f in &host.findings {
            text.push_str(&format!("finding call {}: {}\n", f.call, f.what));
        }
        for (name, (ok, all)) in host.call_counts() {
            text.push_str(&format!("calls {name} {ok} {all}\n"));
        }
        use std::io::Write;
        let _ = report.write_all(text.as_bytes());
        // SAFETY: ends the child without running the parent's exit handlers.
        unsafe { libc::_exit(0) };
    }
    assert!(pid > 0, "fork failed");
    let mut status = 0;
    // SAFETY: our child.
    unsafe { libc::waitpid(pid, &mut status, 0) };
    let mut outcome = Outcome::default();
    if libc::WIFSIGNALED(status) {
        let signal = libc::WTERMSIG(status);
        outcome.problems.push(if signal == libc::SIGALRM {
            format!("hang: no end within {HANG_SECONDS} s")
        } else {
            format!("crash: killed by signal {signal}")
        });
    } else if libc::WEXITSTATUS(status) != 0 {
        outcome
            .problems
            .push(format!("crash: exit status {}", libc::WEXITSTATUS(status)));
    }
    let mut printed = String::new();
    out.seek(SeekFrom::Start(0)).unwrap();
    out.read_to_string(&mut printed).unwrap_or_default();
    if !printed.is_empty() {
        let head: String = printed.chars().take(600).collect();
        outcome
            .problems
            .push(format!("output on stdout/stderr: {head:?}"));
    }
    let mut text = String::new();
    report.seek(SeekFrom::Start(0)).unwrap();
    report.read_to_string(&mut text).unwrap_or_default();
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("calls ") {
            let parts: Vec<&str> = rest.split(' ').collect();
            let e = outcome.calls.entry(parts[0].to_string()).or_default();
            e.0 += parts[1].parse::<u64>().unwrap();
            e.1 += parts[2].parse::<u64>().unwrap();
        } else {
            outcome.problems.push(line.to_string());
        }
    }
    outcome
}

fn scratch(dir: &Path, name: &str) -> std::fs::File {
    std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(true)
        .open(dir.join(name))
        .unwrap()
}

/// `count` sequences from seed `first`, each in a forked child.
fn forked(files: &Files, work: &Path, first: u64, count: u64) -> bool {
    let fmi = load();
    let started = Instant::now();
    let (mut out, mut report) = (scratch(work, "out"), scratch(work, "report"));
    let mut calls: BTreeMap<String, (u64, u64)> = BTreeMap::new();
    let mut failing = Vec::new();
    let mut modes = [0u64; 3];
    for seed in first..first + count {
        modes[Mode::of(seed) as usize] += 1;
        let ops = ops_of(files, seed);
        let outcome = run_forked(&fmi, files, &ops, &mut out, &mut report);
        for (name, (ok, all)) in outcome.calls {
            let e = calls.entry(name).or_default();
            e.0 += ok;
            e.1 += all;
        }
        if !outcome.problems.is_empty() {
            println!("seed {seed}:");
            for p in outcome.problems.iter().take(5) {
                println!("  {p}");
            }
            failing.push(seed);
        }
    }
    let total: u64 = calls.values().map(|c| c.1).sum();
    println!(
        "fuzz: {count} sequences (seeds {first}..{}; {} FMI 2.0, {} FMI 3.0, {} mixed), \
         {total} calls, in {:.1} s; {} failing",
        first + count,
        modes[Mode::Fmi2 as usize],
        modes[Mode::Fmi3 as usize],
        modes[Mode::Mixed as usize],
        started.elapsed().as_secs_f64(),
        failing.len()
    );
    println!("  calls returning OK (fmi2OK, fmi3OK) / all, per function:");
    for (name, (ok, all)) in &calls {
        println!("  {name:36} {ok:>8} / {all}");
    }
    // The functions that never succeed here: unsupported (FMI 2.0's input and output
    // derivatives, cancelled steps, status queries without a kind to answer; FMI 3.0's
    // scheduled execution, configuration mode, step mode without event mode, output
    // derivatives, variable dependencies outside the model description).
    let unsupported = [
        "fmi2SetRealInputDerivatives",
        "fmi2GetRealOutputDerivatives",
        "fmi2CancelStep",
        "fmi2GetStatus",
        "fmi2GetIntegerStatus",
        "fmi2GetStringStatus",
        "fmi3InstantiateScheduledExecution",
        "fmi3ActivateModelPartition",
        "fmi3EnterConfigurationMode",
        "fmi3ExitConfigurationMode",
        "fmi3EnterStepMode",
        "fmi3GetOutputDerivatives",
        "fmi3GetNumberOfVariableDependencies",
        "fmi3GetVariableDependencies",
    ];
    let untested: Vec<&str> = fmi::NAMES
        .iter()
        .chain(fmi::NAMES3)
        .copied()
        .filter(|n| calls.get(*n).is_none_or(|c| c.0 == 0))
        .filter(|n| !unsupported.contains(n))
        .collect();
    if !untested.is_empty() && count >= 1000 {
        println!("fuzz: never returned OK: {untested:?}");
        return false;
    }
    if let Some(seed) = failing.first() {
        println!(
            "fuzz: replay with `cargo test -p pacejka87-tire-fmu --test fuzz -- replay {seed}`, \
             shrink with `... -- shrink {seed}`"
        );
    }
    failing.is_empty()
}

/// The shortest sequence found that still fails as seed `seed` does (same first problem,
/// numbers aside): removes chunks of calls, then single calls, while it still fails.
fn shrink(files: &Files, seed: u64) -> bool {
    let fmi = load();
    let work = files.dir.parent().unwrap();
    let (mut out, mut report) = (scratch(work, "out"), scratch(work, "report"));
    let mut ops = ops_of(files, seed);
    let first = run_forked(&fmi, files, &ops, &mut out, &mut report);
    let Some(problem) = first.problems.first().cloned() else {
        println!("seed {seed} does not fail");
        return true;
    };
    let signature = |p: &str| -> String {
        let p = p.split_once(": ").map_or(p, |(_, rest)| rest);
        p.chars().filter(|c| !c.is_ascii_digit()).take(60).collect()
    };
    let wanted = signature(&problem);
    println!(
        "seed {seed} ({}): {} calls, fails with {problem}",
        Mode::of(seed).name(),
        ops.len()
    );
    let mut chunk = ops.len().div_ceil(2);
    while chunk >= 1 {
        let mut i = 0;
        while i < ops.len() {
            let mut candidate = ops.clone();
            candidate.drain(i..(i + chunk).min(ops.len()));
            let outcome = run_forked(&fmi, files, &candidate, &mut out, &mut report);
            if outcome.problems.iter().any(|p| signature(p) == wanted) {
                ops = candidate;
            } else {
                i += chunk;
            }
        }
        chunk /= 2;
    }
    println!("shrunk to {} calls:", ops.len());
    for (i, op) in ops.iter().enumerate() {
        println!("[{i}] {op:?}");
    }
    let last = run_forked(&fmi, files, &ops, &mut out, &mut report);
    for p in &last.problems {
        println!("  {p}");
    }
    false
}

/// `count` sequences from `first` in one process under valgrind's memcheck: any definite
/// leak or memory error fails, and so does any output of the FMU (valgrind logs to a file).
fn under_valgrind(work: &Path, first: u64, count: u64) -> bool {
    match start_valgrind(work, first, count) {
        Ok(run) => finish_valgrind(run),
        Err(ok) => ok,
    }
}

/// A valgrind run started by [`start_valgrind`].
struct Valgrind {
    child: Child,
    started: Instant,
    /// The same, as the log file's modification time counts.
    started_at: std::time::SystemTime,
    first: u64,
    count: u64,
    /// valgrind's log, and the run's stdout and stderr.
    log: PathBuf,
    out: PathBuf,
    err: PathBuf,
}

/// Starts the valgrind run in the background (the default command runs it alongside the
/// forked run: each keeps one core busy). Without valgrind: `Err(whether that is fine)`.
fn start_valgrind(work: &Path, first: u64, count: u64) -> Result<Valgrind, bool> {
    let have = Command::new("valgrind")
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !have {
        if std::env::var_os("CI").is_some() {
            println!("valgrind: not installed; scripts/setup.sh installs it (CI: this fails)");
            return Err(false);
        }
        println!("valgrind: not installed, memcheck skipped (scripts/setup.sh installs it)");
        return Err(true);
    }
    let log: PathBuf = work.join("valgrind.log");
    let (out, err) = (work.join("valgrind.out"), work.join("valgrind.err"));
    // Files, not pipes: nobody reads while the forked run goes on, and a full pipe would
    // stop the run.
    let child = Command::new("valgrind")
        .args([
            "--tool=memcheck",
            "--leak-check=full",
            "--errors-for-leak-kinds=definite",
            "--error-exitcode=99",
            "--track-fds=no",
        ])
        .arg(format!("--log-file={}", log.display()))
        .arg(std::env::current_exe().unwrap())
        .args(["run", &first.to_string(), &count.to_string()])
        .env("FUZZ_FMU_LIB", fmi::library_path())
        .stdout(std::fs::File::create(&out).unwrap())
        .stderr(std::fs::File::create(&err).unwrap())
        .spawn()
        .expect("valgrind");
    Ok(Valgrind {
        child,
        started: Instant::now(),
        started_at: std::time::SystemTime::now(),
        first,
        count,
        log,
        out,
        err,
    })
}

/// Waits for the valgrind run and reports it.
fn finish_valgrind(mut run: Valgrind) -> bool {
    let deadline = Duration::from_secs(900);
    let status = loop {
        if let Some(status) = run.child.try_wait().unwrap() {
            break Some(status);
        }
        if run.started.elapsed() > deadline {
            let _ = run.child.kill();
            let _ = run.child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let stdout = std::fs::read_to_string(&run.out).unwrap_or_default();
    let stderr = std::fs::read_to_string(&run.err).unwrap_or_default();
    let report = std::fs::read_to_string(&run.log).unwrap_or_default();
    let summary: Vec<&str> = report
        .lines()
        .filter(|l| l.contains("definitely lost") || l.contains("ERROR SUMMARY"))
        .collect();
    let (first, count) = (run.first, run.count);
    // Its own time: until valgrind last wrote its log (it may have ended long before it was
    // waited for).
    let took = std::fs::metadata(&run.log)
        .and_then(|m| m.modified())
        .ok()
        .and_then(|t| t.duration_since(run.started_at).ok())
        .unwrap_or_else(|| run.started.elapsed());
    println!(
        "valgrind: {count} sequences (seeds {first}..{}) in {:.1} s: {}",
        first + count,
        took.as_secs_f64(),
        summary.join(" / ")
    );
    let mut ok = true;
    match status {
        None => {
            println!("valgrind: hang: no end within {} s", deadline.as_secs());
            ok = false;
        }
        Some(s) if !s.success() => {
            println!("valgrind: exit {s}; log:\n{report}");
            ok = false;
        }
        Some(_) => {}
    }
    if !stdout.is_empty() {
        println!("valgrind run findings:\n{stdout}");
        ok = false;
    }
    if !stderr.is_empty() {
        println!("valgrind run: output on stderr: {stderr:?}");
        ok = false;
    }
    ok
}
