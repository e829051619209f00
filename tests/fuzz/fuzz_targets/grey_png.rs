//! The grey PNGs a scene names (a height map; src/scene/grey_png.rs): any
//! bytes are read or refused without a panic, in one line, and never
//! allocate past the header's limit (a declared 100000 x 100000 image is
//! refused before decoding). Run with `scripts/fuzz 300 grey_png`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use meadow::scene::grey_png;

fuzz_target!(|bytes: &[u8]| {
    match grey_png::read_bytes(bytes) {
        Ok(grey) => {
            assert!(grey.width <= grey_png::MAX_SIDE && grey.height <= grey_png::MAX_SIDE);
            assert_eq!(grey.values.len(), (grey.width * grey.height) as usize);
            assert!(grey.values.iter().all(|v| (0.0..=1.0).contains(v)));
        }
        Err(why) => assert!(!why.contains('\n'), "{why}"),
    }
});
