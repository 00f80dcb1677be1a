//! The task runner's command line: help succeeds, an unknown or missing task fails.

use std::process::{Command, Output};

fn xtask(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn help_prints_the_tasks_and_succeeds() {
    for flag in ["help", "-h", "--help"] {
        let out = xtask(&[flag]);
        assert_eq!(out.status.code(), Some(0), "{flag}");
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(
            text.starts_with("usage: cargo xtask <task>") && text.contains("test-win64"),
            "{flag}: {text}"
        );
    }
}

#[test]
fn an_unknown_or_missing_task_fails_with_the_usage() {
    let out = xtask(&["fmuu"]);
    assert_eq!(out.status.code(), Some(2));
    let text = String::from_utf8(out.stderr).unwrap();
    assert!(
        text.starts_with("unknown task: fmuu\nusage: cargo xtask <task>"),
        "{text}"
    );

    let out = xtask(&[]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8(out.stderr).unwrap().starts_with("usage:"));
}
