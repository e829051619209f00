//! A run's claim on its output folder. meadow replaces only what an
//! earlier meadow run wrote there and nobody has changed since: each run
//! lists what it writes in the folder's manifest (`.meadow-run`: each
//! file's size, modification time and name), and the next run removes
//! exactly those files, after checking each is unchanged. A file it did not
//! write is never touched, whatever its name: a run that would write over
//! one is refused before any work, with the fix (another folder, moving
//! the file, or `--overwrite` to replace it anyway).

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::UNIX_EPOCH;

use crate::error::{Error, Result};
use crate::report::files;

/// The manifest's name in the output folder.
pub const MANIFEST_NAME: &str = ".meadow-run";

/// A file as the manifest remembers it.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Entry {
    size: u64,
    modified_ns: u128,
    name: String,
}

impl Entry {
    /// `dir/name` as it is now, or None if it is not a file.
    fn of(dir: &Path, name: &str) -> Option<Entry> {
        let meta = std::fs::metadata(dir.join(name)).ok()?;
        let modified = meta.modified().ok()?.duration_since(UNIX_EPOCH).ok()?;
        meta.is_file().then(|| Entry {
            size: meta.len(),
            modified_ns: modified.as_nanos(),
            name: name.to_string(),
        })
    }

    fn line(&self) -> String {
        format!("{} {} {}\n", self.size, self.modified_ns, self.name)
    }

    /// A manifest line; None for one that is not (the manifest is the
    /// user's to break: a line meadow cannot read lists nothing).
    fn parse(line: &str) -> Option<Entry> {
        let mut parts = line.splitn(3, ' ');
        let size = parts.next()?.parse().ok()?;
        let modified_ns = parts.next()?.parse().ok()?;
        let name = parts.next()?.to_string();
        // Names in the folder itself, never a path out of it.
        let plain = !name.is_empty() && !name.contains(['/', '\\']) && name != "..";
        plain.then_some(Entry {
            size,
            modified_ns,
            name,
        })
    }
}

/// The folder claimed by a run: checked by `new`, taken by `begin` (the
/// last run's files go), each file recorded by `wrote` as it is done.
#[derive(Debug)]
pub struct OutputClaim {
    dir: PathBuf,
    /// The last run's files, unchanged (or `overwrite`): removed by `begin`.
    remove: Vec<String>,
    /// This run's names: their temporary files, if a crash left any, go too.
    planned: Vec<String>,
}

impl OutputClaim {
    /// Checks `dir` (which exists) for a run that writes the files named
    /// `planned` there, changing nothing: each file the last run's manifest
    /// lists must be as that run left it (it goes at `begin`), and no other
    /// file may have a planned name. A changed file, or a planned name the
    /// manifest does not list, refuses the run before it starts, unless
    /// `overwrite` (then they are replaced, and a changed listed file is
    /// removed too).
    pub fn new(dir: &Path, planned: &[String], overwrite: bool) -> Result<Self> {
        let manifest = dir.join(MANIFEST_NAME);
        let listed: Vec<Entry> = match std::fs::read_to_string(&manifest) {
            Ok(text) => text.lines().filter_map(Entry::parse).collect(),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Vec::new(),
            Err(e) => return Err(Error::io(&manifest, e)),
        };
        // Everything checked before anything is removed: a refusal leaves
        // the folder as it was.
        let mut remove = Vec::new();
        for entry in &listed {
            match Entry::of(dir, &entry.name) {
                Some(now) if now == *entry || overwrite => remove.push(entry.name.clone()),
                Some(_) => {
                    return Err(Error::InvalidInput(format!(
                        "{} changed since meadow wrote it; move it out of {}, choose another --out, or pass --overwrite to replace it",
                        dir.join(&entry.name).display(),
                        dir.display()
                    )))
                }
                None => {}
            }
        }
        for name in planned {
            let ours = remove.contains(name);
            if !ours && !overwrite && dir.join(name).exists() {
                return Err(Error::InvalidInput(format!(
                    "{} is not from an earlier meadow run in this folder and this run would write over it; move it, choose another --out, or pass --overwrite to replace it",
                    dir.join(name).display()
                )));
            }
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            remove,
            planned: planned.to_vec(),
        })
    }

    /// Refuses, before the work, a folder without room for `bytes` more
    /// (what the run writes, at least), counting the room the last run's
    /// files leave when they go; `what` says what needs it.
    pub fn ensure_room(&self, bytes: u64, what: &str) -> Result<()> {
        let freed: u64 = self
            .remove
            .iter()
            .filter_map(|name| std::fs::metadata(self.dir.join(name)).ok())
            .map(|m| m.len())
            .sum();
        files::ensure_space(&self.dir, bytes.saturating_sub(freed), what)
    }

    /// Takes the folder, at the start of the work: the last run's files
    /// go, and this run's list starts empty.
    pub fn begin(&self) -> Result<()> {
        for name in &self.remove {
            let path = self.dir.join(name);
            match std::fs::remove_file(&path) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    return Err(Error::io(&path, e))
                }
                _ => {}
            }
        }
        for name in &self.planned {
            let _ = std::fs::remove_file(super::files::temp_name(&self.dir.join(name)));
        }
        let manifest = self.dir.join(MANIFEST_NAME);
        std::fs::write(&manifest, b"").map_err(|e| Error::io(&manifest, e))
    }

    /// Records `name` (in the folder) as this run wrote it; called once it
    /// is complete, so the manifest never lists a file as ours that a
    /// crash left half-written.
    pub fn wrote(&self, name: &str) -> Result<()> {
        let manifest = self.dir.join(MANIFEST_NAME);
        let Some(entry) = Entry::of(&self.dir, name) else {
            return Ok(());
        };
        std::fs::OpenOptions::new()
            .append(true)
            .create(true)
            .open(&manifest)
            .and_then(|mut f| f.write_all(entry.line().as_bytes()))
            .map_err(|e| Error::io(&manifest, e))
    }

    /// Writes `name` in the folder whole or not at all
    /// (`files::write_atomic`) and records it.
    pub fn write(&self, name: &str, bytes: &[u8]) -> Result<()> {
        super::files::write_atomic(&self.dir.join(name), bytes)?;
        self.wrote(name)
    }

    /// As `write`, `value` as pretty JSON.
    pub fn write_json<T: serde::Serialize>(&self, name: &str, value: &T) -> Result<()> {
        let json = serde_json::to_vec_pretty(value).expect("reports serialise");
        self.write(name, &json)
    }

    /// `path` as a name in the claimed folder, if it lies directly in it.
    pub fn name_in(&self, path: &Path) -> Option<String> {
        name_in_folder(&self.dir, path)
    }
}

/// `path`'s file name if it lies directly in `dir` (a video, say, may be
/// written anywhere).
pub fn name_in_folder(dir: &Path, path: &Path) -> Option<String> {
    let parent = path.parent()?;
    let parent = if parent.as_os_str().is_empty() {
        Path::new(".")
    } else {
        parent
    };
    let same = parent == dir || parent.canonicalize().ok()? == dir.canonicalize().ok()?;
    same.then(|| path.file_name().map(|n| n.to_string_lossy().into_owned()))
        .flatten()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("meadow-claim-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n != MANIFEST_NAME)
            .collect();
        v.sort();
        v
    }

    fn planned(names: &[&str]) -> Vec<String> {
        names.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn a_run_replaces_only_what_the_last_run_wrote() {
        let dir = folder("replace");
        std::fs::write(dir.join("frame_9999.png"), b"the user's").unwrap();
        let claim =
            OutputClaim::new(&dir, &planned(&["frame_0000.png", "frame_0001.png"]), false).unwrap();
        claim.begin().unwrap();
        for name in ["frame_0000.png", "frame_0001.png"] {
            std::fs::write(dir.join(name), b"meadow's").unwrap();
            claim.wrote(name).unwrap();
        }
        // The next run writes one frame: both of the last run's go, the
        // user's file of a frame's name stays.
        let next = OutputClaim::new(&dir, &planned(&["frame_0000.png"]), false).unwrap();
        assert_eq!(names(&dir).len(), 3, "nothing goes before the work");
        next.begin().unwrap();
        assert_eq!(names(&dir), ["frame_9999.png"]);
        assert_eq!(
            std::fs::read(dir.join("frame_9999.png")).unwrap(),
            b"the user's"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_file_not_written_by_meadow_is_never_written_over() {
        let dir = folder("foreign");
        std::fs::write(dir.join("frame_0000.png"), b"the user's").unwrap();
        let refused = OutputClaim::new(&dir, &planned(&["frame_0000.png"]), false).unwrap_err();
        let text = refused.to_string();
        assert!(
            text.contains("frame_0000.png is not from an earlier meadow run"),
            "{text}"
        );
        assert!(text.contains("--overwrite"), "{text}");
        assert_eq!(
            std::fs::read(dir.join("frame_0000.png")).unwrap(),
            b"the user's"
        );
        // --overwrite: replaced on purpose.
        OutputClaim::new(&dir, &planned(&["frame_0000.png"]), true).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_changed_output_is_refused_and_the_folder_left_as_it_was() {
        let dir = folder("changed");
        let claim = OutputClaim::new(&dir, &planned(&["a.png", "b.png"]), false).unwrap();
        claim.begin().unwrap();
        for name in ["a.png", "b.png"] {
            std::fs::write(dir.join(name), b"meadow's").unwrap();
            claim.wrote(name).unwrap();
        }
        std::fs::write(dir.join("b.png"), b"edited by the user").unwrap();
        let text = OutputClaim::new(&dir, &planned(&["a.png"]), false)
            .unwrap_err()
            .to_string();
        assert!(
            text.contains("b.png changed since meadow wrote it"),
            "{text}"
        );
        assert_eq!(names(&dir), ["a.png", "b.png"], "nothing removed");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_manifest_line_names_only_a_file_in_the_folder() {
        assert_eq!(
            Entry::parse("12 34 frame 0.png"),
            Some(Entry {
                size: 12,
                modified_ns: 34,
                name: "frame 0.png".into()
            })
        );
        for bad in [
            "12 34 ../escape.png",
            "12 34 /etc/passwd",
            "x 34 a.png",
            "12 34 ..",
            "",
        ] {
            assert_eq!(Entry::parse(bad), None, "{bad}");
        }
    }
}
