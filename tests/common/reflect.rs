//! Resource-binding reflection of the embedded SPIR-V, so tests can check
//! the Rust descriptor-set layouts against what the shaders declare.
//!
//! naga parses and validates the stages it supports (vertex, fragment,
//! compute) and says which bindings each entry point really uses. For
//! tessellation and geometry stages, which naga's SPIR-V reader does not
//! take, `scan_bindings` reads the decorations directly: a few dozen lines
//! where no crate in our dependency set does it.

use std::collections::BTreeMap;

pub use meadow::gpu::DescriptorKind;
use meadow::shaders::Spirv;

/// One descriptor binding a shader declares.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Binding {
    pub set: u32,
    pub binding: u32,
    pub ty: DescriptorKind,
}

/// Parses and validates a module with naga and returns the bindings its
/// entry point uses, or naga's error as text.
pub fn naga_bindings(spirv: &Spirv) -> Result<Vec<Binding>, String> {
    let (module, info) = naga_module(spirv)?;
    let ep_info = info.get_entry_point(0);
    let mut out = Vec::new();
    for (handle, var) in module.global_variables.iter() {
        let Some(rb) = &var.binding else { continue };
        if ep_info[handle].is_empty() {
            continue;
        }
        let ty = match var.space {
            naga::AddressSpace::Uniform => DescriptorKind::UniformBuffer,
            naga::AddressSpace::Storage { .. } => DescriptorKind::StorageBuffer,
            naga::AddressSpace::Handle => match &module.types[var.ty].inner {
                naga::TypeInner::Sampler { .. } => DescriptorKind::Sampler,
                naga::TypeInner::Image {
                    class: naga::ImageClass::Storage { .. },
                    ..
                } => DescriptorKind::StorageImage,
                naga::TypeInner::Image { .. } => DescriptorKind::SampledImage,
                other => return Err(format!("{}: unexpected handle type {other:?}", spirv.path)),
            },
            other => {
                return Err(format!(
                    "{}: unexpected address space {other:?}",
                    spirv.path
                ))
            }
        };
        out.push(Binding {
            set: rb.group,
            binding: rb.binding,
            ty,
        });
    }
    out.sort();
    Ok(out)
}

/// The naga module and its validation info.
pub fn naga_module(spirv: &Spirv) -> Result<(naga::Module, naga::valid::ModuleInfo), String> {
    let module =
        naga::front::spv::parse_u8_slice(spirv.bytes, &naga::front::spv::Options::default())
            .map_err(|e| format!("{}: naga could not parse the SPIR-V: {e}", spirv.path))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| format!("{}: naga validation failed: {e:?}", spirv.path))?;
    Ok((module, info))
}

/// The global variable bound at (set, binding) in a naga module.
pub fn resource_at(module: &naga::Module, set: u32, binding: u32) -> Option<&naga::GlobalVariable> {
    module.global_variables.iter().map(|(_, v)| v).find(|v| {
        v.binding
            .as_ref()
            .is_some_and(|b| b.group == set && b.binding == binding)
    })
}

/// Member offsets of the struct that backs the uniform block at (set, binding),
/// by member name, from naga's reading of the SPIR-V.
pub fn uniform_block_layout(
    spirv: &Spirv,
    set: u32,
    binding: u32,
) -> Result<(u32, Vec<(String, u32)>), String> {
    let (module, _) = naga_module(spirv)?;
    let var = resource_at(&module, set, binding)
        .ok_or_else(|| format!("{}: no resource at set {set} binding {binding}", spirv.path))?;
    match &module.types[var.ty].inner {
        naga::TypeInner::Struct { members, span } => Ok((
            *span,
            members
                .iter()
                .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                .collect(),
        )),
        other => Err(format!("{}: block is not a struct: {other:?}", spirv.path)),
    }
}

/// Every descriptor binding a SPIR-V module declares, read from its
/// decorations (works for every stage).
pub fn scan_bindings(spirv: &Spirv) -> Result<Vec<Binding>, String> {
    const OP_DECORATE: u32 = 71;
    const OP_VARIABLE: u32 = 59;
    const OP_TYPE_POINTER: u32 = 32;
    const OP_TYPE_IMAGE: u32 = 25;
    const OP_TYPE_SAMPLER: u32 = 26;
    const OP_TYPE_SAMPLED_IMAGE: u32 = 27;
    const OP_TYPE_ARRAY: u32 = 28;
    const OP_TYPE_RUNTIME_ARRAY: u32 = 29;
    const DEC_BUFFER_BLOCK: u32 = 3;
    const DEC_BINDING: u32 = 33;
    const DEC_DESCRIPTOR_SET: u32 = 34;
    const SC_UNIFORM_CONSTANT: u32 = 0;
    const SC_UNIFORM: u32 = 2;
    const SC_STORAGE_BUFFER: u32 = 12;

    let words = spirv.words().map_err(|e| e.to_string())?;
    if words.len() < 5 || words[0] != 0x0723_0203 {
        return Err(format!("{}: not SPIR-V", spirv.path));
    }
    let mut sets = BTreeMap::new();
    let mut bindings = BTreeMap::new();
    let mut buffer_blocks = Vec::new();
    let mut pointers = BTreeMap::new(); // id -> (storage class, pointee)
    let mut types = BTreeMap::new(); // id -> (opcode, operands)
    let mut variables = Vec::new(); // (id, pointer type, storage class)
    let mut i = 5;
    while i < words.len() {
        let count = (words[i] >> 16) as usize;
        let op = words[i] & 0xffff;
        if count == 0 || i + count > words.len() {
            return Err(format!("{}: malformed instruction at word {i}", spirv.path));
        }
        let args = &words[i + 1..i + count];
        match op {
            OP_DECORATE if args.len() >= 2 => match args[1] {
                DEC_DESCRIPTOR_SET if args.len() >= 3 => {
                    sets.insert(args[0], args[2]);
                }
                DEC_BINDING if args.len() >= 3 => {
                    bindings.insert(args[0], args[2]);
                }
                DEC_BUFFER_BLOCK => buffer_blocks.push(args[0]),
                _ => {}
            },
            OP_TYPE_POINTER if args.len() >= 3 => {
                pointers.insert(args[0], (args[1], args[2]));
            }
            OP_TYPE_IMAGE
            | OP_TYPE_SAMPLER
            | OP_TYPE_SAMPLED_IMAGE
            | OP_TYPE_ARRAY
            | OP_TYPE_RUNTIME_ARRAY
                if !args.is_empty() =>
            {
                types.insert(args[0], (op, args[1..].to_vec()));
            }
            OP_VARIABLE if args.len() >= 3 => variables.push((args[1], args[0], args[2])),
            _ => {}
        }
        i += count;
    }

    let mut out = Vec::new();
    for (id, ptr_ty, storage) in variables {
        let (Some(&set), Some(&binding)) = (sets.get(&id), bindings.get(&id)) else {
            continue;
        };
        let mut pointee = pointers.get(&ptr_ty).map(|p| p.1).unwrap_or(0);
        // Arrays of descriptors: look through to the element type.
        while let Some((OP_TYPE_ARRAY | OP_TYPE_RUNTIME_ARRAY, operands)) = types.get(&pointee) {
            pointee = operands[0];
        }
        let ty = match storage {
            SC_UNIFORM if buffer_blocks.contains(&pointee) => DescriptorKind::StorageBuffer,
            SC_UNIFORM => DescriptorKind::UniformBuffer,
            SC_STORAGE_BUFFER => DescriptorKind::StorageBuffer,
            SC_UNIFORM_CONSTANT => match types.get(&pointee) {
                Some((OP_TYPE_SAMPLED_IMAGE, _)) => DescriptorKind::CombinedImageSampler,
                Some((OP_TYPE_SAMPLER, _)) => DescriptorKind::Sampler,
                // OpTypeImage operands after the id: sampled type, dim, depth,
                // arrayed, ms, sampled (1 = sampled, 2 = storage), format.
                Some((OP_TYPE_IMAGE, operands)) if operands.get(5) == Some(&2) => {
                    DescriptorKind::StorageImage
                }
                Some((OP_TYPE_IMAGE, _)) => DescriptorKind::SampledImage,
                other => return Err(format!("{}: unknown resource type {other:?}", spirv.path)),
            },
            other => return Err(format!("{}: binding in storage class {other}", spirv.path)),
        };
        out.push(Binding { set, binding, ty });
    }
    out.sort();
    out.dedup();
    Ok(out)
}
