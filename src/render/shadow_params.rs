//! The shadow map's fields of the frame uniforms: what the shader's test
//! and the cull pass's filter reach need to know of the map.

use crate::interface::FrameUniforms;

/// Depth bias in the shader, on top of the pipeline's constant and slope
/// bias: a blade is a thin sheet that is often both occluder and receiver.
const SHADER_DEPTH_BIAS: f32 = 2e-4;

/// The frame uniforms' `shadow_*` fields for a map of `size` texels a
/// side (0: none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowParams {
    /// One texel in uv.
    pub texel: f32,
    pub on: bool,
    /// The depth bias of the shader's test.
    pub bias: f32,
    /// The PCF taps' spacing in texels.
    pub pcf_radius: f32,
}

impl ShadowParams {
    pub fn of(size: u32) -> Self {
        Self {
            texel: 1.0 / size.max(1) as f32,
            on: size > 0,
            bias: SHADER_DEPTH_BIAS,
            // PCF taps 1.5 texels apart: with bilinear comparison, a soft
            // edge about 4 texels wide whatever the map size.
            pcf_radius: 1.5,
        }
    }

    /// Writes them into `uniforms`.
    pub fn write(self, uniforms: &mut FrameUniforms) {
        uniforms.shadow_texel = self.texel;
        uniforms.shadow_on = if self.on { 1.0 } else { 0.0 };
        uniforms.shadow_bias = self.bias;
        uniforms.shadow_pcf_radius = self.pcf_radius;
    }
}
