// A 32-bit integer hash (Wellons' lowbias32; `model::hash::lowbias32`):
// every bit of the input moves about half of the output's. The distance
// thinning draws from it, the cover makes its blades with it.
#ifndef MEADOW_HASH_GLSL
#define MEADOW_HASH_GLSL

uint lowbias32(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

#endif
