// The air's haze, the same for the ground and the grass on it: beyond
// frame.ground_clear metres of clear ground around frame.ground_center (the
// grass's centre, or a cover's camera) whatever stands there fades into
// the sky's horizon colour in its direction from the camera, so the
// ground meets the sky without a band and no blade stands bright over
// hazed ground. Needs frame.glsl and sky.glsl included first.
#ifndef MEADOW_HAZE_GLSL
#define MEADOW_HAZE_GLSL

// `lit` at `world`, seen through the haze.
vec3 hazed(vec3 lit, vec3 world) {
    float clear = frame.ground_clear;
    float beyond = max(distance(world.xz, frame.ground_center) - clear, 0.0);
    float haze = 1.0 - exp(-beyond / (0.25 * clear + 10.0));
    vec3 horizon = sky_horizon(world - frame.camera_pos, frame.light_dir);
    return mix(lit, horizon, haze);
}

#endif
