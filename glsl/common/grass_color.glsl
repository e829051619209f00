// Each blade's colour (ours; docs/scenes.md, [grass.look]): the meadow's
// average blade (the grass texture: dark root, light tip) varied blade by
// blade and clump by clump, all from the scene's seed and the blade's own
// random number, so the same scene gives the same meadow. Real swards
// grow in clumps (tussocks, patches of one plant) that differ in shade,
// and among their blades a few are dry and most dry at the tip.
// Needs frame.glsl and hash.glsl.
#ifndef MEADOW_GRASS_COLOR_GLSL
#define MEADOW_GRASS_COLOR_GLSL

// Linear colours a blade's texture colour is pulled toward: fresher (bluer)
// green, yellower green, and straw.
const vec3 GRASS_FRESH = vec3(0.72, 1.0, 0.85);
const vec3 GRASS_YELLOW = vec3(1.45, 1.12, 0.55);
const vec3 GRASS_STRAW = vec3(0.46, 0.38, 0.17);

// Uniform in [0, 1) from 24 bits of a hash.
float unit_of(uint h) {
    return float(h >> 8) * (1.0 / 16777216.0);
}

// The random number (0..1) of the clump a blade rooted at `root` (x, z)
// belongs to: the nearest of one point jittered in each cell of a
// frame.clump_size-metre lattice (cellular clumps); 0.5 without clumps.
float clump_of(vec2 root) {
    float size = frame.clump_size;
    if (size <= 0.0) {
        return 0.5;
    }
    uint seed = uint(frame.clump_seed) * 0x9e3779b9u;
    vec2 p = root / size;
    ivec2 cell = ivec2(floor(p));
    float best = 1e9;
    uint best_hash = 0u;
    for (int j = -1; j <= 1; ++j) {
        for (int i = -1; i <= 1; ++i) {
            ivec2 c = cell + ivec2(i, j);
            uint h = lowbias32(uint(c.x) * 0x8da6b343u ^ uint(c.y) * 0xd8163841u ^ seed);
            uint h2 = lowbias32(h);
            vec2 point = vec2(c) + vec2(unit_of(h), unit_of(h2));
            vec2 d = point - p;
            float d2 = dot(d, d);
            if (d2 < best) {
                best = d2;
                best_hash = lowbias32(h2);
            }
        }
    }
    return unit_of(best_hash);
}

// A blade's own colour: the tint its hue, lightness and clump give the
// texture's colour, the share of its length its dry tip takes, and whether
// the whole blade is dry (1; its tip then 0).
struct BladeTint {
    vec3 tint;
    float tip_len;
    float dry;
};

// The blade's colour, worked out once per blade (the tessellation control
// stage) from its random number `blade_rand` and its clump's `clump`.
BladeTint blade_tint(float blade_rand, float clump) {
    uint h = lowbias32(floatBitsToUint(blade_rand) ^ 0x5bd1e995u);
    float r_hue = unit_of(h);
    h = lowbias32(h);
    float r_dry = unit_of(h);
    h = lowbias32(h);
    float r_tip = unit_of(h);
    h = lowbias32(h);
    float r_light = unit_of(h);
    // Hue: fresher or yellower, by the blade and by its clump.
    float t = (r_hue - 0.5) * frame.hue + (clump - 0.5) * frame.clump_variation;
    vec3 hue = t < 0.0 ? mix(vec3(1.0), GRASS_FRESH, min(-2.0 * t, 1.0))
                       : mix(vec3(1.0), GRASS_YELLOW, min(2.0 * t, 1.0));
    // Lighter and darker blades, and clumps.
    vec3 tint = hue * (1.0 + 0.25 * (r_light - 0.5) + 0.3 * frame.clump_variation * (clump - 0.5));
    // A share frame.dryness of the blades is dry; of the others, dry tips
    // over the last share of the blade, up to 0.35 of it.
    float tip_len = frame.tip * mix(0.08, 0.35, r_tip);
    bool dry = r_dry < frame.dryness;
    return BladeTint(tint, dry ? 0.0 : tip_len, dry ? 1.0 : 0.0);
}

// The blade's albedo at `uv` (x across, y root to tip): the texture's
// colour `base` under the blade's `tint`, with its dry tip's `tip_len` and
// `dry` (blade_tint).
vec3 grass_albedo(vec3 base, vec2 uv, vec3 tint, float tip_len, float dry) {
    vec3 c = base * tint;
    // Dry blades and tips are straw, darker toward the root as the
    // texture is.
    float shade = dot(base, vec3(0.2126, 0.7152, 0.0722)) / 0.24;
    vec3 straw = GRASS_STRAW * clamp(shade, 0.25, 1.3);
    float tip = tip_len > 0.0 ? smoothstep(1.0 - tip_len, 1.0, uv.y) : 0.0;
    return mix(c, straw, max(dry, 0.85 * tip));
}

#endif
