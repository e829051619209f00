//! The sun's shadow map (paper section 5: 8192 x 8192). Each frame the
//! blades are drawn from the light, depth only, through the same vertex,
//! tessellation and geometry stages as the colour pass, so their shadows
//! have the real deformed shape and level of detail; the colour pass then
//! samples the map with percentage-closer filtering (glsl/common/shadow.glsl).

use ash::vk;
use glam::{Mat4, Vec3};

use crate::error::{Result, VkResultExt};
use crate::gpu::descriptors::{Bound, BufferSet};
use crate::gpu::{Buffer, Gpu, Image, ImageDesc, MemoryLocation};
use crate::render::frame::{depth_cleared, full_area, image_barrier};
use crate::render::frame_uniforms::FrameUniforms;
use crate::render::pipelines::SHADOW_SET;
use crate::scene::Scene;

pub const SHADOW_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The paper's shadow map side, in texels.
pub const DEFAULT_SHADOW_MAP: u32 = 8192;

/// Depth bias in the shader, on top of the pipeline's constant and slope
/// bias: a blade is a thin sheet that is often both occluder and receiver.
const SHADER_DEPTH_BIAS: f32 = 2e-4;

/// World to the shadow map's clip space: an orthographic view from the sun
/// that holds the grass (its footprint grown by the tallest blade, which
/// may lean that far) from the ground up to the tallest blade. The far
/// plane reaches well past the ground so shadows cast there are found.
pub fn light_view_proj(scene: &Scene) -> Mat4 {
    let dir = Vec3::from(scene.light.direction)
        .try_normalize()
        .unwrap_or(Vec3::Y);
    let (lo, hi) = scene.grass_bounds();
    let h = scene.grass.shape.height[1];
    let min = Vec3::new(lo[0] - h, 0.0, lo[1] - h);
    let max = Vec3::new(hi[0] + h, h, hi[1] + h);
    let center = (min + max) * 0.5;
    let radius = (max - min).length() * 0.5;
    let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    let view = Mat4::look_at_rh(center + dir * 2.0 * radius, center, up);
    let mut lo_v = Vec3::splat(f32::MAX);
    let mut hi_v = Vec3::splat(f32::MIN);
    for i in 0..8 {
        let corner = Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        );
        let p = view.transform_point3(corner);
        lo_v = lo_v.min(p);
        hi_v = hi_v.max(p);
    }
    // The view looks down -z from 2 radii away: the near plane at the eye
    // keeps whatever stands above the box (a blade taller than the
    // scene's shapes) in the map.
    let near = 0.0;
    let far = -lo_v.z + 8.0 * radius;
    Mat4::orthographic_rh(lo_v.x, hi_v.x, lo_v.y, hi_v.y, near, far) * view
}

pub struct ShadowMap {
    /// Side in texels; 0 when shadows are off (a 1 x 1 map cleared to
    /// "lit" keeps the colour pass's descriptor valid).
    pub size: u32,
    pub image: Image,
    pub sampler: vk::Sampler,
    /// The frame uniforms as seen from the light.
    uniforms: Buffer,
    /// Set 0 of the shadow pass: the light's uniforms only (the other
    /// bindings are read by fragment shaders, which this pass has none of).
    set: Option<BufferSet>,
}

impl ShadowMap {
    /// `size` 0 turns shadows off.
    pub fn new(gpu: &Gpu, size: u32, set_layout: vk::DescriptorSetLayout) -> Result<Self> {
        let side = size.max(1);
        let image = Image::new(
            gpu,
            &ImageDesc {
                name: "shadow map",
                format: SHADOW_FORMAT,
                extent: vk::Extent2D {
                    width: side,
                    height: side,
                },
                samples: vk::SampleCountFlags::TYPE_1,
                usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
                aspect: vk::ImageAspectFlags::DEPTH,
                mip_levels: 1,
            },
        )?;
        // Hardware depth comparison with bilinear filtering: each tap is
        // already a 2 x 2 PCF. Outside the map: clamp (the shader treats
        // outside as lit before sampling).
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .compare_enable(true)
            .compare_op(vk::CompareOp::LESS_OR_EQUAL)
            .max_lod(0.0);
        // SAFETY: valid create info on a live device.
        let sampler = match unsafe { gpu.device.raw.create_sampler(&info, None) }
            .vk_context("vkCreateSampler", "shadow map sampler")
        {
            Ok(s) => s,
            Err(e) => {
                image.destroy(gpu);
                return Err(e);
            }
        };
        gpu.device.name(sampler, "shadow map sampler");
        let uniforms = match Buffer::new(
            gpu,
            "shadow pass uniforms",
            std::mem::size_of::<FrameUniforms>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        ) {
            Ok(b) => b,
            Err(e) => {
                // SAFETY: nothing uses the sampler yet.
                unsafe { gpu.device.raw.destroy_sampler(sampler, None) };
                image.destroy(gpu);
                return Err(e);
            }
        };
        let mut map = Self {
            size,
            image,
            sampler,
            uniforms,
            set: None,
        };
        match BufferSet::with(
            gpu,
            set_layout,
            SHADOW_SET,
            &[Bound::Buffer(map.uniforms.raw)],
            "shadow pass descriptor set",
        ) {
            Ok(set) => map.set = Some(set),
            Err(e) => {
                map.destroy(gpu);
                return Err(e);
            }
        }
        Ok(map)
    }

    /// The map and its comparison sampler as the colour pass binds them
    /// (bindings 1 and 2 of the frame set).
    pub fn bindings(&self) -> [Bound; 2] {
        [
            Bound::Image {
                view: self.image.view,
                layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            },
            Bound::Sampler(self.sampler),
        ]
    }

    /// The `shadow` vector of the frame uniforms.
    pub fn params(&self) -> [f32; 4] {
        let on = if self.size > 0 { 1.0 } else { 0.0 };
        // PCF taps 1.5 texels apart: with bilinear comparison, a soft edge
        // about 4 texels wide whatever the map size.
        [1.0 / self.size.max(1) as f32, on, SHADER_DEPTH_BIAS, 1.5]
    }

    /// Writes the light's view of `frame` for this frame's shadow pass.
    pub fn write_uniforms(&mut self, frame: &FrameUniforms) {
        let mut light = *frame;
        light.view_proj = light.light_view_proj;
        self.uniforms.write(0, std::slice::from_ref(&light));
    }

    /// Records the shadow pass: clear, draw the blades depth-only from the
    /// light (when shadows are on), and hand the map to the fragment stage.
    pub fn record(
        &self,
        gpu: &Gpu,
        cmd: vk::CommandBuffer,
        pipeline: Option<vk::Pipeline>,
        layout: vk::PipelineLayout,
        blade_vertices: vk::Buffer,
        blade_count: u32,
    ) {
        let device = &gpu.device.raw;
        // The previous frame's colour pass sampled the map: its reads must
        // finish before the clear (an execution dependency suffices for a
        // read-before-write hazard).
        let to_depth = [image_barrier(
            &self.image,
            vk::PipelineStageFlags2::FRAGMENT_SHADER,
            vk::AccessFlags2::NONE,
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
                | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
        )];
        let to_sampled = [image_barrier(
            &self.image,
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
            vk::PipelineStageFlags2::FRAGMENT_SHADER,
            vk::AccessFlags2::SHADER_SAMPLED_READ,
            vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        )];
        let (area, viewport) = full_area(self.image.extent);
        let depth_attachment = depth_cleared(self.image.view, vk::AttachmentStoreOp::STORE);
        let rendering = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .depth_attachment(&depth_attachment);
        let set = self.set.as_ref().expect("shadow set made in new").set;
        // SAFETY (this block): recording into the caller's command buffer;
        // the image, set, pipeline and vertex buffer are alive and owned by
        // the renderer that waits for the GPU before destroying them.
        unsafe {
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&to_depth),
            );
            device.cmd_begin_rendering(cmd, &rendering);
            if let (Some(pipeline), true) = (pipeline, self.size > 0) {
                device.cmd_set_viewport(cmd, 0, &[viewport]);
                device.cmd_set_scissor(cmd, 0, &[area]);
                device.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    layout,
                    0,
                    &[set],
                    &[],
                );
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
                device.cmd_bind_vertex_buffers(cmd, 0, &[blade_vertices], &[0]);
                device.cmd_draw(cmd, blade_count * 4, 1, 0, 0);
            }
            device.cmd_end_rendering(cmd);
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&to_sampled),
            );
        }
    }

    pub fn destroy(self, gpu: &Gpu) {
        if let Some(set) = self.set {
            set.destroy(gpu);
        }
        self.uniforms.destroy(gpu);
        // SAFETY: the owner waited for the GPU to finish with the map.
        unsafe { gpu.device.raw.destroy_sampler(self.sampler, None) };
        self.image.destroy(gpu);
    }
}
