// The air's haze, the same for the ground and the grass on it: beyond
// frame.ground.z metres of clear ground around frame.ground.xy (the
// grass's centre, or a cover's camera) whatever stands there fades into
// the sky's horizon colour in its direction from the camera, so the
// ground meets the sky without a band and no blade stands bright over
// hazed ground. Needs frame.glsl and sky.glsl included first.
#ifndef MEADOW_HAZE_GLSL
#define MEADOW_HAZE_GLSL

// `lit` at `world`, seen through the haze.
vec3 hazed(vec3 lit, vec3 world) {
    float clear = frame.ground.z;
    float beyond = max(distance(world.xz, frame.ground.xy) - clear, 0.0);
    float haze = 1.0 - exp(-beyond / (0.25 * clear + 10.0));
    vec3 horizon = sky_horizon(world - frame.camera_pos.xyz, frame.light_dir.xyz);
    return mix(lit, horizon, haze);
}

#endif
