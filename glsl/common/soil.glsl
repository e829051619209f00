// The ground's soil, as the backdrop's plane (glsl/backdrop/ground.frag)
// and the terrain mesh (glsl/obstacle/obstacle.frag) shade it: the soil
// texture, tiled, with a slow brightness variation so the tiling does not
// show, lit by the sun (`lambert`: the cosine to it) and darkened where the
// shadow map says the sun is hidden; beyond frame.ground.z metres from
// the grass it fades into the sky's horizon colour (in its direction from
// the camera), so the ground meets the
// sky without a band. Needs frame.glsl, shadow.glsl, sky.glsl and
// surfaces.glsl included first.
#ifndef MEADOW_SOIL_GLSL
#define MEADOW_SOIL_GLSL

float hash(vec2 p) {
    return fract(sin(dot(p, vec2(127.1, 311.7))) * 43758.5453);
}

float value_noise(vec2 p) {
    vec2 i = floor(p), f = fract(p);
    vec2 u = f * f * (3.0 - 2.0 * f);
    return mix(mix(hash(i), hash(i + vec2(1, 0)), u.x),
               mix(hash(i + vec2(0, 1)), hash(i + vec2(1, 1)), u.x), u.y);
}

vec3 soil_lit(vec3 world, float lambert) {
    vec3 soil = texture(sampler2D(ground_texture, surface_sampler), world.xz / GROUND_TILE_M).rgb;
    vec3 albedo = soil * mix(0.85, 1.1, value_noise(world.xz * 0.37));
    vec3 lit = albedo * (frame.light_dir.w + frame.light_color.rgb * lambert * sun_visibility(world));
    float clear = frame.ground.z;
    float beyond = max(distance(world.xz, frame.ground.xy) - clear, 0.0);
    float haze = 1.0 - exp(-beyond / (0.25 * clear + 10.0));
    vec3 horizon = sky_horizon(world - frame.camera_pos.xyz, frame.light_dir.xyz);
    return mix(lit, horizon, haze);
}

#endif
