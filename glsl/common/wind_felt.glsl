// The wind a blade feels at a point of the world (`WindField::sample`): on
// a grid that follows the ground (a cover's wind window over terrain), the
// point's height is taken above the ground under it
// (`WindField::window_point`). The includer declares the terrain buffer
// (terrain.glsl's `terrain` and `terrain_words`) and includes
// wind_sample.glsl.
#include "terrain.glsl"

vec3 window_point(WindGridParams g, vec3 p) {
    if (g.follows_ground == 0u) {
        return p;
    }
    precise float y = p.y - terrain_height(p.x, p.z);
    return vec3(p.x, y, p.z);
}

vec3 wind_felt(WindGridParams g, vec3 p) {
    return sample_wind(g, window_point(g, p));
}
