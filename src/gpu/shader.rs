//! Shader modules from SPIR-V embedded in the binary (`crate::shaders`
//! holds meadow's, compiled by build.rs).

use ash::vk;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::owned::Owned;
use crate::gpu::{Access, Bound, BufferUse, DescriptorKind, Gpu, ImageUse, LayoutBinding};

/// The pipeline stage a GLSL file is compiled for (from its extension).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShaderStage {
    Vertex,
    TessellationControl,
    TessellationEvaluation,
    Geometry,
    Fragment,
    Compute,
}

impl ShaderStage {
    pub fn vk(self) -> vk::ShaderStageFlags {
        match self {
            ShaderStage::Vertex => vk::ShaderStageFlags::VERTEX,
            ShaderStage::TessellationControl => vk::ShaderStageFlags::TESSELLATION_CONTROL,
            ShaderStage::TessellationEvaluation => vk::ShaderStageFlags::TESSELLATION_EVALUATION,
            ShaderStage::Geometry => vk::ShaderStageFlags::GEOMETRY,
            ShaderStage::Fragment => vk::ShaderStageFlags::FRAGMENT,
            ShaderStage::Compute => vk::ShaderStageFlags::COMPUTE,
        }
    }

    /// naga's SPIR-V front end reads these stages; the reflection tests
    /// read the others' decorations directly.
    pub fn naga_supported(self) -> bool {
        matches!(
            self,
            ShaderStage::Vertex | ShaderStage::Fragment | ShaderStage::Compute
        )
    }
}

/// What a kernel does to the data behind a binding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BindingAccess {
    Read,
    Write,
    ReadWrite,
    /// Only its size is asked (an array's `length()`): no data touched.
    Size,
}

/// One binding a kernel uses, and how: what build.rs read from its SPIR-V
/// (naga's account of what the entry point loads and stores).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShaderBinding {
    pub set: u32,
    pub binding: u32,
    pub kind: DescriptorKind,
    pub access: BindingAccess,
}

/// One embedded SPIR-V module.
#[derive(Clone, Copy, Debug)]
pub struct Spirv {
    /// Path under `glsl/`, e.g. "blade/blade.tesc".
    pub path: &'static str,
    pub stage: ShaderStage,
    pub bytes: &'static [u8],
    /// Every binding a compute kernel uses and how, in binding order; None
    /// for the graphics stages, whose bindings the passes declare by hand
    /// (naga's SPIR-V reader takes no tessellation or geometry stage).
    pub bindings: Option<&'static [ShaderBinding]>,
}

impl Spirv {
    /// The bindings build.rs reflected; panics for a stage without them
    /// (a graphics stage: a fault of the pass that asks).
    fn reflected(&self) -> &'static [ShaderBinding] {
        self.bindings
            .unwrap_or_else(|| panic!("{}: no reflected bindings", self.path))
    }

    /// What one dispatch of this kernel does to the buffers bound in
    /// `set` (`bound[b]` at binding b), from its reflected accesses: the
    /// uses a recording derives its barriers from. A binding of which only
    /// the size is asked is no use of its data.
    ///
    /// The images it samples are `image_uses`'.
    ///
    /// Panics for a shader without reflected bindings, or a buffer binding
    /// past `bound` or bound to an image: a fault of the pass that binds
    /// it, as the descriptor set's own check would report.
    pub fn buffer_uses(&self, set: u32, bound: &[Bound]) -> Vec<BufferUse> {
        self.reflected()
            .iter()
            .filter(|b| b.set == set && !is_image(b.kind))
            .filter_map(|b| {
                let access = match b.access {
                    BindingAccess::Read if b.kind == DescriptorKind::UniformBuffer => {
                        Access::COMPUTE_UNIFORM_READ
                    }
                    BindingAccess::Read => Access::COMPUTE_READ,
                    BindingAccess::Write => Access::COMPUTE_WRITE,
                    BindingAccess::ReadWrite => Access::COMPUTE_READ_WRITE,
                    BindingAccess::Size => return None,
                };
                let buffer = match bound.get(b.binding as usize) {
                    Some(Bound::Buffer(buffer)) | Some(Bound::Part { buffer, .. }) => *buffer,
                    _ => panic!("{}: binding {} is bound to no buffer", self.path, b.binding),
                };
                Some(BufferUse::new(buffer, access))
            })
            .collect()
    }

    /// What one dispatch of this kernel does to the images bound in `set`
    /// (`bound[b]` at binding b): each it samples, read by compute in the
    /// shader-read-only layout.
    ///
    /// Panics as `buffer_uses` does, and for a storage image (no kernel
    /// writes one: its access would need a layout of its own).
    pub fn image_uses<'a>(&self, set: u32, bound: &[Bound<'a>]) -> Vec<ImageUse<'a>> {
        self.reflected()
            .iter()
            .filter(|b| b.set == set && is_image(b.kind))
            .map(|b| {
                assert!(
                    b.kind != DescriptorKind::StorageImage,
                    "{}: binding {} is a storage image, which no pass declares",
                    self.path,
                    b.binding
                );
                match bound.get(b.binding as usize) {
                    Some(Bound::Image(image)) => ImageUse::new(image, Access::COMPUTE_SAMPLED),
                    _ => panic!("{}: binding {} is bound to no image", self.path, b.binding),
                }
            })
            .collect()
    }
}

fn is_image(kind: DescriptorKind) -> bool {
    matches!(
        kind,
        DescriptorKind::SampledImage
            | DescriptorKind::StorageImage
            | DescriptorKind::CombinedImageSampler
    )
}

/// The layout of set `set` that `kernels` share: every binding any of them
/// uses, of the kind it is, visible to compute. Panics for a shader
/// without reflected bindings, or two kernels that disagree on a
/// binding's kind (a fault of the GLSL, which build.rs compiled as given).
pub fn kernels_set(kernels: &[&Spirv], set: u32) -> Vec<LayoutBinding> {
    let mut layout: Vec<LayoutBinding> = Vec::new();
    for kernel in kernels {
        for b in kernel.reflected().iter().filter(|b| b.set == set) {
            match layout.iter().find(|l| l.binding == b.binding) {
                Some(l) => assert_eq!(
                    l.ty, b.kind,
                    "{}: binding {} is a {:?} elsewhere",
                    kernel.path, b.binding, l.ty
                ),
                None => layout.push(LayoutBinding {
                    set,
                    binding: b.binding,
                    ty: b.kind,
                    stages: vk::ShaderStageFlags::COMPUTE,
                }),
            }
        }
    }
    layout.sort_by_key(|l| l.binding);
    layout
}

impl Spirv {
    pub fn words(&self) -> Result<Vec<u32>> {
        ash::util::read_spv(&mut std::io::Cursor::new(self.bytes)).map_err(|e| {
            Error::InvalidInput(format!("embedded SPIR-V {} is corrupt: {e}", self.path))
        })
    }
}

/// A shader module, destroyed when the pipeline made from it exists.
pub(super) fn module(gpu: &Gpu, spirv: &Spirv) -> Result<Owned<vk::ShaderModule>> {
    let code = spirv.words()?;
    let info = vk::ShaderModuleCreateInfo::default().code(&code);
    let device = gpu.device();
    // SAFETY: the SPIR-V came from glslang and was validated at build time.
    let module = unsafe { device.raw.create_shader_module(&info, None) }
        .vk_context("vkCreateShaderModule", spirv.path)?;
    Ok(Owned::new(device, module, spirv.path))
}
