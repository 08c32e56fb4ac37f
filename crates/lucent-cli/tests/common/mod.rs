//! Helpers shared by the command-line test files: running the `lucent`
//! binary, and checking its exit status and messages.

// Each test file uses its own subset.
#![allow(dead_code)]

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

/// The outcome of one run of the program.
pub struct Run {
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
    pub elapsed: Duration,
}

/// The `lucent` command with `args`, to run in `dir`.
fn command(dir: &Path, args: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_lucent"));
    command
        .args(args)
        .current_dir(dir)
        // With the variable unset a panic prints a note naming it, which the
        // checks below look for.
        .env_remove("RUST_BACKTRACE");
    command
}

fn finished(out: std::process::Output, start: Instant) -> Run {
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        elapsed: start.elapsed(),
    }
}

/// Run `lucent` with `args` in `dir`.
pub fn lucent(dir: &Path, args: &[&str]) -> Run {
    let start = Instant::now();
    finished(command(dir, args).output().expect("the lucent binary runs"), start)
}

/// Start `lucent` with `args` in `dir`, let it run for `after`, then send
/// it `signal` (`INT` as Ctrl-C does, or `TERM`) and wait for it to end.
pub fn lucent_signalled(dir: &Path, args: &[&str], signal: &str, after: Duration) -> Run {
    use std::process::Stdio;
    let start = Instant::now();
    let child = command(dir, args).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("lucent starts");
    std::thread::sleep(after);
    let kill = Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status();
    assert!(kill.is_ok_and(|s| s.success()), "kill -{signal} failed");
    finished(child.wait_with_output().expect("lucent ends"), start)
}

/// Neither output mentions a panic or a backtrace.
#[track_caller]
pub fn assert_no_panic(run: &Run) {
    for bad in ["panicked", "RUST_BACKTRACE", "stack backtrace"] {
        assert!(!run.stderr.contains(bad), "stderr mentions {bad:?}:\n{}", run.stderr);
        assert!(!run.stdout.contains(bad), "stdout mentions {bad:?}:\n{}", run.stdout);
    }
}

/// Exit status 0, no panic.
#[track_caller]
pub fn assert_success(run: &Run) {
    assert_no_panic(run);
    assert_eq!(run.code, Some(0), "exit status; stdout:\n{}\nstderr:\n{}", run.stdout, run.stderr);
}

/// Assert that `run` failed with exit status `code`, a one-screen message
/// starting with `error:`, and every one of `expected` in that message.
#[track_caller]
pub fn assert_fails_with(run: &Run, code: i32, expected: &[&str]) {
    assert_no_panic(run);
    assert_eq!(run.code, Some(code), "exit status; stderr:\n{}", run.stderr);
    assert!(run.stderr.starts_with("error:"), "stderr does not start with `error:`:\n{}", run.stderr);
    let lines = run.stderr.lines().count();
    assert!(lines <= 12, "the message takes {lines} lines:\n{}", run.stderr);
    for want in expected {
        assert!(run.stderr.contains(want), "stderr lacks {want:?}:\n{}", run.stderr);
    }
}

/// A failure other than a command-line parse error (exit status 1), with
/// nothing on stdout.
#[track_caller]
pub fn assert_error(run: &Run, expected: &[&str]) {
    assert_fails_with(run, 1, expected);
    assert!(run.stdout.is_empty(), "stdout on failure:\n{}", run.stdout);
}

/// `text` with `from` (which must occur exactly once) replaced by `to`.
#[track_caller]
pub fn edit(text: &str, from: &str, to: &str) -> String {
    assert_eq!(text.matches(from).count(), 1, "{from:?} should occur once in the fixture");
    text.replace(from, to)
}

/// "LINE:COL" (1-based; columns in characters) of `needle` inside the
/// first occurrence of `context`.
#[track_caller]
pub fn loc_in(text: &str, context: &str, needle: &str) -> String {
    let at = text.find(context).unwrap_or_else(|| panic!("{context:?} not in the fixture"));
    let within = context.find(needle).unwrap_or_else(|| panic!("{needle:?} not in {context:?}"));
    let prefix = &text[..at + within];
    let line = prefix.matches('\n').count() + 1;
    let line_start = prefix.rfind('\n').map_or(0, |i| i + 1);
    format!("{line}:{}", prefix[line_start..].chars().count() + 1)
}
