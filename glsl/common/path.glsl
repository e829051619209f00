// Motion along waypoints: a wind source's (always closed) and a collider's.
// Mirrors `along_path` in src/model/path.rs.
#ifndef MEADOW_PATH_GLSL
#define MEADOW_PATH_GLSL

#include "interface.glsl"   // MAX_PATH_POINTS

// Where a point moving at `speed` through the first n waypoints of `path` is
// at time t (velocity: how fast, where): round and round when closed, else
// once, stopping at the end. With fewer than two points or no speed it stays
// at the first point, or at `fallback` without one.
vec3 along_path(vec4 path[MAX_PATH_POINTS], uint n, float speed, bool closed, float t,
                vec3 fallback, out vec3 velocity) {
    velocity = vec3(0.0);
    if (n < 2u || speed <= 0.0) {
        return n >= 1u ? path[0].xyz : fallback;
    }
    uint segments = closed ? n : n - 1u;
    float total = 0.0;
    for (uint i = 0u; i < segments; ++i) {
        total += distance(path[i].xyz, path[(i + 1u) % n].xyz);
    }
    if (total <= 0.0) {
        return path[0].xyz;
    }
    float travelled = speed * t;
    bool moving = true;
    float s;
    if (closed) {
        s = travelled - total * floor(travelled / total);
    } else if (travelled < total) {
        s = travelled;
    } else {
        s = total;
        moving = false;
    }
    for (uint i = 0u; i < segments; ++i) {
        vec3 from = path[i].xyz;
        vec3 to = path[(i + 1u) % n].xyz;
        float len = distance(from, to);
        if (s <= len || i == segments - 1u) {
            float f = len > 0.0 ? min(s / len, 1.0) : 0.0;
            velocity = moving && len > 0.0 ? (to - from) * (speed / len) : vec3(0.0);
            return mix(from, to, f);
        }
        s -= len;
    }
    return path[0].xyz;
}

#endif
