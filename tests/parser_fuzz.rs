//! A bounded fuzz of the scene-file parser in the normal suite (the
//! unbounded one is the cargo-fuzz target in tests/fuzz, run by
//! scripts/fuzz), checking tests/common/scene_property.rs on arbitrary
//! text, TOML-shaped text and shipped scenes with an edit.

use crate::common;

use common::scene_property::check;
use meadow::scene::{Scene, BUILTIN};
use proptest::prelude::*;

/// A shipped scene with one edit: a span deleted, or text put in.
fn mutated() -> impl Strategy<Value = String> {
    let texts: Vec<&'static str> = BUILTIN.iter().map(|(_, t)| *t).collect();
    let noise = prop_oneof![
        Just(String::new()),
        Just("0".to_string()),
        Just("-1".to_string()),
        Just("1e300".to_string()),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("\"x\"".to_string()),
        Just("[".to_string()),
        Just("]]".to_string()),
        Just("= ".to_string()),
        Just("\n[wind]\n".to_string()),
        Just("\n[[grass.bunch]]\n".to_string()),
        Just("99999999999999999999".to_string()),
        "[ -~]{0,12}",
    ];
    (
        proptest::sample::select(texts),
        any::<prop::sample::Index>(),
        0usize..40,
        noise,
    )
        .prop_map(|(text, at, delete, insert)| {
            let mut bytes = text.as_bytes().to_vec();
            let start = at.index(bytes.len() + 1);
            let end = (start + delete).min(bytes.len());
            bytes.splice(start..end, insert.bytes());
            String::from_utf8_lossy(&bytes).into_owned()
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,300}") {
        check(&text);
    }

    #[test]
    fn toml_shaped_text_never_panics(text in "(\\[{1,2}[a-z.]{1,12}\\]{1,2}\n|[a-z_]{1,10} = (-?[0-9.e]{1,8}|\"[a-z]{0,6}\"|\\[[0-9., ]{0,12}\\]|true)\n){0,12}") {
        check(&text);
    }

    #[test]
    fn edited_shipped_scenes_never_panic(text in mutated()) {
        check(&text);
    }
}

#[test]
fn every_shipped_scene_passes_the_same_check() {
    for (name, text) in BUILTIN {
        check(text);
        assert!(Scene::builtin(name).is_ok());
    }
}

/// A small grey PNG of the fuzz target's seeds with one edit: bytes
/// overwritten, or the file cut short.
fn edited_png() -> impl Strategy<Value = Vec<u8>> {
    let seeds: [&[u8]; 2] = [
        include_bytes!("fuzz/seeds/grey8.png"),
        include_bytes!("fuzz/seeds/grey16.png"),
    ];
    (
        proptest::sample::select(seeds.to_vec()),
        any::<prop::sample::Index>(),
        proptest::collection::vec(any::<u8>(), 0..6),
        any::<bool>(),
    )
        .prop_map(|(seed, at, noise, cut)| {
            let mut bytes = seed.to_vec();
            let start = at.index(bytes.len());
            if cut {
                bytes.truncate(start);
            } else {
                for (i, b) in noise.into_iter().enumerate() {
                    if let Some(slot) = bytes.get_mut(start + i) {
                        *slot = b;
                    }
                }
            }
            bytes
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, failure_persistence: None, ..ProptestConfig::default() })]

    /// The height-map reader (src/scene/grey_png.rs) on edited and cut
    /// PNGs: read within its limits, or refused in one line; never a panic.
    #[test]
    fn edited_height_maps_never_panic(bytes in edited_png()) {
        match meadow::scene::grey_png::read_bytes(&bytes) {
            Ok(grey) => {
                prop_assert_eq!(grey.values.len(), (grey.width * grey.height) as usize);
                prop_assert!(grey.values.iter().all(|v| (0.0..=1.0).contains(v)));
            }
            Err(why) => prop_assert!(!why.contains('\n'), "{}", why),
        }
    }
}
