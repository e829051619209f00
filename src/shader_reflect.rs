//! What each compute kernel binds and how, for build.rs: naga reads the
//! SPIR-V glslang made and says which of its globals the entry point
//! loads and stores (its validator's account, function calls included).
//! build.rs writes the answer into shaders.rs as the kernel's `bindings`
//! (`gpu::shader::ShaderBinding`), from which a pass declares its uses
//! (`Spirv::buffer_uses`) and lays out its set (`gpu::kernels_set`).

use naga::valid::{Capabilities, GlobalUse, ValidationFlags, Validator};

/// The kernel's bindings as a Rust expression of `&[ShaderBinding]`, or
/// why naga could not read them.
pub fn kernel_bindings(path: &str, bytes: &[u8]) -> Result<String, String> {
    let module = naga::front::spv::parse_u8_slice(bytes, &naga::front::spv::Options::default())
        .map_err(|e| format!("{path}: naga could not read the SPIR-V: {e}"))?;
    let info = Validator::new(ValidationFlags::all(), Capabilities::all())
        .validate(&module)
        .map_err(|e| format!("{path}: naga's validation failed: {e:?}"))?;
    let uses = info.get_entry_point(0);
    let mut found = Vec::new();
    for (handle, var) in module.global_variables.iter() {
        let Some(at) = &var.binding else { continue };
        let used = uses[handle];
        if used.is_empty() {
            continue;
        }
        let kind = match var.space {
            naga::AddressSpace::Uniform => "UniformBuffer",
            naga::AddressSpace::Storage { .. } => "StorageBuffer",
            naga::AddressSpace::Handle => match &module.types[var.ty].inner {
                naga::TypeInner::Sampler { .. } => "Sampler",
                naga::TypeInner::Image {
                    class: naga::ImageClass::Storage { .. },
                    ..
                } => "StorageImage",
                naga::TypeInner::Image { .. } => "SampledImage",
                other => return Err(format!("{path}: a binding of type {other:?}")),
            },
            other => return Err(format!("{path}: a binding in {other:?}")),
        };
        // An atomic operation reads and writes.
        let read = used.intersects(GlobalUse::READ | GlobalUse::ATOMIC);
        let write = used.intersects(GlobalUse::WRITE | GlobalUse::ATOMIC);
        let access = match (read, write) {
            (true, true) => "ReadWrite",
            (true, false) => "Read",
            (false, true) => "Write",
            (false, false) => "Size",
        };
        found.push((at.group, at.binding, kind, access));
    }
    found.sort();
    let items: Vec<String> = found
        .iter()
        .map(|(set, binding, kind, access)| {
            format!(
                "ShaderBinding {{ set: {set}, binding: {binding}, kind: DescriptorKind::{kind}, access: BindingAccess::{access} }}"
            )
        })
        .collect();
    Ok(format!("&[{}]", items.join(", ")))
}
