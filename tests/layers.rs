//! The crate's layers hold: each module imports only the layers below it
//! (docs/architecture.md), the simulating and rendering phases do not know
//! each other, and only the Vulkan layer writes `unsafe`. And the test
//! suite's one binary (tests/suite.rs) holds every file of tests/.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Each top-level module and the modules it may reach through `crate::`.
const ALLOWED: &[(&str, &[&str])] = &[
    ("error", &[]),
    ("gpu", &["error"]),
    ("shaders", &["gpu"]),
    ("interface", &[]),
    ("model", &["error", "interface"]),
    ("scene", &["error", "model"]),
    (
        "compute",
        &["error", "gpu", "shaders", "interface", "model", "scene"],
    ),
    (
        "render",
        &["error", "gpu", "shaders", "interface", "model", "scene"],
    ),
    (
        "frame",
        &[
            "error",
            "gpu",
            "interface",
            "model",
            "scene",
            "compute",
            "render",
        ],
    ),
    ("analysis", &["interface"]),
    (
        "report",
        &["error", "gpu", "model", "scene", "frame", "analysis"],
    ),
    (
        "commands",
        &[
            "error",
            "gpu",
            "shaders",
            "interface",
            "model",
            "scene",
            "compute",
            "render",
            "frame",
            "analysis",
            "report",
        ],
    ),
    // The binary's command line (src/cli/): it reaches the library only as
    // `meadow::`, never through `crate::`.
    ("cli", &[]),
];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The text without comments (line and block) and string literals, so a
/// doc comment naming a module or the word unsafe does not count.
fn code_only(text: &str) -> String {
    let mut out = String::new();
    let b = text.as_bytes();
    let mut i = 0;
    while i < b.len() {
        if b[i..].starts_with(b"//") {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if b[i..].starts_with(b"/*") {
            i += 2;
            while i < b.len() && !b[i..].starts_with(b"*/") {
                i += 1;
            }
            i += 2;
        } else if b[i] == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                i += if b[i] == b'\\' { 2 } else { 1 };
            }
            i += 1;
        } else {
            out.push(b[i] as char);
            i += 1;
        }
    }
    out
}

/// Each file under src/ (but lib.rs, main.rs and build helpers), by its
/// top-level module.
fn modules() -> BTreeMap<String, Vec<(PathBuf, String)>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut by_module: BTreeMap<String, Vec<(PathBuf, String)>> = BTreeMap::new();
    for path in files {
        let rel = path.strip_prefix(&src).unwrap();
        let top = rel.iter().next().unwrap().to_string_lossy();
        let top = top.trim_end_matches(".rs").to_string();
        // The crate root, the binary's, and build.rs's own modules.
        let build_only = ["shader_build", "shader_reflect", "interface_build"];
        if ["lib", "main"].contains(&top.as_str()) || build_only.contains(&top.as_str()) {
            continue;
        }
        let code = code_only(&std::fs::read_to_string(&path).unwrap());
        by_module.entry(top).or_default().push((path, code));
    }
    by_module
}

#[test]
fn every_module_imports_only_the_layers_below_it() {
    let modules = modules();
    let allowed: BTreeMap<&str, &[&str]> = ALLOWED.iter().copied().collect();
    let mut wrong = Vec::new();
    for (module, files) in &modules {
        let Some(may) = allowed.get(module.as_str()) else {
            panic!("module {module} has no layer in this test's table");
        };
        for (path, code) in files {
            for (at, _) in code.match_indices("crate::") {
                let mut used: String = code[at + 7..]
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                // The crate root re-exports the error module's two names.
                if used == "Error" || used == "Result" {
                    used = "error".into();
                }
                if used != *module && !may.contains(&used.as_str()) {
                    wrong.push(format!("{} uses crate::{used}", path.display()));
                }
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "imports across layers:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn only_the_vulkan_layer_writes_unsafe() {
    let mut wrong = Vec::new();
    for (module, files) in modules() {
        for (path, code) in files {
            if module != "gpu" && code.contains("unsafe") {
                wrong.push(path.display().to_string());
            }
        }
    }
    assert!(wrong.is_empty(), "unsafe outside src/gpu: {wrong:?}");
}

/// The table itself: the simulating and rendering phases are siblings.
#[test]
fn the_two_phases_do_not_know_each_other() {
    let allowed: BTreeMap<&str, &[&str]> = ALLOWED.iter().copied().collect();
    assert!(!allowed["compute"].contains(&"render"));
    assert!(!allowed["render"].contains(&"compute"));
    assert!(!allowed["gpu"].iter().any(|m| *m != "error"));
}

/// Cargo builds only tests/suite.rs (`autotests = false`): a file of
/// tests/ that it does not name would never compile or run, silently.
#[test]
fn the_suite_names_every_file_of_tests() {
    let tests = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let suite = std::fs::read_to_string(tests.join("suite.rs")).unwrap();
    let named: Vec<&str> = suite
        .lines()
        .filter_map(|l| l.strip_prefix("mod ")?.strip_suffix(';'))
        .collect();
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(&tests).unwrap() {
        let path = entry.unwrap().path();
        let Some(stem) = path.file_stem().and_then(|s| s.to_str()) else {
            continue;
        };
        if path.extension().is_some_and(|e| e == "rs") && stem != "suite" && !named.contains(&stem)
        {
            missing.push(stem.to_string());
        }
    }
    assert!(
        missing.is_empty(),
        "tests/suite.rs does not name tests/{{{}}}.rs: add `mod NAME;` for each",
        missing.join(",")
    );
    assert!(named.len() > 30, "the suite's modules: {named:?}");
}
