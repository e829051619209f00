//! libFuzzer on the scene-file parser: any bytes that are UTF-8 text must
//! satisfy tests/common/scene_property.rs (no panic, one-line refusals
//! naming the file, accepted scenes checked and round-tripping). Non-UTF-8
//! input is refused before parsing (`scene::file::load`), so it is skipped.

#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "../../common/scene_property.rs"]
mod scene_property;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        scene_property::check(text);
    }
});
