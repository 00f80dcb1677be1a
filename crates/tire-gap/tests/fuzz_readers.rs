//! The readers under a fuzzer: mutated CSV, TYDEX, TTC `.dat` and `.mat` files (a MAT-file
//! level 5 with its struct channel list, compressed and plain) are read as a file of that
//! name would be (`front::load_bytes`: detection, reading, then the method's row and channel
//! rules and the split into blocks). Each must give a report's input or a clear error: never a panic, a hang, or an
//! allocation out of proportion to the file.
//!
//! The mutations are those a file meets on its way (truncation, a flipped or lost byte, a
//! duplicated block) and those aimed at a format's structure: a 32-bit field set to 0, to
//! 2^31 - 1 or to 2^32 - 1 (sizes, counts and tags of a MAT-file), a number in a text file
//! replaced by `nan`, `1e308`, a lone sign or nothing, a line duplicated or lost. The draws
//! come from a fixed seed, so a failure names a case that reproduces.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use common::fixture;
use tire_gap::front::load_bytes;
use tire_gap::method::splitmix::splitmix64;

/// Mutated files per seed file.
const CASES_PER_SEED: usize = 1000;

/// The largest single allocation a reader may ask for: far beyond what the seeds (a few
/// kilobytes) need, far below what a size field taken on trust would ask.
const ALLOCATION_LIMIT: usize = 64 << 20;

/// The longest one case may take (the slowest seed reads in milliseconds).
const CASE_LIMIT: Duration = Duration::from_secs(10);

/// The case being read, for the messages of the allocator and the watchdog.
static CASE: Mutex<String> = Mutex::new(String::new());

/// The largest allocation asked for so far.
static LARGEST: AtomicUsize = AtomicUsize::new(0);

/// The system allocator, refusing (with the case named) any allocation above
/// [`ALLOCATION_LIMIT`].
struct Bounded;

// SAFETY: every request is passed to the system allocator unchanged, or refused with a null
// pointer, which `GlobalAlloc::alloc` allows.
unsafe impl GlobalAlloc for Bounded {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        if layout.size() > ALLOCATION_LIMIT {
            let case = CASE.try_lock().map(|c| c.clone()).unwrap_or_default();
            eprintln!(
                "fuzz_readers: an allocation of {} bytes while reading {case}",
                layout.size()
            );
            return std::ptr::null_mut();
        }
        // SAFETY: the caller's layout, as `GlobalAlloc::alloc` requires it.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `System.alloc` with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Bounded = Bounded;

/// The draws: the crate's SplitMix64 from a fixed state.
struct Draws(u64);

impl Draws {
    fn next(&mut self) -> u64 {
        splitmix64(&mut self.0)
    }

    /// A draw in `0..n` (`n` > 0).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// The text of a small CSV file as the CSV reader takes it: two runs of a slip-angle sweep.
fn csv_seed() -> Vec<u8> {
    let mut text = String::from("run,t_s,vx_mps,fz_N,alpha_deg,kappa,gamma_deg,fy_N,mz_Nm\n");
    for run in 1..=2 {
        for i in 0..12 {
            let alpha = -6.0 + i as f64;
            text += &format!(
                "{run},{:.2},16.7,{},{alpha:.1},0,0,{:.1},{:.2}\n",
                0.1 * i as f64,
                3000 + 1000 * run,
                -900.0 * alpha.clamp(-4.0, 4.0),
                12.0 * (alpha / 3.0).sin()
            );
        }
    }
    text.into_bytes()
}

/// One mutation of `bytes`, described.
fn mutate(bytes: &mut Vec<u8>, draws: &mut Draws, binary: bool) -> String {
    let len = bytes.len().max(1);
    match draws.below(if binary { 7 } else { 8 }) {
        0 => {
            let at = draws.below(len);
            bytes.truncate(at);
            format!("truncated at {at}")
        }
        1 => {
            let at = draws.below(len).min(bytes.len().saturating_sub(1));
            let bit = 1u8 << draws.below(8);
            if let Some(b) = bytes.get_mut(at) {
                *b ^= bit;
            }
            format!("bit {bit:#04x} of byte {at} flipped")
        }
        2 => {
            let at = draws.below(len).min(bytes.len());
            let n = 1 + draws.below(16);
            let end = (at + n).min(bytes.len());
            bytes.drain(at..end);
            format!("bytes {at}..{end} removed")
        }
        3 => {
            let at = draws.below(len).min(bytes.len());
            let end = (at + 1 + draws.below(64)).min(bytes.len());
            let block = bytes[at..end].to_vec();
            bytes.splice(at..at, block);
            format!("bytes {at}..{end} duplicated")
        }
        4 => {
            let at = draws.below(len).min(bytes.len());
            let b = draws.next() as u8;
            bytes.insert(at, b);
            format!("byte {b:#04x} inserted at {at}")
        }
        5 | 6 if binary => {
            // A 32-bit field (MAT-file tags and sizes are 4-byte aligned) set to an extreme.
            let at = 4 * draws.below(len / 4 + 1);
            let value: u32 = [0, 1, 0x7FFF_FFFF, 0xFFFF_FFFF, 0x8000_0000][draws.below(5)];
            for (k, b) in value.to_le_bytes().iter().enumerate() {
                if let Some(x) = bytes.get_mut(at + k) {
                    *x = *b;
                }
            }
            format!("32-bit field at {at} set to {value:#x}")
        }
        5 => {
            // A number replaced.
            let text = String::from_utf8_lossy(bytes).into_owned();
            let numbers: Vec<(usize, usize)> = number_spans(&text);
            if numbers.is_empty() {
                return "no number to replace".into();
            }
            let (a, b) = numbers[draws.below(numbers.len())];
            let with = ["nan", "1e308", "-", "", "inf", "0", "-1e-320", "1,5"][draws.below(8)];
            *bytes = format!("{}{with}{}", &text[..a], &text[b..]).into_bytes();
            format!("number at {a}..{b} replaced by {with:?}")
        }
        _ => {
            // A line duplicated or removed.
            let text = String::from_utf8_lossy(bytes).into_owned();
            let mut lines: Vec<&str> = text.split_inclusive('\n').collect();
            if lines.is_empty() {
                return "no line".into();
            }
            let at = draws.below(lines.len());
            if draws.below(2) == 0 {
                lines.insert(at, lines[at]);
                *bytes = lines.concat().into_bytes();
                format!("line {at} duplicated")
            } else {
                lines.remove(at);
                *bytes = lines.concat().into_bytes();
                format!("line {at} removed")
            }
        }
    }
}

/// The byte spans of the numbers in `text`.
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = None;
    for (i, c) in text.char_indices() {
        let part = c.is_ascii_digit() || c == '.' || c == '-' || c == 'e';
        match (part, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                spans.push((s, i));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        spans.push((s, text.len()));
    }
    spans
}

/// Reads `cases` mutations of the seed `bytes` as a file named `name`; panics name the case.
fn fuzz(name: &str, seed: Vec<u8>, draws: &mut Draws) -> (usize, usize) {
    let binary = name.ends_with(".mat");
    let path = Path::new(name);
    let (mut read, mut refused) = (0, 0);
    // The seed itself must read: the mutations start from a good file.
    assert!(
        load_bytes(path, seed.clone()).is_ok(),
        "the seed {name} does not read"
    );
    for case in 0..CASES_PER_SEED {
        let mut bytes = seed.clone();
        let mut what = Vec::new();
        for _ in 0..1 + draws.below(3) {
            what.push(mutate(&mut bytes, draws, binary));
        }
        let described = format!("{name}, case {case}: {}", what.join("; "));
        *CASE.lock().unwrap() = described.clone();
        let start = Instant::now();
        let outcome = catch_unwind(AssertUnwindSafe(|| load_bytes(path, bytes)));
        let took = start.elapsed();
        match outcome {
            Ok(Ok(_)) => read += 1,
            Ok(Err(e)) => {
                let message = e.to_string();
                assert!(
                    message.contains(name) && message.len() > name.len() + 10,
                    "{described}: an error that does not say where and what: {message}"
                );
                refused += 1;
            }
            Err(_) => panic!("{described}: the reader panicked"),
        }
        assert!(took < CASE_LIMIT, "{described}: took {took:?}");
    }
    (read, refused)
}

#[test]
fn mutated_files_of_every_format_read_or_are_refused_in_words() {
    // A watchdog: a reader that hangs fails the test, naming the case.
    let done = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let watched = done.clone();
    std::thread::spawn(move || {
        let limit = Instant::now() + Duration::from_secs(600);
        while !watched.load(Ordering::Relaxed) {
            if Instant::now() > limit {
                let case = CASE.lock().map(|c| c.clone()).unwrap_or_default();
                eprintln!("fuzz_readers: no end after 600 s, reading {case}");
                std::process::abort();
            }
            std::thread::sleep(Duration::from_millis(200));
        }
    });
    let seeds: Vec<(&str, Vec<u8>)> = vec![
        ("rig.csv", csv_seed()),
        (
            "lateral.tdx",
            std::fs::read(fixture("lateral.tdx")).unwrap(),
        ),
        (
            "B2356run4.dat",
            std::fs::read(fixture("ttc/B2356run4.dat")).unwrap(),
        ),
        (
            "B2356run5.dat",
            std::fs::read(fixture("ttc/B2356run5.dat")).unwrap(),
        ),
        // Compressed variables with the struct channel list.
        (
            "B2356run4.mat",
            std::fs::read(fixture("ttc/B2356run4.mat")).unwrap(),
        ),
        // The same without compression.
        (
            "B2356run7_plain.mat",
            std::fs::read(fixture("ttc/B2356run7_plain.mat")).unwrap(),
        ),
    ];
    let mut draws = Draws(0x5EED_F022);
    for (name, seed) in seeds {
        let (read, refused) = fuzz(name, seed, &mut draws);
        // Both outcomes occur: the mutations reach past the first check of each format.
        assert!(
            read > 0 && refused > 0,
            "{name}: {read} read, {refused} refused"
        );
        eprintln!("{name}: {read} read, {refused} refused");
    }
    done.store(true, Ordering::Relaxed);
    assert!(LARGEST.load(Ordering::Relaxed) <= ALLOCATION_LIMIT);
}
