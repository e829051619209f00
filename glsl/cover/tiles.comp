#version 450
#extension GL_GOOGLE_include_directive : require
// The cover's tiles (ours; `[grass.cover]`, src/scene/cover/): one
// invocation per blade makes its four control points at rest from the
// cover's seed, its tile's coordinates and its index in the tile alone,
// bit for bit as `cover::blade` does on the CPU. Hence integer hashing,
// draws of 24 bits, and additions and multiplications that are never
// fused (`precise`); the facing's sine and cosine are the same Taylor
// polynomials, their coefficients given by their bits.

#include "wind_grid.glsl"
#include "blade_vertex.glsl"
#include "cull.glsl"
#include "../grass/quasi_static.glsl"

layout(local_size_x = COVER_GROUP) in;

// CoverPush: src/interface/defs.rs.
layout(push_constant, std430) uniform Push {
    CoverPush pc;
};

// The blade buffer from blade `pc.first` on (a batch of it); the cover's
// blades start at blade `pc.base`, after the scene's patches. Written only; not declared
// writeonly because naga does not take it.
// (Binding 0: the frame uniforms, frame.glsl, which the cull pass's tests read.)
layout(set = 0, binding = 1, std430) buffer Vertices { BladeVertex vertices[]; };
// CoverParams: src/interface/defs.rs.
layout(set = 0, binding = 2, std430) readonly buffer Params { CoverParams params; };
// The wind the blades are posed in (a placeholder with `params.pose` 0).
layout(set = 0, binding = 3, std430) readonly buffer Wind { float wind_velocity[]; };
// How many blades this pass posed quasi-statically, from their dynamics'
// state, and left out beyond the cover's bounds; the largest distance a
// tip posed both frames moved since the last pass, over the blades posed
// quasi-statically and over all (a
// positive float's bits, which order as the float does; cleared before it).
layout(set = 0, binding = 4, std430) buffer Posed {
    uint posed; uint from_state; uint outside; uint far_tip_jump; uint tip_jump;
};
// The kept blades' states (`compute::CoverDynamics`; a placeholder with
// `params.dynamic` 0): the paper's dynamics near the camera.
layout(set = 0, binding = 5, std430) readonly buffer States { GrassState states[]; };
// The ground the blades are rooted on (`Terrain::gpu_words`).
layout(set = 0, binding = 6, std430) readonly buffer Terrain {
    TerrainHeader terrain;
    float terrain_words[];
};
#include "terrain.glsl"
// The kept blades' pressed states (`CoverDynamics::presses`; a placeholder
// with `params.pressed_states` 0): a ball's trail through them.
layout(set = 0, binding = 7, std430) readonly buffer Presses { Press presses[]; };
// Each blade's pose the frame before (`FarPose`, src/interface/defs.rs),
// in the slot its tile wraps to over the whole square.
layout(set = 0, binding = 8, std430) buffer FarPoses { FarPose far_poses[]; };
#define WIND_VELOCITY(i) wind_velocity[i]
#include "wind_sample.glsl"

// `cover::hash`: lowbias32 (hash.glsl, through cull.glsl).
uint hash(uint x) {
    return lowbias32(x);
}

uint draw_bits(uint key, uint k) {
    return hash(key ^ (k * 0x9e3779b9u)) >> 8;
}

// Exact: 24 bits over 2^24.
float draw(uint key, uint k) {
    return float(draw_bits(key, k)) * (1.0 / 16777216.0);
}

// `cover::facing`: (cos, sin) across a quarter turn about the quadrant's axis.
vec2 facing(float u, uint quadrant) {
    precise float x = (u - 0.5) * uintBitsToFloat(0x3FC90FDBu); // pi/2
    precise float x2 = x * x;
    precise float s = x * (1.0 + x2 * (uintBitsToFloat(0xBE2AAAABu)
        + x2 * (uintBitsToFloat(0x3C088889u) + x2 * (uintBitsToFloat(0xB9500D01u)
        + x2 * uintBitsToFloat(0x3638EF1Du)))));
    precise float c = 1.0 + x2 * (-0.5 + x2 * (uintBitsToFloat(0x3D2AAAABu)
        + x2 * (uintBitsToFloat(0xBAB60B61u) + x2 * uintBitsToFloat(0x37D00D01u))));
    switch (quadrant & 3u) {
    case 0u: return vec2(c, s);
    case 1u: return vec2(-s, c);
    case 2u: return vec2(-c, -s);
    default: return vec2(s, -c);
    }
}

// `field::profile`: (along the facing, up) for a unit height.
vec2[4] profile(uint kind, float c) {
    precise vec2 p[4];
    if (kind == 0u) {
        p = vec2[4](vec2(0.0, 0.0), vec2(0.0, 0.34),
                    vec2(0.04 + 0.06 * c, 0.67), vec2(0.08 + 0.14 * c, 0.99));
    } else if (kind == 1u) {
        p = vec2[4](vec2(0.0, 0.0), vec2(0.02, 0.36),
                    vec2(0.12 + 0.12 * c, 0.68), vec2(0.34 + 0.26 * c, 0.86 - 0.1 * c));
    } else {
        p = vec2[4](vec2(0.0, 0.0), vec2(0.06, 0.5),
                    vec2(0.3 + 0.1 * c, 0.84), vec2(0.62 + 0.15 * c, 0.5 - 0.15 * c));
    }
    return p;
}

// The blade as the dynamics read it (`GrassBlade::new`): stiffness
// k_i = k_tip r^((2 - i) / 2), the bending groups split where the slope's
// sign turns, the drag S sigma per motion; its inertia and damping play no
// part at rest.
// The inertia per motion as `GrassBlade::new` makes it from the edge mass
// m (what `far_frequencies` reads; the balance does not).
// The ground's normal and contact's c are left
// at 0: no pose reads them (blades grow and swing upright on a slope; only
// ground contact reads them, and no posed blade is in contact).
GrassBlade cover_grass_blade(vec3 p[4], vec3 width_dir, float half_width, float rand,
                             float k_tip, float ratio, float sigma, float m) {
    GrassBlade b;
    b.rest_root = p[0];
    b.blade_rand = rand;
    b.rest_1 = p[1];
    b.ground_normal_x = 0.0;
    b.rest_2 = p[2];
    b.ground_curvature = 0.0;
    b.rest_tip = p[3];
    b.ground_normal_z = 0.0;
    b.width_dir = width_dir;
    b.half_width = half_width;
    bool rising = p[1].y >= p[0].y;
    int split = 3;
    for (int i = 2; i >= 1; --i) {
        if ((p[i + 1].y >= p[i].y) != rising) {
            split = i;
        }
    }
    b.stiffness = vec3(k_tip * ratio, k_tip * sqrt(ratio), k_tip);
    b.group_b_edge = uint(split);
    float len[3];
    for (int i = 0; i < 3; ++i) {
        len[i] = distance(p[i], p[i + 1]);
    }
    float a = 0.0;
    for (int i = 0; i < split; ++i) {
        a += len[i];
    }
    float all = len[0] + len[1] + len[2];
    float area = 2.0 * half_width;
    b.drag = vec4(sigma * all * area, sigma * a * area,
                  split < 3 ? sigma * (all - a) * area : 0.0, sigma * all * area);
    // `swing_inertia`: each edge a plate swung by its eq. 12 share.
    vec3 below = vec3(0.0);
    float swing = 0.0;
    for (int i = 0; i < 3; ++i) {
        float share = b.stiffness[2] / b.stiffness[i];
        vec3 h = (p[i + 1] - p[i]) * vec3(share, 0.0, share);
        swing += m * (dot(below, below) + dot(below, h) + dot(h, h) / 3.0)
            + m * share * share * half_width * half_width / 3.0;
        below += h;
    }
    int tip_a = split - 1;
    b.inertia = vec4(swing, float(split) * m * len[tip_a] * len[tip_a],
                     split < 3 ? float(3 - split) * m * len[2] * len[2] : 1.0,
                     3.0 * m * half_width * half_width);
    b.damping = vec4(0.0);
    return b;
}

// Whether the frame may draw the blade rooted at `root`, whatever its pose:
// the cull pass's tests (`cull_flags`) on the box its reach allows around
// the root, grown by its widest width: kept by the distance thinning, and
// in view or casting a shadow into it. Branch-free, as `cull_flags` is.
bool may_be_drawn(vec3 root, float rand, float reach, float half_width) {
    float width_scale = thinning_scale(root, rand);
    uint kept = uint(width_scale > 0.0);
    vec3 grow = vec3(reach + half_width * max(width_scale, 1.0));
    vec3 lo = root - grow, hi = root + grow;
    uint in_view = uint(box_in_frustum(frame.view_proj, lo, hi));
    vec3 light = frame.light_dir;
    uint low_sun = uint(light.y < LOWEST_SWEPT_SUN);
    light.y = max(light.y, LOWEST_SWEPT_SUN);
    shadow_sweep(light, lo, hi);
    uint caster = low_sun | uint(box_in_frustum(frame.view_proj, lo, hi));
    return (kept & (in_view | caster)) != 0u;
}

// The curve's point at t = k / COVER_FIT_SAMPLES (eq. 1, as `bezier` sums
// it), never fused.
vec3 fit_sample(vec3 p[4], uint k) {
    precise float t = float(k) / float(COVER_FIT_SAMPLES);
    precise float s = 1.0 - t;
    precise vec3 q = p[0] * (s * s * s) + p[1] * (3.0 * s * s * t)
        + p[2] * (3.0 * s * t * t) + p[3] * (t * t * t);
    return q;
}

// `cover::ground_clearance`: how far the curve keeps above the ground at
// its worst over t = 1/8 .. 1, less FIT_ROOM a metre from the root.
float ground_clearance(vec3 p[4]) {
    float worst = uintBitsToFloat(0x7F7FFFFFu); // f32::MAX
    for (uint k = 1u; k <= COVER_FIT_SAMPLES; ++k) {
        vec3 q = fit_sample(p, k);
        float above = q.y - terrain_height(q.x, q.z);
        worst = min(worst, above - FIT_ROOM * distance(q, p[0]));
    }
    return worst;
}

// `cover::fit_clearance`: the curve clear of the ground, and each control
// point FIT_ROOM a metre above the tangent plane at the root (of
// upward normal n).
float fit_clearance(vec3 p[4], vec3 n) {
    float worst = ground_clearance(p);
    for (int i = 1; i < 4; ++i) {
        vec3 d = p[i] - p[0];
        worst = min(worst, dot(n, d) - FIT_ROOM * length(d));
    }
    return worst;
}

// Whether no ground as steep as the terrain's steepest could bring the
// blade under `fit_clearance`'s 0, so the fit may skip it without
// changing any answer (the CPU reference has no such shortcut): with g
// an upper bound of the slope, every point q of the curve and every
// control point, dy above the root and r from it horizontally, has
// dy - g r >= FIT_ROOM |q - P0| sqrt(1 + g^2) + 0.1 mm. The ground
// under q is at most g r over the root's, and the tangent plane's normal
// from central differences tilts at most as far, its two differences
// each at most the slope bound, hence sqrt(2) times it for g; the 0.1 mm
// covers the two sides' rounding.
bool surely_clear(vec3 p[4]) {
    float g = 1.4143 * params.max_slope;
    float room = FIT_ROOM * sqrt(1.0 + g * g);
    bool clear = true;
    for (uint k = 1u; k <= COVER_FIT_SAMPLES; ++k) {
        vec3 d = fit_sample(p, k) - p[0];
        clear = clear && d.y - g * length(d.xz) >= room * length(d) + 1e-4;
    }
    for (int i = 1; i < 4; ++i) {
        vec3 d = p[i] - p[0];
        clear = clear && d.y - g * length(d.xz) >= room * length(d) + 1e-4;
    }
    return clear;
}

// `cover::fit_turn`: (cos, sin) of k pi / COVER_FIT_TURNS by the facing's
// polynomials, from arguments that are exact.
vec2 fit_turn(int k) {
    int quarter = int(COVER_FIT_TURNS / 2u);
    // Floor division (GLSL's / of a negative int is undefined): exact in
    // floats for these small integers.
    int quadrant = int(floor(float(k + quarter / 2) / float(quarter)));
    float u = 0.5 + float(k - quarter * quadrant) / float(quarter);
    return facing(u, uint(quadrant));
}

// `cover::turned`: about the vertical through the root, never fused.
void fit_turned(inout vec3 p[4], inout vec3 w, vec2 turn) {
    float c = turn.x, s = turn.y;
    vec3 root = p[0];
    for (int i = 0; i < 4; ++i) {
        precise float dx = p[i].x - root.x, dz = p[i].z - root.z;
        precise float x = root.x + (c * dx + s * dz);
        precise float z = root.z + (c * dz - s * dx);
        p[i] = vec3(x, p[i].y, z);
    }
    precise float wx = c * w.x + s * w.z;
    precise float wz = c * w.z - s * w.x;
    w = vec3(wx, w.y, wz);
}

// `cover::shrunk`: the lean toward upright to t of itself.
void fit_shrunk(inout vec3 p[4], float t) {
    vec3 root = p[0];
    for (int i = 0; i < 4; ++i) {
        precise float x = root.x + (p[i].x - root.x) * t;
        precise float z = root.z + (p[i].z - root.z) * t;
        p[i] = vec3(x, p[i].y, z);
    }
}

// `cover::fit_turn_of`: 0, then 1, -1, 2, -2 ..
int fit_turn_of(int c) {
    int k = (c + 1) / 2;
    return (c & 1) == 1 ? k : -k;
}

// The blade as made turned by `k` (none for 0), then its lean shrunk to
// `t` of itself (none for 1).
void fit_candidate(inout vec3 p[4], inout vec3 w, int k, float t) {
    if (k != 0) {
        fit_turned(p, w, fit_turn(k));
    }
    if (t < 1.0) {
        fit_shrunk(p, t);
    }
}

// `cover::fitted`: a blade with a point of its curve under the ground (or
// nearer it than FIT_ROOM), or a control point not above the tangent
// plane at its root, turned about its root's vertical as
// little as clears it, each way in turn; where none does, turned where it
// keeps highest and its lean shrunk toward upright as far as needed.
void fit_to_ground(inout vec3 p[4], inout vec3 w) {
    if (surely_clear(p)) {
        return;
    }
    vec3 n = terrain_normal(p[0].x, p[0].z, TERRAIN_NORMAL_STEP_M);
    // The candidates in one sequence, as `cover::fitted` tries them: the
    // blade as made, the turns, then the best turn's shrinks.
    int turns = int(COVER_FIT_TURNS);
    int best = 0;
    float highest = -uintBitsToFloat(0x7F7FFFFFu);
    for (int c = 0; c <= 2 * turns + int(COVER_FIT_SHRINKS) - 1; ++c) {
        bool turning = c <= 2 * turns;
        int k = turning ? fit_turn_of(c) : best;
        float t = turning ? 1.0 : 1.0 - float(c - 2 * turns) / float(COVER_FIT_SHRINKS);
        vec3 q[4] = p;
        vec3 v = w;
        fit_candidate(q, v, k, t);
        float clearance = fit_clearance(q, n);
        if (clearance >= 0.0) {
            p = q;
            w = v;
            return;
        }
        if (turning && clearance > highest) {
            best = k;
            highest = clearance;
        }
    }
    fit_candidate(p, w, best, 0.0);
}

// `cover::held_above_ground` for a far blade posed `p` at `angle`: where
// its curve does not clear the ground, its angles scaled toward rest
// (which the fit keeps clear) as far as it needs, by halvings, and its
// pose made again; whether it was. One sequence of tries (the pose as
// solved, then each halving), so the kernel holds one copy of the test.
bool held_above_ground(GrassBlade b, inout vec4 angle, inout Pose p) {
    float lo = 0.0, hi = 1.0;
    Pose tried = p;
    for (uint i = 0u; i <= COVER_HOLD_HALVINGS; ++i) {
        float mid = 0.5 * (lo + hi);
        if (i > 0u) {
            tried = blade_pose(b, angle * mid, 0.0);
        }
        bool clear = ground_clearance(tried.points) >= 0.0;
        if (i == 0u && clear) {
            return false;
        }
        if (i > 0u && clear) {
            lo = mid;
        } else if (i > 0u) {
            hi = mid;
        }
    }
    angle *= lo;
    p = blade_pose(b, angle, 0.0);
    return true;
}

// `cover::pressed_fade`: 1 within the radius less the band, 0 from the
// radius on, smoothstep between.
float pressed_fade(float radius, float d) {
    float band = min(COVER_PRESS_FADE_M, radius);
    if (band <= 0.0) {
        return 0.0;
    }
    float t = clamp((radius - d) / band, 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// `cover::state_slot`: the tile's coordinates wrapped (`rem_euclid`).
// GLSL leaves % of negative integers undefined: the coordinate is first
// raised by a multiple of the side, which leaves the remainder as it is,
// past zero for any tile within 2^20 sides (over 4,000 km) of the origin.
uint wrap(int a, uint side) {
    return uint(a + int(side) * (1 << 20)) % side;
}

uint state_slot(ivec2 tile, uint side) {
    return wrap(tile.x, side) + side * wrap(tile.y, side);
}

// `cover::far_tag`.
uint far_tag(ivec2 tile) {
    return (1u << 30) | (uint(tile.x) & 0x7fffu) | ((uint(tile.y) & 0x7fffu) << 15);
}

void main() {
    if (gl_GlobalInvocationID.x >= pc.count) {
        return;
    }
    // The binding's blade, and which of the cover's it is.
    uint local = pc.start + gl_GlobalInvocationID.x;
    uint blade = pc.first + local - pc.base;
    uint slot = blade / pc.per_tile;
    uint index = blade - slot * pc.per_tile;
    ivec2 tile = pc.origin + ivec2(int(slot % pc.side), int(slot / pc.side));
    uint key = hash(pc.seed ^ hash(uint(tile.x) ^ hash(uint(tile.y) ^ hash(index))));
    uint far_slot = state_slot(tile, pc.side) * pc.per_tile + index;

    precise vec2 root = (vec2(tile) + vec2(draw(key, 0u), draw(key, 1u))) * pc.tile_m;
    vec2 f = facing(draw(key, 2u), draw_bits(key, 3u));
    precise float pick = draw(key, 4u) * pc.kinds.z;
    uint kind = pick < pc.kinds.x ? 0u : (pick < pc.kinds.y ? 1u : 2u);
    precise float h = pc.height.x + (pc.height.y - pc.height.x) * draw(key, 5u);
    precise float width = pc.width.x + (pc.width.y - pc.width.x) * draw(key, 6u);
    vec2 unit[4] = profile(kind, draw(key, 7u));
    float rand = draw(key, 8u);
    precise float hw = 0.5 * width;
    // UP x facing, as `cover::blade` leaves it (turned by the fit below).
    vec3 width_dir = vec3(f.y, 0.0, -f.x);
    vec3 rest[4];
    for (int i = 0; i < 4; ++i) {
        // root + facing x + up y, as `Blade`'s rest points are summed.
        precise vec3 p = vec3(root.x, 0.0, root.y) + vec3(f.x, 0.0, f.y) * (unit[i].x * h)
            + vec3(0.0, 1.0, 0.0) * (unit[i].y * h);
        rest[i] = p;
    }
    // Rooted on the ground (`Terrain::lifted`): raised to its height under
    // the root, upright as grass grows on a slope.
    if (!terrain_is_flat()) {
        float lift = terrain_height(root.x, root.y);
        for (int i = 0; i < 4; ++i) {
            precise float y = rest[i].y + lift;
            rest[i].y = y;
        }
    }
    // Beyond the bounds (`CoverTiles::grows_at`): no blade, its rest
    // points without width (`cover::left_out`), which no pass draws.
    if (!(root.x >= pc.bounds_min.x && root.x < pc.bounds_max.x && root.y >= pc.bounds_min.y
          && root.y < pc.bounds_max.y)) {
        atomicAdd(outside, 1u);
        if (params.far_kept != 0u) {
            far_poses[far_slot].tile = 0u;
        }
        for (int i = 0; i < 4; ++i) {
            vertices[4u * local + uint(i)] = BladeVertex(rest[i], rand, vec3(0.0), 0.0);
        }
        return;
    }
    // The box the reach allows around the root holds the blade however
    // the fit turns or shrinks it.
    float reach = distance(rest[0], rest[1]) + distance(rest[1], rest[2]) + distance(rest[2], rest[3]);
    bool drawn = params.pose_drawn_only == 0u || may_be_drawn(rest[0], rand, reach, hw);
    // Fitted to the ground (`cover::fitted`): a blade leaning into a
    // slope turned away from it. Not a blade this frame cannot draw.
    if ((drawn || params.pose == 0u) && !terrain_is_flat()) {
        fit_to_ground(rest, width_dir);
    }
    precise vec3 half_width = width_dir * hw;
    if (params.pose == 0u || !drawn) {
        if (params.far_kept != 0u) {
            far_poses[far_slot].tile = 0u;
        }
        for (int i = 0; i < 4; ++i) {
            vertices[4u * local + uint(i)] = BladeVertex(rest[i], rand, half_width, 0.0);
        }
        return;
    }
    // The quasi-static pose in the wind at the rest tip (`cover::posed_vertices`),
    // written as the grass step writes a blade (`write_blade` in step.glsl);
    // near the camera the dynamics' angles.
    float between_tip = params.tip_stiffness.x + (params.tip_stiffness.y - params.tip_stiffness.x) * draw(key, 9u);
    float ratio = params.stiffness_ratio.x + (params.stiffness_ratio.y - params.stiffness_ratio.x) * draw(key, 10u);
    float sigma = params.sigma.x + (params.sigma.y - params.sigma.x) * draw(key, 11u);
    float edge_mass = params.edge_mass.x + (params.edge_mass.y - params.edge_mass.x) * draw(key, 12u);
    GrassBlade b = cover_grass_blade(rest, width_dir, hw, rand, between_tip, ratio,
                                     sigma, edge_mass);
    // A blade of the simulated square's tiles shows its dynamics' state;
    // the square's edge is crossed without a jump because a tile coming in
    // starts its dynamics from the pose shown the frame before
    // (glsl/cover/enter.comp) and a blade leaving goes on from its state.
    bool kept_blade = false;
    vec4 kept_angle = vec4(0.0);
    vec4 kept_velocity = vec4(0.0);
    float pressed = 0.0;
    ivec2 k = tile - params.kept_origin;
    if (params.dynamic != 0u && all(greaterThanEqual(k, ivec2(0)))
        && all(lessThan(k, ivec2(int(params.kept_side))))) {
        kept_blade = true;
        uint kept = state_slot(tile, params.kept_side) * pc.per_tile + index;
        kept_angle = states[kept].angle;
        kept_velocity = states[kept].velocity;
        // Pressed as the dynamics left it, faded out over the band inside
        // the radius: beyond it no collider presses the far field.
        if (params.pressed_states != 0u) {
            pressed = presses[kept].pressed
                * pressed_fade(params.simulate_radius, distance(root, params.eye));
        }
    }
    // The pose the blade showed the frame before, if it was posed then.
    uint tag = far_tag(tile);
    FarPose last = FarPose(vec4(0.0), vec4(0.0), vec3(0.0), 0u);
    if (params.far_kept != 0u) {
        last = far_poses[far_slot];
    }
    bool had_pose = last.tile == tag;
    vec4 angle = kept_angle;
    vec4 velocity = kept_velocity;
    if (kept_blade) {
        atomicAdd(from_state, 1u);
    } else {
        atomicAdd(posed, 1u);
        // The balance the blade gives into from where it stands: from
        // last frame's pose (the side it was on), else from rest
        // (`quasi_static_angles_from`).
        bool tracked = had_pose && params.far_tracking != 0u;
        angle = quasi_static_angles_from(b, sample_wind(params.grid, rest[3]),
                                         tracked ? last.angle : vec4(0.0));
        velocity = vec4(0.0);
        // Towards the balance from where it was, as its dynamics could go
        // in the frame's time (`quasi_static::far_tracked`): no jump where
        // the balance moves faster than the blade could follow.
        if (tracked) {
            vec4 target = angle;
            angle = last.angle;
            velocity = last.velocity;
            far_tracked(angle, velocity, target, far_frequency(b), params.elapsed);
        }
    }
    Pose p = blade_pose(b, angle, pressed);
    // The far field has no contact: where the pose would press the blade
    // into the ground, the ground holds it, and stops it.
    if (!kept_blade && !terrain_is_flat() && held_above_ground(b, angle, p)) {
        velocity = vec4(0.0);
    }
    vec3 rest_tip = normalize_or(rest[3] - rest[2], UP);
    float displacement = atan(length(cross(rest_tip, p.e[2])), dot(rest_tip, p.e[2]));
    vec3 tip = p.points[BLADE_CONTROL_POINTS - 1];
    if (had_pose) {
        uint jump = floatBitsToUint(distance(tip, last.tip));
        atomicMax(tip_jump, jump);
        if (!kept_blade) {
            atomicMax(far_tip_jump, jump);
        }
    }
    if (params.far_kept != 0u) {
        far_poses[far_slot] = FarPose(angle, velocity, tip, tag);
    }
    for (int i = 0; i < BLADE_CONTROL_POINTS; ++i) {
        int edge = max(i, 1) - 1;
        vertices[4u * local + uint(i)] = BladeVertex(p.points[i], rand, p.w_local[edge] * hw,
                                                     displacement);
    }
}
