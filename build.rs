//! Compiles every GLSL file under `glsl/` to SPIR-V with glslang, ahead of time.
//!
//! The stage comes from the extension (.vert .tesc .tese .geom .frag .comp).
//! `#include "x.glsl"` resolves against the including file's folder, then
//! `glsl/common/`. The SPIR-V lands in OUT_DIR and `shaders.rs` there embeds
//! it, so the binary needs no shader files at run time. A GLSL error fails
//! the build with the file, line and glslang's message.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glslang::include::{IncludeHandler, IncludeResult, IncludeType};
use glslang::{
    Compiler, CompilerOptions, ShaderInput, ShaderMessage, ShaderSource, ShaderStage,
    SourceLanguage, SpirvVersion, Target, VulkanVersion,
};

struct Includer {
    common: PathBuf,
    /// The folder of the file being compiled: includes are looked up there first.
    base: PathBuf,
    /// Every file pulled in, so that cargo rebuilds when one changes.
    seen: Vec<PathBuf>,
}

impl IncludeHandler for Includer {
    fn include(
        &mut self,
        _ty: IncludeType,
        header: &str,
        includer: &str,
        _depth: usize,
    ) -> Option<IncludeResult> {
        let from = Path::new(includer)
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .map(Path::to_path_buf)
            .unwrap_or_else(|| self.base.clone());
        let path = [from.join(header), self.common.join(header)]
            .into_iter()
            .find(|p| p.is_file())?;
        let data = std::fs::read_to_string(&path).ok()?;
        self.seen.push(path.clone());
        Some(IncludeResult {
            name: path.display().to_string(),
            data,
        })
    }
}

fn stage_of(path: &Path) -> Option<(ShaderStage, &'static str)> {
    Some(match path.extension()?.to_str()? {
        "vert" => (ShaderStage::Vertex, "Vertex"),
        "tesc" => (ShaderStage::TesselationControl, "TessellationControl"),
        "tese" => (ShaderStage::TesselationEvaluation, "TessellationEvaluation"),
        "geom" => (ShaderStage::Geometry, "Geometry"),
        "frag" => (ShaderStage::Fragment, "Fragment"),
        "comp" => (ShaderStage::Compute, "Compute"),
        _ => return None,
    })
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
        } else if stage_of(&path).is_some() {
            out.push(path);
        }
    }
}

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap());
    let glsl = root.join("glsl");
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    println!("cargo:rerun-if-changed=glsl");

    let mut files = Vec::new();
    collect(&glsl, &mut files);

    let compiler = Compiler::acquire().expect("glslang failed to initialise");
    let options = CompilerOptions {
        source_language: SourceLanguage::GLSL,
        target: Target::Vulkan {
            version: VulkanVersion::Vulkan1_3,
            spirv_version: SpirvVersion::SPIRV1_6,
        },
        version_profile: None,
        messages: ShaderMessage::DEFAULT,
    };

    let mut table = String::from(
        "/// Every shader of `glsl/`, compiled by build.rs: (path under glsl/, stage, SPIR-V bytes).\n\
         pub static ALL: &[Spirv] = &[\n",
    );
    let mut consts = String::new();
    let mut failures = Vec::new();

    for path in &files {
        let rel = path.strip_prefix(&glsl).unwrap();
        let rel_str = rel.to_string_lossy().replace('\\', "/");
        let (stage, stage_name) = stage_of(path).unwrap();
        println!("cargo:rerun-if-changed={}", path.display());
        let text = std::fs::read_to_string(path).expect("read shader");
        let source = ShaderSource::from(text);
        let mut includer = Includer {
            common: glsl.join("common"),
            base: path.parent().unwrap().to_path_buf(),
            seen: Vec::new(),
        };
        let result = ShaderInput::new(
            &source,
            stage,
            &options,
            None::<&[(&str, Option<&str>)]>,
            Some(&mut includer),
        )
        .and_then(|input| compiler.create_shader(input))
        .and_then(|shader| shader.compile());
        let words = match result {
            Ok(words) => words,
            Err(e) => {
                failures.push(format!("glsl/{rel_str}: {}", glslang_message(&e)));
                continue;
            }
        };
        for p in &includer.seen {
            println!("cargo:rerun-if-changed={}", p.display());
        }
        let spv_path = out_dir.join(format!("{}.spv", rel_str.replace('/', "__")));
        let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        std::fs::write(&spv_path, bytes).expect("write SPIR-V");

        let ident = rel_str.to_uppercase().replace(['/', '.', '-'], "_");
        writeln!(
            consts,
            "pub static {ident}: Spirv = Spirv {{ path: \"{rel_str}\", stage: ShaderStage::{stage_name}, bytes: include_bytes!(r\"{}\") }};",
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

/// glslang's log, with its "ERROR: file:line: message" lines first and the
/// summary noise dropped.
fn glslang_message(e: &glslang::error::GlslangError) -> String {
    use glslang::error::GlslangError as G;
    let log = match e {
        G::PreprocessError(l) | G::ParseError(l) | G::MapIoError(l) | G::LinkError(l) => {
            l.log.clone()
        }
        other => other.to_string(),
    };
    let lines: Vec<&str> = log
        .lines()
        .filter(|l| l.starts_with("ERROR:") && !l.contains("compilation terminated"))
        .collect();
    if lines.is_empty() {
        log
    } else {
        lines.join("\n    ")
    }
}
