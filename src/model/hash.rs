//! A 32-bit integer hash both sides compute alike: the distance thinning
//! draws from it (glsl/common/thinning.glsl), the cover makes its blades
//! with it (glsl/cover/tiles.comp).

/// Wellons' lowbias32: every bit of the input moves about half of the
/// output's; wrapping integer arithmetic only, so the GPU's is the same.
pub fn lowbias32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}
