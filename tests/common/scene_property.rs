//! The property every scene text must have, shared by the bounded fuzz of
//! the normal suite (tests/parser_fuzz.rs) and the cargo-fuzz target
//! (tests/fuzz/fuzz_targets/scene_file.rs): parsing never panics, a
//! refusal is one line that names the file, and whatever is accepted is a
//! checked scene that survives a round trip through TOML.

use meadow::scene::file;

pub fn check(text: &str) {
    match file::parse(text, "fuzz.toml") {
        Err(e) => {
            let msg = e.to_string();
            assert!(!msg.contains('\n'), "a refusal over several lines: {msg:?}");
            assert!(
                msg.starts_with("fuzz.toml"),
                "the refusal does not name the file: {msg}"
            );
        }
        Ok(scene) => {
            scene.validate().expect("accepted scenes are checked");
            let again = file::parse(&file::to_toml(&scene), "round trip").expect("round trip");
            assert_eq!(again, scene);
        }
    }
}
