//! Compiles every GLSL file under `glsl/` to SPIR-V with glslang, ahead of time.
//!
//! The stage comes from the extension (.vert .tesc .tese .geom .frag .comp).
//! `#include "x.glsl"` resolves against the including file's folder, then
//! `glsl/common/`, then the generated `interface.glsl` (src/interface/defs.rs,
//! written as GLSL by src/interface_build.rs). The SPIR-V lands in OUT_DIR and `shaders.rs` there embeds
//! it, so the binary needs no shader files at run time; with each compute
//! kernel, the bindings it uses and how (src/shader_reflect.rs). A GLSL error fails
//! the build with the file, line and glslang's message.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[path = "src/shader_build.rs"]
mod glsl_compile;

#[path = "src/shader_reflect.rs"]
mod shader_reflect;

#[macro_use]
#[path = "src/interface_build.rs"]
mod interface_build;

/// src/interface/defs.rs as the build reads it: its items, recorded.
fn interface_items() -> Vec<interface_build::Item> {
    let mut items = Vec::new();
    macro_rules! gpu_interface {
        ($($t:tt)*) => { gpu_interface_record! { items; $($t)* } };
    }
    include!("src/interface/defs.rs");
    items
}

/// Writes the interface's GLSL into `dir` and its Rust layout checks into
/// OUT_DIR.
fn write_interface(dir: &Path, out_dir: &Path) {
    println!("cargo:rerun-if-changed=src/interface/defs.rs");
    println!("cargo:rerun-if-changed=src/interface_build.rs");
    let generated = interface_build::generate(&interface_items())
        .unwrap_or_else(|e| panic!("src/interface/defs.rs: {e}"));
    std::fs::create_dir_all(dir).expect("make the generated GLSL folder");
    std::fs::write(dir.join("interface.glsl"), generated.glsl).expect("write interface.glsl");
    std::fs::write(out_dir.join("interface_layout.rs"), generated.rust)
        .expect("write interface_layout.rs");
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            collect(&path, out);
        } else if glsl_compile::stage_of(&path).is_some() {
            out.push(path);
        }
    }
}

/// MEADOW_COMMIT: the commit this build is of (`meadow gpu-report` names
/// it), "unknown" outside a git checkout. Rebuilt when HEAD or a branch
/// moves; uncommitted changes are not seen (the report's reader is told to
/// build from a committed tree).
fn commit(root: &Path) {
    let git = root.join(".git");
    for watched in ["HEAD", "refs/heads", "packed-refs"] {
        let path = git.join(watched);
        if path.exists() {
            println!("cargo:rerun-if-changed={}", path.display());
        }
    }
    let sha = std::process::Command::new("git")
        .args(["rev-parse", "HEAD"])
        .current_dir(root)
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=MEADOW_COMMIT={sha}");
}

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap());
    let glsl = root.join("glsl");
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    println!("cargo:rerun-if-changed=glsl");
    commit(&root);
    let generated_glsl = out_dir.join("glsl");
    write_interface(&generated_glsl, &out_dir);

    let mut files = Vec::new();
    collect(&glsl, &mut files);

    let mut table = String::from(
        "/// Every shader of `glsl/`, compiled by build.rs: (path under glsl/, stage, SPIR-V bytes).\n\
         pub static ALL: &[Spirv] = &[\n",
    );
    let mut consts = String::new();
    let mut failures = Vec::new();

    for path in &files {
        let rel = path.strip_prefix(&glsl).unwrap();
        let rel_str = rel.to_string_lossy().replace('\\', "/");
        let (_, stage_name) = glsl_compile::stage_of(path).unwrap();
        println!("cargo:rerun-if-changed={}", path.display());
        let text = std::fs::read_to_string(path).expect("read shader");
        let (words, included) = match glsl_compile::compile(
            &Path::new("glsl").join(rel),
            &text,
            &[&glsl.join("common"), &generated_glsl],
        ) {
            Ok(ok) => ok,
            Err(message) => {
                failures.push(message);
                continue;
            }
        };
        for p in &included {
            println!("cargo:rerun-if-changed={}", p.display());
        }
        let spv_path = out_dir.join(format!("{}.spv", rel_str.replace('/', "__")));
        let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        // A kernel's bindings and what it does to each, reflected.
        let bindings = if stage_name == "Compute" {
            match shader_reflect::kernel_bindings(&rel_str, &bytes) {
                Ok(b) => format!("Some({b})"),
                Err(message) => {
                    failures.push(message);
                    continue;
                }
            }
        } else {
            "None".to_string()
        };
        std::fs::write(&spv_path, bytes).expect("write SPIR-V");

        let ident = rel_str.to_uppercase().replace(['/', '.', '-'], "_");
        writeln!(
            consts,
            "pub static {ident}: Spirv = Spirv {{ path: \"{rel_str}\", stage: ShaderStage::{stage_name}, bytes: include_bytes!(r\"{}\"), bindings: {bindings} }};",
            spv_path.display()
        )
        .unwrap();
        writeln!(table, "    {ident},").unwrap();
    }

    if !failures.is_empty() {
        for f in &failures {
            eprintln!("{f}");
        }
        panic!("GLSL compilation failed:\n{}", failures.join("\n"));
    }
    table.push_str("];\n");
    std::fs::write(out_dir.join("shaders.rs"), consts + &table).expect("write shaders.rs");
}
