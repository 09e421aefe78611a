//! `twin import SCENE -o OUT.toml`: the standalone scene a scene naming a
//! Studio 5000 export stands for, and its routine files.
//!
//! The scene text is the expanded scene the loader validates
//! (`twin::scene::import`), so the written scene runs as the scene naming
//! the export does. Written for people: the lines the bindings left blank
//! are dropped, and the paths the scene file gives (`urdf`, mesh `file`s)
//! are rewritten relative to OUT's folder. Nothing depends on the clock or
//! on map order, so importing twice writes the same bytes.

use std::path::{Component, Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context as _, Result, bail};
use toml::de::{DeTable, DeValue};

use crate::run::Refused;

#[derive(Debug, clap::Args)]
pub struct ImportArgs {
    /// A scene naming an export (`[controller] l5x`).
    scene: PathBuf,
    /// The standalone scene to write; its routines go to `routines/` beside it.
    #[arg(short, long, value_name = "OUT.toml")]
    output: PathBuf,
}

pub fn import(args: &ImportArgs) -> Result<ExitCode> {
    // The whole scene is checked, program included, before anything is written.
    let twin = crate::load(&args.scene)?;
    let scene = twin.scene();
    let Some(l5x) = &scene.l5x else {
        return Err(Refused(format!(
            "{} names no Studio 5000 export ([controller] l5x = \"…\")",
            args.scene.display()
        ))
        .into());
    };
    for input in [&args.scene, &l5x.path] {
        if same_file(&args.output, input) {
            return Err(Refused(format!(
                "-o {} would overwrite the input {}",
                args.output.display(),
                input.display()
            ))
            .into());
        }
    }
    let scene_dir = args.scene.parent().unwrap_or_else(|| Path::new(""));
    let out_dir = args.output.parent().unwrap_or_else(|| Path::new(""));
    let text = rewrite_paths(&l5x.expanded, scene_dir, out_dir)?;
    let text = tidy(&text);
    if !out_dir.as_os_str().is_empty() {
        std::fs::create_dir_all(out_dir).with_context(|| format!("cannot create {}", out_dir.display()))?;
    }
    for (rel, routine) in &l5x.routines {
        let path = out_dir.join(rel);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        }
        std::fs::write(&path, routine.as_bytes()).with_context(|| format!("cannot write {}", path.display()))?;
    }
    std::fs::write(&args.output, text).with_context(|| format!("cannot write {}", args.output.display()))?;
    let aois = l5x.routines.iter().filter(|(rel, _)| rel.starts_with("aoi")).count();
    let routines = l5x.routines.len() - aois;
    let aoi_text = if aois == 0 {
        String::new()
    } else {
        format!(
            " and {aois} Add-On Instruction exports under {}",
            out_dir.join("aoi").display()
        )
    };
    outln!(
        "{}: written, with {routines} routines under {}{aoi_text}",
        args.output.display(),
        out_dir.join("routines").display()
    );
    Ok(ExitCode::SUCCESS)
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// The scene's `urdf` and `file` paths, relative to `out_dir` instead of
/// `scene_dir`.
fn rewrite_paths(text: &str, scene_dir: &Path, out_dir: &Path) -> Result<String> {
    let doc = match DeTable::parse(text) {
        Ok(d) => d,
        Err(e) => bail!("the expanded scene does not parse: {e}"),
    };
    let mut edits: Vec<(std::ops::Range<usize>, String)> = Vec::new();
    collect(doc.get_ref(), &mut |key, value, span| {
        if matches!(key, "urdf" | "file") {
            let absolute = scene_dir.join(value);
            let new = relative(&absolute, out_dir);
            edits.push((span, toml_string(&new.to_string_lossy().replace('\\', "/"))));
        }
    });
    edits.sort_by_key(|(r, _)| r.start);
    let mut out = String::with_capacity(text.len());
    let mut at = 0;
    for (r, new) in edits {
        out.push_str(&text[at..r.start]);
        out.push_str(&new);
        at = r.end;
    }
    out.push_str(&text[at..]);
    Ok(out)
}

fn collect(t: &DeTable<'_>, f: &mut dyn FnMut(&str, &str, std::ops::Range<usize>)) {
    for (k, v) in t.iter() {
        match v.get_ref() {
            DeValue::String(s) => f(k.get_ref(), s, v.span()),
            DeValue::Table(t) => collect(t, f),
            DeValue::Array(a) => {
                for e in a.iter() {
                    if let DeValue::Table(t) = e.get_ref() {
                        collect(t, f);
                    }
                }
            }
            _ => {}
        }
    }
}

/// `path` relative to folder `from` (both as given, made absolute against
/// the working folder).
fn relative(path: &Path, from: &Path) -> PathBuf {
    let cwd = std::env::current_dir().unwrap_or_default();
    let abs_path = lexical(&cwd.join(path));
    let abs_from = lexical(&cwd.join(from));
    let a: Vec<Component<'_>> = abs_path.components().collect();
    let b: Vec<Component<'_>> = abs_from.components().collect();
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &a[common..] {
        out.push(c.as_os_str());
    }
    out
}

/// `..` and `.` resolved without touching the file system.
fn lexical(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other.as_os_str()),
        }
    }
    out
}

fn toml_string(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// The lines the bindings left blank dropped: white space only lines
/// become empty, and no more than one empty line in a row is kept.
fn tidy(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut empty = 0;
    for line in text.lines() {
        let line = line.trim_end();
        if line.is_empty() {
            empty += 1;
            if empty > 1 {
                continue;
            }
        } else {
            empty = 0;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{relative, tidy};
    use std::path::Path;

    #[test]
    fn paths_become_relative_to_the_output_folder() {
        assert_eq!(
            relative(Path::new("scenes/robots/a.urdf"), Path::new("out")),
            Path::new("../scenes/robots/a.urdf")
        );
        assert_eq!(
            relative(Path::new("scenes/l5x/../robots/a.urdf"), Path::new("scenes")),
            Path::new("robots/a.urdf")
        );
    }

    #[test]
    fn blank_runs_collapse_to_one_empty_line() {
        assert_eq!(tidy("a\n   \n\n  \nb  \n"), "a\n\nb\n");
    }
}
