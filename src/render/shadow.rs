//! The sun's shadow map (paper section 5: 8192 x 8192). Each frame the
//! blades are drawn from the light, depth only, through the same vertex,
//! tessellation and geometry stages as the colour pass, so their shadows
//! have the real deformed shape and level of detail; the colour pass then
//! samples the map with percentage-closer filtering (glsl/common/shadow.glsl).

use ash::vk;

use crate::error::Result;
use crate::gpu::{
    Access, Attachments, Bound, Buffer, DescriptorSet, Gpu, Image, ImageDesc, ImageUse,
    PipelineLayout, Recording, Sampler,
};
use crate::render::cull::BladeDraw;
use crate::render::frame_uniforms::FrameUniforms;
use crate::render::obstacles::ObstacleMeshes;
use crate::render::pipelines::{ShadowPipelines, SHADOW_FORMAT, SHADOW_SET};
pub use crate::render::shadow_params::ShadowParams;
use crate::render::terrain::TerrainMesh;

pub struct ShadowMap {
    /// Side in texels; 0 when shadows are off (a 1 x 1 map cleared to
    /// "lit" keeps the colour pass's descriptor valid).
    pub size: u32,
    pub image: Image,
    pub sampler: Sampler,
    /// The frame uniforms as seen from the light.
    uniforms: Buffer,
    /// Set 0 of the shadow pass: the light's uniforms only (the other
    /// bindings are read by fragment shaders, which this pass has none of).
    set: DescriptorSet,
}

impl ShadowMap {
    /// `size` 0 turns shadows off.
    pub fn new(gpu: &Gpu, size: u32, layout: &PipelineLayout) -> Result<Self> {
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
        let sampler = Sampler::new(gpu, &info, "shadow map sampler")?;
        let uniforms = FrameUniforms::buffer(gpu, "shadow pass uniforms")?;
        let set = DescriptorSet::new(
            gpu,
            layout,
            SHADOW_SET,
            &[Bound::Buffer(&uniforms)],
            "shadow pass descriptor set",
        )?;
        Ok(Self {
            size,
            image,
            sampler,
            uniforms,
            set,
        })
    }

    /// The map and its comparison sampler as the colour pass binds them
    /// (bindings 1 and 2 of the frame set).
    pub fn bindings(&self) -> [Bound<'_>; 2] {
        [Bound::Image(&self.image), Bound::Sampler(&self.sampler)]
    }

    /// The frame uniforms' `shadow_*` fields for this map.
    pub fn params(&self) -> ShadowParams {
        ShadowParams::of(self.size)
    }

    /// Writes the light's view of `frame` for this frame's shadow pass.
    pub fn write_uniforms(&mut self, frame: &FrameUniforms) {
        let mut light = *frame;
        light.view_proj = light.light_view_proj;
        light.tess_level = light.shadow_tess_level;
        light.shadow_texel_m = texel_side_m(&light.light_view_proj, self.size);
        self.uniforms.write(0, std::slice::from_ref(&light));
    }

    /// Records the shadow pass: clear, `draw` of `blades` and the obstacles depth-only from the light (when shadows
    /// are on), and hand the map to the fragment stage.
    pub fn record(
        &self,
        rec: &Recording,
        pipelines: Option<&ShadowPipelines>,
        blades: &Buffer,
        draw: BladeDraw,
        obstacles: &ObstacleMeshes,
        terrain: Option<&TerrainMesh>,
    ) {
        // Cleared: the contents are not needed, the previous frame's
        // sampling finishes first.
        rec.declare(
            &[],
            &[ImageUse::discarding(&self.image, Access::DEPTH_ATTACHMENT)],
        );
        rec.begin_rendering(&Attachments {
            color: None,
            depth: &self.image,
            store_depth: true,
        });
        if let (Some(pipelines), true) = (pipelines, self.size > 0) {
            rec.bind_set(&pipelines.blades, &self.set);
            rec.bind_pipeline(&pipelines.blades);
            draw.record(rec, blades);
            obstacles.draw(rec, &pipelines.obstacles);
            if let Some(terrain) = terrain {
                terrain.draw(rec, &pipelines.terrain);
            }
        }
        rec.end_rendering();
    }

    /// What the colour pass does to the map: the fragment stage samples it.
    pub fn sampled(&self) -> ImageUse<'_> {
        ImageUse::new(&self.image, Access::FRAGMENT_SAMPLED)
    }
}

/// The side in metres of one texel of a `size`-texel map drawn through
/// `light_view_proj` (orthographic: its first row scales metres across
/// the sun's view to clip space's 2 units over the map); 0 without a map.
fn texel_side_m(light_view_proj: &crate::interface::Mat4Columns, size: u32) -> f32 {
    let m = glam::Mat4::from_cols_array_2d(light_view_proj);
    let per_m = m.row(0).truncate().length();
    if size == 0 || per_m <= 0.0 {
        return 0.0;
    }
    2.0 / (per_m * size as f32)
}
