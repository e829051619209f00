// The wind grid as every wind kernel sees it (mirrors src/model/wind/, the
// CPU reference, kernel by kernel). Staggered (MAC) layout: component a of
// the velocity lives on the cells' a-faces, so component a has one more
// sample along axis a. The three components are stored one after another;
// the velocity buffer holds two such copies (halves A and B).
#ifndef MEADOW_WIND_GRID_GLSL
#define MEADOW_WIND_GRID_GLSL

// WindGridParams and the face kinds (FACE_FREE, ...): src/interface/defs.rs.
#include "interface.glsl"

uvec3 face_dims(WindGridParams g, uint axis) {
    uvec3 d = g.cells.xyz;
    d[axis] += 1u;
    return d;
}

// Offset of component `axis` inside one velocity copy.
uint component_offset(WindGridParams g, uint axis) {
    uint off = 0u;
    for (uint a = 0u; a < axis; ++a) {
        uvec3 d = face_dims(g, a);
        off += d.x * d.y * d.z;
    }
    return off;
}

uint face_index(WindGridParams g, uint axis, uvec3 f) {
    uvec3 d = face_dims(g, axis);
    return component_offset(g, axis) + f.x + d.x * (f.y + d.y * f.z);
}

// Which component and which face a flat index (within one copy) is.
void face_of(WindGridParams g, uint flat_index, out uint axis, out uvec3 f) {
    uint rest = flat_index;
    axis = 0u;
    for (uint a = 0u; a < 3u; ++a) {
        uvec3 d = face_dims(g, a);
        uint count = d.x * d.y * d.z;
        if (rest < count || a == 2u) {
            axis = a;
            f = uvec3(rest % d.x, (rest / d.x) % d.y, rest / (d.x * d.y));
            return;
        }
        rest -= count;
    }
}

uint cell_index(WindGridParams g, uvec3 c) {
    return c.x + g.cells.x * (c.y + g.cells.y * c.z);
}

vec3 face_position(WindGridParams g, uint axis, uvec3 f) {
    vec3 offset = vec3(0.5);
    offset[axis] = 0.0;
    return g.origin.xyz + (vec3(f) + offset) * g.cell_size.xyz;
}

#endif
