// The sky's colours, shared by the sky and by the ground's haze, so the
// ground fades into exactly the colour the sky has at the horizon.
#ifndef MEADOW_SKY_GLSL
#define MEADOW_SKY_GLSL

const vec3 SKY_HORIZON = vec3(0.62, 0.74, 0.86);
const vec3 SKY_ZENITH = vec3(0.16, 0.33, 0.68);

// The sky seen along the unit direction `dir`: pale at the horizon (and
// below it), deeper blue overhead.
vec3 sky_color(vec3 dir) {
    float elevation = clamp(dir.y, 0.0, 1.0);
    return mix(SKY_HORIZON, SKY_ZENITH, pow(elevation, 0.6));
}

#endif
