// The sky's colours, shared by the sky and by the ground's haze, so the
// ground fades into exactly the colour the sky has at the horizon. The
// sky follows the sun's elevation: above about 15 degrees a clear day's
// blue, pale at the horizon; as the sun sinks toward the horizon the
// horizon warms, most toward the sun (the long path through the air
// scatters the blue out of it), and the zenith deepens. Every shipped
// scene's sun is higher than that: their sky is the day's.
#ifndef MEADOW_SKY_GLSL
#define MEADOW_SKY_GLSL

const vec3 SKY_HORIZON = vec3(0.62, 0.74, 0.86);
const vec3 SKY_ZENITH = vec3(0.16, 0.33, 0.68);
// A sun on the horizon: glowing toward it, dusky away from it, the zenith
// a darker blue.
const vec3 SUNSET_GLOW = vec3(1.00, 0.58, 0.32);
const vec3 SUNSET_AWAY = vec3(0.60, 0.56, 0.66);
const vec3 SUNSET_ZENITH = vec3(0.10, 0.19, 0.45);

// How far toward sunset colours the sky is for a sun (unit direction
// toward it) this high: 0 from sin(elevation) 0.26 (15 degrees) up, 1 at
// the horizon.
float sunset_warmth(vec3 sun) {
    return 1.0 - smoothstep(0.02, 0.26, sun.y);
}

// The horizon's colour in the horizontal direction of `dir`.
vec3 sky_horizon(vec3 dir, vec3 sun) {
    float warmth = sunset_warmth(sun);
    vec2 flat_dir = dir.xz;
    vec2 flat_sun = sun.xz;
    // 1 looking toward the sun's azimuth, 0 away (a sun overhead: 0.5).
    float toward = 0.5;
    if (dot(flat_dir, flat_dir) > 1e-12 && dot(flat_sun, flat_sun) > 1e-12) {
        toward = 0.5 + 0.5 * dot(normalize(flat_dir), normalize(flat_sun));
    }
    vec3 low_sun = mix(SUNSET_AWAY, SUNSET_GLOW, toward * toward * toward);
    return mix(SKY_HORIZON, low_sun, warmth);
}

// The sky seen along the unit direction `dir` under a sun toward `sun`:
// the horizon's colour at the horizon (and below it), the zenith's
// overhead; a low sun's warm band hugs the horizon.
vec3 sky_color(vec3 dir, vec3 sun) {
    float warmth = sunset_warmth(sun);
    float elevation = clamp(dir.y, 0.0, 1.0);
    vec3 zenith = mix(SKY_ZENITH, SUNSET_ZENITH, warmth);
    return mix(sky_horizon(dir, sun), zenith, pow(elevation, mix(0.6, 0.35, warmth)));
}

#endif
