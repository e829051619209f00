//! The GLSL -> SPIR-V step that build.rs runs: a broken shader is reported
//! with its file, line and glslang's message, and includes resolve.

#[path = "../src/shader_build.rs"]
#[allow(dead_code)]
mod glsl_compile;

use std::path::Path;

#[test]
fn a_glsl_error_names_file_line_and_message() {
    let src = "#version 450\nlayout(location = 0) out vec4 c;\nvoid main() {\n    c = vec4(undeclared_thing);\n}\n";
    let err = glsl_compile::compile(
        Path::new("glsl/blade/broken.frag"),
        src,
        &[Path::new("glsl/common")],
    )
    .unwrap_err();
    assert!(err.starts_with("glsl/blade/broken.frag: ERROR:"), "{err}");
    assert!(err.contains(":4:"), "no line number in: {err}");
    assert!(err.contains("undeclared_thing"), "no message in: {err}");
}

#[test]
fn includes_resolve_against_glsl_common() {
    let src = "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include \"frame.glsl\"\nlayout(location = 0) out vec4 c;\nvoid main() { c = vec4(frame.light_color, 1.0); }\n";
    let common = Path::new(env!("CARGO_MANIFEST_DIR")).join("glsl/common");
    // frame.glsl includes the generated interface.glsl, which build.rs
    // writes under OUT_DIR.
    let generated = Path::new(env!("OUT_DIR")).join("glsl");
    let (words, included) = glsl_compile::compile(
        Path::new("glsl/test/include.frag"),
        src,
        &[&common, &generated],
    )
    .unwrap();
    assert_eq!(words[0], 0x0723_0203, "not SPIR-V");
    assert!(
        included.iter().any(|p| p.ends_with("frame.glsl")),
        "{included:?}"
    );
}
