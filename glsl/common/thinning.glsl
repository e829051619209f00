// Distance thinning (ours; issue 18): beyond frame.thinning_from metres from
// the camera only a share of the blades is drawn, and the blades kept are
// widened so that the far meadow keeps its coverage. Mirrored on the CPU
// by src/render/thinning.rs; the cull pass drops the blades whose scale is
// 0 and the tessellation control stage scales the others' width vectors.
//
// share(d) = clamp((d0 / d)^2, least, 1): a blade's projected area falls as
// 1 / d^2, so the blades drawn per pixel stay the same. Each blade has a
// fixed random h in [0, 1) (a hash of its `blade_rand`):
// it is drawn while h < share(d) (1 + band), at full width below share(d)
// and narrowing to nothing over the band above it, so no blade pops as
// the camera moves. Every width is divided by the mean of that profile
// over h, so the expected total width is the unthinned meadow's.
// Branch-free: glsl/common/cull.glsl says why.
#ifndef MEADOW_THINNING_GLSL
#define MEADOW_THINNING_GLSL

#include "frame.glsl"
#include "hash.glsl"

// The blade's h: 24 bits of the hash, exact in a float.
float thinning_h(float variation) {
    return float(lowbias32(floatBitsToUint(variation)) >> 8) * (1.0 / 16777216.0);
}

// The width scale of a blade rooted at `root` with random value
// `blade_rand`: 0 for a blade thinned out, 1 near the camera, above 1 far
// away.
float thinning_scale(vec3 root, float blade_rand) {
    float d0 = frame.thinning_from;
    vec3 r = root - frame.camera_pos;
    float d2 = max(dot(r, r), 1e-12);
    float share = clamp(d0 * d0 / d2, frame.thinning_least, 1.0);
    float band = frame.thinning_band * share;
    float h = thinning_h(blade_rand);
    float fade = clamp((share + band - h) / band, 0.0, 1.0);
    // The mean of fade over h in [0, 1): the band may reach past h = 1.
    float top = min(1.0, share + band);
    float over = share + band - top;
    float mean = share + (band * band - over * over) / (2.0 * band);
    return mix(1.0, fade / mean, frame.thinning_on);
}

#endif
