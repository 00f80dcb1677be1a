//! A call-sequence fuzzer of the FMU's C ABI (see docs/fuzzing.md). It loads the FMU's shared
//! library with dlopen and drives it with seeded random sequences of all 44 FMI 2.0 functions
//! (seq.rs) and all 75 FMI 3.0 functions (seq3.rs), each sequence in a forked child with its
//! stdout and stderr captured and an alarm for hangs. It reports crashes, hangs, any output,
//! statuses outside fmi2Status / fmi3Status, non-finite Reals and Float64s returned with OK or
//! Warning and what else the host checks (run.rs, run3.rs); then runs a subset in-process
//! under valgrind's memcheck (leaks, invalid reads and writes).
//!
//! `cargo test -p pacejka87-tire-fmu --test fuzz -- [COMMAND]`:
//! - (none): `FUZZ_SEQUENCES` (30000) sequences from seed `FUZZ_SEED` (0), and alongside
//!   (the other core) the first `FUZZ_VALGRIND_SEQUENCES` (600) of them under valgrind; a
//!   seed's standard is `seq::Mode::of` (FMI 2.0, FMI 3.0 or both, 2:2:1);
//! - `fuzz FIRST COUNT`: the forked run alone;
//! - `valgrind FIRST COUNT`: the valgrind run alone;
//! - `replay SEED`: one sequence in-process, every call, status and message printed;
//! - `shrink SEED`: the shortest sequence found that still fails the same way, printed;
//! - `run FIRST COUNT`: sequences in-process, no fork (what valgrind runs).
// Every unsafe block is a host's call into the C ABI, a libc call (fork, dup2, waitpid,
// dlopen) or a function pointer from dlsym, each with its arguments described where they are
// made; most have a SAFETY comment, the rest the same argument.
#![allow(clippy::undocumented_unsafe_blocks)]

// The fuzzer forks per sequence and captures output through file descriptors: POSIX only
// (docs/fuzzing.md, "Windows").
#[cfg(unix)]
mod driver;
#[cfg(unix)]
mod fmi;
#[cfg(unix)]
mod run;
#[cfg(unix)]
mod run3;
#[cfg(unix)]
mod seq;
#[cfg(unix)]
mod seq3;

#[cfg(unix)]
fn main() -> std::process::ExitCode {
    driver::main()
}

#[cfg(not(unix))]
fn main() {
    println!("fuzz: needs fork and POSIX file descriptors; not run on this platform");
}
