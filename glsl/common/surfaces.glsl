// The surface textures (paper section 5: a grass texture mapped along the
// blade), made at start-up with their mip chains (src/render/texture_maps.rs)
// and sampled trilinearly with repeat. Images and sampler are bound apart,
// as in shadow.glsl.
#ifndef MEADOW_SURFACES_GLSL
#define MEADOW_SURFACES_GLSL

layout(set = 0, binding = 3) uniform texture2D grass_texture;   // u across the blade, v root -> tip
layout(set = 0, binding = 4) uniform texture2D ground_texture;  // soil, tiles every GROUND_TILE_M
layout(set = 0, binding = 5) uniform sampler surface_sampler;

// Matches texture_maps::GROUND_TILE_M.
#define GROUND_TILE_M 2.0

#endif
