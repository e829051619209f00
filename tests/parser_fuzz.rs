//! A bounded fuzz of the scene-file parser in the normal suite (the
//! unbounded one is the cargo-fuzz target in tests/fuzz, run by
//! scripts/fuzz), checking tests/common/scene_property.rs on arbitrary
//! text, TOML-shaped text and shipped scenes with an edit.

mod common;

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
