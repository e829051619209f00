#version 450
#extension GL_GOOGLE_include_directive : require
// Kernel 1, add forces (paper section 3.2): every free face gains dt * f of
// every wind source; inflow faces take the inflow velocity; walls hold zero.
// Free and buried faces first lose the turbulence the last step added.
// The colliders are moving obstacles (ours, `WindField::add_forces`): a free
// face inside one takes its velocity.
#include "wind_kernel.glsl"
#include "collider.glsl"

layout(set = 0, binding = 10, std430) readonly buffer Colliders { GpuCollider colliders[]; };
// Every collider where it is at this step's time, once per workgroup.
shared GpuColliderState moving[MAX_COLLIDERS];
// Whether the step has wind sources and colliders (1 or 0, a factor of
// their counts): 0 leaves their code
// out of the pipeline (`WindPass`'s plain forces kernel), which matters on
// lavapipe, where a loop's body runs once, masked, even when no invocation
// enters it (the sources' and colliders' loops were most of this kernel's
// time on a scene with neither).
layout(constant_id = 0) const uint WITH_SOURCES = 1u;
layout(constant_id = 1) const uint WITH_COLLIDERS = 1u;

float falloff(float d, float r) {
    float q = 1.0 - (d / r) * (d / r);
    return q > 0.0 ? q * q : 0.0;
}

// Position of a source moving along its closed path at time t.
vec3 source_position(GpuWindSource s, float t) {
    vec3 unused_velocity;
    return along_path(s.path, s.path_points, s.path_speed, true, t, s.position,
                      unused_velocity);
}

// What the last step's turbulence added to face `id`: without turbulence
// the buffer holds one zero, and every face takes 0.
float turbulence_taken(uint id) {
    return id < uint(turbulence_added.length()) ? turbulence_added[id] : 0.0;
}

void main() {
    uint id = gl_GlobalInvocationID.x;
    float t = pc.time;
    float dt = pc.dt;
    uint moving_count = WITH_COLLIDERS * pc.collider_count;
    for (uint i = gl_LocalInvocationIndex; i < moving_count; i += gl_WorkGroupSize.x) {
        moving[i] = collider_at(colliders[i], t);
    }
    barrier();
    if (id >= pc.grid.faces) {
        return;
    }
    uint kind = face_kind[id];
    if (kind == FACE_BURIED) {
        // Holds the ghost value under_ground.comp gave it, without the
        // last step's turbulence.
        vel[id] -= turbulence_taken(id);
        return;
    }
    if (kind == FACE_WALL) {
        vel[id] = 0.0;
        return;
    }
    uint axis;
    uvec3 f;
    face_of(pc.grid, id, axis, f);
    vec3 x = face_position(pc.grid, axis, f);
    if (kind == FACE_INFLOW) {
        vel[id] = inflow_velocity(axis, x, t);
        return;
    }
    float a = 0.0;
    uint source_count = WITH_SOURCES * pc.source_count;
    for (uint i = 0u; i < source_count; ++i) {
        GpuWindSource s = sources[i];
        // The direction turns about +y (paper Fig. 11: a rotating wind).
        float angle = s.rotation_speed * t;
        float sn = sin(angle), cs = cos(angle);
        vec3 d = s.direction;
        vec3 dir = vec3(cs * d.x + sn * d.z, d.y, -sn * d.x + cs * d.z);
        float strength = t >= s.off_after ? 0.0
                       : s.strength * gust_factor(s.gust_amplitude, s.gust_frequency, s.gust_phases, t);
        a += strength * dir[axis] * falloff(distance(x, source_position(s, t)), s.radius);
    }
    // The mean wind: the last step's turbulence taken off.
    float u = vel[id] - turbulence_taken(id) + dt * a;
    for (uint i = 0u; i < moving_count; ++i) {
        if (collider_distance(moving[i], x).x < 0.0) {
            u = moving[i].velocity[axis];
            break;
        }
    }
    vel[id] = u;
}
