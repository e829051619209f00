//! The surface textures on the GPU: the grass texture along the blades and
//! the soil, each uploaded with its whole mip chain (made on the CPU in
//! `texture_maps`), the canopy map (`canopy_map`), and one trilinear,
//! repeating sampler for them all.

use ash::vk;

use crate::error::Result;
use crate::gpu::{
    Access, Bound, Buffer, BufferUse, CommandPool, Gpu, Image, ImageDesc, ImageUse, MemoryLocation,
    Sampler,
};
use crate::render::canopy_map::CanopyMap;
use crate::render::texture_maps::{self, mip_chain};

/// sRGB storage: the GPU decodes to linear before filtering.
pub const TEXTURE_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// The canopy map's format: the leaf area index and its spread over the
/// canopy's height, over the map's scale (`CanopyMap::texels`), filtered
/// linearly.
pub const CANOPY_FORMAT: vk::Format = vk::Format::R8G8_UNORM;

pub struct SurfaceTextures {
    pub grass: Image,
    pub ground: Image,
    /// The leaf area index of the meadows and bunches over the ground
    /// (src/render/canopy_map.rs), and what its 1.0 stands for and where
    /// it lies (`frame.canopy_map_lai`, `frame.canopy_map_min`).
    pub canopy: Image,
    pub canopy_scale: f32,
    pub canopy_placement: ([f32; 2], [f32; 2]),
    pub sampler: Sampler,
}

impl SurfaceTextures {
    pub fn new(gpu: &Gpu, commands: &CommandPool, canopy: &CanopyMap) -> Result<Self> {
        let grass = upload(
            gpu,
            commands,
            "grass texture",
            texture_maps::grass_texture(),
        )?;
        let ground = upload(
            gpu,
            commands,
            "ground texture",
            texture_maps::ground_texture(),
        )?;
        // Trilinear with repeat: the blade texture is clamped by its uv
        // range anyway (0..1 across and along), the soil tiles.
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::REPEAT)
            .address_mode_v(vk::SamplerAddressMode::REPEAT)
            .address_mode_w(vk::SamplerAddressMode::REPEAT)
            .min_lod(0.0)
            .max_lod(vk::LOD_CLAMP_NONE);
        let sampler = Sampler::new(gpu, &info, "surface texture sampler")?;
        let canopy_image = upload_levels(
            gpu,
            commands,
            "canopy map",
            CANOPY_FORMAT,
            &[vk::Extent2D {
                width: canopy.width,
                height: canopy.height,
            }],
            &canopy.texels(),
        )?;
        Ok(Self {
            grass,
            ground,
            canopy: canopy_image,
            canopy_scale: canopy.scale(),
            canopy_placement: canopy.placement(),
            sampler,
        })
    }

    /// What the colour pass does to them: the fragment stage samples all
    /// three.
    pub fn sampled(&self) -> [ImageUse<'_>; 3] {
        [
            ImageUse::new(&self.grass, Access::FRAGMENT_SAMPLED),
            ImageUse::new(&self.ground, Access::FRAGMENT_SAMPLED),
            ImageUse::new(&self.canopy, Access::FRAGMENT_SAMPLED),
        ]
    }

    /// Bindings 3, 4, 5 and 6 of the frame set.
    pub fn bindings(&self) -> [Bound<'_>; 4] {
        [
            Bound::Image(&self.grass),
            Bound::Image(&self.ground),
            Bound::Sampler(&self.sampler),
            Bound::Image(&self.canopy),
        ]
    }
}

/// Makes a device-local image with `base`'s whole mip chain and copies the
/// levels in; the image ends readable by fragment shaders.
fn upload(gpu: &Gpu, commands: &CommandPool, name: &str, base: image::RgbaImage) -> Result<Image> {
    let chain = mip_chain(base);
    let levels: Vec<vk::Extent2D> = chain
        .iter()
        .map(|l| vk::Extent2D {
            width: l.width(),
            height: l.height(),
        })
        .collect();
    let bytes: Vec<u8> = chain
        .iter()
        .flat_map(|l| l.as_raw().iter().copied())
        .collect();
    upload_levels(gpu, commands, name, TEXTURE_FORMAT, &levels, &bytes)
}

/// Makes a device-local image of `format` with the mip `levels` (largest
/// first) and copies `bytes`, the levels one after another, in through one
/// staging buffer; the image ends readable by fragment shaders.
fn upload_levels(
    gpu: &Gpu,
    commands: &CommandPool,
    name: &str,
    format: vk::Format,
    levels: &[vk::Extent2D],
    bytes: &[u8],
) -> Result<Image> {
    let image = Image::new(
        gpu,
        &ImageDesc {
            name,
            format,
            extent: levels[0],
            samples: vk::SampleCountFlags::TYPE_1,
            usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
            aspect: vk::ImageAspectFlags::COLOR,
            mip_levels: levels.len() as u32,
        },
    )?;
    let mut staging = Buffer::new(
        gpu,
        &format!("{name} (staging)"),
        bytes.len() as u64,
        vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::CpuToGpu,
    )?;
    staging.write(0, bytes);
    let rec = commands.begin()?;
    rec.declare(
        &[BufferUse::new(&staging, Access::COPY_READ)],
        &[ImageUse::discarding(&image, Access::COPY_WRITE)],
    );
    rec.copy_buffer_to_image(&staging, &image, levels);
    // Left in the layout the colour pass samples it in.
    rec.declare(&[], &[ImageUse::new(&image, Access::FRAGMENT_SAMPLED)]);
    rec.submit_and_wait(&format!("uploading the {name}"))?;
    Ok(image)
}
