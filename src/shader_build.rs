//! The GLSL -> SPIR-V step of build.rs, kept in its own file so that a test
//! (tests/shader_build.rs) can drive it on broken sources. Not a module of
//! the library: build.rs and that test include it with `#[path]`.

use std::path::{Path, PathBuf};

use glslang::include::{IncludeHandler, IncludeResult, IncludeType};
use glslang::{
    Compiler, CompilerOptions, ShaderInput, ShaderMessage, ShaderSource, ShaderStage,
    SourceLanguage, SpirvVersion, Target, VulkanVersion,
};

struct Includer {
    /// Folders searched after the including file's own (glsl/common, the
    /// generated interface's).
    dirs: Vec<PathBuf>,
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
        let path = std::iter::once(from.join(header))
            .chain(self.dirs.iter().map(|d| d.join(header)))
            .find(|p| p.is_file())?;
        let data = std::fs::read_to_string(&path).ok()?;
        self.seen.push(path.clone());
        Some(IncludeResult {
            name: path.display().to_string(),
            data,
        })
    }
}

pub fn stage_of(path: &Path) -> Option<(ShaderStage, &'static str)> {
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

/// Compiles GLSL `text` (from `name`, for messages and relative includes)
/// to SPIR-V words; includes not beside the including file are looked up
/// in `dirs`, in order. Returns the words and every file it included, or one
/// line per glslang error: "NAME: ERROR: file:line: message".
pub fn compile(
    name: &Path,
    text: &str,
    dirs: &[&Path],
) -> Result<(Vec<u32>, Vec<PathBuf>), String> {
    let (stage, _) =
        stage_of(name).ok_or_else(|| format!("{}: unknown shader stage", name.display()))?;
    let compiler = Compiler::acquire().ok_or("glslang failed to initialise")?;
    let options = CompilerOptions {
        source_language: SourceLanguage::GLSL,
        target: Target::Vulkan {
            version: VulkanVersion::Vulkan1_3,
            // SPIR-V 1.3: from 1.4 glslang copies structs across layouts with
            // OpCopyLogical, which naga's reader does not take.
            spirv_version: SpirvVersion::SPIRV1_3,
        },
        version_profile: None,
        messages: ShaderMessage::DEFAULT,
    };
    let source = ShaderSource::from(text.to_string());
    let mut includer = Includer {
        dirs: dirs.iter().map(|d| d.to_path_buf()).collect(),
        base: name.parent().unwrap_or(Path::new(".")).to_path_buf(),
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
    match result {
        Ok(words) => Ok((words, includer.seen)),
        Err(e) => Err(format!("{}: {}", name.display(), glslang_message(&e))),
    }
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
