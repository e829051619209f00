//! `meadow scenes`: the built-in scenes with their blade counts and
//! captions, or one of them (or any scene file) as TOML to start from.

use crate::error::Result;
use crate::scene::{self, Scene};

/// One line per built-in scene, then where the files and the format are.
pub fn list() -> Result<String> {
    let mut text = String::new();
    for (name, _) in scene::BUILTIN {
        let s = Scene::builtin(name)?;
        text += &format!("{name:<24} {:>8} blades  {}\n", s.blade_count(), s.caption);
    }
    text += "(each is also scenes/<name>.toml; docs/scenes.md describes the format)\n";
    Ok(text)
}

/// The scene named (a built-in or a file) as TOML.
pub fn print(name: &str) -> Result<String> {
    Ok(scene::file::to_toml(&Scene::load(name)?))
}
