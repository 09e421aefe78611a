//! Golden diagnostics: each `tests/diagnostics/<case>.toml` is a scene
//! with one mistake (and, for a routine's, its `<case>.st`);
//! `<case>.stderr` is the whole message `twin check <case>.toml` prints —
//! the first line, the source line with its caret, the help and notes —
//! as plain text (stderr is not a terminal). An error exits with 65, a
//! warning (the scene loads) with 0.
//!
//! `UPDATE_DIAGNOSTICS=1 cargo test -p twin --test diagnostics` rewrites
//! the `.stderr` files (never under `CI`); review the diff.

use std::path::{Path, PathBuf};
use std::process::Command;

fn cases_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/diagnostics")
}

/// Every case's name, sorted.
fn cases() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(cases_dir())
        .expect("tests/diagnostics")
        .filter_map(|e| {
            let path = e.expect("entry").path();
            (path.extension()? == "toml").then(|| path.file_stem()?.to_str().map(str::to_owned))?
        })
        .collect();
    names.sort();
    names
}

/// `twin check <case>.toml` run in the cases' folder: exit code, stdout,
/// stderr.
fn check(case: &str) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_twin"))
        .current_dir(cases_dir())
        .args(["check", &format!("{case}.toml")])
        .env("NO_COLOR", "1")
        .output()
        .expect("run twin");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn every_case_prints_its_golden_message() {
    let names = cases();
    assert!(names.len() >= 20, "{} cases", names.len());
    let update = std::env::var_os("UPDATE_DIAGNOSTICS").is_some() && std::env::var_os("CI").is_none();
    let mut differ = Vec::new();
    for name in &names {
        let (code, stdout, stderr) = check(name);
        let golden = cases_dir().join(format!("{name}.stderr"));
        if update {
            std::fs::write(&golden, &stderr).expect("write golden");
        }
        let expected = std::fs::read_to_string(&golden).unwrap_or_default();
        if stderr != expected {
            differ.push(format!("{name}:\n--- expected\n{expected}--- got\n{stderr}"));
            continue;
        }
        if stderr.starts_with("warning: ") {
            assert_eq!(code, Some(0), "{name}: a warning does not stop the scene");
            assert!(stdout.contains(": ok ("), "{name}: {stdout}");
        } else {
            assert!(stderr.starts_with("error: "), "{name}: {stderr}");
            assert_eq!(code, Some(65), "{name}: invalid input");
        }
    }
    assert!(
        differ.is_empty(),
        "{} of {} diagnostics differ from their golden text (UPDATE_DIAGNOSTICS=1 to rewrite):\n{}",
        differ.len(),
        names.len(),
        differ.join("\n")
    );
}

#[test]
fn every_rendered_message_keeps_the_one_line_form_first_and_shows_its_line() {
    for name in cases() {
        let (_, _, stderr) = check(&name);
        let mut lines = stderr.lines();
        let first = lines.next().unwrap_or_default();
        // `error: FILE:LINE:COLUMN: …`: what scripts grep.
        let rest = first
            .strip_prefix("error: ")
            .or_else(|| first.strip_prefix("warning: "))
            .unwrap_or_else(|| panic!("{name}: {first}"));
        let mut parts = rest.splitn(4, ':');
        let (file, line, column) = (parts.next(), parts.next(), parts.next());
        assert!(
            file.is_some_and(|f| f.ends_with(".toml") || f.ends_with(".st")),
            "{name}: {first}"
        );
        let line: usize = line
            .and_then(|l| l.parse().ok())
            .unwrap_or_else(|| panic!("{name}: {first}"));
        assert!(
            column.and_then(|c| c.parse::<usize>().ok()).is_some(),
            "{name}: {first}"
        );
        // The arrow names the same place, and the caret line follows.
        let arrow = lines.next().unwrap_or_default();
        assert!(arrow.trim_start().starts_with("--> "), "{name}: {arrow}");
        assert!(
            stderr.contains(&format!("{line} | ")),
            "{name}: the source line is shown"
        );
        assert!(stderr.contains('^'), "{name}: a caret under the place");
        assert!(!stderr.contains('\x1b'), "{name}: plain text");
    }
}
