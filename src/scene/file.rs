//! Scene files: TOML read with serde, then checked. Every error is one line
//! that names the file, the line and column, the field and what is allowed:
//! `my.toml:12:9: grass.meadow[0].count: 0 is not allowed, use 1..=10000000`.

use std::ops::Range;
use std::path::Path;

use toml::de::{DeTable, DeValue};
use toml::Spanned;

use super::check::{self, FieldError};
use super::{Scene, SceneFiles};
use crate::error::{Error, Result};

/// The largest scene file read (a scene is a few kilobytes).
const MAX_FILE_BYTES: u64 = 1 << 20;

/// Reads and checks a scene file.
pub fn load(path: &Path) -> Result<Scene> {
    let io = |source| Error::Io {
        path: path.display().to_string(),
        source,
    };
    let size = std::fs::metadata(path).map_err(io)?.len();
    if size > MAX_FILE_BYTES {
        return Err(Error::InvalidInput(format!(
            "{}: {size} bytes is too large for a scene file (at most {MAX_FILE_BYTES})",
            path.display()
        )));
    }
    let bytes = std::fs::read(path).map_err(io)?;
    let text = String::from_utf8(bytes).map_err(|e| {
        Error::InvalidInput(format!(
            "{}: not UTF-8 text (byte {}); scene files are TOML",
            path.display(),
            e.utf8_error().valid_up_to()
        ))
    })?;
    let dir = path.parent().unwrap_or(Path::new("."));
    parse_in(&text, &path.display().to_string(), SceneFiles::Dir(dir))
}

/// Parses and checks scene text; `origin` names it in errors, and the
/// files it names are read relative to the current folder.
pub fn parse(text: &str, origin: &str) -> Result<Scene> {
    parse_in(text, origin, SceneFiles::Dir(Path::new(".")))
}

/// Parses and checks scene text, reading the files it names (a height
/// map) from `files`; `origin` names it in errors.
pub fn parse_in(text: &str, origin: &str, files: SceneFiles<'_>) -> Result<Scene> {
    let mut scene: Scene = match toml::from_str(text) {
        Ok(s) => s,
        Err(e) => {
            let span = e.span().unwrap_or(0..0);
            // toml's messages can run over lines; keep them to one.
            let message =
                plain_words(&e.message().split_whitespace().collect::<Vec<_>>().join(" "));
            // A missing field is reported at the table that lacks it; at the
            // file's top level that is no field at all.
            let top_level = span.start == 0 && message.starts_with("missing field");
            let path = DeTable::parse(text)
                .ok()
                .filter(|_| !top_level)
                .map(|doc| path_at(&doc, span.start))
                .unwrap_or_default();
            let field = if path.is_empty() {
                String::new()
            } else {
                format!("{path}: ")
            };
            // A duplicate key: name it (the document does not parse, so no
            // path can be found for it).
            let message = match (message.as_str(), text.get(span.clone())) {
                ("duplicate key", Some(key)) if !key.trim().is_empty() => format!(
                    "duplicate key `{}`; write each key once per table",
                    key.trim()
                ),
                _ => message,
            };
            let message = if text.trim().is_empty() {
                format!("{message} (the file is empty; docs/scenes.md has a complete example)")
            } else {
                message
            };
            return Err(Error::InvalidInput(format!(
                "{origin}:{}: {field}{message}",
                line_col(text, span.start)
            )));
        }
    };
    check_lengths(text, &scene).map_err(|e| located(text, origin, e))?;
    scene.grass.fill_defaults();
    check::scene(&scene).map_err(|e| located(text, origin, e))?;
    scene
        .read_files(files)
        .map_err(|e| located(text, origin, e))?;
    if scene.ground.map.is_some() {
        // The height map's ground, now that it is read.
        check::above_ground(&scene).map_err(|e| located(text, origin, e))?;
    }
    Ok(scene)
}

/// Refuses an array of another length than its field holds. serde reads a
/// fixed-size field (`center = [x, z]`) from the first values of a longer
/// array and drops the rest silently; a shorter one it refuses itself. The
/// scene written back as TOML has every array at its field's length, so
/// the file's arrays are compared with it, path by path.
fn check_lengths(text: &str, scene: &Scene) -> std::result::Result<(), FieldError> {
    fn walk(
        raw: &DeValue<'_>,
        read: &toml::Value,
        path: &str,
    ) -> std::result::Result<(), FieldError> {
        match (raw, read) {
            (DeValue::Table(raw), toml::Value::Table(read)) => {
                for (key, value) in raw.iter() {
                    let key: &str = key.get_ref();
                    if let Some(read) = read.get(key) {
                        let path = if path.is_empty() {
                            key.to_string()
                        } else {
                            format!("{path}.{key}")
                        };
                        walk(value.get_ref(), read, &path)?;
                    }
                }
                Ok(())
            }
            (DeValue::Array(raw), toml::Value::Array(read)) => {
                if raw.len() != read.len() {
                    return Err(FieldError::new(
                        path,
                        format!("has {} values, use exactly {}", raw.len(), read.len()),
                    ));
                }
                for (i, (raw, read)) in raw.iter().zip(read).enumerate() {
                    walk(raw.get_ref(), read, &format!("{path}[{i}]"))?;
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }
    let (Ok(doc), Ok(read)) = (DeTable::parse(text), toml::Value::try_from(scene)) else {
        return Ok(());
    };
    walk(&DeValue::Table(doc.into_inner()), &read, "")
}

/// serde's messages name Rust types (`expected usize`); say what a scene
/// author writes instead.
fn plain_words(message: &str) -> String {
    [
        ("expected usize", "expected a whole number, 0 or more"),
        ("expected u64", "expected a whole number, 0 or more"),
        ("expected u32", "expected a whole number, 0 or more"),
        ("expected f32", "expected a number"),
        ("expected f64", "expected a number"),
    ]
    .iter()
    .fold(message.to_string(), |m, (rust, plain)| {
        m.replace(rust, plain)
    })
}

/// A scene as TOML, as `meadow scenes --print` writes it.
pub fn to_toml(scene: &Scene) -> String {
    toml::to_string(scene).expect("a scene always serialises")
}

fn located(text: &str, origin: &str, e: FieldError) -> Error {
    let offset = DeTable::parse(text)
        .map(|doc| span_of(&doc, &e.path).start)
        .unwrap_or(0);
    Error::InvalidInput(format!(
        "{origin}:{}: {}: {}",
        line_col(text, offset),
        if e.path.is_empty() { "scene" } else { &e.path },
        e.message
    ))
}

/// "line:column", both from 1, of a byte offset.
fn line_col(text: &str, offset: usize) -> String {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    format!("{line}:{column}")
}

/// One step of a field path: a key or an array index.
enum Step<'a> {
    Key(&'a str),
    Index(usize),
}

fn steps(path: &str) -> Vec<Step<'_>> {
    let mut out = Vec::new();
    for part in path.split('.').filter(|p| !p.is_empty()) {
        let (key, rest) = part.split_at(part.find('[').unwrap_or(part.len()));
        if !key.is_empty() {
            out.push(Step::Key(key));
        }
        for index in rest.split(['[', ']']).filter(|s| !s.is_empty()) {
            if let Ok(i) = index.parse() {
                out.push(Step::Index(i));
            }
        }
    }
    out
}

/// Where the deepest part of `path` present in the file is written (its
/// key if the value has no span of its own). A field left to its default
/// points at the table that should hold it, or the file's start.
fn span_of(doc: &Spanned<DeTable<'_>>, path: &str) -> Range<usize> {
    let mut best = 0..0;
    let mut value: Option<&Spanned<DeValue<'_>>> = None;
    let mut table = Some(doc.get_ref());
    for step in steps(path) {
        let next = match (step, table, value.map(Spanned::get_ref)) {
            (Step::Key(k), Some(t), _) => {
                t.iter()
                    .find(|(key, _)| key.get_ref() == k)
                    .map(|(key, v)| {
                        best = key.span();
                        v
                    })
            }
            (Step::Index(i), _, Some(DeValue::Array(a))) => a.get(i),
            _ => None,
        };
        let Some(v) = next else { break };
        if !v.span().is_empty() {
            best = v.span();
        }
        value = Some(v);
        table = match v.get_ref() {
            DeValue::Table(t) => Some(t),
            _ => None,
        };
    }
    best
}

/// The path of the innermost key whose key or value holds `offset`. Header
/// tables (`[grass]`) do not span their contents, so every branch is
/// searched, not only those whose span holds the offset.
fn path_at(doc: &Spanned<DeTable<'_>>, offset: usize) -> String {
    fn in_value(value: &DeValue<'_>, offset: usize) -> Option<String> {
        match value {
            DeValue::Table(t) => in_table(t, offset),
            DeValue::Array(a) => a.iter().enumerate().find_map(|(i, v)| {
                let inner = in_value(v.get_ref(), offset);
                if inner.is_none() && !v.span().contains(&offset) {
                    return None;
                }
                let rest = inner.map_or(String::new(), |p| format!(".{p}"));
                Some(format!("[{i}]{rest}"))
            }),
            _ => None,
        }
    }
    fn in_table(table: &DeTable<'_>, offset: usize) -> Option<String> {
        table.iter().find_map(|(key, v)| {
            let inner = in_value(v.get_ref(), offset);
            let here = key.span().contains(&offset) || v.span().contains(&offset);
            match inner {
                Some(p) if p.starts_with('[') => Some(format!("{}{p}", key.get_ref())),
                Some(p) => Some(format!("{}.{p}", key.get_ref())),
                None if here => Some(key.get_ref().to_string()),
                None => None,
            }
        })
    }
    in_table(doc.get_ref(), offset).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column_count_from_one() {
        assert_eq!(line_col("a\nbc\n", 0), "1:1");
        assert_eq!(line_col("a\nbc\n", 3), "2:2");
    }

    #[test]
    fn paths_find_their_spans() {
        let text = "seed = 1\n[grass]\n[[grass.bunch]]\ncount = 3\n[[grass.bunch]]\ncount = 0\n";
        let doc = DeTable::parse(text).unwrap();
        let span = span_of(&doc, "grass.bunch[1].count");
        assert_eq!(line_col(text, span.start), "6:9");
        assert_eq!(path_at(&doc, span.start), "grass.bunch[1].count");
        // A field left out points at its nearest written ancestor.
        let span = span_of(&doc, "grass.bunch[0].radius");
        assert_eq!(&line_col(text, span.start)[..2], "3:");
    }
}
