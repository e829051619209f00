//! The surface textures on the GPU: the grass texture along the blades and
//! the soil, each uploaded with its whole mip chain (made on the CPU in
//! `texture_maps`), and one trilinear, repeating sampler for both.

use ash::vk;

use crate::error::{Result, VkResultExt};
use crate::gpu::commands::Commands;
use crate::gpu::descriptors::Bound;
use crate::gpu::{Buffer, Gpu, Image, ImageDesc, MemoryLocation};
use crate::render::frame::image_barrier;
use crate::render::texture_maps::{self, mip_chain, mip_levels};

/// sRGB storage: the GPU decodes to linear before filtering.
pub const TEXTURE_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

pub struct SurfaceTextures {
    pub grass: Image,
    pub ground: Image,
    pub sampler: vk::Sampler,
}

impl SurfaceTextures {
    pub fn new(gpu: &Gpu, commands: &Commands) -> Result<Self> {
        let grass = upload(
            gpu,
            commands,
            "grass texture",
            texture_maps::grass_texture(),
        )?;
        let ground = match upload(
            gpu,
            commands,
            "ground texture",
            texture_maps::ground_texture(),
        ) {
            Ok(g) => g,
            Err(e) => {
                grass.destroy(gpu);
                return Err(e);
            }
        };
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
        // SAFETY: valid create info on a live device.
        let sampler = match unsafe { gpu.device.raw.create_sampler(&info, None) }
            .vk_context("vkCreateSampler", "surface texture sampler")
        {
            Ok(s) => s,
            Err(e) => {
                ground.destroy(gpu);
                grass.destroy(gpu);
                return Err(e);
            }
        };
        gpu.device.name(sampler, "surface texture sampler");
        Ok(Self {
            grass,
            ground,
            sampler,
        })
    }

    /// Bindings 3, 4 and 5 of the frame set.
    pub fn bindings(&self) -> [Bound; 3] {
        let layout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        [
            Bound::Image {
                view: self.grass.view,
                layout,
            },
            Bound::Image {
                view: self.ground.view,
                layout,
            },
            Bound::Sampler(self.sampler),
        ]
    }

    pub fn destroy(self, gpu: &Gpu) {
        // SAFETY: the owner guarantees the GPU is done with the sampler.
        unsafe { gpu.device.raw.destroy_sampler(self.sampler, None) };
        self.ground.destroy(gpu);
        self.grass.destroy(gpu);
    }
}

/// Makes a device-local image with `base`'s whole mip chain and copies the
/// levels in through one staging buffer; the image ends readable by
/// fragment shaders.
fn upload(gpu: &Gpu, commands: &Commands, name: &str, base: image::RgbaImage) -> Result<Image> {
    let (w, h) = base.dimensions();
    let chain = mip_chain(base);
    let image = Image::new(
        gpu,
        &ImageDesc {
            name,
            format: TEXTURE_FORMAT,
            extent: vk::Extent2D {
                width: w,
                height: h,
            },
            samples: vk::SampleCountFlags::TYPE_1,
            usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
            aspect: vk::ImageAspectFlags::COLOR,
            mip_levels: mip_levels(w, h),
        },
    )?;
    let bytes: Vec<u8> = chain
        .iter()
        .flat_map(|l| l.as_raw().iter().copied())
        .collect();
    let mut staging = match Buffer::new(
        gpu,
        &format!("{name} (staging)"),
        bytes.len() as u64,
        vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::CpuToGpu,
    ) {
        Ok(b) => b,
        Err(e) => {
            image.destroy(gpu);
            return Err(e);
        }
    };
    staging.write(0, &bytes);
    let mut regions = Vec::with_capacity(chain.len());
    let mut offset = 0u64;
    for (level, l) in chain.iter().enumerate() {
        regions.push(vk::BufferImageCopy {
            buffer_offset: offset,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: level as u32,
                base_array_layer: 0,
                layer_count: 1,
            },
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D {
                width: l.width(),
                height: l.height(),
                depth: 1,
            },
        });
        offset += l.as_raw().len() as u64;
    }
    let result = (|| {
        let cmd = commands.begin(gpu)?;
        let to_dst = [image_barrier(
            &image,
            vk::PipelineStageFlags2::NONE,
            vk::AccessFlags2::NONE,
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_WRITE,
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        )];
        let to_read = [image_barrier(
            &image,
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_WRITE,
            vk::PipelineStageFlags2::FRAGMENT_SHADER,
            vk::AccessFlags2::SHADER_SAMPLED_READ,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        )];
        let device = &gpu.device.raw;
        // SAFETY: recording into our own command buffer; the image and the
        // staging buffer are live, and every region lies inside both.
        unsafe {
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&to_dst),
            );
            device.cmd_copy_buffer_to_image(
                cmd,
                staging.raw,
                image.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &regions,
            );
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&to_read),
            );
        }
        commands.submit_and_wait(gpu, &format!("uploading the {name}"))
    })();
    staging.destroy(gpu);
    match result {
        Ok(()) => Ok(image),
        Err(e) => {
            image.destroy(gpu);
            Err(e)
        }
    }
}
