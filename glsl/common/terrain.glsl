// The ground's height field (`Terrain::height`, src/model/terrain.rs) as
// `Terrain::gpu_words` packs it: the includer declares `terrain` (the
// TerrainHeader, src/interface/defs.rs) and the words after it,
// `terrain_words[]`. Summed in the CPU's order and never fused
// (`precise`): the two sides differ by their divisions' rounding at most.

bool terrain_is_flat() {
    return terrain.map_size.x == 0u && terrain.hills == 0u && terrain.ridges == 0u;
}

// H / (1 + (d/L)^2), d^2 given (`terrain::agnesi`).
float terrain_agnesi(float height, float half_width, float distance_squared) {
    precise float h = height / (1.0 + distance_squared / (half_width * half_width));
    return h;
}

// The height map at (x, z), bilinear and held at its edges
// (`HeightMap::height`, `terrain::bilinear`); its samples from word `first`.
float terrain_map(float x, float z, uint first) {
    uint columns = terrain.map_size.x, rows = terrain.map_size.y;
    precise float u = (x - terrain.map_center.x) / terrain.map_extent.x + 0.5;
    precise float v = (z - terrain.map_center.y) / terrain.map_extent.y + 0.5;
    precise float nx = float(columns), nz = float(rows);
    precise float su = clamp(u * (nx - 1.0), 0.0, nx - 1.0);
    precise float sv = clamp(v * (nz - 1.0), 0.0, nz - 1.0);
    uint i0 = uint(floor(su)), j0 = uint(floor(sv));
    uint i1 = min(i0 + 1u, columns - 1u), j1 = min(j0 + 1u, rows - 1u);
    precise float fu = su - float(i0), fv = sv - float(j0);
    precise float a = terrain_words[first + i0 + columns * j0] * (1.0 - fu)
        + terrain_words[first + i1 + columns * j0] * fu;
    precise float b = terrain_words[first + i0 + columns * j1] * (1.0 - fu)
        + terrain_words[first + i1 + columns * j1] * fu;
    precise float h = a * (1.0 - fv) + b * fv;
    return h;
}

// The ground's height at (x, z): the map's, then each hill's and each
// ridge's added in turn (`Terrain::height`); 0 where it is flat.
float terrain_height(float x, float z) {
    uint hills = terrain.hills, ridges = terrain.ridges;
    uint map_first = 4u * hills + 8u * ridges;
    precise float h = terrain.map_size.x > 0u ? terrain_map(x, z, map_first) : 0.0;
    for (uint i = 0u; i < hills; ++i) {
        uint w = 4u * i;
        precise float dx = x - terrain_words[w], dz = z - terrain_words[w + 1u];
        precise float r2 = dx * dx + dz * dz;
        h += terrain_agnesi(terrain_words[w + 2u], terrain_words[w + 3u], r2);
    }
    for (uint i = 0u; i < ridges; ++i) {
        uint w = 4u * hills + 8u * i;
        precise float dx = x - terrain_words[w], dz = z - terrain_words[w + 1u];
        // Across the axis (cos, sin) through the centre: perp_dot.
        precise float d = dx * terrain_words[w + 5u] - dz * terrain_words[w + 4u];
        h += terrain_agnesi(terrain_words[w + 2u], terrain_words[w + 3u], d * d);
    }
    return h;
}

// The upward unit normal at (x, z) from central differences over `step`
// metres (`Terrain::normal`); straight up where the terrain is flat.
vec3 terrain_normal(float x, float z, float step) {
    if (terrain_is_flat()) {
        return vec3(0.0, 1.0, 0.0);
    }
    float dx = (terrain_height(x + step, z) - terrain_height(x - step, z)) / (2.0 * step);
    float dz = (terrain_height(x, z + step) - terrain_height(x, z - step)) / (2.0 * step);
    return normalize(vec3(-dx, 1.0, -dz));
}
