// Colliders (ours; docs/physics.md, "Colliders"): spheres and upright
// capsules moving through the meadow, as the grass kernel (which they press)
// and the wind's forces kernel (whose air they push) read them. Mirrors
// `Collider` and `ColliderState` in src/model/collider.rs.
#ifndef MEADOW_COLLIDER_GLSL
#define MEADOW_COLLIDER_GLSL

#include "path.glsl"

// MAX_COLLIDERS, GpuCollider and GpuColliderState (a collider at one
// instant: the segment a..b swept by the radius, and the velocity of its
// centre).
#include "interface.glsl"

const vec3 COLLIDER_UP = vec3(0.0, 1.0, 0.0);

// `Collider::motion_at` and `Collider::at`: position and velocity at time t.
GpuColliderState collider_at(GpuCollider c, float t) {
    vec3 velocity;
    // Until it sets off it waits, still, at its first point.
    bool waiting = t < c.sets_off;
    vec3 p = along_path(c.path, c.path_points, waiting ? 0.0 : c.path_speed, c.closed != 0u,
                        max(t - c.sets_off, 0.0), c.position, velocity);
    float r = c.radius;
    GpuColliderState st;
    st.radius = r;
    if (c.capsule == 0u) {
        st.a = p;
        st.b = p;
    } else {
        st.a = p + COLLIDER_UP * r;
        st.b = p + COLLIDER_UP * max(c.height - r, r);
    }
    st.velocity = velocity;
    return st;
}

// `ColliderState::distance`: signed distance (x) and outward normal (yzw).
vec4 collider_distance(GpuColliderState c, vec3 p) {
    vec3 a = c.a;
    vec3 ab = c.b - a;
    float len2 = dot(ab, ab);
    float t = len2 > 0.0 ? clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    vec3 off = p - (a + ab * t);
    float l = length(off);
    vec3 n = l > 1e-12 ? off / l : COLLIDER_UP;
    return vec4(l - c.radius, n);
}

#endif
